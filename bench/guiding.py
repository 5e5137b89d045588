"""Path guiding at equal time (issue 40): each scene rendered for the same
time with `--guiding off` and `--guiding on` (whose time includes the 16
spp it learns from), against a reference rendered long (cached under
out/bench/): without guiding, but with it for the prism, whose unguided
reference is itself coloured confetti (the agreement tests in
crates/scene/tests/guiding.rs show both converge to the same image). Prints the samples per second each reaches and
relMSE of Y (`common.rel_mse`) averaged over seeds, and the ratio
off / on (above 1: guiding helps). Usage:

    python bench/guiding.py [--seconds 10] [--seeds 2] [--ref-spp 1024]
                            [--scenes cornell-box night-street ...]
                            [--res 320x180] [--threads 2]
"""

import argparse
import sys

import numpy as np

from common import ROOT, read_xyzv, rel_mse, render

SCENES = ["cornell-box", "night-street", "foggy-street", "long-street", "prism"]

# Scenes whose reference is rendered guided.
GUIDED_REFERENCE = {"prism"}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=10.0)
    parser.add_argument("--seeds", type=int, default=2)
    parser.add_argument("--ref-spp", type=int, default=1024)
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--res", default="320x180")
    parser.add_argument("--scenes", nargs="+", default=SCENES)
    parser.add_argument("--bin", default=ROOT / "target" / "release" / "scotopia")
    args = parser.parse_args()
    out = ROOT / "out" / "bench"
    out.mkdir(parents=True, exist_ok=True)
    common = ["--res", args.res, "--threads", str(args.threads)]
    print(f"Equal time, {args.seconds:g} s on {args.threads} threads, {args.res}, "
          f"{args.seeds} seeds; reference {args.ref_spp} spp (guided: "
          f"{', '.join(sorted(GUIDED_REFERENCE)) or 'none'}).\n")
    print("| scene | Msamples/s off | on | spp off | on | relMSE of Y off | on | off / on |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|")
    for scene in args.scenes:
        xml = f"{scene}.xml"
        ref_guiding = "on" if scene in GUIDED_REFERENCE else "off"
        tag = "-guided" if ref_guiding == "on" else ""
        ref_path = out / f"{scene}-{args.res}-ref-{args.ref_spp}{tag}.exr"
        if ref_path.exists():
            ref = read_xyzv(ref_path)
        else:
            print(f"{scene}: reference, {args.ref_spp} spp ...", file=sys.stderr, flush=True)
            _, _, ref = render(args.bin, xml, [], ref_path,
                               common + ["--guiding", ref_guiding], 99, spp=args.ref_spp)
        row = {}
        for g in ("off", "on"):
            e, rates, spps = [], [], []
            for seed in range(1, args.seeds + 1):
                spp, msps, img = render(args.bin, xml, [], out / "guiding.exr",
                                        common + ["--guiding", g], seed, seconds=args.seconds)
                e.append(rel_mse(img, ref, 1))
                rates.append(msps)
                spps.append(spp)
            row[g] = (np.mean(rates), np.mean(spps), float(np.mean(e)))
        (r0, s0, e0), (r1, s1, e1) = row["off"], row["on"]
        print(f"| {scene} | {r0:.3f} | {r1:.3f} | {s0:.0f} | {s1:.0f} | {e0:.4g} | {e1:.4g} "
              f"| {e0 / e1:.2f} |", flush=True)


if __name__ == "__main__":
    main()
