"""scotopia against Mitsuba 3 on the bundled Cornell box (`make bench`).

Both render the same file at 256 × 256, max depth 16: Mitsuba with its best
CPU variant (`llvm_ad_spectral` when its LLVM loads, else `scalar_spectral`),
its film in XYZ; scotopia with its defaults (SWC, K = 4). Printed:

- at equal samples per pixel: each one's time and camera samples per second;
- at equal time (scotopia given Mitsuba's time): the samples each reached;
- for both: the relative RMSE of luminance Y against a high-spp reference
  rendered by Mitsuba (so any systematic difference between the renderers
  counts against scotopia), and the ratio of mean Y.

Mitsuba's Y is ∫L·ȳ dλ / ∫ȳ dλ; it is multiplied by 683 × 106.857 to be
absolute like scotopia's (docs/scene-format.md, "Comparing with Mitsuba 3").
With `--mesh`, the box's floor is replaced by a terrain of 1,002,528
triangles (the displaced grid of `crates/render/benches/bvh.rs`, written as
a binary PLY both renderers read): the large-scene comparison.

Usage: python bench/vs_mitsuba.py [--spp 64] [--ref-spp 1024] [--res 256] [--variant V] [--mesh]
"""

import argparse
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

import scotopia

ROOT = Path(__file__).resolve().parents[1]
SCENE = ROOT / "scenes" / "cornell-box.xml"
# ∫ ȳ dλ of the CIE 1931 2° observer over 360–830 nm, nm (Mitsuba's normaliser).
CIE_Y_INTEGRAL = 106.857


def best_variant():
    """`llvm_ad_spectral` if it renders here, else `scalar_spectral`. Probed
    in a child process: with an unsupported LLVM the variant aborts."""
    probe = (
        "import mitsuba as mi; mi.set_variant('llvm_ad_spectral'); "
        "mi.render(mi.load_dict(mi.cornell_box()), spp=1)"
    )
    ok = subprocess.run([sys.executable, "-c", probe], capture_output=True).returncode == 0
    return "llvm_ad_spectral" if ok else "scalar_spectral"


# The floor's shape in the bundled scene, replaced by the terrain with --mesh.
FLOOR = re.compile(
    r'<shape type="rectangle">\s*<transform name="to_world"><rotate x="1" angle="-90"/></transform>'
    r'\s*<ref id="white"/>\s*</shape>'
)


def terrain_ply(path, n=708):
    """(n² quads × 2) triangles over x, z ∈ [−1, 1], heights of bvh.rs's
    sum of sines scaled to 0–0.13 above the floor, as binary PLY."""
    t = np.linspace(-1.0, 1.0, n + 1, dtype=np.float64)
    x, z = np.meshgrid(t, t)
    h = 0.1 * np.sin(7 * x) * np.cos(5 * z) + 0.03 * np.sin(31 * x + 17 * z)
    verts = np.stack([x, 0.5 * (h + 0.13), z], -1).reshape(-1, 3).astype("<f4")
    v = (np.arange(n)[None, :] + (n + 1) * np.arange(n)[:, None]).ravel().astype("<i4")
    w = n + 1
    # Counter-clockwise seen from above (+y), so normals point up.
    tris = np.concatenate([np.stack([v, v + w + 1, v + 1], -1), np.stack([v, v + w, v + w + 1], -1)])
    faces = np.empty(len(tris), dtype=[("n", "u1"), ("i", "<i4", (3,))])
    faces["n"], faces["i"] = 3, tris
    header = (
        "ply\nformat binary_little_endian 1.0\n"
        f"element vertex {len(verts)}\nproperty float x\nproperty float y\nproperty float z\n"
        f"element face {len(tris)}\nproperty list uchar int vertex_indices\nend_header\n"
    )
    with open(path, "wb") as f:
        f.write(header.encode())
        f.write(verts.tobytes())
        f.write(faces.tobytes())
    return len(tris)


