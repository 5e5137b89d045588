"""Colour spaces, adaptation, CIELAB, CIEDE2000 and Oklab against colour-science."""
import colour
import numpy as np
import pytest

import scotopia

SPACES = {"srgb": "sRGB", "p3": "Display P3", "rec2020": "ITU-R BT.2020", "acescg": "ACEScg"}


@pytest.mark.parametrize("ours,theirs", SPACES.items())
def test_matrices_derived_from_primaries(ours, theirs):
    cs = colour.RGB_COLOURSPACES[theirs]
    ref = colour.normalised_primary_matrix(cs.primaries, cs.whitepoint)
    np.testing.assert_allclose(scotopia.rgb_to_xyz_matrix(ours), ref, atol=1e-12)
    assert scotopia.white_point(ours) == pytest.approx(list(cs.whitepoint), abs=1e-12)


def test_rgb_xyz_round_trip(rng):
    rgb = rng.random((50, 3))
    for space in SPACES:
        back = scotopia.xyz_to_rgb(scotopia.rgb_to_xyz(rgb, space), space)
        np.testing.assert_allclose(back, rgb, atol=1e-12)


@pytest.mark.parametrize("ours,theirs", [("bradford", "Bradford"), ("cat02", "CAT02"), ("vonkries", "Von Kries")])
def test_chromatic_adaptation(rng, ours, theirs):
    xyz = rng.random((20, 3))
    src = colour.xy_to_XYZ(colour.CCS_ILLUMINANTS["CIE 1931 2 Degree Standard Observer"]["A"])
    dst = colour.xy_to_XYZ(colour.CCS_ILLUMINANTS["CIE 1931 2 Degree Standard Observer"]["D65"])
    ref = colour.adaptation.chromatic_adaptation_VonKries(xyz, src, dst, transform=theirs)
    np.testing.assert_allclose(scotopia.chromatic_adaptation(xyz, list(src), list(dst), ours), ref, atol=1e-12)


def test_cielab(rng):
    xyz = rng.random((100, 3)) * [0.95, 1.0, 1.09]
    xyz[:5] *= 0.001  # the linear segment near black
    white = colour.xy_to_XYZ([0.3127, 0.3290])
    ref = colour.XYZ_to_Lab(xyz, [0.3127, 0.3290])
    lab = scotopia.xyz_to_lab(xyz, list(white))
    np.testing.assert_allclose(lab, ref, atol=1e-10)
    np.testing.assert_allclose(scotopia.lab_to_xyz(lab, list(white)), xyz, atol=1e-12)


def test_ciede2000(rng):
    lab1 = rng.random((500, 3)) * [100, 200, 200] - [0, 100, 100]
    lab2 = lab1 + rng.normal(0, 5, (500, 3))
    ref = colour.delta_E(lab1, lab2, method="CIE 2000")
    np.testing.assert_allclose(scotopia.delta_e_2000(lab1, lab2), ref, atol=1e-9)
    # The neutral and hue-wrap cases from Sharma et al. 2005.
    a = np.array([[50.0, 2.49, -0.001], [50.0, 0.0, 0.0]])
    b = np.array([[50.0, -2.49, 0.0009], [50.0, -1.0, 2.0]])
    np.testing.assert_allclose(scotopia.delta_e_2000(a, b), colour.delta_E(a, b, method="CIE 2000"), atol=1e-9)


def test_oklab_and_oklch(rng):
    xyz = rng.random((100, 3))
    ref = colour.XYZ_to_Oklab(xyz)
    lab = scotopia.xyz_to_oklab(xyz)
    np.testing.assert_allclose(lab, ref, atol=1e-10)
    np.testing.assert_allclose(scotopia.oklab_to_xyz(lab), xyz, atol=1e-10)
    lch = scotopia.oklab_to_oklch(lab)
    np.testing.assert_allclose(lch, colour.Oklab_to_Oklch(ref), atol=1e-9)
    np.testing.assert_allclose(scotopia.oklch_to_oklab(lch), lab, atol=1e-12)


def test_bad_shapes_and_names_are_errors():
    with pytest.raises(ValueError, match="last axis"):
        scotopia.rgb_to_xyz(np.zeros((4, 2)))
    with pytest.raises(ValueError, match="unknown colour space"):
        scotopia.rgb_to_xyz(np.zeros(3), "cmyk")


def test_xyy(rng):
    xyz = rng.random((20, 3))
    xyy = scotopia.xyz_to_xyy(xyz)
    np.testing.assert_allclose(xyy, colour.XYZ_to_xyY(xyz), atol=1e-12)
    np.testing.assert_allclose(scotopia.xyy_to_xyz(xyy), xyz, atol=1e-12)
