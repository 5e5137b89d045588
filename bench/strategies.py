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
from pathlib import Path

import numpy as np

from common import ROOT, rel_mse, rel_rmse, render

STRATEGIES = ["swc", "hero", "single"]
# name: (file, parameters for a reduced resolution)
SCENES = {
    "cornell-box": ("cornell-box.xml", ["res=128"]),
    "prism": ("prism.xml", ["width=200", "height=125"]),
    "black-light-poster": ("black-light-poster.xml", ["width=200", "height=138"]),
}


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
        refs = [render(args.bin, scene, params, out / f"{name}-ref-{s}.exr",
                       ["--wavelengths", s], 100 + i,
                       spp=args.ref_spp)[2] for i, s in enumerate(STRATEGIES)]
        ref = np.mean(refs, axis=0)
        for i, s in enumerate(STRATEGIES):
            spp, msps, img = render(args.bin, scene, params, out / f"{name}-{s}.exr",
                                    ["--wavelengths", s], 7 + i,
                                    seconds=args.seconds)
            print(f"| {name} | {s} | {msps:.2f} | {spp} | {rel_rmse(img, ref, 1):.3f} | "
                  f"{rel_rmse(img, ref, 2):.3f} | {rel_mse(img, ref, 1):.4f} |", flush=True)


if __name__ == "__main__":
    main()
