"""scotopia: a spectral renderer that shows what a human eye would see.

The colour-science core: spectra (``Spectrum``), the CIE observers
(``cmfs``, ``vprime``), absolute photometry (``Spectrum.xyzv``,
``colorimetry``), colour spaces and differences, RGB → spectrum upsampling
(``Spectrum.from_rgb``) and its accuracy (``round_trip``).

``spectrum(...)`` is the Python form of the ``scotopia spectrum`` command,
``scene_info(path)`` of ``scotopia info``, ``render(path, ...)`` of
``scotopia render`` (an H × W × 4 array of X, Y, Z, V′ and a metadata dict).
"""

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
    lab_to_xyz,
    oklab_to_oklch,
    oklab_to_xyz,
    oklch_to_oklab,
    planck,
    render,
    rgb_to_xyz,
    rgb_to_xyz_matrix,
    round_trip,
    scene_info,
    vprime,
    white_point,
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


__all__ = [name for name in dir() if not name.startswith("_")]
