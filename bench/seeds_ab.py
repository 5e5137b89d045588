"""Builds against each other at equal samples, seed by seed: every binary
renders the same seeds at the same spp, so the noise they share (the
camera paths, most of the image) is the same and what differs is what the
builds do differently. That resolves changes of a few per cent that
equal-time runs, whose sample counts swing with the machine, cannot.

For each binary it prints the mean relMSE of Y over the seeds against a
reference (`common.rel_mse`; its standard error over seeds; the median and
the largest), the mean seconds per image (from the Msamples/s the render
reports, so without start-up), and their product: relMSE × seconds, the
figure to compare at equal time (relMSE falls as 1/time). Usage:

    python bench/seeds_ab.py --bins A B [...] [--scene glass-and-metals.xml]
        [--spp 32] [--seeds 64] [--seed0 1000] [--res 160x120]
        [--ref-spp 4096] [--threads 2] [-- extra render options]

A binary may be a git revision (`rev:HEAD~1`), built once under out/bench/.
The reference is rendered by the first binary at --ref-spp with seed 12345
and cached under out/bench/.
"""

import argparse
import sys

import numpy as np

from common import ROOT, build_revision, rel_mse, render


def binary(name):
    return build_revision(name[4:]) if name.startswith("rev:") else name


def main():
    argv = sys.argv[1:]
    extra = []
    if "--" in argv:
        i = argv.index("--")
        argv, extra = argv[:i], argv[i + 1:]
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--bins", nargs="+", required=True, help="binaries or rev:REVISION")
    ap.add_argument("--scene", default="glass-and-metals.xml", help="a file in scenes/")
    ap.add_argument("--spp", type=int, default=32)
    ap.add_argument("--seeds", type=int, default=64)
    ap.add_argument("--seed0", type=int, default=1000)
    ap.add_argument("--res", default="160x120")
    ap.add_argument("--ref-spp", type=int, default=4096)
    ap.add_argument("--threads", type=int, default=2)
    a = ap.parse_args(argv)
    bins = [binary(b) for b in a.bins]
    width, height = (int(v) for v in a.res.split("x"))
    opts = ["--res", a.res, "--threads", str(a.threads), *extra]
    out = ROOT / "out" / "bench"
    out.mkdir(parents=True, exist_ok=True)
    ref_file = out / f"seeds_ab-ref-{a.scene}-{a.res}-{a.ref_spp}.npy"
    if ref_file.exists():
        ref = np.load(ref_file)
    else:
        print(f"reference: {a.ref_spp} spp ...", file=sys.stderr)
        _, _, img = render(bins[0], a.scene, [], out / "seeds_ab-ref.exr", opts, 12345,
                           spp=a.ref_spp)
        ref = img[..., 1]
        np.save(ref_file, ref)
    errors = [[] for _ in bins]
    seconds = [[] for _ in bins]
    for seed in range(a.seed0, a.seed0 + a.seeds):
        # Every other seed in the opposite order, so that a machine that
        # runs the second of two renders slower favours neither.
        order = list(enumerate(bins))
        for i, b in order if seed % 2 == 0 else order[::-1]:
            _, rate, img = render(b, a.scene, [], out / f"seeds_ab-{i}.exr", opts, seed,
                                  spp=a.spp)
            errors[i].append(rel_mse(img, ref[..., None].repeat(4, -1), 1))
            seconds[i].append(a.spp * width * height / (rate * 1e6))
    for name, e, t in zip(a.bins, errors, seconds):
        e, t = np.array(e), np.array(t)
        se = e.std(ddof=1) / np.sqrt(len(e)) if len(e) > 1 else float("nan")
        print(f"{name}: {a.spp} spp, {len(e)} seeds: relMSE {e.mean():.4f} (se {se:.4f}, "
              f"median {np.median(e):.4f}, largest {e.max():.3f}), {t.mean():.3f} s, "
              f"relMSE × s {e.mean() * t.mean():.4f}")
    # Equal-time ratio of each build to the first (above 1: better), with
    # its standard error from the seeds' paired errors (delta method).
    e0, t0 = np.array(errors[0]), np.array(seconds[0])
    for name, e, t in zip(a.bins[1:], errors[1:], seconds[1:]):
        e, t = np.array(e), np.array(t)
        ratio = e0.mean() * t0.mean() / (e.mean() * t.mean())
        d = e0 / e0.mean() - e / e.mean()
        se = ratio * d.std(ddof=1) / np.sqrt(len(d)) if len(d) > 1 else float("nan")
        print(f"{a.bins[0]} / {name} at equal time: {ratio:.3f} (se {se:.3f})")


if __name__ == "__main__":
    main()
