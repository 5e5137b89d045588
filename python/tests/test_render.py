"""scotopia.render: the array and metadata, and the OpenEXR file read back
by the OpenEXR project's own Python package (an independent reader)."""

from pathlib import Path

import numpy as np
import pytest
import OpenEXR

import scotopia

SCENES = Path(__file__).resolve().parents[2] / "scenes"


def test_render_returns_xyzv_and_metadata(tmp_path):
    out = tmp_path / "c.exr"
    image, meta = scotopia.render(
        str(SCENES / "cornell-box.xml"), spp=4, params={"res": "16"}, seed=2, output=str(out)
    )
    assert image.shape == (16, 16, 4) and image.dtype == np.float32
    assert np.isfinite(image).all() and image[..., 1].mean() > 0
    assert meta["samplesPerPixel"] == 4 and meta["wavelengthStrategy"] == "swc"
    assert meta["nonfiniteSamples"] == 0
    # The same seed gives the same image.
    again, _ = scotopia.render(str(SCENES / "cornell-box.xml"), spp=4, params={"res": "16"}, seed=2)
    assert np.array_equal(image, again)

    with OpenEXR.File(str(out)) as f:
        header = f.header()
        channels = f.channels()
        assert set(channels) == {"X", "Y", "Z", "V"}
        assert header["samplesPerPixel"] == 4
        assert abs(header["fovHorizontalDegrees"] - meta["fovHorizontalDegrees"]) < 1e-6
        y = channels["Y"].pixels
        assert y.shape == (16, 16)
        np.testing.assert_array_equal(y, image[..., 1])


def test_render_rejects_bad_options():
    import pytest

    with pytest.raises(ValueError, match="swc, hero or single"):
        scotopia.render(str(SCENES / "cornell-box.xml"), wavelengths="rgb")
    with pytest.raises(ValueError, match="cluster size 3"):
        scotopia.render(str(SCENES / "cornell-box.xml"), spp=1, cluster=3, params={"res": "4"})
    with pytest.raises(ValueError, match="wavefront or scalar"):
        scotopia.render(str(SCENES / "cornell-box.xml"), spp=1, res=4, tracer="gpu")


def test_the_two_path_tracers_give_the_same_bits():
    scene = str(SCENES / "prism.xml")
    # The prism's own integrator is bdpt, which the wavefront tracer does
    # not run: the path tracer in both forms.
    a, _ = scotopia.render(scene, spp=2, res=16, integrator="path", tracer="wavefront")
    b, _ = scotopia.render(scene, spp=2, res=16, integrator="path", tracer="scalar")
    assert np.array_equal(a, b)


def test_guiding_is_an_option_and_keeps_the_image():
    import pytest

    scene = str(SCENES / "cornell-box.xml")
    off, meta_off = scotopia.render(scene, spp=32, res=8)
    on, meta = scotopia.render(scene, spp=32, res=8, guiding="on")
    assert (meta["guiding"], meta_off["guiding"]) == ("on", "off")
    # At 8 × 8 the guide's probe has too few pixels to tell that the
    # Cornell box's light is too flat for guiding to pay, so the image
    # learns, its first 16 spp weighed less (`learn.rs`): close, not
    # equal (the Rust tests check guided images against unguided ones
    # within standard errors).
    assert np.isfinite(on).all() and not np.array_equal(on, off)
    assert abs(on[..., 1].mean() / off[..., 1].mean() - 1) < 0.03
    # At 160 × 90 the probe finds the field worth too little and the
    # render declines to guide (docs/guiding.md): the unguided image,
    # and it says so.
    on, meta = scotopia.render(scene, spp=2, res="160x90", guiding="on")
    off, _ = scotopia.render(scene, spp=2, res="160x90")
    assert meta["guidingStopped"] and meta["guidingLearnedSpp"] == 0
    assert 0 <= meta["guidingWorth"] < 0.05
    assert np.array_equal(on, off)
    assert "guidingWorth" not in meta_off
    with pytest.raises(ValueError, match="on or off"):
        scotopia.render(scene, spp=1, res=4, guiding="yes")
    with pytest.raises(ValueError, match="--guiding off"):
        scotopia.render(scene, spp=1, res=4, guiding="on", tracer="wavefront")
    # The bidirectional tracer guides its light paths' emission.
    image, meta = scotopia.render(scene, spp=4, res=4, guiding="on", integrator="bdpt")
    assert meta["guiding"] == "on" and np.isfinite(image).all()


