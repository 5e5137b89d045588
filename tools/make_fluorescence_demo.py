"""Writes the fluorescence demo's spectra (run once; the files are committed).

Both are models, not measurements; their headers say so.
- scenes/lamps/uv-blacklight.csv: a "blacklight blue" UV-A tube. A Gaussian
  band at 368 nm (sigma 9 nm; the Eu2+-doped strontium borate phosphor's band,
  as BLB tubes are commonly described) plus the mercury lines at 404.656 nm and
  435.833 nm (NIST Atomic Spectra Database, air), which leak through the tube's
  Wood's glass; here at 30 % and 10 % of the band's peak (about 1.3 % and 0.4 % of its power), triangles 1 nm wide.
- scenes/materials/highlighter-yellow.csv: a reradiation (Donaldson) matrix of
  a yellow highlighter ink in scotopia's CSV layout (docs/scene-format.md),
  built from a separable model so that its cells are known exactly: elastic
  reflectance on the diagonal; off the diagonal, for lambda_o > lambda_i,
  Q * e(lambda_i) * eta(lambda_o) * 10 nm * lambda_i / lambda_o (the Stokes
  factor), with Q = 0.85, e the absorbed fraction and eta the emission shape
  normalised to unit area. A 10 nm grid over 360-780 nm.
"""
import math

STEP = 10
GRID = list(range(360, 781, STEP))


def lerp_table(points, x):
    """Piecewise-linear through (x, y) points, constant beyond the ends."""
    if x <= points[0][0]:
        return points[0][1]
    for (x0, y0), (x1, y1) in zip(points, points[1:]):
        if x <= x1:
            return y0 + (y1 - y0) * (x - x0) / (x1 - x0)
    return points[-1][1]


def blacklight():
    lines = [(404.656, 0.3), (435.833, 0.1)]
    # 1 nm samples, plus each line's foot and peak so its triangle is exact.
    waves = {float(w) for w in range(360, 461)}
    waves |= {c + dx for c, _ in lines for dx in (-0.5, 0.0, 0.5)}

    def radiance(w):
        band = math.exp(-0.5 * ((w - 368) / 9) ** 2)
        return band + sum(max(0.0, h * (1 - abs(w - c) / 0.5)) for c, h in lines)

    out = [(w, radiance(w)) for w in sorted(waves)]
    with open("scenes/lamps/uv-blacklight.csv", "w") as f:
        f.write("# UV-A 'blacklight blue' tube, model (not a measurement): Gaussian band 368 nm (sigma 9 nm)\n")
        f.write("# + Hg 404.656 and 435.833 nm (NIST ASD, air) at 30 % and 10 % of the peak, triangles 1 nm wide;\n")
        f.write("# relative spectral radiance, peak 1. Made by tools/make_fluorescence_demo.py.\n")
        f.write("wavelength_nm,relative_radiance\n")
        for w, v in out:
            f.write(f"{w:.3f},{v:.5f}\n")


def highlighter():
    reflectance = [(360, 0.08), (470, 0.08), (520, 0.85), (780, 0.88)]
    absorbed = [(360, 0.45), (400, 0.35), (450, 0.55), (490, 0.6), (505, 0.0)]
    q = 0.85
    # Emission shape: a skewed band peaking at 515 nm, zero below 495 nm.
    def eta(w):
        if w < 495:
            return 0.0
        width = 14 if w < 515 else 28
        return math.exp(-0.5 * ((w - 515) / width) ** 2)

    area = sum(eta(w) * STEP for w in GRID)
    rows = []
    for lo in GRID:
        cells = []
        for li in GRID:
            if li == lo:
                v = lerp_table(reflectance, lo)
            elif lo > li:
                v = q * lerp_table(absorbed, li) * eta(lo) / area * STEP * li / lo
            else:
                v = 0.0
            cells.append(v)
        rows.append((lo, cells))
    with open("scenes/materials/highlighter-yellow.csv", "w") as f:
        f.write("# Yellow highlighter ink, reradiation (Donaldson) matrix - a model, not a measurement:\n")
        f.write("# diagonal = elastic reflectance; below it Q*e(li)*eta(lo)*10nm*li/lo, Q = 0.85,\n")
        f.write("# emission peak 515 nm. Rows: emission nm; columns: excitation nm.\n")
        f.write("# Made by tools/make_fluorescence_demo.py.\n")
        f.write("emission\\excitation," + ",".join(str(w) for w in GRID) + "\n")
        for lo, cells in rows:
            f.write(f"{lo}," + ",".join(f"{v:.6g}" for v in cells) + "\n")


if __name__ == "__main__":
    blacklight()
    highlighter()
