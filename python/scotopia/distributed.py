"""Distributed rendering on Ray (issue 27; docs/distributed.md).

``render(scene, spp=..., shards=N)`` cuts one render into shards — ranges of
sample indices (the default) or of rows — runs each as a Ray task that calls
the core's ``render_shard``, and adds the shards' raw film sums with the
core's ``merge_shards``. A pixel's random numbers depend on (seed, pixel,
sample index) alone, so the merged image is the single-process image: bit
for bit when each pixel's samples all come from one shard (row shards with
the path tracer), within 1e-6 relative otherwise (sample shards, and bdpt's
light-tracing splats, add the same f64 terms in another order).

The scene's folder (the scene file's directory, recursively) is packed into
one tar in Ray's object store; each worker unpacks it once per scene (keyed
by its content hash) into a temporary directory and renders there, so
workers need no shared file system and relative asset paths keep working.

Ray is optional: ``pip install 'scotopia[distributed]'``. Importing
``scotopia`` never imports Ray; calling these functions without it raises
``ImportError`` naming the extra.
"""

import hashlib
import io
import os
import sys
import tarfile
import tempfile
import time
import warnings
from pathlib import Path

__all__ = ["render", "render_many", "pack_scene", "cut_shards"]

EXTRA = "pip install 'scotopia[distributed]'"

#: Files larger than this (bytes) are left out of a scene's pack, with a warning.
MAX_FILE_BYTES = 256 * 1024 * 1024
#: Folders never packed.
SKIP_DIRS = {".git", "__pycache__", ".venv", "node_modules"}
#: Task retries when a worker dies mid-shard (the retried shard renders the
#: same samples, so the image is unchanged).
MAX_RETRIES = 3
#: Whether interrupting kills the workers running shards (ray.cancel(force=True))
#: or lets their current shard end. Ray 2.60 can abort the driver ("Tried to
#: complete task that was not pending") when a force-cancel races a finishing
#: task, so the default lets running shards end (their results are dropped).
FORCE_CANCEL = False

_SHARD_OPTIONS = (
    "params",
    "res",
    "integrator",
    "wavelengths",
    "cluster",
    "tracer",
    "quantity",
    "guiding",
)


def _ray():
    try:
        import ray
    except ImportError as e:  # pragma: no cover - exercised without ray
        raise ImportError(
            f"scotopia.distributed needs Ray, an optional dependency: {EXTRA}"
        ) from e
    return ray


def _core():
    """The core's shard API: render_shard (Rust) and merge_shards."""
    from . import merge_shards, render_shard

    return render_shard, merge_shards


# ---------------------------------------------------------------- packing


class ScenePack:
    """A scene's folder as tar bytes: ``data``, its sha256 ``digest``, the
    scene file's ``name`` inside it and the files ``skipped``."""

    def __init__(self, data, digest, name, skipped):
        self.data, self.digest, self.name, self.skipped = data, digest, name, skipped

    def __repr__(self):
        return f"ScenePack({self.name!r}, {len(self.data)} bytes, {self.digest[:12]})"


def pack_scene(scene, *, max_file_bytes=MAX_FILE_BYTES):
    """Packs the scene file's directory, recursively, into a deterministic
    tar (sorted names, zeroed times and owners). Files over
    ``max_file_bytes`` are left out with a warning (a scene that needs them
    then fails on the workers with the loader's error). Assets outside the
    folder (``../x.png``, absolute paths) are not packed."""
    path = Path(scene).resolve()
    if not path.is_file():
        raise ValueError(f"{scene}: no such scene file")
    root = path.parent
    buf = io.BytesIO()
    skipped = []
    with tarfile.open(fileobj=buf, mode="w") as tar:
        for dirpath, dirnames, filenames in os.walk(root):
            dirnames[:] = sorted(d for d in dirnames if d not in SKIP_DIRS)
            for fname in sorted(filenames):
                full = Path(dirpath) / fname
                if not full.is_file():
                    continue
                rel = full.relative_to(root).as_posix()
                size = full.stat().st_size
                if size > max_file_bytes and full != path:
                    skipped.append(rel)
                    continue
                info = tarfile.TarInfo(rel)
                info.size = size
                info.mode = 0o644
                with open(full, "rb") as f:
                    tar.addfile(info, f)
    if skipped:
        warnings.warn(
            f"{scene}: left out of the pack sent to Ray workers (over "
            f"{max_file_bytes} bytes): {', '.join(skipped)}",
            stacklevel=2,
        )
    data = buf.getvalue()
    return ScenePack(data, hashlib.sha256(data).hexdigest(), path.name, skipped)