def test_render_with_the_bidirectional_tracer():
    # The same Cornell box by both tracers: the image means agree roughly
    # (the Rust tests check them within standard errors).
    path, _ = scotopia.render(str(SCENES / "cornell-box.xml"), spp=64, params={"res": "8"})
    image, meta = scotopia.render(
        str(SCENES / "cornell-box.xml"), spp=64, params={"res": "8"}, integrator="bdpt"
    )
    assert meta["integrator"] == "bdpt"
    assert (meta["nonfiniteSamples"], meta["nonfiniteSplats"]) == (0, 0)
    assert np.isfinite(image).all()
    assert abs(image[..., 1].mean() / path[..., 1].mean() - 1) < 0.1
    import pytest

    with pytest.raises(ValueError, match="use path or bdpt"):
        scotopia.render(str(SCENES / "cornell-box.xml"), spp=1, integrator="light")


def test_a_checkpointed_render_resumes_to_the_same_bits(tmp_path):
    scene = str(SCENES / "cornell-box.xml")
    ckpt = tmp_path / "box.ckpt"
    opts = dict(params={"res": "8"}, seed=4, integrator="bdpt")
    first, _ = scotopia.render(scene, spp=8, checkpoint=str(ckpt), checkpoint_every=0, **opts)
    assert ckpt.exists()
    resumed, meta = scotopia.render(scene, spp=24, checkpoint=str(ckpt), resume=True, **opts)
    whole, _ = scotopia.render(scene, spp=24, **opts)
    assert np.array_equal(resumed, whole)
    assert not np.array_equal(first, whole)
    # Other options: refused.
    with pytest.raises(ValueError, match="another scene"):
        scotopia.render(scene, spp=24, checkpoint=str(ckpt), resume=True, cluster=8, **opts)


def test_a_checkpoint_refuses_to_resume_after_a_file_of_the_scene_changed(tmp_path):
    # Issue 38: the key hashes every file the scene reads; the refusal
    # names the file. A damaged checkpoint is refused too.
    import pytest

    (tmp_path / "refl.spd").write_text("400 0.5\n700 0.6\n")
    scene = tmp_path / "s.xml"
    scene.write_text(
        '<scene version="3.0.0"><sensor type="perspective"><film type="hdrfilm">'
        '<integer name="width" value="2"/><integer name="height" value="1"/></film>'
        '</sensor><shape type="sphere"><float name="radius" value="0.5"/>'
        '<transform name="to_world"><translate z="3"/></transform><bsdf type="diffuse">'
        '<spectrum name="reflectance" filename="refl.spd"/></bsdf></shape>'
        '<emitter type="constant"/></scene>'
    )
    ckpt = tmp_path / "s.ckpt"
    scotopia.render(str(scene), spp=2, checkpoint=str(ckpt), checkpoint_every=0)
    (tmp_path / "refl.spd").write_text("400 0.5\n700 0.7\n")
    with pytest.raises(ValueError, match="refl.spd has changed"):
        scotopia.render(str(scene), spp=4, checkpoint=str(ckpt), resume=True)
    (tmp_path / "refl.spd").write_text("400 0.5\n700 0.6\n")
    data = bytearray(ckpt.read_bytes())
    data[-20] ^= 0xFF
    ckpt.write_bytes(bytes(data))
    with pytest.raises(ValueError, match="checksum"):
        scotopia.render(str(scene), spp=4, checkpoint=str(ckpt), resume=True)
    with pytest.raises(ValueError, match="the scene"):
        scotopia.render(str(scene), spp=1, output=str(scene))


