"""A copy of a scotopia scene that Mitsuba 3 reads too, for
`bench/vs_mitsuba.py`: both renderers then render the copy, so the
comparison is of the same physics.

What the copy changes (the bundled streets need each):

- `<include>` is replaced by the included file's contents, and every
  `filename` becomes absolute (the copy lives in a temporary folder).
- A spectrum with scotopia's `luminance` extension (docs/scene-format.md)
  becomes an inline spectrum of absolute values: the relative spectrum (a
  file's own points, or `d65` / `blackbody` tabulated at 1 nm) times
  luminance / (683 ∫ S ȳ dλ), the latter as scotopia computes it. A spectrum
  file without `luminance` becomes the file's own points. Mitsuba reads a
  file of comma-separated columns with a header as no spectrum at all.
- An `ies` emitter (a scotopia extension; Mitsuba has no goniometric light)
  becomes a `spot` in the same frame (both shine along local +z) of the
  same spectrum and the same luminous flux: full intensity to 55° off the
  axis, falling linearly in angle to 0 at 75° (Mitsuba's spot falloff).
  The streets' lamps then light the road more evenly than their IES files
  say, but the scene keeps its many lights of two spectra.
- An area emitter declared once with an `id` and referenced from several
  shapes is copied into each shape (Mitsuba attaches an area emitter to
  one shape).

Usage: python bench/mitsuba_port.py SCENE OUT  (writes OUT; vs_mitsuba.py
calls `port` itself)
"""

import copy
import math
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np

import scotopia

# The spot that stands in for a goniometric lamp: beam and cut-off, degrees.
SPOT_BEAM, SPOT_CUTOFF = 55.0, 75.0


def _defaults(root):
    return {d.get("name"): d.get("value") for d in root.iter("default")}


def _value(text, defaults):
    """A property's value with `$name` taken from the scene's defaults."""
    if text and text.startswith("$"):
        return defaults[text[1:]]
    return text


def _inline_includes(root, base):
    """Replaces each `<include filename>` by the included scene's children."""
    for parent in list(root.iter()):
        for i, child in enumerate(list(parent)):
            if child.tag != "include":
                continue
            included = ET.parse(base / child.get("filename")).getroot()
            _inline_includes(included, base)
            parent.remove(child)
            for j, grand in enumerate(list(included)):
                parent.insert(i + j, grand)


def _csv_points(path):
    """A spectrum file's (wavelengths, values): scotopia's CSV (comments
    after `#`, a header line, then `λ,value`) or Mitsuba's `.spd`
    (whitespace-separated)."""
    points = []
    for line in Path(path).read_text().splitlines():
        line = line.split("#", 1)[0].strip()
        if not line:
            continue
        parts = line.replace(",", " ").split()
        try:
            points.append((float(parts[0]), float(parts[1])))
        except ValueError:
            continue  # the header line
    lam, val = np.array(points).T
    return lam, val


def _relative(spec, base, defaults):
    """A spectrum element's relative (wavelengths, values, scotopia's Y of
    them as given), or None when it is neither a file, `d65` nor
    `blackbody`."""
    if spec.get("filename"):
        path = base / spec.get("filename")
        lam, val = _csv_points(path)
        return lam, val, scotopia.spectrum(file=str(path))["xyz"][1]
    kind = spec.get("type")
    if kind == "d65":
        got = scotopia.spectrum(illuminant="D65")
    elif kind == "blackbody":
        temp = next(f for f in spec if f.get("name") == "temperature")
        got = scotopia.spectrum(blackbody=float(_value(temp.get("value"), defaults)))
    else:
        return None
    return np.array(got["wavelengths"], float), np.array(got["values"], float), got["xyz"][1]


def _points(lam, val):
    return ", ".join(f"{a:g}:{b:.6g}" for a, b in zip(lam, val))


