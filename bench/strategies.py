"""The cost of fluorescence and dispersion, and what each wavelength strategy
buys on them (`make bench`).

For the Cornell box (the baseline), the prism (dispersion: clusters collapse)
and the black-light poster (fluorescence under a UV lamp), at a reduced
resolution: camera samples per second of each strategy, and the relative RMSE
of Y and Z against a reference after an equal time. The reference is the
mean of one long render per strategy (so it favours none of them); its own
noise is included in every row. Relative RMSE is dominated by rare bright
pixels (the lamp seen through the prism); relMSE weighs each pixel by its level. Usage:

    python bench/strategies.py [--seconds 5] [--ref-spp 1024] [--bin target/release/scotopia]
"""

import argparse
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import OpenEXR

ROOT = Path(__file__).resolve().parents[1]
SUMMARY = re.compile(r"(\d+) spp in ([\d.]+) s \(([\d.]+) Msamples/s")
STRATEGIES = ["swc", "hero", "single"]
# name: (file, parameters for a reduced resolution)
SCENES = {
    "cornell-box": ("cornell-box.xml", ["res=128"]),
    "prism": ("prism.xml", ["width=200", "height=125"]),
    "black-light-poster": ("black-light-poster.xml", ["width=200", "height=138"]),
}


def render(binary, scene, params, out, strategy, seed, spp=None, seconds=None):
    """One render; returns (spp, Msamples/s, the X, Y, Z, V channels)."""
    cmd = [str(binary), "render", str(ROOT / "scenes" / scene), "-o", str(out),
           "--wavelengths", strategy, "--seed", str(seed)]
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


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=5.0, help="equal-time budget (5)")
    parser.add_argument("--ref-spp", type=int, default=1024, help="spp of each reference render (1024)")
    parser.add_argument("--bin", default=ROOT / "target" / "release" / "scotopia")
    parser.add_argument("--out", default=ROOT / "out" / "bench")
    args = parser.parse_args()
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)

    print(f"equal time {args.seconds:g} s; reference: mean of swc, hero and single at "
          f"{args.ref_spp} spp each; K = 4")
    print("| scene | strategy | Msamples/s | spp in the time | rel. RMSE of Y | rel. RMSE of Z | relMSE of Y |")
    print("|---|---|---:|---:|---:|---:|---:|")
    for name, (scene, params) in SCENES.items():
        refs = [render(args.bin, scene, params, out / f"{name}-ref-{s}.exr", s, 100 + i,
                       spp=args.ref_spp)[2] for i, s in enumerate(STRATEGIES)]
        ref = np.mean(refs, axis=0)
        for i, s in enumerate(STRATEGIES):
            spp, msps, img = render(args.bin, scene, params, out / f"{name}-{s}.exr", s, 7 + i,
                                    seconds=args.seconds)
            print(f"| {name} | {s} | {msps:.2f} | {spp} | {rel_rmse(img, ref, 1):.3f} | "
                  f"{rel_rmse(img, ref, 2):.3f} | {rel_mse(img, ref, 1):.4f} |", flush=True)


if __name__ == "__main__":
    main()
