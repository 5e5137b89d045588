"""RGB → spectrum: the Jakob & Hanika round trip measured with
colour-science's colorimetry, and Smits against colour-science's Smits."""
import colour
import numpy as np
import pytest
from colour.recovery import RGB_to_sd_Smits1999, SDS_SMITS1999

import scotopia


def reflectance_xyz(values, wl, illuminant_name):
    """XYZ (white Y = 1) of reflectances (N, 471) under a CIE illuminant, with
    colour-science's observer and illuminant data."""
    cmfs = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"].values
    ill = colour.SDS_ILLUMINANTS[illuminant_name]
    # colour tabulates D65 to 780 nm; beyond, the CIE table's last values hold.
    i = np.interp(wl, ill.wavelengths, ill.values)
    weights = cmfs * i[:, None]
    return values @ weights / weights[:, 1].sum()


def test_jakob2019_srgb_round_trip_with_colour_science(wl):
    n = 32
    grid = np.stack(np.meshgrid(*[np.linspace(0, 1, n)] * 3, indexing="ij"), -1).reshape(-1, 3)
    values = np.array([scotopia.Spectrum.from_rgb(tuple(c))(wl) for c in grid])
    assert values.min() >= 0.0 and values.max() <= 1.0
    xyz = reflectance_xyz(values, wl, "D65")
    cs = colour.RGB_COLOURSPACES["sRGB"]
    target = grid @ colour.normalised_primary_matrix(cs.primaries, cs.whitepoint).T
    lab_t = colour.XYZ_to_Lab(target, cs.whitepoint)
    lab_s = colour.XYZ_to_Lab(xyz, cs.whitepoint)
    de = colour.delta_E(lab_t, lab_s, method="CIE 2000")
    assert de.max() <= 0.1, (de.max(), grid[de.argmax()])
    assert de.mean() <= 0.01, de.mean()


def test_round_trip_report_matches_the_rust_measurement():
    r = scotopia.round_trip("jakob2019", "srgb", 32)
    assert r["count"] == 32**3 and r["out_of_range"] == 0
    assert r["max_de"] <= 0.1 and r["mean_de"] <= 0.01


def test_jakob2019_agrees_with_colour_science_fit(wl):
    # colour-science solves the same 3-parameter problem with its own
    # optimiser; where the solution is unique, the spectra agree.
    cs = colour.RGB_COLOURSPACES["sRGB"]
    m = colour.normalised_primary_matrix(cs.primaries, cs.whitepoint)
    d65 = colour.SDS_ILLUMINANTS["D65"]
    for rgb in [(0.6, 0.3, 0.2), (0.2, 0.5, 0.3), (0.25, 0.3, 0.7)]:
        sd = colour.recovery.XYZ_to_sd_Jakob2019(m @ np.array(rgb), illuminant=d65)
        ours = scotopia.Spectrum.from_rgb(rgb)(sd.wavelengths)
        np.testing.assert_allclose(ours, sd.values, atol=0.01)


def test_smits_matches_colour_science(rng, wl):
    basis_wl = SDS_SMITS1999["white"].wavelengths
    for rgb in rng.random((20, 3)):
        ref = RGB_to_sd_Smits1999(rgb)
        ours = scotopia.Spectrum.from_rgb(tuple(rgb), method="smits")(basis_wl)
        # Tabulated spectra are read from a uniform grid within 1e-4 of
        # their peak (crates/color/src/spectrum/lookup.rs).
        np.testing.assert_allclose(ours, ref.values, atol=1e-4 * ref.values.max())


def test_kinds(wl):
    refl = scotopia.Spectrum.from_rgb((0.5, 0.25, 0.1))
    unb = scotopia.Spectrum.from_rgb((5.0, 2.5, 1.0), kind="unbounded")
    assert unb(wl).max() > 1.0
    # An sRGB emitter of (1, 1, 1) is D65-white, as luminous as E at 1 W·sr⁻¹·m⁻²·nm⁻¹.
    white = scotopia.spectrum(rgb=(1.0, 1.0, 1.0), kind="illuminant")
    equal = scotopia.spectrum(illuminant="E")
    assert white["xyz"][1] == pytest.approx(equal["xyz"][1], rel=2e-3)
    assert white["xy"] == pytest.approx([0.3127, 0.3290], abs=5e-4)
    with pytest.raises(ValueError, match="above 1"):
        scotopia.Spectrum.from_rgb((1.5, 0.2, 0.1))
    with pytest.raises(ValueError, match="outside the srgb gamut"):
        scotopia.Spectrum.from_rgb((-0.1, 0.2, 0.1), kind="unbounded")
    assert refl(wl).max() <= 1.0


def test_bad_spectrum_files_name_file_and_line(tmp_path):
    bad = tmp_path / "lamp.csv"
    bad.write_text("400,1\n500,x\n")
    with pytest.raises(ValueError, match=r"lamp.csv:2: 'x' is not a number"):
        scotopia.Spectrum.from_file(str(bad))
    with pytest.raises(OSError, match="missing.csv"):
        scotopia.Spectrum.from_file(str(tmp_path / "missing.csv"))


def test_plot_writes_a_png(tmp_path):
    out = tmp_path / "f11.png"
    scotopia.spectrum(illuminant="F11", plot=out)
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
