"""Non-finite and absurd pixels are left out of the vision pipeline's
statistics with a warning, and leave the other pixels as they were."""
import warnings

import numpy as np
import pytest

import scotopia

D65 = np.array([0.95047, 1.0, 1.08883])


def grey(y, w=48, h=32, sp=2.4645):
    img = np.zeros((h, w, 4), np.float32)
    img[..., :3] = D65 * y
    img[..., 3] = sp * y
    return img


def test_a_nan_block_and_an_absurd_pixel_warn_and_change_nothing_else():
    clean = grey(20.0)
    clean[16, 24] *= 1e4  # a lamp, so glare is on
    broken = clean.copy()
    broken[4:8, 4:8] = np.nan
    broken[20, 40] = 2e38
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        a, ra = scotopia.display(clean, fov=30.0)
    assert ra["left_out"] is None
    with pytest.warns(UserWarning, match="16 non-finite.*1 pixel"):
        b, rb = scotopia.display(broken, fov=30.0)
    # The absurd pixel counts in the adaptation at 1e10 cd/m², as it is
    # shown (issue 38): (1e10/20)^(1/1520) = 1.0133 at most; the lamp
    # weighs 1/1520 of the pixels instead of 1/1536: 7e-5 more.
    assert ra["log_average"] < rb["log_average"] < 1.0135 * ra["log_average"]
    keep = np.ones(clean.shape[:2], bool)
    keep[4:8, 4:8] = False
    keep[20, 40] = False
    assert np.abs(a[keep] - b[keep]).max() <= 0.5 / 255
    assert (b[4:8, 4:8] == 0).all() and (b[20, 40] == 1).all()
