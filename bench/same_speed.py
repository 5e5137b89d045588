"""Render speed of this build against an earlier revision's, measured in
the same run (`make bench`): issue 39 restructured the render core and
asked that speed not drop.

The earlier revision is built once in a git worktree under out/bench/
(its own target folder, so neither build passes for the other). Each case
is rendered by both binaries in turn, `--rounds` times, the order swapped
every round so that drift of the shared machine falls on both alike; the
figure is the median over rounds of the ratio after/before of the render
time the summary line reports (< 1: faster now). Usage:

    python bench/same_speed.py [--before 0b04716] [--before-bin PATH]
                               [--rounds 5] [--threads 2]
"""

import argparse
import statistics
import subprocess
import sys
import time
from pathlib import Path

from common import build_revision

ROOT = Path(__file__).resolve().parents[1]

# The commit before issue 39's restructure began.
BEFORE = "0b04716"

# (name, scene, options): one per integrator and tracer.
CASES = [
    ("Cornell box, path", "cornell-box.xml", ["--integrator", "path", "--res", "200", "--spp", "96"]),
    ("Cornell box, wavefront", "cornell-box.xml",
     ["--integrator", "path", "--tracer", "wavefront", "--res", "200", "--spp", "96"]),
    ("night street, path", "night-street.xml", ["--res", "160", "--spp", "128"]),
    ("prism, bdpt", "prism.xml", ["--integrator", "bdpt", "--res", "160", "--spp", "128"]),
    ("foggy street, volpath", "foggy-street.xml", ["--res", "160", "--spp", "32"]),
]


def seconds(binary, scene, options, threads, out):
    """The run's wall-clock time (the summary line's is rounded to 0.1 s);
    loading the scene counts alike for both binaries."""
    cmd = [str(binary), "render", str(ROOT / "scenes" / scene), "-o", str(out), *options]
    if threads:
        cmd += ["--threads", str(threads)]
    start = time.perf_counter()
    proc = subprocess.run(cmd, capture_output=True, text=True)
    elapsed = time.perf_counter() - start
    if proc.returncode != 0:
        sys.exit(f"{scene}: {binary} failed ({proc.returncode}):\n{proc.stderr}")
    return elapsed


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--before", default=BEFORE, help=f"earlier revision ({BEFORE})")
    parser.add_argument("--before-bin", help="its binary, built already")
    parser.add_argument("--bin", default=ROOT / "target" / "release" / "scotopia")
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--only", default="", help="the cases whose name holds this text")
    args = parser.parse_args()
    before = Path(args.before_bin) if args.before_bin else build_revision(args.before)
    after = Path(args.bin)
    out = ROOT / "out" / "bench"
    out.mkdir(parents=True, exist_ok=True)
    print(f"| case | before (s) | after (s) | after/before, median of {args.rounds} |")
    print("|---|---|---|---|")
    for name, scene, options in CASES:
        if args.only not in name:
            continue
        ratios, tb, ta = [], [], []
        for r in range(args.rounds):
            pair = [(before, tb), (after, ta)]
            for binary, times in (pair if r % 2 == 0 else pair[::-1]):
                times.append(seconds(binary, scene, options, args.threads, out / "speed.exr"))
            ratios.append(ta[-1] / tb[-1])
        print(f"| {name} | {statistics.median(tb):.2f} | {statistics.median(ta):.2f} "
              f"| {statistics.median(ratios):.3f} (range {min(ratios):.3f}–{max(ratios):.3f}) |",
              flush=True)


if __name__ == "__main__":
    main()
