"""Driving `scotopia view` and its page in headless Chromium: shared by
test_view_browser.py and bench/view_screenshot.py.

The browser is Debian's `chromium` (`make browser` installs it), driven by
Playwright with `executable_path`: Playwright's own browser download is not
reachable here, so `playwright install` is never run."""

import io
import json
import math
import os
import re
import shutil
import signal
import subprocess
import threading
import time
import urllib.request
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
URL_LINE = re.compile(r"view at (http://127\.0\.0\.1:\d+/)")

HOW_TO_INSTALL = (
    "run `make browser` (as root, or with passwordless sudo, it runs "
    "`apt-get install -y chromium`), or install Debian's `chromium` package "
    "by hand; SCOTOPIA_CHROMIUM names another Chromium executable. Playwright "
    "itself comes from python/requirements-dev.txt (`pip install playwright`); "
    "`playwright install` is not needed."
)


class BrowserMissing(RuntimeError):
    """Chromium or Playwright could not be found; the message says how to install them."""


def scotopia_binary():
    """The release binary: SCOTOPIA_BIN, else CARGO_TARGET_DIR's or the
    repository's target/release/scotopia (`make pytest` builds it)."""
    if os.environ.get("SCOTOPIA_BIN"):
        return Path(os.environ["SCOTOPIA_BIN"])
    target = Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target"))
    if not target.is_absolute():
        target = ROOT / target
    return target / "release" / "scotopia"


def chromium_executable():
    """Debian's Chromium, or SCOTOPIA_CHROMIUM; raises BrowserMissing."""
    named = os.environ.get("SCOTOPIA_CHROMIUM")
    candidates = [named] if named else ["/usr/bin/chromium", shutil.which("chromium"),
                                        shutil.which("chromium-browser")]
    for c in candidates:
        if c and os.path.isfile(c) and os.access(c, os.X_OK):
            return c
    raise BrowserMissing(
        f"the browser could not be installed or found ({named or '/usr/bin/chromium'} "
        f"is missing): {HOW_TO_INSTALL}")


def launch_chromium(playwright):
    """A headless Chromium. As root Chromium refuses to start without
    --no-sandbox. --force-color-profile=srgb makes the page's output space
    sRGB, so that an sRGB PNG is drawn with its own code values (no
    conversion to a display profile)."""
    exe = chromium_executable()
    args = ["--force-color-profile=srgb"]
    if os.geteuid() == 0:
        args.append("--no-sandbox")
    return playwright.chromium.launch(executable_path=exe, headless=True, args=args)


def sync_playwright():
    """Playwright's sync entry point; raises BrowserMissing if it is not installed."""
    try:
        from playwright.sync_api import sync_playwright as sp
    except ImportError as e:
        raise BrowserMissing(f"Playwright is not installed ({e}): {HOW_TO_INSTALL}") from e
    return sp()


