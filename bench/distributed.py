"""Distributed rendering on Ray against one process (`make bench`, issue 27):
the Cornell box at equal total spp, rendered by one process (the core's
threads on every core) and by Ray workers on this machine (one core each,
sample shards), and how the shard count trades overhead against balance.

    python bench/distributed.py [--spp 64] [--res 256] [--workers 2]
        [--shards 2 8 32] [--address ADDRESS]

Overhead = Ray's wall time over the one process's, less 1. Balance =
the summed shard render seconds over (wall seconds × workers): 100 % when
every worker renders all the time; what is missing is scene loading per
shard, packing and transfer, scheduling, and workers idle at the end.
Ray's own start-up is not counted (a cluster is started once). With
--address the shards run on that cluster (docs/distributed.md) and the
one-process row is this machine's.
"""

import argparse
import os
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
CORNELL = str(ROOT / "scenes" / "cornell-box.xml")


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--spp", type=int, default=64)
    p.add_argument("--res", type=int, default=256)
    p.add_argument("--workers", type=int, default=2, help="Ray CPUs on this machine (2)")
    p.add_argument("--shards", type=int, nargs="+", default=[2, 8, 32])
    p.add_argument("--address", help="a Ray cluster instead of a local Ray")
    p.add_argument("--repeat", type=int, default=2, help="best of N (2)")
    a = p.parse_args()

    import ray
    import scotopia
    from scotopia import distributed

    opts = dict(res=a.res, seed=1)
    if a.address:
        ray.init(address=a.address, logging_level="WARNING", log_to_driver=False)
    else:
        ray.init(num_cpus=a.workers, include_dashboard=False, logging_level="WARNING",
                 log_to_driver=False)
    workers = int(ray.cluster_resources().get("CPU", a.workers))
    # Workers started and the scene unpacked once, as on a running cluster.
    distributed.render(CORNELL, spp=workers, shards=workers, progress=False, **opts)
    ref, _ = scotopia.render(CORNELL, spp=a.spp, **opts)

    def local():
        t = time.perf_counter()
        scotopia.render(CORNELL, spp=a.spp, **opts)
        return time.perf_counter() - t

    print(f"Cornell box {a.res}×{a.res}, {a.spp} spp, {os.cpu_count()} cores here; "
          f"Ray: {workers} CPUs; best of {a.repeat}, each Ray run paired with a "
          "one-process run just before it (a busy machine drifts)")
    print(f"{'run':<28} {'1 proc s':>8} {'Ray s':>7} {'overhead':>9} {'balance':>8} "
          f"{'max |Δ|/peak':>13}")
    for split in ("samples", "rows"):
        for n in a.shards:
            best_local, best, meta, image = float("inf"), float("inf"), None, None
            for _ in range(a.repeat):
                best_local = min(best_local, local())
                t = time.perf_counter()
                image, m = distributed.render(CORNELL, spp=a.spp, shards=n, split=split,
                                              progress=False, **opts)
                wall = time.perf_counter() - t
                if wall < best:
                    best, meta = wall, m
            busy = sum(meta["shardSeconds"]) / (best * workers)
            diff = float(np.abs(image - ref).max() / ref.max())
            print(f"{f'{workers} workers, {n} {split} shards':<28} {best_local:8.2f} "
                  f"{best:7.2f} {100 * (best / best_local - 1):8.1f}% {100 * busy:7.1f}% "
                  f"{diff:13.1e}")
            sys.stdout.flush()
    ray.shutdown()


if __name__ == "__main__":
    main()
