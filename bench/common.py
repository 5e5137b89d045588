"""What the bench scripts share: running `scotopia render` and reading its
summary and image, and the error measures."""

import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import OpenEXR

ROOT = Path(__file__).resolve().parents[1]
SUMMARY = re.compile(r"(\d+) spp in ([\d.]+) s \(([\d.]+) Msamples/s")


def render(binary, scene, params, out, extra, seed, spp=None, seconds=None):
    """One render of scenes/`scene` with `-D` `params` and further options
    `extra`; returns (spp, Msamples/s, the X, Y, Z, V channels)."""
    cmd = [str(binary), "render", str(ROOT / "scenes" / scene), "-o", str(out),
           "--seed", str(seed), *extra]
    for p in params:
        cmd += ["-D", p]
    cmd += ["--spp", str(spp)] if spp else ["--time", str(seconds), "--spp", "1000000"]
    proc = subprocess.run(cmd, capture_output=True, text=True)
    if proc.returncode != 0:
        sys.exit(f"{scene}: scotopia failed ({proc.returncode}):\n{proc.stderr}")
    m = SUMMARY.search(proc.stderr)
    if not m:
        sys.exit(f"{scene}: no summary line in:\n{proc.stderr}")
    with OpenEXR.File(str(out)) as f:
        ch = f.channels()
        img = np.stack([np.asarray(ch[c].pixels, dtype=np.float64) for c in "XYZV"], -1)
    return int(m.group(1)), float(m.group(3)), img


def rel_rmse(img, ref, c):
    return float(np.sqrt(np.mean((img[..., c] - ref[..., c]) ** 2)) / np.mean(ref[..., c]))


def rel_mse(img, ref, c):
    """Per-pixel relative MSE, (I − R)² / (R² + ε) averaged (Rousselle et al.
    2011), ε = 1e-4 of the mean squared: rare bright outliers (caustics seen
    through glass) dominate RMSE; this weighs every pixel by its own level."""
    r = ref[..., c]
    eps = 1e-4 * np.mean(r) ** 2
    return float(np.mean((img[..., c] - r) ** 2 / (r * r + eps)))
