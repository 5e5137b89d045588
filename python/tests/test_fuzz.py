"""Seeded fuzzing of every Python entry point (issue 22): each call gets a
few of its arguments replaced by wrong types and extreme values (None,
huge and negative integers, NaN, ±inf, subnormals, odd strings and paths,
bytes, lists, arrays of any shape and dtype, dicts, arbitrary objects).
Every call must return or raise an ``Exception``; a ``PanicException``
(a ``BaseException``: it escapes ``except Exception``) or a crash of the
interpreter fails the test.

Hypothesis draws the arguments, derandomised (the same cases on every
run). ``SCOTOPIA_FUZZ_CASES`` sets the calls per entry point (default 25,
well under a minute for all of them); ``make fuzz`` runs many more.
"""
import inspect
import math
import os
import tempfile
import warnings
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

import scotopia
from scotopia import bsdf, vision

ROOT = Path(__file__).resolve().parents[2]
CORNELL = str(ROOT / "scenes/cornell-box.xml")
LAMP = str(ROOT / "scenes/lamps/led-4000k.csv")
CASES = int(os.environ.get("SCOTOPIA_FUZZ_CASES", "25"))
DIFFUSE = '<bsdf type="diffuse"><rgb name="reflectance" value="0.5"/></bsdf>'

# Calls write relative paths (a fuzzed `output`) into a scratch folder.
SCRATCH = tempfile.mkdtemp(prefix="scotopia-fuzz-")
np.random.seed(0)
IMAGE = (np.random.rand(4, 5, 4) * 0.05).astype(np.float32)


def _fisheye():
    """IMAGE as a 180° angular fisheye EXR, for `glare`."""
    path = str(Path(SCRATCH) / "fisheye.exr")
    scotopia.write_exr(path, IMAGE, meta={"projection": "angular", "fovHorizontalDegrees": 180.0})
    return path
XYZ3 = IMAGE[..., :3].copy()
DIRS = np.array([[0.0, 0.0, 1.0], [0.6, 0.0, 0.8]])
LAMBDAS = np.array([[450.0, 500.0, 550.0, 600.0], [420.0, 480.0, 560.0, 640.0]])


def _numbers():
    return st.one_of(
        st.integers(min_value=-(2**70), max_value=2**70),
        st.sampled_from([0, -1, 2**31, 2**32, 2**63, 2**64, 10**30]),
        st.floats(allow_nan=True, allow_infinity=True),
        st.sampled_from([math.nan, math.inf, -math.inf, 1e308, 5e-324, -0.0, 1e-300, 3.5e38]),
    )


def _arrays():
    return hnp.arrays(
        dtype=st.sampled_from([np.float32, np.float64, np.int64, np.bool_, np.complex128]),
        shape=hnp.array_shapes(min_dims=0, max_dims=4, min_side=0, max_side=6),
    )


WEIRD = st.one_of(
    st.none(),
    st.booleans(),
    _numbers(),
    st.text(max_size=12),
    st.sampled_from(["", "\0", "srgb", "nan", "1e400", "-1", "x" * 300]),
    st.binary(max_size=8),
    st.lists(_numbers(), max_size=5),
    st.tuples(_numbers(), _numbers(), _numbers()),
    _arrays(),
    st.dictionaries(st.text(max_size=3), st.one_of(st.text(max_size=3), _numbers()), max_size=2),
    st.builds(object),
)
# Paths read: missing, a folder, a device that never ends, the wrong kind.
PATH_IN = st.one_of(
    WEIRD,
    st.sampled_from(["/dev/zero", "/", "missing.xml", ROOT / "scenes", LAMP, CORNELL, "\0x"]),
)
# Paths written stay relative (inside SCRATCH): never a device or /.
PATH_OUT = st.one_of(
    st.none(),
    _numbers(),
    st.text(alphabet="abc./_-", max_size=8),
    st.sampled_from(["", ".", "..", "x.png", "x.exr", "x.jpg", "no/such/dir/x.png"]),
)


