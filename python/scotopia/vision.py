"""The vision pipeline, stage by stage, on numpy arrays.

Images are H × W × 4 arrays of X, Y, Z (cd/m²) and V′ (scotopic cd/m²), as
``scotopia.render`` returns them; any float dtype is accepted. Each function
is one stage of ``scotopia display`` (docs/vision.md):

- ``visual_state(luminance, sp_ratio)`` and ``image_stats(image)``: stage 1;
- ``glare(image, degrees_per_pixel, threshold, s)``: stage 2;
- ``multiscale(image, ...)``: stage 3 (display X, Y, Z in cd/m²);
- ``night_shift(image, s)`` and ``acuity_blur(image, sigma)``: stage 4;
- ``gamut_map(xyz, gamut)``: stage 5;
- ``read_image(path, units, input_space)``: an EXR as X, Y, Z, V′.
"""

import numpy as np

from . import _scotopia as _s

visual_state = _s.visual_state


def _f32(image, channels=4):
    a = np.ascontiguousarray(image, dtype=np.float32)
    if a.ndim != 3 or a.shape[2] != channels:
        raise ValueError(f"expected an H × W × {channels} array, got shape {a.shape}")
    return a


def image_stats(image):
    """Log-average and maximum luminance (cd/m²) and S/P ratio of an image."""
    return _s.image_stats(_f32(image))


def glare(image, degrees_per_pixel, threshold=None, s=1.0, age=25.0, pigmentation=0.5):
    """Glare in absolute units: CIE 146:2002's glare spread function for an
    observer of ``age`` years and eye ``pigmentation`` (0 dark, 0.5 brown, 1
    light blue), with Spencer et al. 1995's halo at scotopic sensitivity
    ``s``, of the light above ``threshold`` cd/m² (``None``: all of it, the
    retinal image)."""
    return _s.glare(_f32(image), degrees_per_pixel, threshold, s, age, pigmentation)


def multiscale(image, display_peak=100.0, display_adaptation=None, adaptation=None,
               degrees_per_pixel=40.0 / 1024.0, mean_ceiling=0.25):
    """Pattanaik et al. 1998's model: display X, Y, Z in cd/m² (H × W × 3).

    ``mean_ceiling``: the image's adaptation luminance is shown below this
    fraction of ``display_peak`` (``math.inf``: the plain brightness match).
    """
    return _s.multiscale(_f32(image), display_peak, display_adaptation, adaptation,
                         degrees_per_pixel, mean_ceiling)


def night_shift(image, s):
    """Jensen et al. 2001's shift of X, Y, Z, V′ (V′ on Y's scale): H × W × 3."""
    return _s.night_shift(_f32(image), s)


def acuity_blur(image, sigma):
    """The scotopic acuity blur: a Gaussian of ``sigma`` pixels."""
    return _s.acuity_blur(_f32(image), sigma)


def gamut_map(xyz, gamut="srgb"):
    """Display-relative X, Y, Z (white Y = 1) to linear RGB in [0, 1]."""
    return _s.gamut_map(_f32(xyz, 3), gamut)


def read_image(path, units=None, input_space="srgb"):
    """An OpenEXR as (X, Y, Z, V′ array, horizontal fov or None, notes)."""
    return _s.read_image(str(path), units, input_space)
