"""Scene loading from Python, and the bundled Cornell box against Mitsuba's view of it."""
from pathlib import Path

import pytest

import scotopia

SCENES = Path(__file__).resolve().parents[2] / "scenes"


def test_scene_info_of_the_cornell_box():
    info = scotopia.scene_info(SCENES / "cornell-box.xml", {"res": "40"})
    assert info["shapes"] == 8 and info["triangles"] == 24
    assert info["film"]["width"] == 40
    assert info["lights"][0]["type"] == "area" and info["lights"][0]["lumens"] > 0
    assert any("pixel_format" in w for w in info["warnings"])


def test_scene_errors_are_value_errors(tmp_path):
    bad = tmp_path / "bad.xml"
    bad.write_text('<scene version="3.0.0">\n<shape type="teapot"/>\n</scene>')
    with pytest.raises(ValueError, match=r"bad.xml:2:1: <shape>: shape type 'teapot'"):
        scotopia.scene_info(bad)


def test_scene_info_reports_media_and_an_irradiancemeter(tmp_path):
    scene = tmp_path / "fog.xml"
    scene.write_text(
        '<scene version="3.0.0">'
        '<medium type="homogeneous" id="fog"><float name="sigma_t" value="0.5"/>'
        '<phase type="hg"><float name="g" value="0.6"/></phase></medium>'
        '<shape type="rectangle"><ref name="exterior" id="fog"/>'
        '<sensor type="irradiancemeter"><film type="hdrfilm"><integer name="width" value="1"/>'
        '<integer name="height" value="1"/></film></sensor></shape></scene>'
    )
    info = scotopia.scene_info(scene)
    assert info["camera"]["irradiancemeter_shape"] == 0
    (fog,) = info["media"]
    assert fog["type"] == "homogeneous" and fog["g"] == pytest.approx(0.6)
    # σ_t 0.5 across the 2 × 2 rectangle's bounding sphere (diameter 2√2).
    assert fog["optical_thickness"] == pytest.approx(0.5 * 2 * 2**0.5, rel=1e-4)
