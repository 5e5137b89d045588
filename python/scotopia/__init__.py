"""scotopia: a spectral renderer that shows what a human eye would see.

The colour-science core: spectra (``Spectrum``), the CIE observers
(``cmfs``, ``vprime``), absolute photometry (``Spectrum.xyzv``,
``colorimetry``), colour spaces and differences, RGB → spectrum upsampling
(``Spectrum.from_rgb``) and its accuracy (``round_trip``).

``spectrum(...)`` is the Python form of the ``scotopia spectrum`` command,
``scene_info(path)`` of ``scotopia info``, ``render(path, ...)`` of
``scotopia render`` (an H × W × 4 array of X, Y, Z, V′ and a metadata dict),
``display(image_or_path, ...)`` of ``scotopia display``,
``false_colour(image_or_path, quantity, ...)`` of ``scotopia display
--false-colour``, ``measure(path, points, ...)`` of ``scotopia measure``
(illuminance at points, in lx);
``scotopia.vision``
holds each stage of the vision pipeline as a function on arrays;
``scotopia.bsdf`` evaluates and samples one BSDF given as Mitsuba XML.
"""

import os
import warnings

from . import bsdf, vision  # noqa: F401
from ._scotopia import display as _display
from ._scotopia import false_colour as _false_colour
from ._scotopia import view as _view
from ._scotopia import (  # noqa: F401
    K_M,
    K_M_SCOTOPIC,
    LAMBDA_MAX,
    LAMBDA_MIN,
    Spectrum,
    cct_from_xy,
    chromatic_adaptation,
    cmfs,
    colorimetry,
    delta_e_2000,
    glare_ratings as glare,
    lab_to_xyz,
    measure,
    oklab_to_oklch,
    oklab_to_xyz,
    oklch_to_oklab,
    planck,
    render,
    render_shard,
    road,
    rgb_to_xyz,
    rgb_to_xyz_matrix,
    round_trip,
    scene_info,
    vprime,
    white_point,
    write_exr,
    xyz_to_lab,
    xyz_to_oklab,
    xyz_to_rgb,
    xyy_to_xyz,
    xyz_to_xyy,
)


def spectrum(
    *,
    illuminant=None,
    blackbody=None,
    daylight=None,
    file=None,
    rgb=None,
    space="srgb",
    method="jakob2019",
    kind="reflectance",
    plot=None,
):
    """The colorimetry of one spectrum, as ``scotopia spectrum --json`` prints it.

    Give exactly one of ``illuminant`` (a CIE name), ``blackbody`` (K),
    ``daylight`` (K), ``file`` (a spectrum file) or ``rgb`` (a linear RGB
    triple, with ``space``, ``method`` and ``kind``). ``plot`` names a PNG to
    draw the spectrum to. Returns a dict with ``xyz`` (cd/m²), ``xy``,
    ``vprime`` (scotopic cd/m²), ``sp_ratio``, ``cct``, ``duv``,
    ``wavelengths`` and ``values``.
    """
    given = {
        "illuminant": illuminant,
        "blackbody": blackbody,
        "daylight": daylight,
        "file": file,
        "rgb": rgb,
    }
    chosen = [k for k, v in given.items() if v is not None]
    if len(chosen) != 1:
        raise ValueError(
            "give exactly one of illuminant, blackbody, daylight, file, rgb; got "
            + (", ".join(chosen) or "none")
        )
    if illuminant is not None:
        s = Spectrum.illuminant(illuminant)
    elif blackbody is not None:
        s = Spectrum.blackbody(blackbody)
    elif daylight is not None:
        s = Spectrum.daylight(daylight)
    elif file is not None:
        s = Spectrum.from_file(str(file))
    else:
        s = Spectrum.from_rgb(tuple(rgb), space=space, method=method, kind=kind)
    return colorimetry(s, plot=None if plot is None else str(plot))




