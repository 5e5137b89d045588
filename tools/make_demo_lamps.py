"""Writes the demo lamp spectra in scenes/lamps/ (run once; the files are committed).

Both are models, not measurements; their headers say so.
- low-pressure sodium: the Na D lines at 588.995 nm and 589.592 nm (NIST Atomic
  Spectra Database, wavelengths in air), intensity ratio D2:D1 = 2:1, each a
  triangle 0.2 nm wide; the lamp's weak other lines are left out.
- white LED, 4000 K class: a blue InGaN emitter (Gaussian, 450 nm, sigma 10 nm)
  plus a broad YAG:Ce phosphor band (Gaussian, 585 nm, sigma 70 nm), blue weight 0.8
  relative to the phosphor, for a CCT near 4000 K (3966 K, Duv 0.001).
"""
import math

LINES = [(588.995, 2.0), (589.592, 1.0)]
HALF = 0.1

with open("scenes/lamps/low-pressure-sodium.csv", "w") as f:
    f.write("# Low-pressure sodium lamp, model: Na D2 588.995 nm and D1 589.592 nm (NIST ASD, air),\n")
    f.write("# D2:D1 = 2:1, triangles 0.2 nm wide; relative spectral radiance. Made by tools/make_demo_lamps.py.\n")
    f.write("wavelength_nm,relative_radiance\n")
    points = [(380.0, 0.0)]
    for centre, height in LINES:
        points += [(centre - HALF, 0.0), (centre, height), (centre + HALF, 0.0)]
    points.append((780.0, 0.0))
    for w, v in points:
        f.write(f"{w:.3f},{v:g}\n")

with open("scenes/lamps/led-4000k.csv", "w") as f:
    f.write("# White phosphor-converted LED, model (not a measurement): blue 450 nm (sigma 10 nm)\n")
    f.write("# + YAG:Ce phosphor 585 nm (sigma 70 nm), weights 0.8:1; relative spectral radiance, peak 1.\n")
    f.write("# Made by tools/make_demo_lamps.py.\n")
    f.write("wavelength_nm,relative_radiance\n")
    values = []
    for w in range(380, 781, 5):
        blue = 0.8 * math.exp(-0.5 * ((w - 450) / 10) ** 2)
        phosphor = math.exp(-0.5 * ((w - 585) / 70) ** 2)
        values.append((w, blue + phosphor))
    peak = max(v for _, v in values)
    for w, v in values:
        f.write(f"{w},{v / peak:.5f}\n")
