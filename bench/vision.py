"""Times the whole vision pipeline on a 1920 × 1080 X, Y, Z, V′ image and
prints each stage's share (`make bench`; target ≤ 250 ms on 2 cores).

The image is the bundled night street rendered at 640 × 360 (8 spp, seed 0)
and enlarged 3× by pixel repetition: a real night scene's luminance range
and lamps at full-HD size. Usage:

    python bench/vision.py [--runs 5] [--tonemap multiscale]
"""

import argparse
import time
from pathlib import Path

import numpy as np

import scotopia

ROOT = Path(__file__).resolve().parents[1]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("--tonemap", default="multiscale")
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


if __name__ == "__main__":
    main()