def test_measure_gives_the_inverse_square_law_and_its_standard_errors(tmp_path):
    # A 1000 cd point source 3 m above the floor: E = I cos θ / d². The
    # scene has no sensor: a measurement needs none.
    scene = tmp_path / "point.xml"
    scene.write_text(
        '<scene version="3.0.0">'
        '<integrator type="path"><integer name="max_depth" value="2"/></integrator>'
        '<emitter type="point"><point name="position" x="0" y="3" z="0"/>'
        '<spectrum name="intensity" type="d65"><float name="luminance" value="1000"/></spectrum>'
        "</emitter></scene>"
    )
    x = np.array([0.0, 2.0, 4.0])
    points = np.stack([x, 0 * x, 0 * x, 0 * x, 1 + 0 * x, 0 * x], -1)
    m = scotopia.measure(str(scene), points, spp=256, reflectance=0.02)
    d2 = x**2 + 9.0
    expected = 1000.0 * 3.0 / d2**1.5
    assert np.all(np.abs(m["E_lx"] - expected) <= 4 * m["E_lx_se"] + 5e-3 * expected)
    assert np.all(m["E_lx_se"] > 0) and np.allclose(m["SP"], m["Es_lx"] / m["E_lx"])
    # CIE 191 of a dark surface (reflectance 0.02) there: L = 0.02 E/π, the
    # mesopic range's m, and a D65 light (S/P 2.47) looks brighter to it.
    np.testing.assert_allclose(m["L_cdm2"], 0.02 * m["E_lx"] / np.pi, rtol=1e-12)
    assert np.all((m["m"] > 0) & (m["m"] < 1)), m["m"]
    assert np.all(m["Lmes_cdm2"] > m["L_cdm2"])
    # CIE S 026: a D65 lamp's α-opic equivalent daylight illuminances are
    # its illuminance.
    for name in ["scEDI_lx", "mcEDI_lx", "lcEDI_lx", "rhEDI_lx", "mEDI_lx"]:
        assert np.all(np.abs(m[name] - m["E_lx"]) <= 4 * m[name + "_se"] + 5e-3 * m["E_lx"]), name
    # A small vertical cylinder there: E_z = I sin θ / (π d²), sin θ = x/d;
    # a half-cylinder facing the lamp (−x), twice that.
    cyl = scotopia.measure(str(scene), points, spp=256, receiver="cylindrical")
    ez = 1000.0 * (x / np.sqrt(d2)) / (np.pi * d2)
    assert np.all(np.abs(cyl["E_lx"] - ez) <= 4 * cyl["E_lx_se"] + 5e-3 * ez + 1e-12)
    assert np.all(np.isnan(cyl["L_cdm2"]))
    facing = points.copy()
    facing[:, 3:] = [-1.0, 0.0, 0.0]
    semi = scotopia.measure(str(scene), facing, spp=256, receiver="semicylindrical")
    assert np.all(np.abs(semi["E_lx"] - 2 * ez) <= 4 * semi["E_lx_se"] + 1e-2 * ez + 1e-12)
    with pytest.raises(ValueError, match="plane, cylindrical or semicylindrical"):
        scotopia.measure(str(scene), points, receiver="sphere")
    with pytest.raises(ValueError, match="lies along it"):
        scotopia.measure(str(scene), points, receiver="semicylindrical")
    with pytest.raises(ValueError, match="reflectance"):
        scotopia.measure(str(scene), points, reflectance=1.5)
    with pytest.raises(ValueError, match="N × 6"):
        scotopia.measure(str(scene), points[:, :5])


def test_measure_sees_an_r_table_road_from_an_observer(tmp_path):
    # A 1000 cd lamp 10 m over a CIE R3 road: seen from far along −x, 1°
    # up, the road straight under the lamp has L = I·r(0, 0)/h², r(0, 0)
    # of R3 0.0294 (CIE 144), by direct light; the full transport adds
    # nothing here (no other surface), within the noise.
    scene = tmp_path / "road.xml"
    scene.write_text(
        '<scene version="3.0.0">'
        '<emitter type="point"><point name="position" x="0" y="10" z="0"/>'
        '<spectrum name="intensity" type="d65"><float name="luminance" value="1000"/></spectrum>'
        "</emitter>"
        '<shape type="rectangle"><transform name="to_world"><scale value="100"/>'
        '<rotate x="1" angle="-90"/></transform>'
        '<bsdf type="roadsurface"><string name="class" value="R3"/></bsdf></shape></scene>'
    )
    points = np.array([[0.0, 0.0, 0.0, 0.0, 1.0, 0.0]])
    eye = (-1e4, 1e4 * np.tan(np.radians(1.0)), 0.0)
    m = scotopia.measure(str(scene), points, spp=256, observer=eye, direct=True)
    want = 1000.0 * 0.0294 / 100.0
    assert abs(m["Lobs_cdm2"][0] - want) <= 4 * m["Lobs_cdm2_se"][0] + 1e-3 * want
    # D65: scotopic over photopic 2.47, and mesopic luminance above it.
    assert abs(m["Lobs_SP"][0] - 2.47) < 0.05 and m["Lobs_mes_cdm2"][0] > m["Lobs_cdm2"][0]
    assert "Lobs_cdm2" not in scotopia.measure(str(scene), points, spp=4)
    with pytest.raises(ValueError, match="finite point"):
        scotopia.measure(str(scene), points, spp=4, observer=(np.inf, 0.0, 0.0))