def scene_file(tmp, mesh):
    """The Cornell box, with the terrain for a floor when `mesh`."""
    if not mesh:
        return SCENE
    ply = Path(tmp) / "terrain.ply"
    count = terrain_ply(ply)
    text, found = FLOOR.subn(
        f'<shape type="ply"><string name="filename" value="{ply}"/><ref id="white"/></shape>',
        SCENE.read_text(),
    )
    assert found == 1, "the floor's shape was not found in cornell-box.xml"
    out = Path(tmp) / "cornell-terrain.xml"
    out.write_text(text)
    print(f"terrain: {count:,} triangles", flush=True)
    return out


def mitsuba_renderer(variant, res, depth, tmp, scene_path):
    import mitsuba as mi

    mi.set_variant(variant)
    xml = Path(tmp) / "mitsuba-xyz.xml"
    xml.write_text(scene_path.read_text().replace('value="rgb"', 'value="xyz"'))
    scene = mi.load_file(str(xml), res=res, max_depth=depth)

    def render(spp, seed=0):
        start = time.perf_counter()
        img = np.array(mi.render(scene, spp=spp, seed=seed), dtype=np.float64)
        secs = time.perf_counter() - start
        return img[..., 1] * 683.0 * CIE_Y_INTEGRAL, secs

    render(1)  # compile the kernels (llvm) before anything is timed
    return render


def scotopia_render(scene_path, res, depth, spp=None, seconds=None):
    img, meta = scotopia.render(
        str(scene_path),
        spp=spp,
        time=seconds,
        seed=1,
        params={"res": str(res), "max_depth": str(depth)},
    )
    return img[..., 1].astype(np.float64), float(meta["renderSeconds"]), int(meta["samplesPerPixel"])


def rel_rmse(img, ref):
    return float(np.sqrt(np.mean((img - ref) ** 2)) / np.mean(ref))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--spp", type=int, default=64)
    parser.add_argument("--ref-spp", type=int, default=1024)
    parser.add_argument("--res", type=int, default=256)
    parser.add_argument("--depth", type=int, default=16)
    parser.add_argument("--variant", help="Mitsuba variant (default: the best that runs)")
    parser.add_argument("--mesh", action="store_true", help="a 1M-triangle terrain for a floor")
    args = parser.parse_args()
    pixels = args.res * args.res

    variant = args.variant or best_variant()
    with tempfile.TemporaryDirectory() as tmp:
        scene_path = scene_file(tmp, args.mesh)
        mitsuba = mitsuba_renderer(variant, args.res, args.depth, tmp, scene_path)
        print(f"reference: Mitsuba {variant}, {args.ref_spp} spp …", flush=True)
        ref, ref_secs = mitsuba(args.ref_spp, seed=12345)
        theirs, t_m = mitsuba(args.spp)
        ours, t_s, _ = scotopia_render(scene_path, args.res, args.depth, spp=args.spp)
        ours_eq, t_eq, spp_eq = scotopia_render(scene_path, args.res, args.depth, seconds=t_m)

    rate = lambda spp, secs: pixels * spp / secs * 1e-6  # noqa: E731
    print(
        f"\nCornell box{' with the terrain' if args.mesh else ''} {args.res}×{args.res}, max depth {args.depth}; "
        f"reference {args.ref_spp} spp ({ref_secs:.0f} s)\n"
    )
    print("| renderer | spp | seconds | M camera samples/s | rel. RMSE of Y | mean Y / reference |")
    print("|---|---:|---:|---:|---:|---:|")
    rows = [
        (f"Mitsuba 3 {variant}", args.spp, t_m, theirs),
        ("scotopia (equal spp)", args.spp, t_s, ours),
        ("scotopia (equal time)", spp_eq, t_eq, ours_eq),
    ]
    for name, spp, secs, img in rows:
        print(
            f"| {name} | {spp} | {secs:.2f} | {rate(spp, secs):.2f} | "
            f"{rel_rmse(img, ref):.4f} | {img.mean() / ref.mean():.4f} |"
        )
    print(f"\nspeed ratio scotopia / Mitsuba at equal spp: {t_m / t_s:.2f}")
    print(
        "equal-time RMSE ratio scotopia / Mitsuba: "
        f"{rel_rmse(ours_eq, ref) / rel_rmse(theirs, ref):.2f}"
    )


if __name__ == "__main__":
    main()
