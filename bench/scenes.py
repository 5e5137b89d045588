"""Renders every bundled scene at a fixed sample count and prints camera
samples per second, rays per second and peak memory (`make bench`).

Each render is a separate `scotopia render` process, so its peak resident
memory (getrusage of that child) is its own. Usage:

    python bench/scenes.py [--spp 16] [--threads N] [--bin target/release/scotopia]
"""

import argparse
import os
import re
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SUMMARY = re.compile(
    r"(\d+) spp in ([\d.]+) s \(([\d.]+) Msamples/s, ([\d.]+) Mrays/s\)"
)


def render(binary, scene, spp, threads, out):
    """Runs one render; returns (spp, seconds, Msamples/s, Mrays/s, peak MiB)."""
    cmd = [str(binary), "render", str(scene), "--spp", str(spp), "-o", str(out)]
    if threads:
        cmd += ["--threads", str(threads)]
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    # wait4 gives this child's own resource usage (ru_maxrss in KiB on Linux).
    _, status, usage = os.wait4(proc.pid, 0)
    stderr = proc.stderr.read()
    proc.returncode = os.waitstatus_to_exitcode(status)
    if proc.returncode != 0:
        sys.exit(f"{scene.name}: scotopia failed ({proc.returncode}):\n{stderr}")
    match = SUMMARY.search(stderr)
    if not match:
        sys.exit(f"{scene.name}: no summary line in:\n{stderr}")
    done, secs, msps, mrps = match.groups()
    return int(done), float(secs), float(msps), float(mrps), usage.ru_maxrss / 1024


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--spp", type=int, default=16, help="samples per pixel (16)")
    parser.add_argument("--threads", type=int, default=0, help="worker threads (all)")
    parser.add_argument("--bin", default=ROOT / "target" / "release" / "scotopia")
    parser.add_argument("--out", default=ROOT / "out" / "bench")
    args = parser.parse_args()
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)

    print(f"scotopia render --spp {args.spp}, {args.threads or os.cpu_count()} threads")
    print("| scene | resolution | spp | seconds | Msamples/s | Mrays/s | peak MiB |")
    print("|---|---|---:|---:|---:|---:|---:|")
    for scene in sorted((ROOT / "scenes").glob("*.xml")):
        exr = out / f"{scene.stem}.exr"
        done, secs, msps, mrps, mib = render(args.bin, scene, args.spp, args.threads, exr)
        res = _resolution(exr)
        print(
            f"| {scene.stem} | {res} | {done} | {secs:.1f} | {msps:.2f} | {mrps:.2f} | {mib:.0f} |",
            flush=True,
        )


def _resolution(exr):
    """Width × height of a written EXR (via the OpenEXR package when present)."""
    try:
        import OpenEXR
    except ImportError:
        return "?"
    with OpenEXR.File(str(exr)) as f:
        w, h = f.header()["dataWindow"][1] + 1
        return f"{w}×{h}"


if __name__ == "__main__":
    main()
