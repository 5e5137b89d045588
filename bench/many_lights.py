"""Many-light sampling at equal time (issue 40): the long street (30 road
luminaires and their 30 lenses, two spectra) rendered for the same time by
this build and by the build before the light hierarchy, each against a
reference rendered long by this build (cached under out/bench/). Prints
relMSE of Y (`common.rel_mse`) averaged over seeds, and the ratio, over
the whole image and outside the lamps: pixels whose light comes partly
straight from an emitter seen by the camera (in a render of depth 1,
grown by two pixels for the filter) have the noise of where a sample
lands on a lens smaller than a pixel, which no light choice changes, and
at 320 × 180 they hold most of the error. The scene needs a `max_depth`
parameter for that render of depth 1 (the script stops if it has none).
Usage:

    python bench/many_lights.py [--seconds 10] [--seeds 3] [--ref-spp 1024]
                                [--before db6257e] [--before-bin PATH]
                                [--scene long-street.xml] [--res 320x180]
                                [--names "before (power choice)" "this build"]
"""

import argparse
import sys
from pathlib import Path

import numpy as np
from scipy import ndimage

from common import ROOT, build_revision, read_xyzv, rel_mse, render

# The last commit before the light hierarchy chose lights.
BEFORE = "db6257e"


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=10.0)
    parser.add_argument("--seeds", type=int, default=3)
    parser.add_argument("--ref-spp", type=int, default=1024)
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--before", default=BEFORE)
    parser.add_argument("--before-bin")
    parser.add_argument("--bin", default=ROOT / "target" / "release" / "scotopia")
    parser.add_argument("--scene", default="long-street.xml")
    parser.add_argument("--res", default="320x180")
    parser.add_argument("--names", nargs=2, default=["before (power choice)", "this build"],
                        help="what to call the two builds")
    args = parser.parse_args()
    SCENE, RES = args.scene, ["--res", args.res]
    out = ROOT / "out" / "bench"
    out.mkdir(parents=True, exist_ok=True)
    before = Path(args.before_bin) if args.before_bin else build_revision(args.before)
    after = Path(args.bin)
    threads = ["--threads", str(args.threads)]
    ref_path = out / f"{Path(SCENE).stem}-{args.res}-ref-{args.ref_spp}.exr"
    if ref_path.exists():
        ref = read_xyzv(ref_path)
    else:
        print(f"reference: {args.ref_spp} spp ...", file=sys.stderr, flush=True)
        _, _, ref = render(after, SCENE, [], ref_path, RES + threads, 99, spp=args.ref_spp)
    # The lamps: where emitters seen straight give a pixel over 2 % of its
    # light (the night sky too, whose pixels have no noise in either).
    _, _, direct = render(after, SCENE, ["max_depth=1"], out / "many-direct.exr", RES + threads,
                          99, spp=64)
    lamps = direct[..., 1] > 0.02 * ref[..., 1]
    if lamps.mean() > 0.9:
        sys.exit(f"{SCENE}: -D max_depth=1 changed nothing (no max_depth parameter?)")
    lamps = ndimage.binary_dilation(lamps, iterations=2)
    outside = ~lamps
    print(f"| build | Msamples/s | spp in {args.seconds:g} s | relMSE of Y | "
          f"outside the lamps and sky ({outside.mean():.1%} of pixels) |")
    print("|---|---:|---:|---:|---:|")
    errors, errors_out = {}, {}
    b, a = args.names
    for name, binary in ((b, before), (a, after)):
        e, e_out, rates, spps = [], [], [], []
        for seed in range(1, args.seeds + 1):
            spp, msps, img = render(binary, SCENE, [], out / "many.exr", RES + threads, seed,
                                    seconds=args.seconds)
            e.append(rel_mse(img, ref, 1))
            e_out.append(rel_mse(img[outside], ref[outside], 1))
            rates.append(msps)
            spps.append(spp)
        errors[name] = float(np.mean(e))
        errors_out[name] = float(np.mean(e_out))
        print(f"| {name} | {np.mean(rates):.3f} | {np.mean(spps):.0f} | {errors[name]:.4g} "
              f"| {errors_out[name]:.4g} |", flush=True)
    print(f"\nrelMSE of Y, before / now: {errors[b] / errors[a]:.2f}× (whole image), "
          f"{errors_out[b] / errors_out[a]:.2f}× (outside the lamps and sky)")


if __name__ == "__main__":
    main()