def _spectrum():
    return scotopia.Spectrum.blackbody(3000.0)


def _bsdf():
    return bsdf.load(DIFFUSE)


# Each entry point: (function, positional arguments, keyword arguments,
# arguments that are paths read, paths written). Valid as given.
ENTRIES = {
    "render": (
        scotopia.render,
        [CORNELL],
        # `time` bounds every call (a huge fuzzed spp is not a hang); its
        # own extremes are in test_boundaries.
        dict(spp=1, seed=0, wavelengths="swc", cluster=4, params=None, spectral=None,
             bands=47, integrator=None, res=4, checkpoint=None, checkpoint_every=60.0,
             resume=False, output=None, tracer="scalar", quantity="radiance", radiance=None),
        {"path"},
        {"output", "spectral", "checkpoint", "radiance"},
    ),
    "scene_info": (scotopia.scene_info, [CORNELL], dict(params=None, res=None), {"path"}, set()),
    "render_shard": (
        scotopia.render_shard,
        [CORNELL],
        dict(samples=(0, 2), rows=None, seed=0, wavelengths="swc", cluster=4, params=None,
             integrator=None, res=4, tracer="scalar", quantity="radiance"),
        {"path"},
        set(),
    ),
    "merge_shards": (
        lambda *a: scotopia.merge_shards(*a),
        [lambda: [scotopia.render_shard(CORNELL, samples=(0, 1), res=4)]],
        {},
        set(),
        set(),
    ),
    "road": (
        scotopia.road,
        [CORNELL, (-0.5, 0.0, 0.5), (0.0, 0.0, -1.0), (1.0, 0.0, 0.0), 1.0],
        dict(lanes=1, lane_width=1.0, up=(0.0, 1.0, 0.0), age=23.0, direct=False, spp=2, seed=0,
             params=None),
        {"path"},
        set(),
    ),
    "glare": (
        scotopia.glare,
        [lambda: _fisheye()],
        dict(projection=None, fov=None, threshold=5.0, age=25.0, output=None),
        {"image"},
        {"output"},
    ),
    "write_exr": (
        scotopia.write_exr,
        [str(Path(SCRATCH) / "written.exr"), IMAGE],
        dict(meta={"fovHorizontalDegrees": 40.0, "samplesPerPixel": 4, "units": "cd/m2"}),
        set(),
        {"path"},
    ),
    # Started and stopped at once: the page's server and a short render.
    "view": (
        lambda *a, **k: scotopia.view(*a, **k).stop(),
        [CORNELL],
        dict(port=0, open_browser=False, output=str(Path(SCRATCH) / "view.exr"),
             define={"res": 4}, spp=1, time=0.3,
             scale=1.0, adaptation="global", age=25.0, pigmentation=0.5),
        {"path"},
        {"output"},
    ),
    "measure": (
        scotopia.measure,
        [CORNELL, np.array([[0.0, 0.01, 0.0, 0.0, 1.0, 0.0]])],
        dict(spp=4, seed=0, wavelengths="swc", cluster=4, params=None, reflectance=1.0,
             observer=(0.0, 0.5, 1.0), direct=False),
        {"path"},
        set(),
    ),
    "false_colour": (
        scotopia.false_colour,
        [IMAGE],
        dict(quantity="luminance", range=None, log=False, output=None),
        {"image"},
        {"output"},
    ),
    "display": (
        scotopia.display,
        [IMAGE],
        dict(fov=40.0, display_peak=None, adaptation="global", glare=True, night_shift=True,
             tonemap="multiscale", gamut=None, hdr=False, bits=8, output=None, compare=None,
             units=None, input_space="srgb", age=25.0, pigmentation=0.5),
        {"image"},
        {"output", "compare"},
    ),
    "spectrum": (scotopia.spectrum, [], dict(blackbody=3000.0, space="srgb", method="jakob2019",
                                             kind="reflectance", plot=None), {"file"}, {"plot"}),
    "colorimetry": (scotopia.colorimetry, [_spectrum], dict(plot=None), set(), {"plot"}),
    "round_trip": (scotopia.round_trip, [], dict(method="smits", space="srgb", n=4), set(), set()),
    "cmfs": (scotopia.cmfs, [np.array([450.0, 550.0])], {}, set(), set()),
    "vprime": (scotopia.vprime, [np.array([450.0, 550.0])], {}, set(), set()),
    "planck": (scotopia.planck, [np.array([450.0, 550.0]), 3000.0], {}, set(), set()),
    "rgb_to_xyz": (scotopia.rgb_to_xyz, [XYZ3], dict(space="srgb"), set(), set()),
    "xyz_to_rgb": (scotopia.xyz_to_rgb, [XYZ3], dict(space="srgb"), set(), set()),
    "rgb_to_xyz_matrix": (scotopia.rgb_to_xyz_matrix, [], dict(space="srgb"), set(), set()),
    "white_point": (scotopia.white_point, [], dict(space="srgb"), set(), set()),
    "chromatic_adaptation": (
        scotopia.chromatic_adaptation,
        [XYZ3, [0.95, 1.0, 1.09], [1.1, 1.0, 0.36]],
        dict(method="bradford"),
        set(),
        set(),
    ),
    "xyz_to_lab": (scotopia.xyz_to_lab, [XYZ3], {}, set(), set()),
    "lab_to_xyz": (scotopia.lab_to_xyz, [XYZ3], {}, set(), set()),
    "delta_e_2000": (scotopia.delta_e_2000, [XYZ3, XYZ3], {}, set(), set()),
    "xyz_to_xyy": (scotopia.xyz_to_xyy, [XYZ3], {}, set(), set()),
    "xyy_to_xyz": (scotopia.xyy_to_xyz, [XYZ3], {}, set(), set()),
    "xyz_to_oklab": (scotopia.xyz_to_oklab, [XYZ3], {}, set(), set()),
    "oklab_to_xyz": (scotopia.oklab_to_xyz, [XYZ3], {}, set(), set()),
    "oklab_to_oklch": (scotopia.oklab_to_oklch, [XYZ3], {}, set(), set()),
    "oklch_to_oklab": (scotopia.oklch_to_oklab, [XYZ3], {}, set(), set()),
    "cct_from_xy": (scotopia.cct_from_xy, [[0.3127, 0.329]], {}, set(), set()),
    "Spectrum.constant": (scotopia.Spectrum.constant, [0.5], {}, set(), set()),
    "Spectrum.tabulated": (
        scotopia.Spectrum.tabulated,
        [np.array([400.0, 700.0]), np.array([0.2, 0.8])],
        {},
        set(),
        set(),
    ),
    "Spectrum.blackbody": (scotopia.Spectrum.blackbody, [3000.0], {}, set(), set()),
    "Spectrum.daylight": (scotopia.Spectrum.daylight, [6500.0], {}, set(), set()),
    "Spectrum.illuminant": (scotopia.Spectrum.illuminant, ["D65"], {}, set(), set()),
    "Spectrum.from_file": (scotopia.Spectrum.from_file, [LAMP], {}, {"path"}, set()),
    "Spectrum.from_rgb": (
        scotopia.Spectrum.from_rgb,
        [(0.2, 0.5, 0.7)],
        dict(space="srgb", method="jakob2019", kind="reflectance"),
        set(),
        set(),
    ),
    "Spectrum.__call__": (lambda s, w: s(w), [_spectrum, np.array([500.0])], {}, set(), set()),
    "Spectrum.scaled": (lambda s, f: s.scaled(f), [_spectrum, 2.0], {}, set(), set()),
    "Spectrum.xyzv": (lambda s: s.xyzv(), [_spectrum], {}, set(), set()),
    "vision.image_stats": (vision.image_stats, [IMAGE], {}, set(), set()),
    "vision.visual_state": (vision.visual_state, [0.05], dict(sp_ratio=2.46), set(), set()),
    "vision.glare": (vision.glare, [IMAGE, 0.05, 1.0], dict(s=1.0), set(), set()),
    "vision.multiscale": (
        vision.multiscale,
        [IMAGE],
        dict(display_peak=100.0, display_adaptation=None, adaptation=None, degrees_per_pixel=0.04,
             mean_ceiling=0.25),
        set(),
        set(),
    ),
    "vision.night_shift": (vision.night_shift, [IMAGE, 0.5], {}, set(), set()),
    "vision.acuity_blur": (vision.acuity_blur, [IMAGE, 1.0], {}, set(), set()),
    "vision.gamut_map": (vision.gamut_map, [XYZ3], dict(gamut="srgb"), set(), set()),
    "vision.read_image": (vision.read_image, [None], dict(units=None, input_space="srgb"),
                          {"path"}, set()),
    "bsdf.load": (bsdf.load, [DIFFUSE], {}, set(), set()),
    "bsdf.eval": (bsdf.eval, [DIFFUSE, DIRS, DIRS, LAMBDAS], dict(importance=False, uv=None),
                  set(), set()),
    "bsdf.sample": (
        bsdf.sample,
        [DIFFUSE, DIRS, LAMBDAS, np.array([0.3, 0.7]), np.array([[0.1, 0.2], [0.6, 0.9]])],
        dict(importance=False, uv=None),
        set(),
        set(),
    ),
    "Bsdf.eval": (lambda b, *a: b.eval(*a), [_bsdf, DIRS, DIRS, LAMBDAS, False, None], {},
                  set(), set()),
    "Bsdf.sample": (
        lambda b, *a: b.sample(*a),
        [_bsdf, DIRS, LAMBDAS, np.array([0.3, 0.7]), np.array([[0.1, 0.2], [0.6, 0.9]]), False,
         None],
        {},
        set(),
        set(),
    ),
}

