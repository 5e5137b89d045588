"""scotopia against Mitsuba 3 on bundled scenes (`make bench`: the Cornell box).

Both render the same file: the Cornell box at 256 × 256, max depth 16 by
default; another scene (`--scene NAME`, a file in scenes/) at `--res` pixels
wide keeping its aspect and its own max depth unless `--depth` is given.
Mitsuba runs its best CPU variant (`llvm_ad_spectral` when its LLVM loads,
else `scalar_spectral`) with its film in XYZ; scotopia its defaults (SWC,
K = 4). Printed per scene:

- at equal samples per pixel: each one's time and camera samples per second;
- at equal time (scotopia given Mitsuba's time): the samples each reached;
- for each: against a high-spp reference of luminance Y, the relative RMSE
  (√mean (I − R)² / mean R: dominated by the brightest pixels) and the
  relMSE (bench/common.py's: per pixel (I − R)² / (R² + ε), ε = 1e-4 ×
  (mean R)², averaged: every pixel weighed by its own level, so dim
  regions count as much as bright ones), and the ratio of mean Y;
- how few pixels hold 90 % of each relMSE: where a handful do, rare
  fireflies decide it and one pair of images says little, so `--seeds N`
  repeats the equal-time pair with N seeds and reports the mean relMSE
  (the summary table of `--all` gives those means).

The reference is rendered by Mitsuba (`--ref-spp`, another seed than the
timed render): one reference for both, so the two errors are comparable
figures; Mitsuba's own noise in it is independent of both images, and any
systematic difference between the renderers counts against scotopia (the
mean-Y column shows it). The streets are the exception (`--ref`'s default,
REF_BY_SCENE): their sodium lamps emit in two lines 0.6 nm apart, which
Mitsuba's wavelengths (drawn from the eye's sensitivity, not the lamps')
find a few times in a thousand, so its reference there is noise wherever
sodium light falls; scotopia's, of another seed, is used, and its
agreement with Mitsuba's, away from the lamps' own pixels, is printed.
So is the glass scene's: Mitsuba's, even at 8192 spp, keeps fireflies of
its caustic paths. The scenes compared use only what both renderers
implement alike (glass-and-metals.xml gives its ball Mitsuba's constant
BK7 index, 1.5046, not scotopia's dispersive `bk7`). Every scene but the
Cornell box is first copied by bench/mitsuba_port.py into a form Mitsuba
reads, and both render that copy: the streets' lamp spectra become inline
absolute spectra, and the long street's goniometric (`ies`) lamps become
spot lights of the same flux and spectrum. A scene Mitsuba still cannot
load is reported as such, with Mitsuba's error, and skipped.

Mitsuba's Y is ∫L·ȳ dλ / ∫ȳ dλ; it is multiplied by 683 × 106.857 to be
absolute like scotopia's (docs/scene-format.md, "Comparing with Mitsuba 3").
With `--mesh`, the box's floor is replaced by a terrain of 1,002,528
triangles (the displaced grid of `crates/render/benches/bvh.rs`, written as
a binary PLY both renderers read): the large-scene comparison. `--all`
runs cornell-box.xml, night-street.xml, long-street.xml and
glass-and-metals.xml in turn.

Usage: python bench/vs_mitsuba.py [--scene cornell-box.xml | --all] [--spp 64]
       [--ref-spp 1024] [--ref mitsuba|scotopia] [--res 256] [--depth D] [--seeds N]
       [--variant V] [--mesh] [--save DIR]
"""

import argparse
import os
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from scipy import ndimage

import scotopia

# Dr.Jit loads the first libLLVM it finds; Debian 12 also ships LLVM 14 and
# 15, which abort on some of the glass scene's kernels. Point it at
# Debian's libllvm19 where that is installed (`apt-get install libllvm19`).
LLVM19 = "/usr/lib/x86_64-linux-gnu/libLLVM-19.so"
if os.path.exists(LLVM19):
    os.environ.setdefault("DRJIT_LIBLLVM_PATH", LLVM19)

ROOT = Path(__file__).resolve().parents[1]
SCENES = ROOT / "scenes"
SCENE = SCENES / "cornell-box.xml"
ALL = ["cornell-box.xml", "night-street.xml", "long-street.xml", "glass-and-metals.xml"]
# ∫ ȳ dλ of the CIE 1931 2° observer over 360–830 nm, nm (Mitsuba's normaliser).
CIE_Y_INTEGRAL = 106.857
# Whose render is the reference by default (the module's docstring says why).
# The glass scene too: Mitsuba's own reference, even at 8192 spp, keeps
# caustic noise of its own (README, "Caustics through glass balls").
REF_BY_SCENE = {
    "night-street.xml": "scotopia",
    "long-street.xml": "scotopia",
    "glass-and-metals.xml": "scotopia",
}
# scotopia's integrator where it is not the scene's (`--integrator`'s
# default). The glass scene's is the path tracer since its caustics are
# found by the manifold estimator, joins and light tracing (0.17x Mitsuba
# against 0.55x for the bidirectional tracer); it named bdpt before.
INTEGRATOR_BY_SCENE = {"glass-and-metals.xml": "path"}