# Per worker process: digest -> unpacked folder.
_UNPACKED = {}


def _unpack(data, digest):
    """Unpacks a scene once per node and scene: into
    $TMPDIR/scotopia-ray/<digest>, made atomically by renaming a private
    folder, so concurrent workers never see half a scene."""
    done = _UNPACKED.get(digest)
    if done and os.path.isdir(done):
        return done
    base = Path(tempfile.gettempdir()) / "scotopia-ray"
    base.mkdir(parents=True, exist_ok=True)
    final = base / digest
    if not final.is_dir():
        if hashlib.sha256(data).hexdigest() != digest:
            raise RuntimeError("scene pack corrupted in transit (hash mismatch)")
        tmp = Path(tempfile.mkdtemp(prefix=f".{digest[:12]}-", dir=base))
        with tarfile.open(fileobj=io.BytesIO(data)) as tar:
            if hasattr(tarfile, "data_filter"):
                tar.extractall(tmp, filter="data")
            else:  # pragma: no cover - Python without PEP 706
                tar.extractall(tmp)
        try:
            os.rename(tmp, final)
        except OSError:  # another worker won the race
            import shutil

            shutil.rmtree(tmp, ignore_errors=True)
    _UNPACKED[digest] = str(final)
    return str(final)


def _render_shard_task(pack_data, digest, name, options, samples, rows, threads):
    """The body of one Ray task: unpack (once), render the shard there."""
    if threads:
        # The core's thread pool starts on first use and reads this then.
        os.environ.setdefault("RAYON_NUM_THREADS", str(threads))
    folder = _unpack(pack_data, digest)
    render_shard, _ = _core()
    return render_shard(
        os.path.join(folder, name), samples=samples, rows=rows, **options
    )


# ---------------------------------------------------------------- cutting