def display(
    image,
    *,
    fov=None,
    display_peak=None,
    adaptation="global",
    glare=True,
    night_shift=True,
    tonemap="multiscale",
    gamut=None,
    hdr=False,
    bits=8,
    output=None,
    compare=None,
    units=None,
    input_space="srgb",
    age=25.0,
    pigmentation=0.5,
):
    """What a person would see: the ``scotopia display`` pipeline.

    ``image`` is an H × W × 4 array of X, Y, Z (cd/m²), V′ (scotopic cd/m²)
    or the path of an OpenEXR (X, Y, Z[, V], or R, G, B with ``units``).
    ``fov`` is the horizontal field of view in degrees (a file's metadata
    when not given). ``adaptation`` is "global", "local" or a luminance in
    cd/m². Returns (linear RGB H × W × 3 in [0, 1] of ``gamut``, report
    dict with the adaptation luminance, s, m, mode and stage timings).
    Non-finite pixels and pixels above 1e10 cd/m² are left out of the
    image statistics (shown black and at peak white) with a warning, as are
    pixels of negative luminance (shown black: not an absolute image).
    ``output`` writes a .png or .exr, ``compare`` a sheet of the stages.
    ``age`` (years, 1 to 100; default 25) and ``pigmentation`` (CIE
    146:2002's factor: 0 very dark eyes, 0.5 brown, the default, 1 light
    blue) describe the observer: the glare veil (CIE 146's glare spread
    function) and the lens's density (Pokorny et al. 1987) follow them
    (``--age`` and ``--pigmentation``). A value out of range raises
    ValueError naming the argument.
    """
    import numpy as np

    if isinstance(image, (str, os.PathLike)):
        image, file_fov, notes = vision.read_image(image, units, input_space)
        for note in notes:
            warnings.warn(note, stacklevel=2)
        if fov is None:
            fov = file_fov
    if fov is None:
        raise ValueError("fov (horizontal field of view, degrees) is needed for an array")
    rgb, report = _display(
        np.ascontiguousarray(image, dtype=np.float32),
        float(fov),
        display_peak,
        str(adaptation),
        glare,
        night_shift,
        tonemap,
        gamut,
        hdr,
        bits,
        None if output is None else str(output),
        None if compare is None else str(compare),
        age,
        pigmentation,
    )
    if report.get("left_out"):
        warnings.warn(report["left_out"], stacklevel=2)
    if report.get("negative"):
        warnings.warn(report["negative"], stacklevel=2)
    return rgb, report


def false_colour(image, quantity="luminance", *, range=None, log=False, output=None):
    """A false-colour map with a labelled scale bar: ``scotopia display
    --false-colour``.

    ``image`` is an H × W × 4 array of X, Y, Z, V′ or the path of an
    OpenEXR. ``quantity``: "luminance" (cd/m²), "mesopic" (CIE 191 mesopic
    luminance per pixel, cd/m²), "illuminance" (lx, of an image rendered
    with ``quantity="illuminance"`` or ``"melanopic-edi"``) or
    "melanopic-edi" (the fourth channel of an image rendered with
    ``quantity="melanopic-edi"``: CIE S 026's melanopic EDI, lx). ``range`` is (lo, hi); by default 0
    to the 99th percentile, or with ``log`` the three decades below it.
    Returns the picture, scale bar included, as an uint8 array
    (H + bar) × W × 3; ``output`` also writes it as a PNG.
    """
    import numpy as np

    if isinstance(image, (str, os.PathLike)):
        image, _, notes = vision.read_image(image, None, "srgb")
        for note in notes:
            warnings.warn(note, stacklevel=2)
    return _false_colour(
        np.ascontiguousarray(image, dtype=np.float32),
        quantity,
        None if range is None else (float(range[0]), float(range[1])),
        log,
        None if output is None else str(output),
    )