sys.path.insert(0, str(Path(__file__).resolve().parent))
from common import rel_mse as _rel_mse  # noqa: E402
from mitsuba_port import port  # noqa: E402


def scene_params(scene_path, res, depth):
    """The `<default>` overrides both renderers get: `res` (and `max_depth`)
    for a scene that declares them, as the Cornell box does; else `width`
    = res and `height` keeping the scene's aspect. Returns (params, pixels,
    description of the size)."""
    text = scene_path.read_text()
    defaults = dict(re.findall(r'<default\s+name="(\w+)"\s+value="([^"]*)"', text))
    params = {}
    if "res" in defaults:
        params["res"] = str(res)
        w = h = res
    else:
        w0, h0 = int(defaults["width"]), int(defaults["height"])
        w, h = res, max(1, round(res * h0 / w0))
        params.update(width=str(w), height=str(h))
    if depth is not None:
        if "max_depth" not in defaults:
            sys.exit(f"{scene_path.name} has no max_depth parameter: leave out --depth")
        params["max_depth"] = str(depth)
    md = params.get("max_depth", defaults.get("max_depth"))
    if md is None:
        found = re.search(r'<integer name="max_depth" value="(\d+)"', text)
        md = found.group(1) if found else "?"
    return params, w * h, f"{w}×{h}, max depth {md}"


def best_variant(xml, params):
    """`llvm_ad_spectral` if it renders this scene here, else
    `scalar_spectral`. Probed in a child process: with an unsupported LLVM
    (Debian 12's LLVM 15 "cannot select fminimum" in a kernel of
    glass-and-metals.xml) the variant aborts the process."""
    probe = (
        "import sys, mitsuba as mi; mi.set_variant('llvm_ad_spectral'); "
        "mi.file_resolver().prepend(sys.argv[2]); "
        "p = dict(a.split('=', 1) for a in sys.argv[3:]); "
        "mi.render(mi.load_file(sys.argv[1], **p), spp=1)"
    )
    args = [f"{k}={v}" for k, v in params.items()]
    run = subprocess.run([sys.executable, "-c", probe, str(xml), str(SCENES), *args], capture_output=True)
    return "llvm_ad_spectral" if run.returncode == 0 else "scalar_spectral"


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


def mitsuba_xml(tmp, scene_path):
    """A copy of the scene with Mitsuba's film in XYZ (files it names are
    found through the resolver, which gets scenes/ first). A film without a
    `pixel_format` is Mitsuba's default RGB, whose G is not Y (5 % off on
    white, more on sodium light): it gets one."""
    xml = Path(tmp) / f"mitsuba-xyz-{scene_path.name}"
    text = scene_path.read_text().replace('value="rgb"', 'value="xyz"')
    if 'name="pixel_format"' not in text:
        text, films = re.subn(
            r'(<film type="hdrfilm"[^>]*>)', r'\1<string name="pixel_format" value="xyz"/>', text
        )
        assert films == 1, f"{scene_path.name}: one hdrfilm expected, found {films}"
    xml.write_text(text)
    return xml


def mitsuba_renderer(variant, xml, params):
    """A function spp, seed → (Y in cd/m², seconds), or the reason Mitsuba
    cannot load the scene (a string)."""
    import mitsuba as mi

    mi.set_variant(variant)
    mi.file_resolver().prepend(str(SCENES))
    try:
        scene = mi.load_file(str(xml), **params)
    except Exception as err:  # Mitsuba raises RuntimeError naming the line
        return " ".join(str(err).split())

    def render(spp, seed=0):
        start = time.perf_counter()
        img = np.array(mi.render(scene, spp=spp, seed=seed), dtype=np.float64)
        secs = time.perf_counter() - start
        return img[..., 1] * 683.0 * CIE_Y_INTEGRAL, secs

    render(1)  # compile the kernels (llvm) before anything is timed
    return render


def scotopia_render(scene_path, params, spp=None, seconds=None, seed=1, integrator=None):
    if integrator is not None:
        params = dict(params, integrator=integrator)
    img, meta = scotopia.render(str(scene_path), spp=spp, time=seconds, seed=seed, params=params)
    return img[..., 1].astype(np.float64), float(meta["renderSeconds"]), int(meta["samplesPerPixel"])


def rel_rmse(img, ref):
    return float(np.sqrt(np.mean((img - ref) ** 2)) / np.mean(ref))


