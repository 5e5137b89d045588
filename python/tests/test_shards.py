"""Shards of a render (``render_shard``, the core of distributed rendering,
issue 27) merged by ``merge_shards`` against one process rendering all
of it: bit for bit when shards split rows of a box-filtered film, within
float64 summation order when they split sample ranges, carry bdpt's
splats, or split rows under a filter that reaches across them."""
from pathlib import Path

import numpy as np
import pytest

import scotopia

ROOT = Path(__file__).resolve().parents[2]
CORNELL = str(ROOT / "scenes/cornell-box.xml")
PRISM = str(ROOT / "scenes/prism.xml")


def shards(path, cuts_rows, cuts_samples, **kw):
    return [scotopia.render_shard(path, samples=s, rows=r, **kw)
            for r in cuts_rows for s in cuts_samples]


def test_row_shards_are_the_whole_render_bit_for_bit():
    whole, meta = scotopia.render(CORNELL, spp=8, res=16, seed=5)
    parts = shards(CORNELL, [(0, 5), (5, 11), (11, 16)], [(0, 8)], res=16, seed=5)
    image, merged = scotopia.merge_shards(parts)
    assert np.array_equal(image, whole)
    assert merged["samplesPerPixel"] == 8
    assert merged["fovHorizontalDegrees"] == meta["fovHorizontalDegrees"]


def test_row_shards_keep_what_the_filter_spills_across_their_edges():
    # The prism's Gaussian filter (σ = 0.5) reaches two rows: a shard's
    # samples add to the two rows on either side of it too.
    whole, _ = scotopia.render(PRISM, spp=8, res=24, integrator="path", seed=3)
    parts = shards(PRISM, [(0, 5), (5, 9), (9, 15)], [(0, 8)], res=24, integrator="path", seed=3)
    assert parts[1]["weights"][3:5].sum() > 0 and parts[1]["weights"][9:11].sum() > 0
    assert parts[1]["weights"][:3].sum() == 0 and parts[1]["weights"][11:].sum() == 0
    assert parts[1]["counts"][:5].sum() == 0 and parts[1]["counts"][5:9].min() == 8
    image, _ = scotopia.merge_shards(parts)
    np.testing.assert_allclose(image, whole, rtol=1e-6, atol=1e-30)
    assert image[..., 1].max() > 0


@pytest.mark.parametrize("integrator", ["path", "bdpt"])
def test_sample_shards_agree_within_summation_order(integrator):
    whole, _ = scotopia.render(PRISM, spp=12, res=24, integrator=integrator)
    parts = shards(PRISM, [None], [(0, 3), (3, 7), (7, 12)], res=24, integrator=integrator)
    image, meta = scotopia.merge_shards(parts)
    assert meta["samplesPerPixel"] == 12
    # Same samples, float64 sums added in another order (bdpt: its splats
    # too), then rounded to float32.
    np.testing.assert_allclose(image, whole, rtol=1e-6, atol=1e-30)
    assert image[..., 1].max() > 0


def test_squares_are_the_second_moments():
    one = scotopia.render_shard(CORNELL, samples=(3, 4), res=8)
    # One sample per pixel: its square is the square of the sum (the
    # samples are float32, squared in float64).
    np.testing.assert_array_equal(one["squares"], one["sums"] ** 2)
    two = scotopia.render_shard(CORNELL, samples=(0, 16), res=8)
    mean = two["sums"] / 16
    variance = two["squares"] / 16 - mean ** 2
    assert (variance >= -1e-9 * mean ** 2).all() and variance[..., 1].max() > 0
    assert two["counts"].min() == 16


def test_bad_shards_are_value_errors():
    with pytest.raises(ValueError, match="i0 < i1"):
        scotopia.render_shard(CORNELL, samples=(4, 4), res=8)
    with pytest.raises(ValueError, match="rows"):
        scotopia.render_shard(CORNELL, samples=(0, 1), rows=(2, 99), res=8)
    with pytest.raises(ValueError, match="no shards"):
        scotopia.merge_shards([])


def test_a_merged_image_is_written_as_render_writes_it(tmp_path):
    image, meta = scotopia.merge_shards(
        shards(CORNELL, [(0, 8)], [(0, 2), (2, 4)], res=8))
    out = tmp_path / "merged.exr"
    scotopia.write_exr(out, image, meta)
    back, fov, _ = scotopia.vision.read_image(str(out), None, "srgb")
    assert np.array_equal(back, image)
    assert fov == pytest.approx(meta["fovHorizontalDegrees"])
