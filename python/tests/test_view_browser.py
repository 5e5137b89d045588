"""`scotopia view` in a real browser (issue 26): headless Chromium loads the
page, the light-level slider is moved, the displayed image changes, and what
the browser shows matches /image.png for the same settings.

The browser is Debian's `chromium`, which `make browser` (a prerequisite of
`make pytest`) installs; Playwright drives it. Where it cannot be installed,
these tests fail and say how to install it: they never skip."""

import numpy as np
import pytest

from view_harness import (
    ROOT,
    BrowserMissing,
    Viewer,
    chromium_executable,
    decode_png,
    image_box,
    launch_chromium,
    open_page,
    scale_of,
    screenshot_image,
    set_light_level,
    sync_playwright,
)

# The night street, small: a second's render on 2 cores.
SCENE = ROOT / "scenes" / "night-street.xml"
RENDER_ARGS = ["-D", "width=128", "-D", "height=72", "--spp", "16"]

# What the browser shows against the PNG it was sent, in 8-bit codes. The
# PNG is sRGB (it carries sRGB and cICP chunks) and Chromium runs with
# --force-color-profile=srgb, so colour management is the identity and the
# screenshot should hold the PNG's own codes; measured here (Chromium 156,
# headless, software rendering): identical, 0 codes, with and without
# that flag, at seven light levels. Another build's colour management or a
# GPU compositor may still round a code in a conversion sRGB → linear →
# sRGB, by at most 1 per step: so a mean of at most 1 code and a maximum of
# 3 codes (a few such roundings). Resampling or a wrong image is far
# outside that: the night street shifted by 1 px differs by 12 codes on
# average and 252 at most.
MEAN_TOLERANCE = 1.0
MAX_TOLERANCE = 3

# The slider's setting in the test: log10 of the scale factor, 100 times
# less light (moonlight-like: the mode shifts towards scotopic and the
# image darkens and loses colour).
LOG10_SCALE = -2.0

# The page may write the scale in its query to 4 significant digits
# (`scale=794.3` for 10^2.9): a relative rounding of at most 5e-4.
SCALE_DIGITS = 1e-3


def test_chromium_is_installed():
    """First and plainly: the browser the other tests need is here."""
    try:
        chromium_executable()
        sync_playwright()
    except BrowserMissing as e:
        pytest.fail(str(e))


@pytest.fixture(scope="module")
def browser():
    try:
        chromium_executable()
        pw = sync_playwright().start()
    except BrowserMissing as e:
        pytest.fail(str(e))
    b = None
    try:
        b = launch_chromium(pw)
        yield b
    finally:
        if b is not None:
            b.close()
        pw.stop()


@pytest.fixture(scope="module")
def viewer(tmp_path_factory):
    out = tmp_path_factory.mktemp("view") / "night-street.exr"
    v = Viewer(SCENE, RENDER_ARGS, out)
    try:
        v.wait_for_phase("done")
        yield v
    finally:
        v.stop()


def _diff(a, b):
    d = np.abs(a.astype(np.int32) - b.astype(np.int32))
    return float(d.mean()), int(d.max())


def _assert_shows(page, viewer, shot, query):
    """The screenshot `shot` is /image.png?`query` within the tolerance."""
    png = decode_png(viewer.get("image.png?" + query))
    assert shot.shape == png.shape, (
        f"the browser shows {shot.shape[1]}x{shot.shape[0]} px, /image.png is "
        f"{png.shape[1]}x{png.shape[0]}: the img is not at its natural size ({image_box(page)})")
    mean, worst = _diff(shot, png)
    assert mean <= MEAN_TOLERANCE and worst <= MAX_TOLERANCE, (
        f"screenshot vs /image.png?{query}: mean |diff| {mean:.3f}, max {worst} codes")