# Arguments named by position, for the path sets above.
POSITIONAL_NAMES = {"render": ["path"], "view": ["path"], "scene_info": ["path"],
                    "display": ["image"],
                    "false_colour": ["image"],
                    "measure": ["path", "points"], "road": ["path"],
                    "write_exr": ["path", "image"],
                    "Spectrum.from_file": ["path"], "vision.read_image": ["path"]}


def _render_image():
    """An EXR for read_image's valid call (rendered once)."""
    path = Path(SCRATCH) / "valid.exr"
    if not path.exists():
        scotopia.render(CORNELL, spp=1, res=4, output=str(path))
    return str(path)


def _guard(name, kwargs, args=()):
    """Leaves out legitimate but costly values (a big render is not bad
    input): the fuzz is about wrong values, not about waiting."""
    if name == "render":
        kwargs["time"] = 0.3
        res = kwargs.get("res")
        if isinstance(res, (int, float)) and not isinstance(res, bool) and 64 < res < 1e7:
            kwargs["res"] = 4
    if name == "render_shard":
        res = kwargs.get("res")
        if isinstance(res, (int, float)) and not isinstance(res, bool) and 64 < res < 1e7:
            kwargs["res"] = 4
        samples = kwargs.get("samples")
        if (isinstance(samples, tuple) and len(samples) == 2
                and all(isinstance(v, int) and not isinstance(v, bool) for v in samples)
                and samples[1] - samples[0] > 64):
            kwargs["samples"] = (samples[0], samples[0] + 4)
    if name == "view":
        # Never a real browser, and a bounded render (as for render).
        kwargs["open_browser"] = False
        kwargs["time"] = 0.3
    if name == "road":
        # Wide roads and many samples are legitimate, only slow.
        spp = kwargs.get("spp")
        if isinstance(spp, (int, float)) and not isinstance(spp, bool) and 16 < spp:
            kwargs["spp"] = 2
        lanes = kwargs.get("lanes")
        if isinstance(lanes, int) and not isinstance(lanes, bool) and 2 < lanes:
            kwargs["lanes"] = 1
        if (len(args) > 4 and isinstance(args[4], (int, float)) and not isinstance(args[4], bool)
                and 30 < args[4]):
            args[4] = 1.0
    if name == "measure":
        spp = kwargs.get("spp")
        if isinstance(spp, (int, float)) and not isinstance(spp, bool) and 256 < spp:
            kwargs["spp"] = 4
        # Many points are legitimate, only slow.
        if len(args) > 1 and isinstance(args[1], np.ndarray) and args[1].size > 600:
            args[1] = args[1].reshape(-1)[:6]
    if name == "round_trip":
        n = kwargs.get("n")
        if isinstance(n, (int, float)) and not isinstance(n, bool) and 16 < n <= 256:
            kwargs["n"] = 4


