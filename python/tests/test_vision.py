"""The vision pipeline from Python: each stage's contract, the whole
pipeline on the bundled night street at three light levels, and its files."""
import inspect
from pathlib import Path

import numpy as np
import OpenEXR
import pytest

import scotopia
from scotopia import vision

ROOT = Path(__file__).resolve().parents[2]
D65 = np.array([0.95047, 1.0, 1.08883])


def grey(y, w=48, h=32, sp=2.4645):
    img = np.zeros((h, w, 4), np.float32)
    img[..., :3] = D65 * y
    img[..., 3] = sp * y
    return img


def test_visual_state_follows_jensen_and_cie_191():
    s = [vision.visual_state(10.0**e)["s"] for e in np.linspace(-4, 2, 61)]
    assert all(b >= a for a, b in zip(s, s[1:]))
    assert vision.visual_state(0.005)["s"] == 0.0
    assert vision.visual_state(5.0)["s"] == 1.0
    assert vision.visual_state(0.001)["mode"] == "scotopic"
    assert vision.visual_state(100.0)["mode"] == "photopic"
    assert vision.visual_state(0.5)["mode"] == "mesopic"


def test_night_shift_endpoints():
    rng = np.random.default_rng(5)
    img = rng.uniform(0.1, 1.0, (8, 8, 4)).astype(np.float32)
    # s = 1: unchanged.
    assert np.allclose(vision.night_shift(img, 1.0), img[..., :3], rtol=1e-6)
    # s = 0: chromaticity (0.25, 0.25), Y = 0.4468 V′.
    out = vision.night_shift(img, 0.0).astype(np.float64)
    xy = out[..., :2] / out.sum(axis=-1, keepdims=True)
    assert np.allclose(xy, 0.25, atol=1e-6)
    assert np.allclose(out[..., 1], 0.4468 * img[..., 3], rtol=1e-5)


def test_gamut_mapping_keeps_hue_and_stays_in_range():
    # Colours well outside sRGB: Rec.2020 primaries and mixtures, at
    # several lightnesses (relative to the display's white).
    rng = np.random.default_rng(7)
    rgb2020 = rng.uniform(0.0, 1.0, (16, 16, 3)) ** 3
    xyz = scotopia.rgb_to_xyz(rgb2020, "rec2020")
    out = vision.gamut_map(xyz.astype(np.float32), "srgb").astype(np.float64)
    assert out.min() >= 0.0 and out.max() <= 1.0
    h_in = scotopia.oklab_to_oklch(scotopia.xyz_to_oklab(xyz))
    h_out = scotopia.oklab_to_oklch(scotopia.xyz_to_oklab(scotopia.rgb_to_xyz(out, "srgb")))
    # Hue is meaningless for near-greys and for colours mapped to black
    # or white; compare where both keep chroma.
    keep = (h_in[..., 1] > 0.02) & (h_out[..., 1] > 0.02)
    dh = np.abs((h_in[..., 2] - h_out[..., 2] + 180.0) % 360.0 - 180.0)
    assert keep.sum() > 100
    assert dh[keep].max() < 1.0, dh[keep].max()
    # In-gamut colours are unchanged.
    inside = scotopia.rgb_to_xyz(np.full((2, 2, 3), 0.4), "srgb").astype(np.float32)
    assert np.allclose(vision.gamut_map(inside, "srgb"), 0.4, atol=1e-5)


def test_glare_conserves_luminance():
    # ±64° at 0.5° a pixel holds nearly all of the 1/θ² bloom.
    img = grey(1e-3, 256, 256)
    img[128, 128] = [9.5e5, 1e6, 1.09e6, 2.4e6]
    out = vision.glare(img, 0.5, threshold=100.0, s=1.0)
    assert abs(out[..., 1].sum() / img[..., 1].sum() - 1.0) < 0.01


def test_multiscale_keeps_a_uniform_field_uniform():
    out = vision.multiscale(grey(3.0))
    assert np.ptp(out[..., 1]) < 1e-4 * out[..., 1].mean()


def test_multiscale_shows_daylight_below_its_ceiling():
    # A uniform daylight field: the brightness match alone puts it at the
    # display's peak; the ceiling keeps it under a quarter of the peak.
    plain = vision.multiscale(grey(3000.0), mean_ceiling=float("inf"))[..., 1].mean()
    limited = vision.multiscale(grey(3000.0))[..., 1].mean()
    assert plain > 90.0
    assert 20.0 < limited < 25.0
    assert vision.multiscale(grey(3000.0), mean_ceiling=0.1)[..., 1].mean() < 10.0
    with pytest.raises(ValueError, match="mean_ceiling"):
        vision.multiscale(grey(3.0), mean_ceiling=0.0)


@pytest.fixture(scope="module")
def street():
    img, meta = scotopia.render(str(ROOT / "scenes/night-street.xml"), spp=4, params={"width": "320", "height": "180"})
    return img, meta["fovHorizontalDegrees"]


