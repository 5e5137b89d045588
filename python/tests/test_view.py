"""``scotopia.view`` from Python: the CLI's viewer started, read and
stopped from a script (its routes are tested in crates/cli/tests/view.rs,
its page in a real browser in test_view_browser.py)."""
import urllib.request
from pathlib import Path

import pytest

import scotopia

ROOT = Path(__file__).resolve().parents[2]
CORNELL = ROOT / "scenes/cornell-box.xml"


def get(url):
    with urllib.request.urlopen(url, timeout=60) as r:
        return r.status, r.headers, r.read()


def test_a_render_is_seen_then_stopped_and_its_film_kept(tmp_path):
    out = tmp_path / "box.exr"
    v = scotopia.view(CORNELL, port=0, open_browser=False, output=out, define={"res": 16},
                      spp=32, scale=0.5, adaptation="local", glare=False, age=70,
                      pigmentation=1)
    assert v.url.startswith("http://127.0.0.1:")
    v.wait()
    s = v.status()
    assert (s["phase"], s["spp"], s["width"]) == ("done", 32, 16)
    # The keyword arguments are the page's starting settings.
    assert s["settings"]["scale"] == "0.5"
    assert s["settings"]["adaptation"] == "local"
    assert s["settings"]["glare"] == "off"
    assert (s["settings"]["age"], s["settings"]["pigmentation"]) == ("70", "1")
    status, headers, body = get(v.url + "image.png?scale=2")
    assert status == 200 and headers["Content-Type"] == "image/png"
    assert body[:8] == b"\x89PNG\r\n\x1a\n"
    # A picture asked for changes nothing; the page is told file names only.
    s = v.status()
    assert s["settings"]["scale"] == "0.5"
    assert (s["name"], s["output"]) == ("cornell-box.xml", "box.exr")
    v.stop()
    # The film was written at the end; the page is gone.
    image, meta = scotopia.vision.read_image(out, None, "srgb")[0], None
    assert image.shape == (16, 16, 4) and image[..., 1].max() > 0
    # The port is closed: refused.
    with pytest.raises(OSError):
        get(v.url + "status")
    with pytest.raises(RuntimeError, match="stopped"):
        v.status()


def test_stopping_mid_render_writes_what_was_rendered(tmp_path):
    out = tmp_path / "box.exr"
    v = scotopia.view(CORNELL, port=0, open_browser=False, output=out, define={"res": 16},
                      time=600)
    v.stop()
    assert out.exists()


def test_bad_arguments_are_value_errors(tmp_path, monkeypatch):
    # Nothing starts; were it to, its film would go here.
    monkeypatch.chdir(tmp_path)
    with pytest.raises(ValueError, match="--scale 0"):
        scotopia.view(CORNELL, port=0, open_browser=False, scale=0)
    with pytest.raises(ValueError, match="--adaptation sideways"):
        scotopia.view(CORNELL, port=0, open_browser=False, adaptation="sideways")
    with pytest.raises(ValueError, match="--age.*age -3: use years"):
        scotopia.view(CORNELL, port=0, open_browser=False, age=-3)
    with pytest.raises(ValueError, match="--pigmentation.*pigmentation 2"):
        scotopia.view(CORNELL, port=0, open_browser=False, pigmentation=2)
    with pytest.raises(ValueError, match="unexpected argument '--colour'"):
        scotopia.view(CORNELL, port=0, open_browser=False, colour="blue")
    with pytest.raises(ValueError, match="nope.xml"):
        scotopia.view(ROOT / "nope.xml", port=0, open_browser=False)