def _port_spectra(root, base, defaults):
    for parent in list(root.iter()):
        for i, spec in enumerate(list(parent)):
            if spec.tag != "spectrum":
                continue
            lum = [f for f in spec if f.tag == "float" and f.get("name") == "luminance"]
            if not lum and not spec.get("filename"):
                continue
            rel = _relative(spec, base, defaults)
            if rel is None:
                raise SystemExit(f"cannot port the spectrum {ET.tostring(spec, 'unicode')[:80]}")
            lam, val, y = rel
            if lum:
                val = val * float(_value(lum[0].get("value"), defaults)) / y
            new = ET.Element("spectrum", name=spec.get("name"), value=_points(lam, val))
            parent.remove(spec)
            parent.insert(i, new)


def spot_flux_per_candela(beam=SPOT_BEAM, cutoff=SPOT_CUTOFF):
    """Lumens of a Mitsuba spot of 1 cd on its axis: 2π ∫ falloff(θ) sin θ dθ,
    falloff 1 to `beam`, then linear in θ to 0 at `cutoff`."""
    theta = np.linspace(0.0, math.radians(cutoff), 20001)
    b, c = math.radians(beam), math.radians(cutoff)
    fall = np.where(theta <= b, 1.0, (c - theta) / (c - b))
    return 2.0 * math.pi * np.trapezoid(fall * np.sin(theta), theta)


def _ies_flux(path):
    """An IES file's lumens: [LAMP] line's `N lm`, else its lumens field."""
    text = Path(path).read_text()
    for line in text.splitlines():
        if line.startswith("[LAMP]") and " lm" in line:
            words = line.replace(",", " ").split()
            return float(words[words.index("lm") - 1])
    raise SystemExit(f"{path}: no flux in [LAMP]")


def _port_ies(root, base, defaults):
    for parent in list(root.iter()):
        for i, em in enumerate(list(parent)):
            if em.tag != "emitter" or em.get("type") != "ies":
                continue
            props = {p.get("name"): p for p in em}
            flux = _ies_flux(base / _value(props["filename"].get("value"), defaults))
            scale = float(_value(props["scale"].get("value"), defaults)) if "scale" in props else 1.0
            candela = flux * scale / spot_flux_per_candela()
            spot = ET.Element("emitter", type="spot")
            if "spectrum" in props:
                spec = copy.deepcopy(props["spectrum"])
                spec.set("name", "intensity")
                ET.SubElement(spec, "float", name="luminance", value=f"{candela:.6g}")
            else:
                spec = ET.Element("spectrum", name="intensity", type="d65")
                ET.SubElement(spec, "float", name="luminance", value=f"{candela:.6g}")
            spot.append(spec)
            ET.SubElement(spot, "float", name="beam_width", value=f"{SPOT_BEAM:g}")
            ET.SubElement(spot, "float", name="cutoff_angle", value=f"{SPOT_CUTOFF:g}")
            if "to_world" in props:
                spot.append(props["to_world"])
            parent.remove(em)
            parent.insert(i, spot)


def _inline_emitter_refs(root):
    named = {e.get("id"): e for e in root.iter("emitter") if e.get("id")}
    if not named:
        return
    for shape in root.iter("shape"):
        for i, ref in enumerate(list(shape)):
            if ref.tag == "ref" and ref.get("id") in named:
                em = copy.deepcopy(named[ref.get("id")])
                del em.attrib["id"]
                shape.remove(ref)
                shape.insert(i, em)
    for parent in list(root.iter()):
        for em in list(parent):
            if em.tag == "emitter" and em.get("id") in named:
                parent.remove(em)


def _absolute_files(root, base):
    for s in root.iter("string"):
        if s.get("name") == "filename" and not s.get("value", "").startswith("$"):
            s.set("value", str((base / s.get("value")).resolve()))


def port(scene, out):
    """Writes `out`, a copy of `scene` that Mitsuba 3 and scotopia read
    alike (the module's docstring says what changes); returns `out`."""
    scene, out = Path(scene), Path(out)
    base = scene.resolve().parent
    root = ET.parse(scene).getroot()
    _inline_includes(root, base)
    defaults = _defaults(root)
    _port_ies(root, base, defaults)
    _port_spectra(root, base, defaults)
    _inline_emitter_refs(root)
    _absolute_files(root, base)
    ET.indent(root)
    out.write_text(ET.tostring(root, encoding="unicode"))
    return out


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__.strip().splitlines()[-2])
    print(port(sys.argv[1], sys.argv[2]))