def view(path, *, port=None, open_browser=True, output=None, define=None, **options):
    """See it while it renders: ``scotopia view`` from Python.

    ``path`` is a scene (Mitsuba 3 XML), rendered progressively, or an
    X, Y, Z, V′ OpenEXR. The page (127.0.0.1, ``port``: default 8650 or
    the next free one; 0 for any) shows it as the eye sees it, with the
    vision pipeline's controls. ``options`` are the CLI's flags with ``_``
    for ``-``: render options (``spp=256``, ``time=60``, ``res="640"``,
    ``integrator="bdpt"``, …) and the page's starting display settings
    (``scale=0.02``, ``adaptation="local"``, ``glare=False``, ``age=70``,
    ``pigmentation=1``, …);
    ``define`` a dict of scene parameters (``-D``). Returns a ``Viewer``:
    ``.url``, ``.status()`` (the page's ``/status`` as a dict), ``.wait()``
    (until the render ends; the page stays up) and ``.stop()`` (ends the
    render, writing its film to ``output`` as Ctrl-C does, and the page).
    """
    argv = [str(path)]
    for name, value in (define or {}).items():
        argv += ["-D", f"{name}={value}"]
    if output is not None:
        argv += ["-o", str(output)]
    if port is not None:
        argv += ["--port", str(int(port))]
    if not open_browser:
        argv.append("--no-open")
    for name, value in options.items():
        flag = "--" + name.replace("_", "-")
        if value is None:
            continue
        if flag in ("--glare", "--night-shift"):
            value = value if isinstance(value, str) else ("on" if value else "off")
        if value is True:
            argv.append(flag)
        elif value is False:
            continue
        else:
            argv.append(f"{flag}={value}")
    return _view(argv)


def merge_shards(shards):
    """Adds up shards made by ``render_shard`` into ``(image, meta)`` as
    ``render`` returns them: image[y, x] = the summed X, Y, Z, V′ over the
    summed filter weights (0 where none). With the box filter, shards that
    split rows (each pixel's samples in one shard) give the single-process
    image bit for bit with the path tracer; shards that split sample
    ranges, carry bdpt's light-tracing splats, or split rows under a filter
    that reaches across rows (a sample adds to the rows round its own) add
    the same float64 sums in another order (equal within about 1e-12
    relative, documented as 1e-6). The meta is the first shard's, with the
    samples per pixel and the counters of all of them. Also returned in
    meta: "squares", the summed weighted second moments (H × W × 4): a
    pixel's weighted sample variance is squares / weights − image²."""
    import numpy as np

    shards = list(shards)
    if not shards:
        raise ValueError("merge_shards: no shards")
    first = shards[0]
    shape = (first["height"], first["width"])
    sums = np.zeros(shape + (4,), dtype=np.float64)
    squares = np.zeros(shape + (4,), dtype=np.float64)
    weights = np.zeros(shape, dtype=np.float64)
    counts = np.zeros(shape, dtype=np.uint64)
    for s in shards:
        if (s["height"], s["width"]) != shape:
            raise ValueError(
                f"merge_shards: a {s['width']}×{s['height']} shard among {shape[1]}×{shape[0]} ones")
        sums += s["sums"]
        squares += s["squares"]
        weights += s["weights"]
        counts += s["counts"]
    with np.errstate(invalid="ignore", divide="ignore"):
        image = np.where(weights[..., None] > 0, sums / weights[..., None], 0.0).astype(np.float32)
    meta = dict(first["meta"])
    # Every pixel of a whole render has the same count; a partial merge
    # reports the fewest.
    meta["samplesPerPixel"] = int(counts.min())
    meta["renderSeconds"] = float(sum(s["seconds"] for s in shards))
    meta["raysTraced"] = str(sum(s["rays"] for s in shards))
    meta["nonfiniteSamples"] = sum(s["dropped"] for s in shards)
    meta["nonfiniteSplats"] = sum(s["dropped_splats"] for s in shards)
    kept = int(counts.sum())
    meta["collapsedFraction"] = sum(s["collapsed"] for s in shards) / kept if kept else 0.0
    meta["squares"] = squares
    return image, meta


__all__ = [
    name
    for name in dir()
    if not name.startswith("_") and name not in ("os", "warnings")
]