def test_slider_changes_the_image_and_it_is_image_png(browser, viewer):
    page = open_page(browser, viewer.url)
    try:
        first_query = page.get_attribute("#seen", "data-query")
        assert first_query, "the img has no data-query once loaded"
        assert scale_of(first_query) == pytest.approx(1.0, rel=SCALE_DIGITS), first_query
        before = screenshot_image(page)
        _assert_shows(page, viewer, before, first_query)

        query = set_light_level(page, LOG10_SCALE)
        assert scale_of(query) == pytest.approx(10**LOG10_SCALE, rel=SCALE_DIGITS), (
            f"the slider holds log10 of the scale: {LOG10_SCALE} should ask for "
            f"scale={10**LOG10_SCALE}, the page asked for {query}")
        after = screenshot_image(page)
        mean, _ = _diff(before, after)
        # 100 times less light darkens the street by far more than noise.
        assert mean > 5.0, f"the image hardly changed (mean |diff| {mean:.2f} codes)"
        _assert_shows(page, viewer, after, query)
    finally:
        page.close()


def test_slider_contract(browser, viewer):
    """The light-level control: a range over log10 of the scale, -4 to 4 in
    steps of 0.05, whose value is the scale the shown image was asked for
    (the page opens at the viewer's current setting: 0, as rendered, until
    someone moves it)."""
    page = open_page(browser, viewer.url)
    try:
        attrs = page.evaluate(
            """() => { const s = document.getElementById('scale');
                       return {type: s.type, min: s.min, max: s.max, step: s.step, value: s.value}; }""")
        assert attrs["type"] == "range"
        assert float(attrs["min"]) == -4 and float(attrs["max"]) == 4
        assert float(attrs["step"]) == pytest.approx(0.05)
        query = page.get_attribute("#seen", "data-query")
        assert scale_of(query) == pytest.approx(10 ** float(attrs["value"]), rel=SCALE_DIGITS), (
            f"slider at {attrs['value']} (log10), image asked for {query}")
    finally:
        page.close()


def test_save_from_the_page_writes_what_it_shows(browser, viewer):
    """The page's Save sends its settings with the session's token (issue
    38): the PNG written is /image.png for the query the image shows."""
    page = open_page(browser, viewer.url)
    try:
        query = set_light_level(page, -1.0)
        page.click("#save")
        page.wait_for_function(
            "() => document.getElementById('saved').textContent.startsWith('saved')"
            " || document.getElementById('error').textContent !== ''",
            timeout=60_000)
        assert page.text_content("#error") == ""
        said = page.text_content("#saved")
        # File names only: the page is told no folders.
        assert "night-street.png" in said and "/" not in said, said
        assert viewer.out.with_suffix(".png").read_bytes() == viewer.get("image.png?" + query)
    finally:
        page.close()


def test_another_site_cannot_save(browser, viewer):
    """A page of another origin posts a form to /save and tries a fetch with
    JSON: neither writes anything (issue 38)."""
    png = viewer.out.with_suffix(".png")
    before = png.read_bytes() if png.exists() else None
    page = browser.new_page()
    try:
        save = viewer.url + "save"
        page.set_content(
            f'<form id="f" method="POST" action="{save}">'
            '<input name="scale" value="1e-30"></form>')
        with page.expect_response(save) as answer:
            page.evaluate("() => document.getElementById('f').submit()")
        assert answer.value.status in (403, 415)
        # The form's submission navigates the page to the refusal: the
        # fetch goes from a fresh page, not one whose context the
        # navigation may still be replacing.
        page.close()
        page = browser.new_page()
        page.set_content("<p>elsewhere</p>")
        sent = page.evaluate(
            """url => fetch(url, {method: 'POST', headers: {'Content-Type': 'application/json'},
                                  body: '{"scale": 1e-30}'})
                      .then(r => 'answered ' + r.status, e => 'blocked')""",
            save)
        assert sent == "blocked" or sent in ("answered 403", "answered 415"), sent
        assert (png.read_bytes() if png.exists() else None) == before
    finally:
        page.close()
