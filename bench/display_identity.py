"""Checks that two builds of `scotopia display` write the same bytes: each
option set below on each input EXR, run with both binaries, output files
compared by MD5 (the test kept for the display's speed work, issue 23).
Prints one line per case and exits non-zero if any differs. Usage:

    python bench/display_identity.py BEFORE_BIN AFTER_BIN IN.exr [IN.exr ...]

`scotopia render scenes/night-street.xml --res 1920 --spp 1 -o ns.exr`
makes the main input; a daylight or coloured scene adds out-of-gamut
colours.
"""

import hashlib
import subprocess
import sys
import tempfile
from pathlib import Path

# (name, options, output suffix, extra outputs to compare)
CASES = [
    ("default", [], ".png"),
    ("reinhard", ["--tonemap", "reinhard"], ".png"),
    ("exposure", ["--tonemap", "exposure"], ".png"),
    ("local", ["--adaptation", "local"], ".png"),
    ("fixed 0.05", ["--adaptation", "0.05"], ".png"),
    ("bits 16", ["--bits", "16"], ".png"),
    ("hdr", ["--hdr"], ".png"),
    ("p3 no glare", ["--gamut", "p3", "--glare", "off"], ".png"),
    ("rec2020", ["--gamut", "rec2020"], ".png"),
    ("no night shift", ["--night-shift", "off"], ".png"),
    ("false colour", ["--false-colour", "luminance"], ".png"),
    ("false colour log", ["--false-colour", "luminance", "--log"], ".png"),
    ("scale 0.02", ["--scale", "0.02"], ".png"),
    ("scale 50", ["--scale", "50"], ".png"),
    ("exr out", [], ".exr"),
    ("compare", ["--compare", "{tmp}/sheet.png"], ".png"),
]


def digest(path):
    data = Path(path).read_bytes()
    if path.endswith(".exr"):
        data = exr_canonical(data)
    return hashlib.md5(data).hexdigest()


def exr_canonical(data):
    """An EXR's bytes with its header attributes sorted by name: the exr
    crate writes custom attributes in hash order, which changes from run
    to run while the pixels do not."""
    at, attrs = 8, []
    while data[at] != 0:
        start = at
        for _ in range(2):  # name, type: null-terminated
            at = data.index(b"\0", at) + 1
        at += 4 + int.from_bytes(data[at:at + 4], "little")
        attrs.append(data[start:at])
    return data[:8] + b"".join(sorted(attrs)) + data[at:]


def run(binary, exr, opts, out, tmp):
    opts = [o.replace("{tmp}", tmp) for o in opts]
    cmd = [binary, "display", exr, "-o", out, *opts]
    proc = subprocess.run(cmd, capture_output=True, text=True)
    if proc.returncode != 0:
        sys.exit(f"{' '.join(cmd)} failed:\n{proc.stderr}")
    files = [out] + [o for o in opts if o.endswith("sheet.png")]
    return [digest(f) for f in files]


def main():
    if len(sys.argv) < 4:
        sys.exit(__doc__)
    before, after, inputs = sys.argv[1], sys.argv[2], sys.argv[3:]
    differ = 0
    with tempfile.TemporaryDirectory() as a, tempfile.TemporaryDirectory() as b:
        for exr in inputs:
            for name, opts, suffix in CASES:
                da = run(before, exr, opts, f"{a}/out{suffix}", a)
                db = run(after, exr, opts, f"{b}/out{suffix}", b)
                same = da == db
                differ += not same
                print(f"{'same' if same else 'DIFFERS'}  {Path(exr).name}  {name}  {db[0]}")
    print(f"{differ} of {len(CASES) * len(inputs)} differ")
    sys.exit(1 if differ else 0)


if __name__ == "__main__":
    main()
