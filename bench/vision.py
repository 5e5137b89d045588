"""Times the whole vision pipeline on a 1920 × 1080 X, Y, Z, V′ image and
prints each stage's share (`make bench`; target ≤ 250 ms on 2 cores), then
the whole `scotopia display` process, EXR in and PNG out (target ≤ 250 ms).

The pipeline's image is the bundled night street rendered at 640 × 360
(8 spp, seed 0) and enlarged 3× by pixel repetition: a real night scene's
luminance range and lamps at full-HD size. The process reads the night
street rendered by the CLI at 1920 × 1080, 1 spp. Usage:

    python bench/vision.py [--runs 5] [--tonemap multiscale] [--bin target/release/scotopia]
"""

import argparse
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

import scotopia

ROOT = Path(__file__).resolve().parents[1]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("--tonemap", default="multiscale")
    ap.add_argument("--bin", default=ROOT / "target" / "release" / "scotopia",
                    help="the CLI for the whole-process time (skipped if missing)")
    args = ap.parse_args()
    img, meta = scotopia.render(str(ROOT / "scenes/night-street.xml"), spp=8, seed=0)
    big = np.ascontiguousarray(np.repeat(np.repeat(img, 3, axis=0), 3, axis=1))
    fov = meta["fovHorizontalDegrees"]
    best = None
    for _ in range(args.runs):
        t = time.perf_counter()
        _, report = scotopia.display(big, fov=fov, tonemap=args.tonemap)
        total = time.perf_counter() - t
        if best is None or total < best[0]:
            best = (total, report["timings"])
    total, stages = best
    print(f"| pipeline, {big.shape[1]}×{big.shape[0]}, --tonemap {args.tonemap} | {total * 1e3:.0f} ms |")
    for name, secs in stages.items():
        print(f"|   {name} | {secs * 1e3:.0f} ms ({100 * secs / total:.0f} %) |")
    if Path(args.bin).exists():
        whole_process(Path(args.bin), args.runs, args.tonemap)
    else:
        print(f"({args.bin} not built: no whole-process time)")


def whole_process(binary, runs, tonemap):
    """Best wall time of `scotopia display night-street-1080p.exr -o out.png`,
    a fresh process each run."""
    with tempfile.TemporaryDirectory() as tmp:
        exr, png = Path(tmp) / "street.exr", Path(tmp) / "street.png"
        cmd = [str(binary), "render", str(ROOT / "scenes/night-street.xml"),
               "--res", "1920", "--spp", "1", "-o", str(exr)]
        proc = subprocess.run(cmd, capture_output=True, text=True)
        if proc.returncode != 0:
            sys.exit(f"scotopia render failed:\n{proc.stderr}")
        cmd = [str(binary), "display", str(exr), "-o", str(png), "--tonemap", tonemap]
        best = None
        for _ in range(runs):
            t = time.perf_counter()
            proc = subprocess.run(cmd, capture_output=True, text=True)
            total = time.perf_counter() - t
            if proc.returncode != 0:
                sys.exit(f"scotopia display failed:\n{proc.stderr}")
            best = total if best is None else min(best, total)
        print(f"| `scotopia display` process, EXR → PNG, 1920×1080 | {best * 1e3:.0f} ms "
              f"(PNG {png.stat().st_size / 1e6:.1f} MB) |")


if __name__ == "__main__":
    main()
