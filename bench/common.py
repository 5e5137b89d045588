"""What the bench scripts share: running `scotopia render` and reading its
summary and image, and the error measures."""

import os
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
    return int(m.group(1)), float(m.group(3)), read_xyzv(out)


def read_xyzv(path):
    """An EXR's X, Y, Z, V channels, stacked last."""
    with OpenEXR.File(str(path)) as f:
        ch = f.channels()
        return np.stack([np.asarray(ch[c].pixels, dtype=np.float64) for c in "XYZV"], -1)


def rel_rmse(img, ref, c):
    return float(np.sqrt(np.mean((img[..., c] - ref[..., c]) ** 2)) / np.mean(ref[..., c]))


def rel_mse(img, ref, c):
    """Per-pixel relative MSE, (I − R)² / (R² + ε) averaged (Rousselle et al.
    2011), ε = 1e-4 of the mean squared: rare bright outliers (caustics seen
    through glass) dominate RMSE; this weighs every pixel by its own level."""
    r = ref[..., c]
    eps = 1e-4 * np.mean(r) ** 2
    return float(np.mean((img[..., c] - r) ** 2 / (r * r + eps)))


def build_revision(rev):
    """The release binary of git revision `rev`, built once in a worktree
    under out/bench/ with its own target folder (so that neither build
    passes for the other)."""
    base = ROOT / "out" / "bench"
    tree = base / f"before-{rev}"
    target = base / f"target-before-{rev}"
    binary = target / "release" / "scotopia"
    if binary.exists():
        return binary
    base.mkdir(parents=True, exist_ok=True)
    if not tree.exists():
        subprocess.run(["git", "-C", str(ROOT), "worktree", "add", "--detach", str(tree), rev],
                       check=True)
    env = dict(os.environ, CARGO_TARGET_DIR=str(target))
    print(f"building {rev} (once) ...", file=sys.stderr)
    subprocess.run(["cargo", "build", "--release", "-q", "-p", "scotopia"], cwd=tree, env=env,
                   check=True)
    return binary