def test_every_entry_point_is_fuzzed():
    public = {n for n in scotopia.__all__ if callable(getattr(scotopia, n))
              and not inspect.isclass(getattr(scotopia, n))
              and not inspect.ismodule(getattr(scotopia, n))}
    for module in (vision, bsdf):
        short = module.__name__.split(".")[-1]
        public |= {f"{short}.{n}" for n in dir(module) if not n.startswith("_")
                   and callable(getattr(module, n)) and not inspect.isclass(getattr(module, n))}
    public |= {f"Spectrum.{n}" for n in dir(scotopia.Spectrum) if not n.startswith("_")}
    public |= {"Spectrum.__call__"}
    public |= {f"Bsdf.{n}" for n in ("eval", "sample")}
    assert "display" in scotopia.__all__ and "os" not in scotopia.__all__
    missing = public - set(ENTRIES)
    assert not missing, f"entry points the fuzz does not call: {sorted(missing)}"


def _valid_call(name):
    function, args, kwargs, _, _ = ENTRIES[name]
    args = [a() if callable(a) and not isinstance(a, np.ndarray) else a for a in args]
    if name == "vision.read_image":
        args = [_render_image()]
    return function, args, dict(kwargs)


@pytest.mark.parametrize("name", sorted(ENTRIES))
def test_the_unmutated_calls_work(name):
    # The fuzz starts from calls that succeed, or it tests nothing.
    function, args, kwargs = _valid_call(name)
    _guard(name, kwargs)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        function(*args, **kwargs)


