"""This build against an earlier one at equal time (issue 40's "N× lower
than today"): each scene rendered for the same time by both binaries, with
the same options, against a reference rendered long by the earlier binary
(cached under out/bench/; the earlier build's own image, so any change of
the expected image counts against this one). Prints the samples per
second each reaches, relMSE of Y (`common.rel_mse`) averaged over seeds,
the ratio before / now (above 1: this build is better), and the pixels
above 10× their neighbours' median outside the lamps (`fireflies.py`'s
count, summed over seeds). Usage:

    python bench/against_before.py --before-bin PATH [--seconds 10] [--seeds 2]
        [--ref-spp 1024] [--scenes foggy-street ...] [--res 320x180]
        [--threads 2] [-- extra render options]

Build the earlier binary from a worktree with its own target directory:
`git worktree add ../before <commit>; CARGO_TARGET_DIR=../target-before
cargo build --release -p scotopia`.
"""

import argparse
import sys

import numpy as np

from common import ROOT, read_xyzv, rel_mse, render
from fireflies import ratios


def fireflies(y, lamp=1000.0, halo=6, k=10.0):
    """Pixels above k× their neighbours' median outside the lamps
    (fireflies.py's defaults: lamps above 1000 cd/m² and 6 pixels round)."""
    lamps = y >= lamp
    floor = 1e-6 * np.max(y, where=~lamps, initial=0.0)
    r, _ = ratios(y, lamps, halo, floor)
    return int(np.sum(r > k))


def main():
    argv = sys.argv[1:]
    extra = []
    if "--" in argv:
        extra = argv[argv.index("--") + 1:]
        argv = argv[:argv.index("--")]
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--before-bin", required=True)
    parser.add_argument("--bin", default=ROOT / "target" / "release" / "scotopia")
    parser.add_argument("--seconds", type=float, default=10.0)
    parser.add_argument("--seeds", type=int, default=2)
    parser.add_argument("--ref-spp", type=int, default=1024)
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--res", default="320x180")
    parser.add_argument("--scenes", nargs="+", default=["foggy-street"])
    args = parser.parse_args(argv)
    out = ROOT / "out" / "bench"
    out.mkdir(parents=True, exist_ok=True)
    common = ["--res", args.res, "--threads", str(args.threads), *extra]
    print(f"Equal time, {args.seconds:g} s on {args.threads} threads, {args.res}, "
          f"{args.seeds} seeds, options {' '.join(extra) or '(none)'}; reference "
          f"{args.ref_spp} spp by the earlier build.\n")
    print("| scene | Msamples/s before | now | relMSE of Y before | now | before / now "
          "| fireflies > 10× before | now |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|")
    for scene in args.scenes:
        xml = f"{scene}.xml"
        tag = "-".join(extra).replace("/", "_")
        ref_path = out / f"{scene}-{args.res}-before-ref-{args.ref_spp}{tag}.exr"
        if ref_path.exists():
            ref = read_xyzv(ref_path)
        else:
            print(f"{scene}: reference, {args.ref_spp} spp ...", file=sys.stderr, flush=True)
            _, _, ref = render(args.before_bin, xml, [], ref_path, common, 99, spp=args.ref_spp)
        row = {}
        for name, binary in (("before", args.before_bin), ("now", args.bin)):
            e, rates, flies = [], [], 0
            for seed in range(1, args.seeds + 1):
                _, msps, img = render(binary, xml, [], out / "against-before.exr", common,
                                      seed, seconds=args.seconds)
                e.append(rel_mse(img, ref, 1))
                rates.append(msps)
                flies += fireflies(img[..., 1])
            row[name] = (np.mean(rates), float(np.mean(e)), flies)
        (r0, e0, f0), (r1, e1, f1) = row["before"], row["now"]
        print(f"| {scene} | {r0:.3f} | {r1:.3f} | {e0:.4g} | {e1:.4g} | {e0 / e1:.2f} "
              f"| {f0} | {f1} |", flush=True)


if __name__ == "__main__":
    main()
