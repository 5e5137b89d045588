"""Extreme and absurd numbers are Python exceptions naming the argument
and the limit, never a PanicException or a lost interpreter (issue 22)."""
import math
from pathlib import Path

import numpy as np
import pytest

import scotopia
from scotopia import vision

ROOT = Path(__file__).resolve().parents[2]
CORNELL = str(ROOT / "scenes/cornell-box.xml")


def image(h=8, w=8, y=0.01):
    return np.tile(np.array([0.95 * y, y, 1.09 * y, 2.4 * y], np.float32), (h, w, 1))


@pytest.mark.parametrize("time", [1e20, 1e30, math.inf, math.nan, -1.0, 0.0])
def test_render_time_out_of_range_is_a_value_error(time):
    with pytest.raises(ValueError, match="time"):
        scotopia.render(CORNELL, time=time, res=8)


def test_a_film_that_cannot_fit_is_an_error_naming_the_limit():
    # The scene's own width/height parameters make a 1e9 × 1e9 film.
    with pytest.raises((ValueError, MemoryError), match="limit is"):
        scotopia.render(CORNELL, spp=1, params={"res": "1000000000"})


@pytest.mark.parametrize("sigma", [math.inf, -math.inf, math.nan, -1.0, 1e300])
def test_acuity_blur_sigma_out_of_range_is_a_value_error(sigma):
    with pytest.raises(ValueError, match="sigma"):
        vision.acuity_blur(image(), sigma)


def test_acuity_blur_wider_than_the_image_is_quick_and_keeps_a_flat_image():
    out = vision.acuity_blur(image(64, 64, 1.0), 5e4)
    assert np.allclose(out, image(64, 64, 1.0), rtol=1e-3)


@pytest.mark.parametrize("n", [10**12, 2**64 - 1, 257, 1, 0])
def test_round_trip_grid_out_of_range_is_an_error(n):
    with pytest.raises((ValueError, OverflowError)):
        scotopia.round_trip("smits", "srgb", n)


@pytest.mark.parametrize("fov", [1e-10, 1e-20, 1e-30, 0.0, 360.0, math.nan, math.inf])
def test_display_fov_out_of_range_is_a_value_error(fov):
    with pytest.raises(ValueError, match="fov"):
        scotopia.display(image(), fov=fov)


@pytest.mark.parametrize(
    "call",
    [
        lambda: vision.glare(image(), math.inf, 1.0),
        lambda: vision.glare(image(), 0.01, 1.0, s=math.nan),
        lambda: vision.glare(image(), 0.01, math.nan),
        lambda: vision.night_shift(image(), math.inf),
        lambda: vision.multiscale(image(), display_peak=math.inf),
        lambda: vision.multiscale(image(), adaptation=-1.0),
        lambda: vision.multiscale(image(), display_adaptation=math.nan),
    ],
)
def test_vision_stages_reject_non_finite_parameters(call):
    with pytest.raises(ValueError):
        call()


@pytest.mark.parametrize("spp", [-1, 2**40])
def test_integer_arguments_out_of_their_type_are_overflow_errors(spp):
    with pytest.raises((OverflowError, ValueError)):
        scotopia.render(CORNELL, spp=spp, res=8)


def test_an_exr_declaring_a_huge_window_is_a_memory_error(tmp_path):
    path = tmp_path / "small.exr"
    img, _ = scotopia.render(CORNELL, spp=1, res=4, output=str(path))
    data = bytearray(path.read_bytes())
    key = b"dataWindow\0box2i\0"
    at = data.index(key) + len(key) + 4
    for k in (8, 12):
        data[at + k:at + k + 4] = (999_999_999).to_bytes(4, "little")
    forged = tmp_path / "forged.exr"
    forged.write_bytes(bytes(data))
    with pytest.raises(MemoryError, match="forged.exr.*limit is"):
        vision.read_image(forged)


# Issue 38: numbers checked in the precision they are used in (f32).
@pytest.mark.parametrize(
    "kwargs, names",
    [
        (dict(display_peak=1e-300), "display-peak"),
        (dict(display_peak=1e-40), "display-peak"),
        (dict(adaptation="1e39"), "adaptation"),
        (dict(adaptation="1e-300"), "adaptation"),
    ],
)
def test_display_numbers_that_are_0_or_infinite_in_f32_are_value_errors(kwargs, names):
    with pytest.raises(ValueError, match=names):
        scotopia.display(image(), fov=40.0, **kwargs)


@pytest.mark.parametrize("name", ["display_peak", "adaptation", "display_adaptation"])
def test_multiscale_luminances_that_are_0_in_f32_are_value_errors(name):
    with pytest.raises(ValueError, match=name):
        vision.multiscale(image(), **{name: 1e-300})


def test_a_negative_image_is_warned_about_not_shown_black_silently():
    neg = -image(y=5.0)
    with pytest.warns(UserWarning, match="64 pixel.*negative luminance"):
        scotopia.display(neg, fov=40.0)


def test_resume_without_a_checkpoint_is_a_value_error():
    with pytest.raises(ValueError, match="resume=True needs checkpoint"):
        scotopia.render(CORNELL, spp=1, params={"res": "4"}, resume=True)
