"""Writes the CIE tables in data/cie/ from the CIE datasets distributed with
colour-science (which transcribes them from the CIE publications named in each
file). Run once; the files are committed. Each file names its source."""
import sys
import warnings

warnings.filterwarnings("ignore")
import colour  # noqa: E402
from colour.colorimetry.datasets.illuminants.sds_d_illuminant_series import (  # noqa: E402
    SDS_BASIS_FUNCTIONS_CIE_ILLUMINANT_D_SERIES as BASIS,
)

OUT = sys.argv[1] if len(sys.argv) > 1 else "data/cie"


def write(name, header, columns, rows):
    with open(f"{OUT}/{name}", "w") as f:
        for line in header.strip().splitlines():
            f.write(f"# {line}\n")
        f.write(",".join(columns) + "\n")
        for row in rows:
            f.write(",".join(row) + "\n")


cmfs = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"]
write(
    "cie1931_2deg_xyz.csv",
    """CIE 1931 2-degree standard colorimetric observer, x-bar, y-bar, z-bar.
Source: CIE 015:2018 Colorimetry, 4th ed., table of the CIE 1931 standard observer,
1 nm, 360-830 nm; transcribed from the CIE dataset distributed with colour-science 0.4.7.""",
    ["wavelength_nm", "x_bar", "y_bar", "z_bar"],
    # colour-science carries a -1.9e-21 rounding artefact where the CIE table has 0.
    [[f"{w:g}"] + [f"{max(v, 0.0):.6e}" for v in cmfs[w]] for w in cmfs.wavelengths],
)

v = colour.colorimetry.SDS_LEFS["CIE 1951 Scotopic Standard Observer"]
write(
    "cie1951_scotopic_vprime.csv",
    """CIE 1951 scotopic luminous efficiency function V'(lambda), peak 1 at 507 nm.
Source: ISO 23539:2005(E)/CIE S 010/E:2004, 1 nm, 380-780 nm; transcribed from the
CIE dataset distributed with colour-science 0.4.7.
Zero outside the tabulated range.""",
    ["wavelength_nm", "v_prime"],
    [[f"{w:g}", f"{v[w]:.6e}"] for w in v.wavelengths],
)

basis = BASIS
write(
    "daylight_basis_s0_s1_s2.csv",
    """CIE daylight basis functions S0, S1, S2 for the D-series illuminants.
Source: CIE 015:2018 Colorimetry, 4th ed., daylight components (5 nm, 300-830 nm);
transcribed from the CIE dataset distributed with colour-science 0.4.7.""",
    ["wavelength_nm", "s0", "s1", "s2"],
    [
        [f"{w:g}"] + [f"{basis[k][w]:.4f}" for k in ("S0", "S1", "S2")]
        for w in basis["S0"].wavelengths
    ],
)

for i in range(1, 13):
    sd = colour.SDS_ILLUMINANTS[f"FL{i}"]
    write(
        f"illuminant_f{i}.csv",
        f"""CIE illuminant F{i} (fluorescent lamp), relative spectral power, 5 nm, 380-780 nm.
Source: CIE 015:2018 Colorimetry, 4th ed., fluorescent illuminants F1-F12; transcribed
from the CIE dataset distributed with colour-science 0.4.7. Zero outside the tabulated range.""",
        ["wavelength_nm", "relative_power"],
        [[f"{w:g}", f"{sd[w]:.4f}"] for w in sd.wavelengths],
    )