def test_night_street_fades_as_light_falls(street):
    """The bundled night street at daylight, dusk and moonlight levels.

    Every light in the scene (sky, moon, lamps) scaled by one factor scales
    the rendered radiance by that factor exactly (light transport is
    linear), so the render is scaled instead of rendered three times.
    What must hold: colour fades from daylight to dusk and to moonlight
    (mean OkLCh chroma falls), moonlight is darker than both, and at
    moonlight the image is still readable — mean display luminance above
    2 % of peak and more than 45 % of the pixels above 1 % of peak.

    Not asserted: that dusk is darker on average than daylight. The model
    shows daylight's adaptation luminance at most at a quarter of the peak
    (the display's limit, docs/vision.md §3 step 6) while at dusk the rods'
    response adds to the cones' in the achromatic channel, so the dusk
    picture's mean display luminance is above daylight's: 0.43 against
    0.34 here since issue 37's local adaptation, and already 0.199 against
    0.187 before it on a 48-spp 640 × 360 render of this scene (this 4-spp
    fixture happened to order them). docs/vision.md records it as an open
    question of the model."""
    img, fov = street
    log_avg = vision.image_stats(img)["log_average"]
    rows = []
    for target in (200.0, 1.0, 0.005):
        rgb, report = scotopia.display(img * (target / log_avg), fov=fov)
        xyz = scotopia.rgb_to_xyz(rgb.astype(np.float64), "srgb")
        lch = scotopia.oklab_to_oklch(scotopia.xyz_to_oklab(xyz))
        rows.append((report["mode"], xyz[..., 1].mean(), lch[..., 1].mean(), (xyz[..., 1] > 0.01).mean()))
    modes = [r[0] for r in rows]
    assert modes == ["photopic", "mesopic", "scotopic"], rows
    (_, y_day, c_day, _), (_, y_dusk, c_dusk, _), (_, y_moon, c_moon, lit) = rows
    assert c_dusk < c_day and c_moon < c_day, rows
    assert y_moon < y_dusk and y_moon < y_day, rows
    assert y_moon > 0.02 and lit > 0.45, rows


def test_display_cli_files(street, tmp_path):
    img, fov = street
    exr = tmp_path / "street.exr"
    # An XYZ-only EXR (no V): V′ is estimated and said.
    header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}
    channels = {c: np.ascontiguousarray(img[..., i]) for i, c in enumerate("XYZ")}
    with OpenEXR.File(header, channels) as f:
        f.write(str(exr))
    with pytest.warns(UserWarning, match="estimated"):
        rgb, report = scotopia.display(exr, fov=fov, output=tmp_path / "o.png", compare=tmp_path / "c.png")
    assert rgb.shape == (180, 320, 3) and report["mode"] in ("mesopic", "scotopic", "photopic")
    assert (tmp_path / "o.png").stat().st_size > 1000 and (tmp_path / "c.png").exists()

    # HDR: a 16-bit PNG whose cICP chunk says Rec. 2020 primaries, PQ.
    scotopia.display(img, fov=fov, hdr=True, output=tmp_path / "hdr.png")
    data = (tmp_path / "hdr.png").read_bytes()
    assert data[24] == 16  # bit depth in IHDR
    at = data.index(b"cICP")
    assert data[at + 4 : at + 8] == bytes([9, 16, 0, 1])
    assert data.index(b"cICP") < data.index(b"IDAT")

    # A linear display EXR in [0, 1].
    scotopia.display(img, fov=fov, output=tmp_path / "lin.exr", gamut="p3")
    with OpenEXR.File(str(tmp_path / "lin.exr")) as f:
        ch = f.channels()
        r = ch["RGB"].pixels[..., 0] if "RGB" in ch else ch["R"].pixels
        assert "P3" in str(f.header()["colorSpace"]).upper()
    assert r.min() >= 0.0 and r.max() <= 1.0

    with pytest.raises(ValueError, match="fov"):
        scotopia.display(img)
    with pytest.raises(ValueError, match="tonemap"):
        scotopia.display(img, fov=fov, tonemap="filmic")


def test_any_array_layout_reads_the_same():
    # A strided view (every second column of a wider image) and its
    # contiguous copy give the same display.
    rng = np.random.default_rng(3)
    wide = rng.uniform(0.0, 50.0, (16, 48, 4)).astype(np.float32)
    view = wide[:, ::2]
    assert not view.flags["C_CONTIGUOUS"]
    a, _ = scotopia.display(view, fov=30.0)
    b, _ = scotopia.display(np.ascontiguousarray(view), fov=30.0)
    assert np.array_equal(a, b)


def test_the_observer_is_an_age_and_a_pigmentation():
    img = grey(0.01)
    img[16, 24] = [9.5e4, 1e5, 1.09e5, 2.4e5]
    # The defaults: CIE 146's young observer (25 years) with brown eyes.
    params = inspect.signature(scotopia.display).parameters
    assert (params["age"].default, params["pigmentation"].default) == (25.0, 0.5)
    plain, _ = scotopia.display(img, fov=30.0)
    given, _ = scotopia.display(img, fov=30.0, age=25, pigmentation=0.5)
    assert np.array_equal(plain, given)
    # Accepted: any adult, any pigmentation from 0 to 1.
    for age, pigmentation in [(70.0, 1.0), (20, 0), (1.0, 0.5), (100.0, 0.25)]:
        rgb, _ = scotopia.display(img, fov=30.0, age=age, pigmentation=pigmentation)
        assert rgb.shape == (32, 48, 3) and np.isfinite(rgb).all()
    # Refused, with a ValueError naming the argument.
    for kwargs, says in [
        (dict(age=-3), "age -3"),
        (dict(age=0.0), "age 0"),
        (dict(age=float("nan")), "age NaN"),
        (dict(age=1e300), "age"),
        (dict(pigmentation=1.5), "pigmentation 1.5"),
        (dict(pigmentation=-0.1), "pigmentation -0.1"),
        (dict(pigmentation=float("inf")), "pigmentation"),
    ]:
        with pytest.raises(ValueError, match=says):
            scotopia.display(img, fov=30.0, **kwargs)
    with pytest.raises(TypeError, match="age"):
        scotopia.display(img, fov=30.0, age="old")
