"""Agreement with Mitsuba 3 (an independent spectral renderer) on the
bundled Cornell box: mean Y within 1 % and chromaticity within 0.002.

Mitsuba's XYZ film reports Y = ∫ L ȳ dλ / ∫ ȳ dλ (∫ ȳ = 106.857 nm);
scotopia's is absolute, 683 ∫ L ȳ dλ, so Mitsuba's values are scaled by
683 × 106.857 before comparing."""

from pathlib import Path

import numpy as np
import pytest

import scotopia

mi = pytest.importorskip("mitsuba")

SCENE = Path(__file__).resolve().parents[2] / "scenes" / "cornell-box.xml"
CIE_Y_INTEGRAL = 106.857


def test_cornell_box_agrees_with_mitsuba(tmp_path):
    mi.set_variant("scalar_spectral")
    # The same scene with Mitsuba's film in XYZ.
    xml = SCENE.read_text().replace('value="rgb"', 'value="xyz"')
    copy = tmp_path / "cornell-xyz.xml"
    copy.write_text(xml)
    theirs = np.array(mi.render(mi.load_file(str(copy), spp=256, res=64)), dtype=np.float64)
    theirs = theirs.reshape(-1, 3).mean(axis=0) * 683.0 * CIE_Y_INTEGRAL

    ours, meta = scotopia.render(str(SCENE), spp=256, params={"res": "64"}, seed=1)
    ours = ours.reshape(-1, 4)[:, :3].astype(np.float64).mean(axis=0)

    assert abs(ours[1] / theirs[1] - 1.0) < 0.01, (ours, theirs)
    xy = lambda v: v[:2] / v.sum()  # noqa: E731
    np.testing.assert_allclose(xy(ours), xy(theirs), atol=2e-3)


METER_SCENE = """<scene version="3.0.0">
  <integrator type="path"><integer name="max_depth" value="6"/></integrator>
  <shape type="rectangle">
    <transform name="to_world"><scale value="3"/></transform>
    <bsdf type="diffuse"><float name="reflectance" value="0.5"/></bsdf>
  </shape>
  <shape type="rectangle">
    <transform name="to_world"><scale value="3"/><rotate y="1" angle="-90"/><translate x="1.5" z="1"/></transform>
    <bsdf type="diffuse"><float name="reflectance" value="0.8"/></bsdf>
  </shape>
  <shape type="rectangle">
    <transform name="to_world"><scale value="0.5"/><rotate x="1" angle="180"/><translate x="-0.5" z="2"/></transform>
    <emitter type="area"><spectrum name="radiance" value="10"/></emitter>
  </shape>
  <shape type="rectangle">
    <transform name="to_world"><scale value="0.2"/><rotate y="1" angle="60"/><translate x="0.6" z="0.4"/></transform>
    <sensor type="irradiancemeter">
      <film type="hdrfilm"><integer name="width" value="1"/><integer name="height" value="1"/>
        <string name="pixel_format" value="xyz"/><rfilter type="box"/></film>
      <sampler type="independent"><integer name="sample_count" value="16384"/></sampler>
    </sensor>
  </shape>
</scene>
"""


@pytest.mark.parametrize("max_depth", [2, 6])
def test_irradiancemeter_agrees_with_mitsuba(tmp_path, max_depth):
    # A meter tilted towards a lit wall, above a floor, under an area
    # light: E over its face, direct and interreflected, in lx. At depth 2
    # (direct light and one bounce: max_depth counts segments from the
    # meter) and 6. Both sides render several seeds; the tolerance is four
    # standard errors of the difference plus 0.5 %.
    mi.set_variant("scalar_spectral")
    path = tmp_path / "meter.xml"
    path.write_text(METER_SCENE.replace('value="6"', f'value="{max_depth}"'))
    scene = mi.load_file(str(path))
    theirs = np.array(
        [np.array(mi.render(scene, seed=s), dtype=np.float64).reshape(3)[1] for s in range(4)]
    ) * 683.0 * CIE_Y_INTEGRAL
    ours = np.array(
        [scotopia.render(str(path), seed=s)[0].reshape(4)[1] for s in range(4)], dtype=np.float64
    )
    se = np.sqrt(theirs.var(ddof=1) / 4 + ours.var(ddof=1) / 4)
    assert abs(ours.mean() - theirs.mean()) <= 4 * se + 5e-3 * theirs.mean(), (ours, theirs)
