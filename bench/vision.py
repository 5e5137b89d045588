"""Times the whole vision pipeline on a 1920 × 1080 X, Y, Z, V′ image and
prints each stage's share (`make bench`; target ≤ 250 ms on 2 cores), then
the whole `scotopia display` process, EXR in and PNG out (target ≤ 250 ms),
with the wall time of its phases (read, pipeline, write, free).

The pipeline's image is the bundled night street rendered at 640 × 360
(8 spp, seed 0) and enlarged 3× by pixel repetition: a real night scene's
luminance range and lamps at full-HD size. The process reads the night
street rendered by the CLI at 1920 × 1080, 1 spp. Usage:

    python bench/vision.py [--runs 5] [--tonemap multiscale] [--bin target/release/scotopia]
                           [--process-only]

`--process-only` times the CLI alone (no `scotopia` Python module or
numpy needed).
"""

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("--tonemap", default="multiscale")
    ap.add_argument("--bin", default=ROOT / "target" / "release" / "scotopia",
                    help="the CLI for the whole-process time (skipped if missing)")
    ap.add_argument("--process-only", action="store_true",
                    help="only the whole-process time, from the CLI")
    args = ap.parse_args()
    if not args.process_only:
        pipeline(args.runs, args.tonemap)
    if Path(args.bin).exists():
        whole_process(Path(args.bin), args.runs, args.tonemap)
    else:
        print(f"({args.bin} not built: no whole-process time)")


def pipeline(runs, tonemap):
    """Best time of the pipeline called from Python, with its stages."""
    import numpy as np

    import scotopia

    img, meta = scotopia.render(str(ROOT / "scenes/night-street.xml"), spp=8, seed=0)
    big = np.ascontiguousarray(np.repeat(np.repeat(img, 3, axis=0), 3, axis=1))
    fov = meta["fovHorizontalDegrees"]
    best = None
    for _ in range(runs):
        t = time.perf_counter()
        _, report = scotopia.display(big, fov=fov, tonemap=tonemap)
        total = time.perf_counter() - t
        if best is None or total < best[0]:
            best = (total, report["timings"])
    total, stages = best
    print(f"| pipeline, {big.shape[1]}×{big.shape[0]}, --tonemap {tonemap} | {total * 1e3:.0f} ms |")
    for name, secs in stages.items():
        print(f"|   {name} | {secs * 1e3:.0f} ms ({100 * secs / total:.0f} %) |")


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
        # SCOTOPIA_TIMES: the process prints each phase's wall time.
        env = dict(os.environ, SCOTOPIA_TIMES="1")
        best = None
        for _ in range(runs):
            t = time.perf_counter()
            proc = subprocess.run(cmd, capture_output=True, text=True, env=env)
            total = time.perf_counter() - t
            if proc.returncode != 0:
                sys.exit(f"scotopia display failed:\n{proc.stderr}")
            if best is None or total < best[0]:
                best = (total, phases(proc.stderr))
        total, times = best
        print(f"| `scotopia display` process, EXR → PNG, 1920×1080 | {total * 1e3:.0f} ms "
              f"(PNG {png.stat().st_size / 1e6:.1f} MB) |")
        for name, ms in times:
            print(f"|   {name} | {ms:.0f} ms |")
        rest = total * 1e3 - sum(ms for _, ms in times)
        print(f"|   process start and exit | {rest:.0f} ms |")


def phases(stderr):
    """(phase, ms) from the lines `scotopia: time: PHASE  12.3 ms`."""
    found = []
    for line in stderr.splitlines():
        if line.startswith("scotopia: time: "):
            name, ms, _ = line[len("scotopia: time: "):].rsplit(maxsplit=2)
            found.append((name.strip(), float(ms)))
    return found


if __name__ == "__main__":
    main()
