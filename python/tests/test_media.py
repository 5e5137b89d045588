"""Participating media from Python: a lamp's illuminance through an
absorbing slab follows Beer–Lambert (`scotopia.measure`), and
`scene_info` reports a heterogeneous medium's grids."""

import math
import struct

import numpy as np
import pytest

import scotopia

LAMP = (
    '<emitter type="point"><point name="position" x="0" y="3" z="0"/>'
    '<spectrum name="intensity" value="400:10, 700:10"/></emitter>'
)
SLAB = (
    '<medium type="homogeneous" id="slab"><float name="sigma_t" value="0.7"/>'
    '<float name="albedo" value="0"/></medium>'
    '<shape type="cube"><bsdf type="null"/><ref name="interior" id="slab"/>'
    '<transform name="to_world"><scale x="50" y="0.5" z="50"/><translate y="1.5"/></transform></shape>'
)


def _scene(tmp_path, name, slab):
    f = tmp_path / f"{name}.xml"
    f.write_text(
        f'<scene version="3.0.0"><integrator type="volpath"/>{LAMP}{SLAB if slab else ""}</scene>'
    )
    return str(f)


def test_a_lamp_through_an_absorbing_slab_is_dimmed_by_beer_lambert(tmp_path):
    # 1 m of σ_t = 0.7 between the lamp and the receiver: E = I/d² e^{−0.7},
    # against the same lamp in clear air.
    points = np.array([[0, 0, 0, 0, 1, 0], [1, 0, 0, 0, 1, 0]], dtype=float)
    fog = scotopia.measure(_scene(tmp_path, "fog", True), points, spp=256, seed=3)
    clear = scotopia.measure(_scene(tmp_path, "clear", False), points, spp=256, seed=4)
    for i, (x, y) in enumerate([(0.0, 3.0), (1.0, 3.0)]):
        d = math.hypot(x, y)
        # The slab's 1 m is crossed along the slanted ray: 1 m · d / y.
        expected = math.exp(-0.7 * d / y)
        ratio = fog["E_lx"][i] / clear["E_lx"][i]
        se = ratio * math.hypot(
            fog["E_lx_se"][i] / fog["E_lx"][i], clear["E_lx_se"][i] / clear["E_lx"][i]
        )
        assert ratio == pytest.approx(expected, abs=4 * se + 1e-4), (i, ratio, se)


def _vol(path, res, values):
    head = b"VOL" + bytes([3]) + struct.pack("<5i", 1, *res, 1) + struct.pack("<6f", 0, 0, 0, 1, 1, 1)
    path.write_bytes(head + np.asarray(values, dtype="<f4").tobytes())


def test_scene_info_reports_a_heterogeneous_mediums_grids(tmp_path):
    _vol(tmp_path / "smoke.vol", (4, 3, 2), np.linspace(0, 2, 24))
    scene = tmp_path / "smoke.xml"
    scene.write_text(
        '<scene version="3.0.0"><integrator type="volpath"/><sensor type="perspective"/>'
        '<medium type="heterogeneous" id="smoke"><float name="scale" value="3"/>'
        '<volume type="gridvolume" name="sigma_t"><string name="filename" value="smoke.vol"/></volume>'
        "</medium>"
        '<shape type="cube"><bsdf type="null"/><ref name="interior" id="smoke"/></shape></scene>'
    )
    info = scotopia.scene_info(scene)
    (smoke,) = info["media"]
    assert smoke["type"] == "heterogeneous"
    assert smoke["sigma_t_max"] == pytest.approx(6.0)
    (grid,) = smoke["grids"]
    assert grid["parameter"] == "sigma_t" and list(grid["cells"]) == [4, 3, 2]
    assert grid["channels"] == 1
    assert not any("not rendered" in w for w in info["warnings"])