class Viewer:
    """`scotopia view SCENE ARGS --no-open --port 0 -o OUT` as a subprocess:
    the URL from the `view at http://127.0.0.1:PORT/` line of its stderr;
    stop() sends SIGINT (on which it writes OUT) and waits, then kills."""

    def __init__(self, scene, args, out, binary=None, start_timeout=60.0):
        self.binary = Path(binary) if binary else scotopia_binary()
        if not self.binary.is_file():
            raise FileNotFoundError(
                f"{self.binary} is missing: `cargo build --release -p scotopia` "
                "(make pytest does), or set SCOTOPIA_BIN")
        self.out = Path(out)
        self.cmd = [str(self.binary), "view", str(scene), *args,
                    "--no-open", "--port", "0", "-o", str(self.out)]
        self.stderr_lines = []
        self._url_found = threading.Event()
        self.url = None
        self.proc = subprocess.Popen(self.cmd, stdin=subprocess.DEVNULL,
                                     stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
        # Read stderr to the end on a thread: the URL line, and afterwards
        # keep the pipe drained so a progress bar never blocks the viewer.
        self._reader = threading.Thread(target=self._read_stderr, daemon=True)
        self._reader.start()
        deadline = time.monotonic() + start_timeout
        while not self._url_found.wait(0.1):
            if self.proc.poll() is not None:
                self._reader.join(2)
                raise RuntimeError(f"`{' '.join(self.cmd)}` exited with {self.proc.returncode} "
                                   f"before printing its URL; stderr:\n{self.stderr()}")
            if time.monotonic() > deadline:
                self.stop()
                raise TimeoutError(f"no `view at http://...` line on stderr within "
                                   f"{start_timeout:.0f} s of `{' '.join(self.cmd)}`; "
                                   f"stderr:\n{self.stderr()}")

    def _read_stderr(self):
        # Progress bars end lines with \r: split on both.
        buf = b""
        while True:
            chunk = self.proc.stderr.read1(4096)
            if not chunk:
                break
            buf += chunk
            *lines, buf = re.split(rb"[\r\n]", buf)
            for raw in lines:
                self._line(raw)
        if buf:
            self._line(buf)

    def _line(self, raw):
        line = raw.decode("utf-8", "replace")
        if not line.strip():
            return
        self.stderr_lines.append(line)
        m = URL_LINE.search(line)
        if m and self.url is None:
            self.url = m.group(1)
            self._url_found.set()

    def stderr(self):
        return "\n".join(self.stderr_lines[-40:])

    def get(self, path, timeout=30.0):
        """The body of GET URL + path (no leading slash)."""
        with urllib.request.urlopen(self.url + path.lstrip("/"), timeout=timeout) as r:
            return r.read()

    def status(self):
        return json.loads(self.get("status"))

    def wait_for_phase(self, phase="done", timeout=180.0):
        """Polls /status until its phase is `phase`; returns that status."""
        deadline = time.monotonic() + timeout
        st = None
        while time.monotonic() < deadline:
            if self.proc.poll() is not None:
                raise RuntimeError(f"the viewer exited with {self.proc.returncode}; "
                                   f"stderr:\n{self.stderr()}")
            st = self.status()
            if st.get("phase") == phase:
                return st
            time.sleep(0.2)
        raise TimeoutError(f"/status not {phase!r} within {timeout:.0f} s; last: {st}")

    def stop(self, timeout=30.0):
        """SIGINT, then wait; kill if it has not exited within `timeout`.
        Returns the exit code (None if it had to be killed)."""
        if self.proc.poll() is None:
            self.proc.send_signal(signal.SIGINT)
            try:
                self.proc.wait(timeout)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait()
                self._reader.join(5)
                return None
        self._reader.join(5)
        return self.proc.returncode


# The page's contract: <img id="seen"> at its natural size, and the
# light-level slider <input type="range" id="scale"> holding log10 of the
# scale factor; the img's data-query is the query string its image was
# fetched with, data-loaded "1" once shown and "0" while a fetch is in flight.
LOADED = '#seen[data-loaded="1"]'


def open_page(browser, url, width=1280, height=1000):
    """A page at `url` with a viewport larger than the image and 1 device
    pixel per CSS pixel; waits until the first image is shown."""
    page = browser.new_page(viewport={"width": width, "height": height}, device_scale_factor=1)
    page.goto(url)
    page.wait_for_selector(LOADED, timeout=60_000)
    return page


def set_light_level(page, log10_scale, timeout_ms=60_000):
    """Moves the slider to `log10_scale` as a person would (the value, then
    `input` and `change` events) and waits until the image fetched for the
    new setting is shown; returns its data-query. The slider snaps the
    value to its step (0.05), so the page may ask for 10^(snapped value)."""
    before = page.get_attribute("#seen", "data-query")
    page.evaluate(
        """v => { const s = document.getElementById('scale');
                  s.value = String(v);
                  s.dispatchEvent(new Event('input', {bubbles: true}));
                  s.dispatchEvent(new Event('change', {bubbles: true})); }""",
        log10_scale)
    page.wait_for_function(
        """before => { const i = document.getElementById('seen');
                       return i.dataset.loaded === '1' && i.dataset.query !== before; }""",
        arg=before, timeout=timeout_ms)
    return page.get_attribute("#seen", "data-query")


def image_box(page):
    """The img's content box in page coordinates (CSS px = device px here),
    and its natural size."""
    return page.evaluate(
        """() => { const i = document.getElementById('seen'), r = i.getBoundingClientRect(),
                          cs = getComputedStyle(i);
                   const px = p => parseFloat(cs[p]) || 0;
                   return {x: r.left + window.scrollX + px('borderLeftWidth') + px('paddingLeft'),
                           y: r.top + window.scrollY + px('borderTopWidth') + px('paddingTop'),
                           width: r.width - px('borderLeftWidth') - px('borderRightWidth')
                                  - px('paddingLeft') - px('paddingRight'),
                           height: r.height - px('borderTopWidth') - px('borderBottomWidth')
                                   - px('paddingTop') - px('paddingBottom'),
                           naturalWidth: i.naturalWidth, naturalHeight: i.naturalHeight}; }""")


def screenshot_image(page):
    """The pixels the browser shows for #seen, as uint8 RGB (H, W, 3)."""
    box = image_box(page)
    clip = {k: box[k] for k in ("x", "y", "width", "height")}
    return decode_png(page.screenshot(full_page=True, clip=clip))


def decode_png(data):
    """PNG bytes → uint8 RGB array (H, W, 3); alpha is dropped."""
    from PIL import Image

    im = Image.open(io.BytesIO(data))
    if im.mode not in ("RGB", "RGBA", "L", "LA", "P"):
        raise ValueError(f"unexpected PNG mode {im.mode} (8-bit expected)")
    return np.asarray(im.convert("RGB"))


def scale_of(query):
    """The `scale` a query string asks for (1 if absent)."""
    from urllib.parse import parse_qs

    return float(parse_qs(query).get("scale", ["1"])[0])


def log10_step(scale, step=0.05):
    """log10 of `scale` on the slider's step."""
    return round(math.log10(scale) / step) * step
