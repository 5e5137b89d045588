"""Conformance with Mitsuba 3 on Mitsuba's own scenes (issue 21).

Usage:
  python bench/mitsuba_conformance.py DATA_DIR [--spp 64] [--res 64]
      [--only GLOB] [--json OUT] [--cap 60] [--keep-xml DIR] [-D NAME=VALUE ...]
      [--mitsuba-cache DIR [--warm-cache]]
  python bench/mitsuba_conformance.py --table --json OUT _   (reprint a run)

DATA_DIR is a checkout of Mitsuba's data repository (mitsuba-data). Every
scene XML under it is tried: files under `include/` or `fragments/` folders
and files whose root element is not `<scene>` are fragments and skipped.

For each scene:

1. Loading. scotopia: `scotopia.scene_info(path, res=W)` (loads / the first
   line of the error / the number of warnings). Mitsuba 3 (`mitsuba`,
   variant `scalar_spectral`): `mi.load_file(path)`. Both get the -D
   parameters (none by default: the scenes are loaded as they are).
   Whether Mitsuba loads is asked of the file as it is; what it renders
   is a rewritten copy (below).
2. Rendering, for scenes that both load: both at the same film size (width
   W, the scene's aspect kept as scotopia's `res` keeps it, any crop
   window scaled with it) and the same samples per pixel, each as two
   independent halves (seeds 1 and 2, spp/2 each) whose average is the
   image. Mitsuba renders with its film in XYZ; its values are
   Y = ∫Lȳ dλ / ∫ȳ dλ, scotopia's are absolute, 683 ∫Lȳ dλ, so Mitsuba's
   XYZ is multiplied by 683 × 106.857 (as python/tests/test_mitsuba.py).
3. Comparison of the image means: the ratio of mean Y (scotopia / Mitsuba)
   must lie within 1 % of 1, and the CIE xy chromaticities of the mean XYZ
   within 0.002 of each other.

Monte Carlo standard errors. The two halves A, B of each render give the
variance of the averaged image: E[((A − B)/2)²] = Var((A + B)/2). The
differences are summed over 4 × 4 pixel blocks before squaring, so that
the correlation between neighbouring pixels that a reconstruction filter
wider than a pixel brings is counted; the squared block sums, added over
the image, give the covariance of the mean XYZ with hundreds of degrees
of freedom. The ratio's and Δxy's standard errors follow by the delta
method from both renderers' covariances (noise correlated over more than
4 × 4 pixels, e.g. from light tracing, would be underestimated). Verdicts:
  pass   both within tolerance, and the tolerance more than 3 SE wide;
  pass?  within tolerance, but the tolerance is within 3 SE (too noisy
         to be sure);
  fail   outside tolerance by more than 3 SE;
  fail?  outside tolerance, but within 3 SE of it (could be noise).

How Mitsuba's resolution and spp are overridden. Scenes set their film
size and spp in many ways (`$res`/`$spp` parameters, literals, films
inside included fragments), so the scene is rewritten: its `<include>`s
are inlined recursively (each resolved against the including file's
folder, then the scene's folder, then the scene's `<path>` folders, as
Mitsuba does), `<path value="…"/>` entries for the scene's folder and for
every included file's folder are put first in the root so that relative
file names (meshes, textures) resolve from the temporary copy as they do
from the original, and every `<film>` becomes an `hdrfilm` with
`pixel_format` "xyz", `component_format` "float32", the new width and
height (and crop window, scaled as scotopia scales it), every `<sampler>`
gets `sample_count` = spp. The copy is written to a temporary folder
outside DATA_DIR (kept with --keep-xml). If the rewrite itself fails (an
include not found) or the copy does not load, the scene is not rendered
and the table says why. The integrator is left as the scene gives it: a scene with
`direct` is rendered by Mitsuba with direct lighting, whatever scotopia
makes of it.

Isolation and time. Every load and render runs in a child process with a
time limit, so a crash or a hang in either renderer costs one scene only:
scotopia loads; if it does, Mitsuba loads and renders; then scotopia
renders. Each renderer first renders pilots of 2 and 6 spp, whose time
difference gives the time per spp; when the full spp
would take more than --cap seconds it renders with the (even) spp that
fits, Mitsuba first and scotopia at most at Mitsuba's spp (the table shows
"ours/theirs" if they still differ: the means stay comparable, only the
standard errors grow). A scene where fewer than 4 spp fit is skipped.
"""

