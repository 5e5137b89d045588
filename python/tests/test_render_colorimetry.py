"""A diffuse plane of a measured reflectance (ColorChecker "dark skin",
Ohta) under a uniform sky of CIE D65 seen head-on: every pixel's X, Y, Z
must be 683 ∫ ρ L {x̄, ȳ, z̄} dλ, computed here with colour-science's data
(ΔE2000 < 0.2 against the white of L)."""

import warnings

import numpy as np

import scotopia

with warnings.catch_warnings():
    warnings.simplefilter("ignore")
    import colour

SCENE = """<scene version="3.0.0">
  <integrator type="path"><integer name="max_depth" value="2"/></integrator>
  <sensor type="perspective">
    <float name="fov" value="20"/>
    <transform name="to_world"><lookat origin="0, 0, 5" target="0, 0, 0" up="0, 1, 0"/></transform>
    <film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/></film>
  </sensor>
  <emitter type="constant"><spectrum name="radiance" value="{sky}"/></emitter>
  <shape type="rectangle">
    <transform name="to_world"><scale value="10"/></transform>
    <bsdf type="diffuse"><spectrum name="reflectance" value="{rho}"/></bsdf>
  </shape>
</scene>"""


def pairs(sd, scale=1.0):
    return ", ".join(f"{w:g}:{v * scale:.6g}" for w, v in zip(sd.wavelengths, sd.values))


def test_plane_under_d65_matches_colour_science(tmp_path):
    rho = colour.SDS_COLOURCHECKERS["ColorChecker N Ohta"]["dark skin"]
    d65 = colour.SDS_ILLUMINANTS["D65"].copy().trim(colour.SpectralShape(360, 830, 1))
    scene = tmp_path / "plane.xml"
    scene.write_text(SCENE.format(sky=pairs(d65, 0.01), rho=pairs(rho)))
    image, _ = scotopia.render(str(scene), spp=64)
    ours = image[..., :3].reshape(-1, 3).astype(np.float64).mean(axis=0)

    # The oracle: ρ and L linear between their samples, zero outside, on 1 nm.
    wl = np.arange(360.0, 831.0)
    cmfs = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"].copy().align(
        colour.SpectralShape(360, 830, 1)
    )
    inside = lambda sd: np.where(  # noqa: E731
        (wl >= sd.wavelengths[0]) & (wl <= sd.wavelengths[-1]),
        np.interp(wl, sd.wavelengths, sd.values),
        0.0,
    )
    radiance = inside(rho) * inside(d65) * 0.01
    white = inside(d65) * 0.01
    trapezoid = getattr(np, "trapezoid", None) or np.trapz
    xyz = lambda s: 683.0 * trapezoid(s[:, None] * cmfs.values, wl, axis=0)  # noqa: E731
    want, reference = xyz(radiance), xyz(white)
    lab = lambda v: colour.XYZ_to_Lab(v / reference[1], colour.XYZ_to_xy(reference))  # noqa: E731
    delta = colour.delta_E(lab(ours), lab(want), method="CIE 2000")
    assert delta < 0.2, (ours, want, delta)
