"""Screenshots of `scotopia view` for the README: the night street rendered
in the viewer, its page in headless Chromium at three light levels (every
light scaled as `make demo` does: day 800, dusk 4, moonlight 0.02), saved as
docs/images/view-day.png, view-dusk.png and view-moonlight.png.

    python bench/view_screenshot.py [--spp 176] [--bin target/release/scotopia]
                                    [--out docs/images] [--width 990 --height 620]

Needs the release binary (`cargo build --release -p scotopia`), Debian's
Chromium (`make browser`) and the dev venv (Playwright, Pillow). Not part of
`make test`. The slider moves in steps of 0.05 in log10, so the levels are
shown at 10^2.90 ≈ 794, 10^0.60 ≈ 3.98 and 10^-1.70 ≈ 0.0200."""

import argparse
import os
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "python" / "tests"))

from view_harness import (  # noqa: E402
    Viewer,
    launch_chromium,
    log10_step,
    open_page,
    scale_of,
    set_light_level,
    sync_playwright,
)

LEVELS = [("day", 800.0), ("dusk", 4.0), ("moonlight", 0.02)]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--scene", default="scenes/night-street.xml",
                    help="relative to the repository root (the page shows it as given)")
    ap.add_argument("--spp", type=int, default=176, help="as `make demo` renders the night street")
    ap.add_argument("--bin", default=None, help="default: target/release/scotopia")
    ap.add_argument("--out", default=str(ROOT / "docs" / "images"))
    # The page's side panel and the 640x360 street, with little else.
    ap.add_argument("--width", type=int, default=990, help="viewport width, CSS px")
    ap.add_argument("--height", type=int, default=620, help="viewport height, CSS px")
    ap.add_argument("--full-page", action="store_true", help="the whole page, not the viewport")
    ap.add_argument("--timeout", type=float, default=900, help="seconds to wait for the render")
    a = ap.parse_args()

    out_dir = Path(a.out).resolve()
    os.chdir(ROOT)
    out_dir.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory() as tmp, sync_playwright() as pw:
        viewer = Viewer(a.scene, ["--spp", str(a.spp)], Path(tmp) / "view.exr", binary=a.bin)
        browser = launch_chromium(pw)
        try:
            print(f"rendering {a.scene} at {a.spp} spp in {viewer.url} ...", file=sys.stderr)
            st = viewer.wait_for_phase("done", timeout=a.timeout)
            print(f"done: {st.get('spp')} spp in {st.get('seconds')} s", file=sys.stderr)
            page = open_page(browser, viewer.url, a.width, a.height)
            for name, scale in LEVELS:
                level = log10_step(scale)
                current = page.evaluate("() => Number(document.getElementById('scale').value)")
                if abs(current - level) > 1e-9:
                    query = set_light_level(page, level)
                else:
                    query = page.get_attribute("#seen", "data-query")
                path = out_dir / f"view-{name}.png"
                page.screenshot(path=str(path), full_page=a.full_page)
                print(f"{path}: scale {scale_of(query):.4g} ({query})", file=sys.stderr)
        finally:
            browser.close()
            viewer.stop()


if __name__ == "__main__":
    main()