import argparse
import fnmatch
import hashlib
import json
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np

# ∫ ȳ dλ of the CIE 1931 2° observer, nm (Mitsuba's normaliser of Y).
CIE_Y_INTEGRAL = 106.857
MITSUBA_SCALE = 683.0 * CIE_Y_INTEGRAL
Y_TOL = 0.01
XY_TOL = 0.002
BLOCK = 4
SEEDS = (1, 2)
PILOT_SPP = 2
MIN_SPP = 4
LOAD_TIMEOUT = 180


# ---------------------------------------------------------------- discovery


def is_fragment(path, root):
    parts = path.relative_to(root).parts[:-1]
    return any(p in ("include", "includes", "fragments") for p in parts)


def root_tag(path):
    try:
        for _, elem in ET.iterparse(path, events=("start",)):
            return elem.tag
    except ET.ParseError:
        text = path.read_text(errors="replace")
        return "scene" if re.search(r"<scene[\s>]", text) else None
    return None


def find_scenes(data, only):
    scenes = []
    for p in sorted(data.rglob("*.xml")):
        rel = p.relative_to(data).as_posix()
        if only and not any(fnmatch.fnmatch(rel, g) for g in only):
            continue
        if is_fragment(p, data) or root_tag(p) != "scene":
            continue
        scenes.append(p)
    return scenes


# ------------------------------------------------- Mitsuba's rewritten copy


def substitute(text, params):
    """`$name` replaced by its value, longest names first (Mitsuba's rule)."""
    for name in sorted(params, key=len, reverse=True):
        text = text.replace("$" + name, params[name])
    return text


def resolve(name, folders):
    p = Path(name)
    if p.is_absolute():
        return p if p.exists() else None
    for f in folders:
        if (f / p).exists():
            return (f / p).resolve()
    return None


def inline_includes(elem, here, scene_dir, paths, seen_dirs, depth=0):
    """Replaces every `<include filename>` below `elem` by the included
    file's elements (its root's children when the root is a scene)."""
    if depth > 16:
        raise RuntimeError("includes nested deeper than 16")
    i = 0
    while i < len(elem):
        child = elem[i]
        if child.tag == "path" and child.get("value"):
            # Relative to the file that holds it: made absolute for the copy.
            v = Path(child.get("value"))
            if not v.is_absolute() and (here / v).exists():
                v = (here / v).resolve()
                child.set("value", str(v))
            paths.append(v)
        if child.tag == "include":
            name = child.get("filename", "")
            target = resolve(name, [here, scene_dir, *paths])
            if target is None:
                raise RuntimeError(f"include '{name}' not found")
            seen_dirs.append(target.parent)
            inc = ET.parse(target).getroot()
            inline_includes(inc, target.parent, scene_dir, paths, seen_dirs, depth + 1)
            parts = list(inc) if inc.tag == "scene" else [inc]
            elem.remove(child)
            for k, part in enumerate(parts):
                elem.insert(i + k, part)
            i += len(parts)
            continue
        inline_includes(child, here, scene_dir, paths, seen_dirs, depth)
        i += 1


def set_prop(parent, tag, name, value):
    for c in list(parent):
        if c.get("name") == name:
            parent.remove(c)
    ET.SubElement(parent, tag, {"name": name, "value": str(value)})


def prop(parent, name, params, default=None):
    for c in parent:
        if c.get("name") == name and c.get("value") is not None:
            return substitute(c.get("value"), params)
    return default


def film_size(width, height, res):
    """scotopia's `res` rule: the width given, the height keeping the aspect
    (rounded half away from zero), at least 1."""
    return res, max(1, math.floor(res * height / width + 0.5))


