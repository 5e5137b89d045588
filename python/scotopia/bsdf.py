"""One BSDF, evaluated and sampled by scotopia's renderer code.

``Bsdf(xml)`` builds a Mitsuba 3 ``<bsdf>`` element (nested BSDFs and
textures included; or a ``<scene>`` of definitions whose last top-level
``<bsdf>`` is taken) with the scene loader. Directions are N × 3 arrays in
the local shading frame (z = the normal), both pointing away from the
surface; wavelengths are in nm, shape (N,) or (N, K). Mitsuba's
conventions: ``eval`` is f(wi, wo)·|cos θ_o|, ``sample``'s weight is
f·|cos θ_o| / pdf, and a delta lobe's density is reported as 1.
"""

import warnings as _warnings

import numpy as np

from ._scotopia import Bsdf

__all__ = ["Bsdf", "load", "eval", "sample"]


def _f64(a):
    return np.ascontiguousarray(a, dtype=np.float64)


def load(xml):
    """The BSDF of ``xml`` (a ``Bsdf`` passes through); loader warnings are
    issued as Python warnings."""
    if isinstance(xml, Bsdf):
        return xml
    b = Bsdf(str(xml))
    for w in b.warnings:
        _warnings.warn(w, stacklevel=3)
    return b


def eval(xml, wi, wo, wavelengths, *, importance=False, uv=None):  # noqa: A001
    """(f·|cos θ_o| as N × K, pdf as N) for each row of ``wi``, ``wo``.

    ``importance`` selects adjoint transport (light paths), which does not
    scale refracted values by 1/η². The pdf is that of ``sample`` producing
    ``wo`` by its non-delta lobes, for each row's first wavelength.
    """
    b = load(xml)
    return b.eval(
        _f64(wi),
        _f64(wo),
        _f64(wavelengths),
        importance,
        None if uv is None else _f64(uv),
    )


def sample(xml, wi, wavelengths, u_lobe, u, *, importance=False, uv=None):
    """(wo N × 3, weight N × K, pdf N, delta N) sampled with the random
    numbers ``u_lobe`` (N, picks the lobe) and ``u`` (N × 2, the direction),
    all in [0, 1]; at most 4 wavelengths per row (one cluster). A row with
    no sample has wo = 0, weight 0 and pdf 0."""
    b = load(xml)
    return b.sample(
        _f64(wi),
        _f64(wavelengths),
        _f64(u_lobe),
        _f64(u),
        importance,
        None if uv is None else _f64(uv),
    )