@pytest.mark.parametrize("name", sorted(ENTRIES))
@settings(
    max_examples=CASES,
    derandomize=True,
    deadline=None,
    database=None,
    suppress_health_check=list(HealthCheck),
)
@given(data=st.data())
def test_wrong_arguments_are_python_exceptions(name, data):
    _, _, _, path_in, path_out = ENTRIES[name]
    function, args, kwargs = _valid_call(name)
    positional = POSITIONAL_NAMES.get(name, [])
    slots = [("arg", i) for i in range(len(args))] + [("kw", k) for k in kwargs]
    if name == "spectrum":
        slots += [("kw", k) for k in ("illuminant", "daylight", "file", "rgb")]
    if not slots:
        return
    chosen = data.draw(st.lists(st.sampled_from(slots), min_size=1, max_size=3, unique=True))
    for kind, key in chosen:
        arg_name = key if kind == "kw" else (positional[key] if key < len(positional) else "")
        strategy = PATH_IN if arg_name in path_in else PATH_OUT if arg_name in path_out else WEIRD
        value = data.draw(strategy, label=f"{name}:{arg_name or key}")
        if kind == "kw":
            kwargs[key] = value
        else:
            args[key] = value
    _guard(name, kwargs, args)
    cwd = os.getcwd()
    os.chdir(SCRATCH)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            function(*args, **kwargs)
    except Exception:
        pass  # a Python exception is the clean outcome for bad input
    finally:
        os.chdir(cwd)