def cut_shards(spp, height, shards, split="samples"):
    """The shards of a render as (samples, rows) pairs: ``split="samples"``
    cuts [0, spp) into ``shards`` near-equal ranges over the whole film;
    ``split="rows"`` cuts the rows, each shard taking all spp samples."""
    spp, height, shards = int(spp), int(height), int(shards)
    if spp < 1:
        raise ValueError(f"spp {spp}: give at least 1")
    if shards < 1:
        raise ValueError(f"shards {shards}: give at least 1")
    if split == "samples":
        n = min(shards, spp)
        b = [k * spp // n for k in range(n + 1)]
        return [((b[k], b[k + 1]), None) for k in range(n)]
    if split == "rows":
        n = min(shards, height)
        b = [k * height // n for k in range(n + 1)]
        return [((0, spp), (b[k], b[k + 1])) for k in range(n)]
    raise ValueError(f"split '{split}': use samples or rows")


# ---------------------------------------------------------------- Ray


#: Seconds a cluster's address has to answer before connecting fails
#: (environment variable SCOTOPIA_RAY_CONNECT_TIMEOUT overrides it). Ray's
#: own connection retries for minutes on an address that does not answer.
CONNECT_TIMEOUT = 30.0


def connect_timeout():
    """CONNECT_TIMEOUT, or SCOTOPIA_RAY_CONNECT_TIMEOUT (seconds) when set."""
    text = os.environ.get("SCOTOPIA_RAY_CONNECT_TIMEOUT")
    if text is None:
        return CONNECT_TIMEOUT
    try:
        value = float(text)
    except ValueError:
        value = float("nan")
    if not (0 < value <= 3600):
        raise ValueError(
            f"SCOTOPIA_RAY_CONNECT_TIMEOUT={text}: give seconds from 0 to 3600"
        )
    return value


def _host_port(address):
    """(host, port) of an address that names one ("ray://h:p", "h:p"),
    else None ("auto", "local": Ray finds the cluster itself)."""
    rest = address.split("://", 1)[1] if "://" in address else address
    host, sep, port = rest.rpartition(":")
    if not sep or not port.isdigit():
        return None
    return host.strip("[]") or "127.0.0.1", int(port)


def check_reachable(address, timeout=None):
    """Raises ConnectionError naming ``address`` unless a TCP connection to
    its host and port opens within ``timeout`` seconds (default
    ``connect_timeout()``): an unreachable cluster fails at once or within
    the timeout, where ``ray.init`` would retry for minutes."""
    timeout = connect_timeout() if timeout is None else timeout
    target = _host_port(address)
    if target is None:
        return
    import socket

    try:
        socket.create_connection(target, timeout=timeout).close()
    except OSError as e:
        why = "no answer" if isinstance(e, socket.timeout) else e.strerror or str(e)
        raise ConnectionError(
            f"Ray address {address}: cannot reach {target[0]}:{target[1]} within "
            f"{timeout:g} s ({why}); is the cluster up (ray start --head)?"
        ) from None


def _connect(address, num_cpus):
    ray = _ray()
    if not ray.is_initialized():
        kw = dict(logging_level="WARNING", log_to_driver=False)
        if address is None:
            ray.init(num_cpus=num_cpus or os.cpu_count(), include_dashboard=False, **kw)
        else:
            check_reachable(address)
            ray.init(address=address, **kw)
    return ray


class _Progress:
    """tqdm over all shards when installed, else one line per shard on stderr."""

    def __init__(self, total, enabled):
        self.total, self.done, self.bar = total, 0, None
        self.enabled = enabled
        if enabled:
            try:
                from tqdm import tqdm

                self.bar = tqdm(total=total, unit="shard", file=sys.stderr)
            except ImportError:
                pass

    def step(self, what=""):
        self.done += 1
        if not self.enabled:
            return
        if self.bar is not None:
            self.bar.update(1)
        else:
            print(f"scotopia: shard {self.done}/{self.total} {what}", file=sys.stderr)

    def close(self):
        if self.bar is not None:
            self.bar.close()


def _scene_error(err):
    """The core's error inside a Ray task error, else None."""
    cause = getattr(err, "cause", None)
    if isinstance(cause, (ValueError, MemoryError)):
        return cause
    if isinstance(err, (ValueError, MemoryError)):
        return err
    return None


class _Job:
    def __init__(self, index, scene, spp, seed, shards, split, options):
        self.index, self.scene, self.options = index, str(scene), dict(options)
        self.options["seed"] = int(seed)
        info = _scene_info(self.scene, options.get("params"), options.get("res"))
        self.spp = int(spp if spp is not None else info["samples_per_pixel"])
        height = info["film"]["height"]
        self.cuts = cut_shards(self.spp, height, shards, split)
        self.results = [None] * len(self.cuts)
        self.left = len(self.cuts)

    def merge(self, interrupted=False):
        _, merge_shards = _core()
        done = [r for r in self.results if r is not None]
        image, meta = merge_shards(done)
        meta = dict(meta)
        meta["sceneFile"] = self.scene  # not the worker's unpacked copy
        meta["shards"] = len(self.cuts)
        meta["shardsMerged"] = len(done)
        meta["shardSeconds"] = [float(r["seconds"]) for r in done]
        if interrupted:
            meta["interrupted"] = 1
        return image, meta


def _scene_info(scene, params, res):
    from . import scene_info

    return scene_info(scene, params=params, res=res)


def _check_options(options):
    bad = sorted(set(options) - set(_SHARD_OPTIONS))
    if bad:
        raise TypeError(
            f"scotopia.distributed.render: unsupported option(s) {', '.join(bad)}; "
            f"shards take {', '.join(_SHARD_OPTIONS)} (time limits, checkpoints and "
            "outputs are for local renders)"
        )


def _run(jobs, *, shards, split, address, num_cpus, cpus_per_shard, progress,
         max_file_bytes, on_interrupt):
    """Submits every shard of every job, yields (job, interrupted) as jobs
    complete. ``on_interrupt``: "merge" (stop, yield the unfinished jobs with
    what they have) or "raise"."""
    ray = _connect(address, num_cpus)
    task = ray.remote(_render_shard_task).options(
        num_cpus=cpus_per_shard,
        max_retries=MAX_RETRIES,
        retry_exceptions=False,
        name="scotopia_shard",
    )
    packs = {}
    refs = {}
    for job in jobs:
        key = str(Path(job.scene).resolve())
        if key not in packs:
            pack = pack_scene(job.scene, max_file_bytes=max_file_bytes)
            packs[key] = (pack, ray.put(pack.data))
        pack, data_ref = packs[key]
        job.digest = pack.digest
        for k, (samples, rows) in enumerate(job.cuts):
            ref = task.remote(
                data_ref, pack.digest, pack.name, job.options, samples, rows,
                cpus_per_shard,
            )
            refs[ref] = (job, k)
    bar = _Progress(len(refs), progress)
    pending = list(refs)
    try:
        while pending:
            ready, pending = ray.wait(pending, num_returns=1)
            for ref in ready:
                job, k = refs[ref]
                try:
                    job.results[k] = ray.get(ref)
                except Exception as e:
                    scene_err = _scene_error(e)
                    _cancel(ray, pending)
                    _drain(ray, pending)
                    pending = []
                    if scene_err is not None:
                        raise type(scene_err)(_local_paths(str(scene_err), job)) from None
                    raise
                job.left -= 1
                bar.step(f"{Path(job.scene).name} {job.cuts[k]}")
                if job.left == 0:
                    yield job, False
    except KeyboardInterrupt:
        _cancel(ray, pending)
        if on_interrupt != "merge":
            raise
        for job in jobs:
            if 0 < job.left < len(job.cuts):
                print(
                    f"scotopia: interrupted; merged {len(job.cuts) - job.left} of "
                    f"{len(job.cuts)} shards of {job.scene}",
                    file=sys.stderr,
                )
                yield job, True
            elif job.left == len(job.cuts):
                raise
    finally:
        if pending:  # the consumer stopped early
            _cancel(ray, pending)
        bar.close()


def _local_paths(message, job):
    """A worker's error with its unpacked copy's paths as the driver's."""
    import re

    digest = job.digest
    folder = str(Path(job.scene).resolve().parent)
    return re.sub(r"[^\s'\"]*scotopia-ray/" + digest, lambda _: folder, message)


def _drain(ray, refs, timeout=2.0):
    """Collects the shards that fail alongside the first (a bad scene fails
    every shard at once), so that Ray does not log each of them again as
    an unhandled error: the render reports its error once."""
    if not refs:
        return
    ready, _ = ray.wait(refs, num_returns=len(refs), timeout=timeout)
    for ref in ready:
        try:
            ray.get(ref)
        except Exception:
            pass


def _cancel(ray, refs):
    for ref in refs:
        try:
            ray.cancel(ref, force=FORCE_CANCEL)
        except Exception:  # already finished or gone
            pass


def render(
    scene,
    spp=None,
    seed=0,
    shards=None,
    address=None,
    *,
    split="samples",
    num_cpus=None,
    cpus_per_shard=1,
    progress=True,
    max_file_bytes=MAX_FILE_BYTES,
    output=None,
    **render_options,
):
    """Renders ``scene`` on Ray in ``shards`` shards and returns ``(image,
    meta)`` like ``scotopia.render``.

    ``address=None`` uses the Ray already initialised in this process or
    starts a local one with ``num_cpus`` CPUs (default: all); otherwise it
    connects (``"auto"``, ``"ray://head:10001"``, ``"head:6379"``).
    ``shards`` defaults to twice the cluster's CPUs. ``split="samples"``
    (default) gives every shard the whole film and a range of sample
    indices: equal work per shard, merged within 1e-6 relative;
    ``split="rows"`` gives every shard all samples of a band of rows:
    bit-identical for the path tracer but unbalanced where rows differ in
    cost. Each shard task takes ``cpus_per_shard`` CPUs (and as many core
    threads). ``render_options``: params, res, integrator, wavelengths,
    cluster, tracer, quantity, guiding.

    ``output`` also writes the merged image as the OpenEXR ``scotopia.render``
    writes (``scotopia.write_exr``), after an interruption too.

    On KeyboardInterrupt the unfinished shards are cancelled and those that
    finished are merged (meta["interrupted"] = 1, meta["shardsMerged"]).
    A shard failing on bad input raises the core's ValueError once.
    """
    _check_options(render_options)
    ray = _connect(address, num_cpus)
    if shards is None:
        shards = max(1, 2 * int(ray.cluster_resources().get("CPU", 1)))
    job = _Job(0, scene, spp, seed, shards, split, render_options)
    for done, interrupted in _run(
        [job], shards=shards, split=split, address=address, num_cpus=num_cpus,
        cpus_per_shard=cpus_per_shard, progress=progress,
        max_file_bytes=max_file_bytes, on_interrupt="merge",
    ):
        image, meta = done.merge(interrupted)
        if output is not None:
            from . import write_exr

            write_exr(str(output), image, meta)
        return image, meta
    raise RuntimeError("no shard finished")  # pragma: no cover


def render_many(
    jobs,
    *,
    shards=1,
    split="samples",
    address=None,
    num_cpus=None,
    cpus_per_shard=1,
    progress=True,
    max_file_bytes=MAX_FILE_BYTES,
):
    """Runs many renders (a sweep over ``params``, lamps, frames) and yields
    ``(index, image, meta)`` as each finishes, in finishing order. Each job
    is a scene path or a dict of ``render``'s arguments with ``"scene"``
    (``spp``, ``seed``, ``shards``, ``split`` and the render options). All
    shards of all jobs are queued at once; a scene folder is packed once.
    KeyboardInterrupt cancels what is left and propagates."""
    built = []
    _connect(address, num_cpus)
    for i, j in enumerate(jobs):
        j = {"scene": j} if isinstance(j, (str, os.PathLike)) else dict(j)
        scene = j.pop("scene")
        spp = j.pop("spp", None)
        seed = j.pop("seed", 0)
        n = j.pop("shards", shards)
        sp = j.pop("split", split)
        _check_options(j)
        built.append(_Job(i, scene, spp, seed, n, sp, j))
    for job, interrupted in _run(
        built, shards=shards, split=split, address=address, num_cpus=num_cpus,
        cpus_per_shard=cpus_per_shard, progress=progress,
        max_file_bytes=max_file_bytes, on_interrupt="raise",
    ):
        image, meta = job.merge(interrupted)
        yield job.index, image, meta


def _main(argv=None):
    """``python -m scotopia.distributed SCENE --spp N --shards N [--address A]
    [-D k=v] [--res R] [--integrator I] [--split rows] -o out.exr``: the
    entry a CLI ``--ray`` can run (prints the meta as JSON)."""
    import argparse
    import json

    import numpy as np

    p = argparse.ArgumentParser(prog="python -m scotopia.distributed")
    p.add_argument("scene")
    p.add_argument("--spp", type=int)
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--shards", type=int)
    p.add_argument("--split", default="samples", choices=["samples", "rows"])
    p.add_argument("--address")
    p.add_argument("--res")
    p.add_argument("--integrator")
    p.add_argument("--wavelengths", default="swc")
    p.add_argument("--cluster", type=int, default=4)
    p.add_argument("--tracer", default="scalar")
    p.add_argument("--guiding", default="off", choices=["on", "off"])
    p.add_argument("--quantity", default="radiance")
    p.add_argument("-D", action="append", default=[], metavar="NAME=VALUE")
    p.add_argument("-o", "--output", help="write the X, Y, Z, V′ image (.exr, or .npy)")
    a = p.parse_args(argv)
    params = dict(d.split("=", 1) for d in a.D) or None
    t = time.perf_counter()
    if a.address:
        _connect_or_exit(a.address)
    exr = a.output if a.output and a.output.lower().endswith(".exr") else None
    image, meta = render(
        a.scene, spp=a.spp, seed=a.seed, shards=a.shards, address=a.address,
        split=a.split, res=a.res, integrator=a.integrator, params=params, output=exr,
        wavelengths=a.wavelengths, cluster=a.cluster, tracer=a.tracer, quantity=a.quantity,
        guiding=a.guiding,
    )
    meta["wallSeconds"] = time.perf_counter() - t
    meta.pop("squares", None)  # an array, not for JSON
    if a.output and not exr:
        np.save(a.output, image)
    print(json.dumps(meta, indent=1, default=str))


def _connect_or_exit(address):
    """Connects this process (the CLI's driver) to the cluster at
    ``address`` within ``connect_timeout()`` seconds, or exits with status
    3 and says why: past the TCP check, ``ray.init`` can still wait for
    minutes (an open port that is not Ray's), in C++ where no Python
    exception reaches it, so a watchdog thread ends the process."""
    import threading

    timeout = connect_timeout()

    def give_up():
        print(
            f"scotopia: Ray address {address}: no Ray cluster answered within "
            f"{timeout:g} s (SCOTOPIA_RAY_CONNECT_TIMEOUT sets the limit)",
            file=sys.stderr,
            flush=True,
        )
        os._exit(3)

    watchdog = threading.Timer(timeout, give_up)
    watchdog.daemon = True
    watchdog.start()
    try:
        _connect(address, None)
    except ConnectionError as e:
        print(f"scotopia: {e}", file=sys.stderr)
        sys.exit(3)
    finally:
        watchdog.cancel()


if __name__ == "__main__":
    _main()
