"""A stand-in for the core's shard API, used only while the extension module
lacks ``render_shard`` / ``merge_shards`` (issue 27: the Rust side is being
written). It implements the same contract with ``scotopia.render``:

* a sample range [i0, i1) is the difference of two renders with i1 and i0
  samples per pixel (a pixel's random numbers depend on (seed, pixel,
  index) alone, so the first i samples of any render are the same samples);
  the float32 images make this exact only to ~1e-7 relative;
* a row range renders the whole film and keeps those rows.

It costs up to two full renders per shard and has no second moments
(``squares`` is zero). Delete this file once the core has the real
functions; ``scotopia.distributed`` picks the real ones when they exist.
"""

import time

import numpy as np


def render_shard(
    path,
    *,
    samples,
    rows=None,
    seed=0,
    params=None,
    res=None,
    integrator=None,
    wavelengths="swc",
    cluster=4,
    tracer="scalar",
    quantity="radiance",
):
    from . import render

    i0, i1 = (int(v) for v in samples)
    if not 0 <= i0 < i1:
        raise ValueError(f"samples ({i0}, {i1}): give 0 <= i0 < i1")
    opts = dict(
        seed=seed,
        params=params,
        res=res,
        integrator=integrator,
        wavelengths=wavelengths,
        cluster=cluster,
        tracer=tracer,
        quantity=quantity,
    )
    t = time.perf_counter()
    hi, meta = render(str(path), spp=i1, **opts)
    sums = hi.astype(np.float64) * i1
    rays = int(meta.get("raysTraced", 0))
    if i0 > 0:
        lo, meta_lo = render(str(path), spp=i0, **opts)
        sums -= lo.astype(np.float64) * i0
        rays -= int(meta_lo.get("raysTraced", 0))
    h, w = sums.shape[:2]
    y0, y1 = (0, h) if rows is None else (int(rows[0]), int(rows[1]))
    if not 0 <= y0 < y1 <= h:
        raise ValueError(f"rows ({y0}, {y1}): give 0 <= y0 < y1 <= {h}")
    counts = np.zeros((h, w), np.uint32)
    counts[y0:y1] = i1 - i0
    sums[:y0] = 0.0
    sums[y1:] = 0.0
    return {
        "sums": sums,
        "squares": np.zeros_like(sums),
        "counts": counts,
        "dropped": int(meta.get("nonfiniteSamples", 0)),
        "dropped_splats": int(meta.get("nonfiniteSplats", 0)),
        "collapsed": 0,
        "rays": rays,
        "seconds": time.perf_counter() - t,
        "width": w,
        "height": h,
        "samples": (i0, i1),
        "rows": (y0, y1),
        "meta": meta,
    }


def merge_shards(shards):
    shards = list(shards)
    if not shards:
        raise ValueError("merge_shards: no shards")
    sums = np.zeros_like(shards[0]["sums"])
    counts = np.zeros(shards[0]["counts"].shape, np.uint64)
    for s in shards:
        sums += s["sums"]
        counts += s["counts"]
    image = np.zeros(sums.shape, np.float32)
    seen = counts > 0
    image[seen] = (sums[seen] / counts[seen][:, None]).astype(np.float32)
    meta = dict(shards[0]["meta"])
    meta["samplesPerPixel"] = int(counts.max())
    meta["raysTraced"] = str(sum(int(s["rays"]) for s in shards))
    meta["renderSeconds"] = float(sum(s["seconds"] for s in shards))
    meta["nonfiniteSamples"] = sum(int(s["dropped"]) for s in shards)
    meta["nonfiniteSplats"] = sum(int(s["dropped_splats"]) for s in shards)
    return image, meta