def rel_mse(img, ref):
    """bench/common.py's relMSE of one channel: (I − R)² / (R² + ε)."""
    return _rel_mse(img[..., None], ref[..., None], 0)


def near_lamps(*images, level=50.0, grow=2):
    """Pixels that see an emitter (Y above `level` cd/m² in any image) or lie
    within `grow` pixels of one."""
    hot = np.any([img > level for img in images], axis=0)
    return ndimage.binary_dilation(hot, iterations=grow)


def pixels_holding(img, ref, share=0.9):
    """How few pixels hold `share` of the relMSE: a handful means rare
    fireflies decide the figure (then it varies widely between seeds)."""
    r2 = ref * ref
    err = np.sort(((img - ref) ** 2 / (r2 + 1e-4 * np.mean(ref) ** 2)).ravel())[::-1]
    return int(np.searchsorted(np.cumsum(err), share * err.sum()) + 1)


def compare(name, args):
    """One scene: prints its table; returns its summary row, or None when
    Mitsuba cannot load it."""
    depth = args.depth if args.depth is not None else (16 if name == "cornell-box.xml" else None)
    with tempfile.TemporaryDirectory() as tmp:
        if name == "cornell-box.xml":
            scene_path = scene_file(tmp, args.mesh)
        else:
            if not (SCENES / name).is_file():
                sys.exit(f"no scene {SCENES / name}")
            # Both render a copy Mitsuba reads (bench/mitsuba_port.py).
            scene_path = port(SCENES / name, Path(tmp) / name)
        params, pixels, size = scene_params(scene_path, args.res, depth)
        xml = mitsuba_xml(tmp, scene_path)
        variant = args.variant or best_variant(xml, params)
        mitsuba = mitsuba_renderer(variant, xml, params)
        if isinstance(mitsuba, str):
            print(f"\n{name}: Mitsuba 3 cannot load it (tried {variant}), not compared: {mitsuba}", flush=True)
            return None
        whose = args.ref or REF_BY_SCENE.get(name, "mitsuba")
        integ = args.integrator or INTEGRATOR_BY_SCENE.get(name)
        if integ is not None and 'name="integrator"' not in scene_path.read_text():
            sys.exit(f"{name} has no integrator parameter: leave out --integrator")
        ours_by = f"scotopia {integ or 'path'}"
        print(f"\n{name}: reference: {whose}, {args.ref_spp} spp …", flush=True)
        if whose == "mitsuba":
            ref, ref_secs = mitsuba(args.ref_spp, seed=12345)
        else:
            ref, ref_secs, _ = scotopia_render(scene_path, params, spp=args.ref_spp, seed=12345, integrator=integ)
            check, _ = mitsuba(args.ref_spp, seed=12345)
            away = ~near_lamps(ref, check)
            print(
                f"mean Y away from the lamps' pixels, Mitsuba {args.ref_spp} spp / reference: "
                f"{check[away].mean() / ref[away].mean():.4f} ({away.mean():.0%} of the pixels)",
                flush=True,
            )
        theirs, t_m = mitsuba(args.spp)
        ours, t_s, _ = scotopia_render(scene_path, params, spp=args.spp, integrator=integ)
        ours_eq, t_eq, spp_eq = scotopia_render(scene_path, params, seconds=t_m, integrator=integ)
        # More equal-time pairs, other seeds: a few fireflies can decide one
        # pair's relMSE, so its mean over seeds is the steadier figure.
        pairs = [(rel_mse(theirs, ref), rel_mse(ours_eq, ref))]
        for seed in range(1, args.seeds):
            img_m, secs = mitsuba(args.spp, seed=seed)
            img_s, _, _ = scotopia_render(scene_path, params, seconds=secs, seed=1 + seed, integrator=integ)
            pairs.append((rel_mse(img_m, ref), rel_mse(img_s, ref)))

    if args.save:
        out = Path(args.save)
        out.mkdir(parents=True, exist_ok=True)
        stem = Path(name).stem
        for tag, img in (("reference", ref), ("mitsuba", theirs), ("scotopia-equal-time", ours_eq)):
            np.save(out / f"{stem}-{tag}.npy", img.astype(np.float32))

    rate = lambda spp, secs: pixels * spp / secs * 1e-6  # noqa: E731
    title = "Cornell box" if name == "cornell-box.xml" else name
    print(
        f"\n{title}{' with the terrain' if args.mesh else ''} {size}; "
        f"reference: {whose}, {args.ref_spp} spp ({ref_secs:.0f} s)\n"
    )
    print(
        "| renderer | spp | seconds | M camera samples/s | rel. RMSE of Y | relMSE of Y | mean Y / reference |"
    )
    print("|---|---:|---:|---:|---:|---:|---:|")
    rows = [
        (f"Mitsuba 3 {variant}", args.spp, t_m, theirs),
        (f"{ours_by} (equal spp)", args.spp, t_s, ours),
        (f"{ours_by} (equal time)", spp_eq, t_eq, ours_eq),
    ]
    for label, spp, secs, img in rows:
        print(
            f"| {label} | {spp} | {secs:.2f} | {rate(spp, secs):.2f} | "
            f"{rel_rmse(img, ref):.4f} | {rel_mse(img, ref):.4g} | {img.mean() / ref.mean():.4f} |"
        )
    rmse_ratio = rel_rmse(ours_eq, ref) / rel_rmse(theirs, ref)
    mse_ratio = rel_mse(ours_eq, ref) / rel_mse(theirs, ref)
    print(f"\nspeed ratio scotopia / Mitsuba at equal spp: {t_m / t_s:.2f}")
    print(f"equal-time RMSE ratio scotopia / Mitsuba: {rmse_ratio:.2f}")
    print(f"equal-time relMSE of Y ratio scotopia / Mitsuba: {mse_ratio:.2f}")
    print(
        f"pixels holding 90 % of the relMSE (of {pixels:,}): Mitsuba {pixels_holding(theirs, ref):,}, "
        f"scotopia at equal time {pixels_holding(ours_eq, ref):,}",
        flush=True,
    )
    m_mse, s_mse = (float(np.mean(v)) for v in zip(*pairs))
    if len(pairs) > 1:
        m_all, s_all = (np.array(v) for v in zip(*pairs))
        print(
            f"over {len(pairs)} seeds at equal time, relMSE of Y mean (min–max): Mitsuba {m_mse:.4g} "
            f"({m_all.min():.4g}–{m_all.max():.4g}), scotopia {s_mse:.4g} ({s_all.min():.4g}–{s_all.max():.4g}); "
            f"ratio of the means {s_mse / m_mse:.2f}, per-seed ratios {np.min(s_all / m_all):.2f}–{np.max(s_all / m_all):.2f}",
            flush=True,
        )
    return (name, size, variant, whose, ours_by, args.spp, t_m, spp_eq, m_mse, s_mse, s_mse / m_mse, len(pairs))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scene", default="cornell-box.xml", help="a file in scenes/ (default cornell-box.xml)")
    parser.add_argument("--all", action="store_true", help="the four scenes: " + ", ".join(ALL))
    parser.add_argument("--spp", type=int, default=64)
    parser.add_argument("--ref-spp", type=int, default=1024)
    parser.add_argument("--res", type=int, default=256, help="width in pixels (the Cornell box is square)")
    parser.add_argument("--depth", type=int, help="max depth (default: 16 for the Cornell box, else the scene's)")
    parser.add_argument("--variant", help="Mitsuba variant (default: the best that runs)")
    parser.add_argument(
        "--ref", choices=["mitsuba", "scotopia"],
        help="whose render is the reference (default: scotopia's for the streets, else Mitsuba's)",
    )
    parser.add_argument(
        "--integrator", choices=["path", "bdpt"],
        help="scotopia's integrator, for scenes with an `integrator` parameter (default: bdpt for "
        + ", ".join(INTEGRATOR_BY_SCENE) + ", else the scene's)",
    )
    parser.add_argument("--mesh", action="store_true", help="a 1M-triangle terrain for the Cornell box's floor")
    parser.add_argument("--seeds", type=int, default=1, help="equal-time pairs per scene, each its own seed (1)")
    parser.add_argument("--save", metavar="DIR", help="write each scene's Y images (reference, Mitsuba, scotopia at equal time) as .npy")
    args = parser.parse_args()
    names = ALL if args.all else [Path(args.scene).name]
    if args.mesh and names != ["cornell-box.xml"]:
        sys.exit("--mesh is for the Cornell box alone")

    summary, skipped = [], []
    for name in names:
        row = compare(name, args)
        (summary if row else skipped).append(row or name)
    if len(names) > 1:
        print(
            "\nEqual time (scotopia given Mitsuba's seconds), relMSE of Y against the reference "
            "(mean over the seeds; spp and seconds of the first):\n"
        )
        print(
            "| scene | size | Mitsuba variant | reference | scotopia | Mitsuba spp | seconds | scotopia spp "
            "| relMSE Mitsuba | relMSE scotopia | scotopia / Mitsuba | seeds |"
        )
        print("|---|---|---|---|---|---:|---:|---:|---:|---:|---:|---:|")
        for name, size, variant, whose, ours_by, spp, secs, spp_eq, m, s, r, n in summary:
            print(
                f"| {name} | {size} | {variant} | {whose} | {ours_by} | {spp} | {secs:.2f} | {spp_eq} "
                f"| {m:.4g} | {s:.4g} | {r:.3g} | {n} |"
            )
        for name in skipped:
            print(f"| {name} | | Mitsuba cannot load it (above) | | | | | | | | | |")


if __name__ == "__main__":
    main()