def rewrite_for_mitsuba(scene, res, spp, out, given=None):
    """Writes the rewritten copy of `scene` (see the module docstring) to
    `out`; returns notes: the integrator type and the film size set."""
    root = ET.parse(scene).getroot()
    dirs = []
    inline_includes(root, scene.parent, scene.parent, [], dirs)
    params = {d.get("name"): d.get("value", "") for d in root.iter("default")}
    params.update(given or {})
    integrators = [substitute(e.get("type", "?"), params) for e in root.iter("integrator")]
    sizes = []
    for sensor in root.iter("sensor"):
        films = sensor.findall("film")
        if not films:
            films = [ET.SubElement(sensor, "film", {"type": "hdrfilm"})]
        for film in films:
            w = int(float(prop(film, "width", params, 768)))
            h = int(float(prop(film, "height", params, 576)))
            nw, nh = film_size(w, h, res)
            crop = {k: prop(film, k, params) for k in
                    ("crop_offset_x", "crop_offset_y", "crop_width", "crop_height")}
            film.set("type", "hdrfilm")
            for c in list(film):
                n = c.get("name") or ""
                if n in ("width", "height", "pixel_format", "component_format") \
                        or n.startswith("crop_"):
                    film.remove(c)
            set_prop(film, "integer", "width", nw)
            set_prop(film, "integer", "height", nh)
            set_prop(film, "string", "pixel_format", "xyz")
            set_prop(film, "string", "component_format", "float32")
            if any(v is not None for v in crop.values()):
                ox = int(float(crop["crop_offset_x"] or 0))
                oy = int(float(crop["crop_offset_y"] or 0))
                cw = int(float(crop["crop_width"] or (w - ox)))
                ch = int(float(crop["crop_height"] or (h - oy)))
                set_prop(film, "integer", "crop_offset_x", ox * nw // w)
                set_prop(film, "integer", "crop_offset_y", oy * nh // h)
                set_prop(film, "integer", "crop_width", max(1, cw * nw // w))
                set_prop(film, "integer", "crop_height", max(1, ch * nh // h))
            sizes.append((nw, nh))
        for sampler in sensor.findall("sampler"):
            set_prop(sampler, "integer", "sample_count", spp)
    # Resource folders first: the scene's, then every included file's.
    folders = []
    for d in [scene.parent, *dirs]:
        if d.resolve() not in folders:
            folders.append(d.resolve())
    for k, d in enumerate(folders):
        root.insert(k, ET.Element("path", {"value": str(d)}))
    ET.ElementTree(root).write(out, encoding="utf-8", xml_declaration=True)
    return {"integrator": ",".join(integrators) or "(default)", "film": sizes}


# ------------------------------------------------------------------ workers


def first_line(e):
    lines = [ln.strip() for ln in str(e).splitlines() if ln.strip()]
    return lines[0] if lines else type(e).__name__


LOCATION = re.compile(r"^\S+:\d+:\d+: ")
MITSUBA_PREFIX = re.compile(r"^\[[\w.]+:\d+\] (.*?\(line \d+, col \d+\): )?")


def scotopia_errors(text):
    """The error lines of scotopia's report (without its "N errors:" header
    and the warnings), each without its file:line:col."""
    out = []
    for ln in text.splitlines():
        ln = ln.strip()
        if not ln or ln.startswith("warning:") or re.fullmatch(r"\d+ errors?:?", ln):
            continue
        out.append(LOCATION.sub("", ln))
    return out or [first_line(text)]


def mitsuba_error(text):
    return MITSUBA_PREFIX.sub("", first_line(text))


def causes(r, who):
    """The distinct causes of one renderer's load failure."""
    if r.get("loads"):
        return []
    if "full_error" not in r:
        return [r.get("error", "?")]
    if who == "scotopia":
        return list(dict.fromkeys(scotopia_errors(r["full_error"])))
    return [mitsuba_error(r["full_error"])]


def worker(args):
    """One renderer's job for one scene, in a child process; writes its
    result as JSON (and the two half images as .npy) under args.out."""
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    res = {}
    cache = None  # Mitsuba's render cache entry (--mitsuba-cache)

    def save():
        (out / "result.json").write_text(json.dumps(res))

    scene = Path(args.scene)
    params = dict(d.split("=", 1) for d in args.define)
    if args.renderer == "scotopia":
        import scotopia

        if args.task == "load":
            try:
                info = scotopia.scene_info(str(scene), params=params, res=args.res)
                res.update(loads=True, warnings=list(info["warnings"]),
                           film=[info["film"]["width"], info["film"]["height"]])
            except Exception as e:  # noqa: BLE001 — any failure is a result
                res.update(loads=False, error=first_line(e), full_error=str(e))
            save()
            return

        def run(spp, seed):
            img, _ = scotopia.render(str(scene), spp=spp, res=args.res, seed=seed,
                                     params=params)
            return np.asarray(img, dtype=np.float64)[..., :3]
    else:
        import mitsuba as mi

        mi.set_variant("scalar_spectral")
        mi.set_log_level(mi.LogLevel.Error)
        # Whether it loads: the file as it is. What renders: the rewrite.
        try:
            mi.load_file(str(scene), **params)
            res.update(loads=True)
        except Exception as e:  # noqa: BLE001
            res.update(loads=False, error=first_line(e), full_error=str(e))
        save()
        if not res["loads"] or args.task == "load":
            return
        copy = out / "mitsuba.xml"
        try:
            res["notes"] = rewrite_for_mitsuba(scene, args.res, args.spp, copy, params)
            loaded = mi.load_file(str(copy), **params)
        except Exception as e:  # noqa: BLE001
            res["error"] = "rewritten copy: " + first_line(str(e).replace(str(copy), scene.name))
            save()
            return

        # Mitsuba's renders depend only on the rewritten scene and the
        # settings: --mitsuba-cache keeps them between runs.
        if args.mitsuba_cache:
            key = hashlib.sha256("\n".join(
                [copy.read_text(), mi.__version__, str(args.spp), str(args.cap),
                 json.dumps(params, sort_keys=True)]).encode()).hexdigest()[:24]
            cache = Path(args.mitsuba_cache) / key
            if (cache / "result.json").exists():
                for f in cache.iterdir():
                    shutil.copy(f, out / f.name)
                return

        def run(spp, seed):
            img = mi.render(loaded, spp=spp, seed=seed)
            return np.asarray(img, dtype=np.float64)[..., :3] * MITSUBA_SCALE

    # Two pilots time it (their difference leaves out what a render costs
    # whatever its spp: scotopia loads the scene in each); the spp is
    # lowered to fit the cap.
    times = []
    for k in (1, 3):
        t0 = time.monotonic()
        run(PILOT_SPP * k, 7 + k)
        times.append(time.monotonic() - t0)
    per_spp = (times[1] - times[0]) / (2 * PILOT_SPP)
    if per_spp <= 0:
        per_spp = times[1] / (3 * PILOT_SPP)
    spp = args.spp
    if per_spp * spp > args.cap:
        spp = int(args.cap / per_spp) // 2 * 2
    res.update(pilot_s_per_spp=per_spp, spp=spp)
    save()
    if spp < MIN_SPP:
        return
    t0 = time.monotonic()
    halves = [run(spp // 2, s) for s in SEEDS]
    res["render_s"] = time.monotonic() - t0
    for k, h in enumerate(halves):
        np.save(out / f"half{k}.npy", h)
    res["rendered"] = True
    save()
    if cache is not None:
        cache.mkdir(parents=True, exist_ok=True)
        for f in ("result.json", "half0.npy", "half1.npy"):
            shutil.copy(out / f, cache / f)


def spawn(renderer, task, scene, opts, out, timeout, spp=None):
    out.mkdir(parents=True, exist_ok=True)
    cmd = [sys.executable, __file__, "--worker", renderer, "--task", task,
           "--scene", str(scene), "--out", str(out), "--res", str(opts.res),
           "--spp", str(spp or opts.spp), "--cap", str(opts.cap), str(scene.parent)]
    for d in opts.define:
        cmd += ["-D", d]
    if opts.mitsuba_cache:
        cmd += ["--mitsuba-cache", str(opts.mitsuba_cache.resolve())]
    try:
        proc = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return {"loads": None, "error": f"timed out after {timeout} s", "timeout": True}
    f = out / "result.json"
    res = json.loads(f.read_text()) if f.exists() else {}
    if proc.returncode != 0:
        tail = [ln for ln in proc.stderr.splitlines() if ln.strip()][-1:] or [""]
        res.setdefault("error", f"worker exit {proc.returncode}: {tail[0][:200]}")
        res.setdefault("loads", None)
        res["crashed"] = True
    return res


# --------------------------------------------------------------- statistics


def mean_and_cov(a, b):
    """Mean XYZ of (a + b)/2 and its covariance from the block sums of
    (a − b)/2 (see the module docstring)."""
    m = 0.5 * (a + b)
    d = 0.5 * (a - b)
    h, w, _ = d.shape
    rows = np.add.reduceat(d, np.arange(0, h, BLOCK), axis=0)
    blocks = np.add.reduceat(rows, np.arange(0, w, BLOCK), axis=1).reshape(-1, 3)
    n = h * w
    return m.reshape(-1, 3).mean(axis=0), blocks.T @ blocks / (n * n)


def xy_and_jacobian(v):
    s = v.sum()
    xy = v[:2] / s
    jac = np.array([[s - v[0], -v[0], -v[0]], [-v[1], s - v[1], -v[1]]]) / (s * s)
    return xy, jac


def compare(ours, theirs):
    """Y ratio, Δxy and their standard errors, and the verdict."""
    (mo, co), (mt, ct) = mean_and_cov(*ours), mean_and_cov(*theirs)
    out = {"scotopia_xyz": mo.tolist(), "mitsuba_xyz": mt.tolist()}
    if not (np.all(np.isfinite(mo)) and np.all(np.isfinite(mt))):
        out["verdict"] = "non-finite"
        return out
    if mo[1] <= 0 and mt[1] <= 0:
        out["verdict"] = "both black"
        return out
    if mt[1] <= 0 or mo.sum() <= 0:
        out["verdict"] = "fail"
        out["ratio"] = float("inf") if mt[1] <= 0 else 0.0
        return out
    r = mo[1] / mt[1]
    se_r = r * math.sqrt(co[1, 1] / mo[1] ** 2 + ct[1, 1] / mt[1] ** 2)
    (xo, jo), (xt, jt) = xy_and_jacobian(mo), xy_and_jacobian(mt)
    cxy = jo @ co @ jo.T + jt @ ct @ jt.T
    diff = xo - xt
    dxy = float(np.hypot(*diff))
    u = diff / dxy if dxy > 0 else np.array([1.0, 1.0]) / math.sqrt(2)
    se_xy = math.sqrt(max(float(u @ cxy @ u), 0.0))
    dy = abs(r - 1)
    ok = dy <= Y_TOL and dxy <= XY_TOL
    if ok:
        sure = dy + 3 * se_r <= Y_TOL and dxy + 3 * se_xy <= XY_TOL
        verdict = "pass" if sure else "pass?"
    else:
        sure = dy - 3 * se_r > Y_TOL or dxy - 3 * se_xy > XY_TOL
        verdict = "fail" if sure else "fail?"
    out.update(ratio=float(r), ratio_se=float(se_r), dxy=dxy, dxy_se=se_xy,
               scotopia_xy=xo.tolist(), mitsuba_xy=xt.tolist(), verdict=verdict)
    return out


# -------------------------------------------------------------------- main


def run_scene(scene, data, opts, work):
    name = scene.relative_to(data).as_posix()
    tmp = work / re.sub(r"[^A-Za-z0-9_.-]", "_", name)
    row = {"scene": name}
    print(f"[{time.strftime('%H:%M:%S')}] {name}", file=sys.stderr, flush=True)
    s = spawn("scotopia", "load", scene, opts, tmp / "scotopia", LOAD_TIMEOUT)
    row["scotopia"] = s
    both = bool(s.get("loads"))
    # Mitsuba: load, and when scotopia loads too, render (spp capped).
    limit = LOAD_TIMEOUT + 3 * opts.cap
    m = spawn("mitsuba", "render" if both else "load", scene, opts, tmp / "mitsuba",
              limit)
    row["mitsuba"] = m
    if not (both and m.get("loads")):
        return row
    row["integrator"] = m.get("notes", {}).get("integrator")
    if not m.get("rendered"):
        row["skipped"] = mitsuba_skip(m, opts)
        return row
    if opts.warm_cache:
        return row
    # scotopia at Mitsuba's spp (or fewer, if that is over the cap for it).
    ro = spawn("scotopia", "render", scene, opts, tmp / "scotopia-render", limit, m["spp"])
    if not ro.get("rendered"):
        row["skipped"] = mitsuba_skip(ro, opts).replace("Mitsuba", "scotopia")
        return row
    row["spp"] = ro["spp"] if ro["spp"] == m["spp"] else f"{ro['spp']}/{m['spp']}"
    row["render_s"] = {"scotopia": ro["render_s"], "mitsuba": m["render_s"]}
    ours = [np.load(tmp / "scotopia-render" / f"half{k}.npy") for k in range(2)]
    theirs = [np.load(tmp / "mitsuba" / f"half{k}.npy") for k in range(2)]
    if ours[0].shape != theirs[0].shape:
        row["skipped"] = f"image sizes differ: {ours[0].shape[:2]} vs {theirs[0].shape[:2]}"
        return row
    row["size"] = list(ours[0].shape[:2][::-1])
    row.update(compare(ours, theirs))
    return row


def mitsuba_skip(r, opts):
    if "pilot_s_per_spp" in r and r.get("spp", 0) < MIN_SPP:
        return f"too slow for Mitsuba: {opts.spp} spp ≈ {r['pilot_s_per_spp'] * opts.spp:.0f} s"
    return f"Mitsuba render failed: {r.get('error') or '?'}"


def cell(text, n=70):
    text = str(text).replace("|", "\\|").replace("\n", " ")
    return text if len(text) <= n else text[: n - 1] + "…"


def load_cell(r, who):
    if r.get("loads"):
        return f"yes ({len(r.get('warnings', []))} w)" if who == "scotopia" else "yes"
    return cell("; ".join(causes(r, who)), 110)


def table(rows):
    lines = ["| scene | scotopia loads | Mitsuba loads | integrator | spp | Y ratio ± SE "
             "| Δxy ± SE | verdict |", "|---|---|---|---|---|---|---|---|"]
    for r in rows:
        ratio = dxy = ""
        if "ratio_se" in r:
            ratio = f"{r['ratio']:.4f} ± {r['ratio_se']:.4f}"
            dxy = f"{r['dxy']:.4f} ± {r['dxy_se']:.4f}"
        verdict = r.get("verdict") or cell(r.get("skipped", "—"), 50)
        lines.append(f"| {r['scene']} | {load_cell(r['scotopia'], 'scotopia')} | "
                     f"{load_cell(r['mitsuba'], 'mitsuba')} | {r.get('integrator', '')} | "
                     f"{r.get('spp', '')} | {ratio} | {dxy} | {verdict} |")
    return "\n".join(lines)


def error_groups(rows, who):
    """Load-error causes of `who`, with the number of scenes each stops,
    most common first (a scene counts once per distinct cause)."""
    count = {}
    for r in rows:
        for c in causes(r[who], who):
            count[c] = count.get(c, 0) + 1
    lines = [f"| {who} load error | scenes |", "|---|---|"]
    for c, n in sorted(count.items(), key=lambda kv: (-kv[1], kv[0])):
        lines.append(f"| {cell(c, 160)} | {n} |")
    return "\n".join(lines), count


def totals(rows):
    t = {
        "found": len(rows),
        "scotopia_loads": sum(bool(r["scotopia"].get("loads")) for r in rows),
        "mitsuba_loads": sum(bool(r["mitsuba"].get("loads")) for r in rows),
        "both_load": sum(bool(r["scotopia"].get("loads") and r["mitsuba"].get("loads"))
                         for r in rows),
        "compared": sum("verdict" in r for r in rows),
    }
    for v in ("pass", "pass?", "fail", "fail?", "both black", "non-finite"):
        t[v] = sum(r.get("verdict") == v for r in rows)
    t["skipped"] = sum("skipped" in r for r in rows)
    return t


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("data", type=Path, help="Mitsuba's data repository")
    ap.add_argument("--spp", type=int, default=64)
    ap.add_argument("--res", type=int, default=64, help="film width; the aspect is kept")
    ap.add_argument("--only", action="append",
                    help="glob on the scene's path relative to DATA_DIR (repeatable)")
    ap.add_argument("--json", type=Path, help="write the rows and totals here")
    ap.add_argument("--cap", type=float, default=60.0,
                    help="seconds one renderer may spend on one scene's render")
    ap.add_argument("--keep-xml", type=Path, help="keep the rewritten scenes and renders here")
    ap.add_argument("-D", dest="define", action="append", default=[], metavar="NAME=VALUE",
                    help="a scene parameter for both renderers (repeatable)")
    ap.add_argument("--mitsuba-cache", type=Path,
                    help="keep Mitsuba's renders here and reuse them when the rewritten scene "
                         "and the settings are the same (outside DATA_DIR and the repo)")
    ap.add_argument("--warm-cache", action="store_true",
                    help="with --mitsuba-cache: only fill the cache (scotopia loads, does not render)")
    ap.add_argument("--table", action="store_true",
                    help="only print the tables of an earlier run's --json file (DATA_DIR unused)")
    # The child processes' options.
    ap.add_argument("--worker", choices=("scotopia", "mitsuba"), help=argparse.SUPPRESS)
    ap.add_argument("--task", choices=("load", "render"), help=argparse.SUPPRESS)
    ap.add_argument("--scene", help=argparse.SUPPRESS)
    ap.add_argument("--out", help=argparse.SUPPRESS)
    opts = ap.parse_args()
    if opts.worker:
        worker(argparse.Namespace(renderer=opts.worker, **vars(opts)))
        return
    if opts.table:
        saved = json.loads(opts.json.read_text())
        settings = saved.get("settings", {})
        opts.res, opts.spp = settings.get("res", opts.res), settings.get("spp", opts.spp)
        report(saved["rows"], opts)
        return
    if any("=" not in d for d in opts.define):
        sys.exit("-D takes NAME=VALUE")
    if opts.spp < MIN_SPP or opts.spp % 2:
        sys.exit(f"--spp must be even and at least {MIN_SPP}")
    data = opts.data.resolve()
    scenes = find_scenes(data, opts.only)
    if opts.keep_xml:
        opts.keep_xml.mkdir(parents=True, exist_ok=True)
        work, cleanup = opts.keep_xml.resolve(), None
    else:
        cleanup = tempfile.TemporaryDirectory(prefix="conformance-")
        work = Path(cleanup.name)
    rows = []
    for scene in scenes:
        rows.append(run_scene(scene, data, opts, work))
        if opts.json:  # written as it goes, so a long run can be read early
            opts.json.write_text(json.dumps({"rows": rows, "totals": totals(rows),
                                             "settings": {"res": opts.res, "spp": opts.spp,
                                                          "cap": opts.cap}}, indent=1))
    report(rows, opts)
    if opts.json:
        opts.json.write_text(json.dumps({"rows": rows, "totals": totals(rows),
                                         "settings": {"res": opts.res, "spp": opts.spp,
                                                      "cap": opts.cap}}, indent=1))
    if cleanup:
        cleanup.cleanup()


def report(rows, opts):
    t = totals(rows)
    print(table(rows))
    print()
    for who in ("scotopia", "mitsuba"):
        print(error_groups(rows, who)[0])
        print()
    print(f"**Totals** (W = {opts.res}, {opts.spp} spp; tolerances |Y ratio − 1| ≤ {Y_TOL}, "
          f"Δxy ≤ {XY_TOL}): " + ", ".join(f"{k}: {v}" for k, v in t.items()))


if __name__ == "__main__":
    os.environ.setdefault("PYTHONUNBUFFERED", "1")
    main()
