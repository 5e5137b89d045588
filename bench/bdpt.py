"""The bidirectional tracer against the path tracer on every bundled scene
(`make bench`): camera samples per second of each, and the relative RMSE of
Y against a reference after an equal time. The reference is a long
bidirectional render with another seed (both tracers converge to the same
image: crates/scene/tests/bdpt.rs); its own noise is in every row. Usage:

    python bench/bdpt.py [--seconds 5] [--ref-spp 512] [--bin target/release/scotopia]
        [--only NAME ...]
"""

import argparse
from pathlib import Path

from common import ROOT, rel_mse, rel_rmse, render

SMALL = ["width=160", "height=100"]
# name: (file, parameters for a reduced resolution)
SCENES = {
    "cornell-box": ("cornell-box.xml", ["res=128"]),
    "material-showcase": ("material-showcase.xml", SMALL),
    "night-street": ("night-street.xml", SMALL),
    "foggy-street": ("foggy-street.xml", SMALL),
    "prism": ("prism.xml", SMALL),
    "black-light-poster": ("black-light-poster.xml", SMALL),
    "paper": ("paper.xml", SMALL),
    "caustic-sphere": ("caustic-sphere.xml", SMALL),
    "lamp-shade": ("lamp-shade.xml", SMALL),
}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=5.0, help="equal-time budget (5)")
    parser.add_argument("--ref-spp", type=int, default=512, help="spp of the reference (512)")
    parser.add_argument("--bin", default=ROOT / "target" / "release" / "scotopia")
    parser.add_argument("--out", default=ROOT / "out" / "bench")
    parser.add_argument("--only", action="append", choices=sorted(SCENES),
                        help="this scene only (repeatable)")
    args = parser.parse_args()
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)

    print(f"equal time {args.seconds:g} s; reference: bdpt at {args.ref_spp} spp; swc, K = 4")
    print("| scene | path Msamples/s | bdpt Msamples/s | path rel. RMSE of Y | "
          "bdpt rel. RMSE of Y | RMSE ratio path/bdpt | path relMSE | bdpt relMSE |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|")
    for name, (scene, params) in SCENES.items():
        if args.only and name not in args.only:
            continue
        ref = render(args.bin, scene, params, out / f"{name}-bdpt-ref.exr",
                     ["--integrator", "bdpt"], 100, spp=args.ref_spp)[2]
        row = {}
        for i, integrator in enumerate(["path", "bdpt"]):
            _, msps, img = render(args.bin, scene, params, out / f"{name}-{integrator}.exr",
                                  ["--integrator", integrator], 7 + i, seconds=args.seconds)
            row[integrator] = (msps, rel_rmse(img, ref, 1), rel_mse(img, ref, 1))
        (pm, pe, pr), (bm, be, br) = row["path"], row["bdpt"]
        print(f"| {name} | {pm:.2f} | {bm:.2f} | {pe:.3f} | {be:.3f} | {pe / be:.2f} | "
              f"{pr:.4f} | {br:.4f} |", flush=True)


if __name__ == "__main__":
    main()