def test_road_gives_the_luminance_methods_figures():
    # The bundled street with the CIE R3 road, EN 13201-3's grid between
    # its first two poles: per lane L_av, U_o, U_l and TI, and each
    # observer's luminance at every point.
    r = scotopia.road(str(SCENES / "ies-street.xml"), (-3.5, 0.0, 0.0), (0.0, 0.0, -1.0),
                      (1.0, 0.0, 0.0), 30.0, lanes=2, spp=16, params={"road": "r3"},
                      direct=True)
    assert r["grid"].shape == (60, 3) and r["L_cdm2"].shape == (2, 60)
    assert sorted(set(r["lane"])) == [0, 1] and r["row"].max() == 9
    for o in r["observers"]:
        lum = r["L_cdm2"][o["lane"]]
        assert abs(o["L_av_cdm2"] - lum.mean()) < 1e-9 * lum.mean()
        assert abs(o["U_o"] - lum.min() / lum.mean()) < 1e-9
        assert 0 < o["U_l"] <= 1 and o["Lv_cdm2"] > 0 and o["TI_percent"] > 0
    with pytest.raises(ValueError, match="lanes"):
        scotopia.road(str(SCENES / "ies-street.xml"), (0, 0, 0), (0, 0, -1), (1, 0, 0), 30.0,
                      lanes=0)


def test_false_colour_maps_luminance_mesopic_and_illuminance(tmp_path):
    # A melanopic image: illuminance with the melanopic EDI fourth.
    mel, meta = scotopia.render(str(SCENES / "cornell-box.xml"), spp=2, res=8,
                                quantity="melanopic-edi", output=tmp_path / "mel.exr")
    # The Cornell box's warm lamp stirs melanopsin less than daylight does.
    assert meta["quantity"] == "melanopic-edi" and mel[..., 3].mean() < mel[..., 1].mean()
    m = scotopia.false_colour(tmp_path / "mel.exr", "melanopic-edi")
    assert m.dtype == np.uint8 and m.shape[1] == 8
    img, _ = scotopia.render(str(SCENES / "night-street.xml"), spp=2, res=32)
    out = tmp_path / "map.png"
    lum = scotopia.false_colour(img, "luminance", range=(0, 5), output=out)
    # The picture, then the scale bar below it; written as a PNG too.
    assert lum.dtype == np.uint8 and lum.shape[1] == 32 and lum.shape[0] > 32 + 20
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    # Mesopic and photopic maps differ where the light is mesopic.
    mes = scotopia.false_colour(img, "mesopic", range=(0, 5))
    assert mes.shape == lum.shape and np.any(mes[:32] != lum[:32])
    with pytest.raises(ValueError, match="mesopic, illuminance or melanopic-edi"):
        scotopia.false_colour(img, "photons")
    with pytest.raises(ValueError, match="lo < hi"):
        scotopia.false_colour(img, range=(5, 1))


def test_glare_rates_a_fisheye_picture(tmp_path):
    # A 180° angular fisheye of a 100 cd/m² sky with a 20 000 cd/m² disc,
    # 3° in radius, 30° above the centre, written by OpenEXR's own writer.
    n = 200
    j, i = np.mgrid[0:n, 0:n] + 0.5
    a, b = (i - n / 2) / (n / 2), (n / 2 - j) / (n / 2)
    rho = np.hypot(a, b)
    t = rho * np.pi / 2
    s = np.where(rho > 0, np.sin(t) / np.maximum(rho, 1e-12), 0.0)
    d = np.stack([a * s, b * s, np.cos(t)], -1)
    c = np.array([0.0, np.sin(np.radians(30)), np.cos(np.radians(30))])
    y = np.where(d @ c >= np.cos(np.radians(3)), 2e4, 100.0)
    y = np.where(rho > 1, 0.0, y).astype(np.float32)
    path = tmp_path / "eye.exr"
    header = {"projection": "angular", "fovHorizontalDegrees": 180.0}
    channels = {c: y for c in "XYZV"}
    with OpenEXR.File(header, channels) as f:
        f.write(str(path))
    g = scotopia.glare(path, output=tmp_path / "sources.png")
    assert len(g["sources"]) == 1 and g["UGR"] > 0 and 0 < g["DGP"] <= 1
    omega = g["sources"][0]["solid_angle_sr"]
    ev = np.pi * 100 + (2e4 - 100) * omega * np.cos(np.radians(30))
    assert abs(g["Ev_lx"] / ev - 1) < 3e-3
    assert (tmp_path / "sources.png").read_bytes()[:4] == b"\x89PNG"
    with pytest.raises(ValueError, match="angular or equisolid"):
        scotopia.glare(path, projection="stereographic")
