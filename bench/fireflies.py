"""Counts fireflies: pixels whose luminance exceeds k× the median of their
5×5 neighbours (the pixel itself left out), for k = 2, 3, 5, 10, 20.

    python bench/fireflies.py IMAGE.exr|IMAGE.png [...] [--lamp CD] [--halo PX]
        [--channel Y|X|Z|V] [--structure OTHER]

An EXR is read as scotopia writes it: channel Y (cd/m²), or the one
--channel names (X, Z, or V for scotopic V′; the lamps are found by Y
whichever is counted). A PNG (8-bit grey, RGB or RGBA, as `scotopia
display` writes it) is read by the relative luminance of its linearised
sRGB values (Rec. 709 weights). The lamps and their halos are left out: every pixel within
--halo pixels of one brighter than --lamp cd/m² (EXR) or of a saturated
one (PNG), where a lamp's edge and glare are sharp by nature. Values
below a floor count as the floor (EXR: 1e-6 of the maximum outside the
lamps; PNG: linear luma 0.01, sRGB code 25), so that a dim pixel among
black ones, or one 8-bit step, is not an outlier.

A thin bright line (a lamp post two pixels wide) also stands above its
neighbours' median, in every render. With --structure OTHER (the same
picture rendered with another --seed, same kind of file) the pixels more
than 2× their neighbours' median there are structure, not noise, and are
not counted (noise puts 0.6 % of the night street's pixels there in Y,
1.6 % in Z, at 256 spp).
"""

import argparse
import struct
import sys
import zlib
from pathlib import Path

import numpy as np
from scipy import ndimage


def read_exr(path, channel):
    """The EXR's `channel` and its Y."""
    import OpenEXR

    with OpenEXR.File(str(path)) as f:
        ch = f.channels()
        if channel not in ch:
            sys.exit(f"{path}: no channel {channel} (has {', '.join(ch)})")
        return (np.asarray(ch[channel].pixels, dtype=np.float64),
                np.asarray(ch["Y"].pixels, dtype=np.float64))


def read_png_luma(path):
    """The PNG's luma, 0–1 (non-interlaced, 8 bits per sample)."""
    data = Path(path).read_bytes()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        sys.exit(f"{path}: not a PNG")
    pos, idat, head = 8, b"", None
    while pos < len(data):
        (n,) = struct.unpack(">I", data[pos:pos + 4])
        kind, body = data[pos + 4:pos + 8], data[pos + 8:pos + 8 + n]
        if kind == b"IHDR":
            head = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat += body
        pos += 12 + n
    w, h, depth, colour, _, _, interlace = head
    channels = {0: 1, 2: 3, 4: 2, 6: 4}.get(colour)
    if depth != 8 or channels is None or interlace:
        sys.exit(f"{path}: only 8-bit non-interlaced grey/RGB/RGBA PNGs are read")
    raw = zlib.decompress(idat)
    stride, bpp = w * channels, channels
    out = np.zeros((h, stride), dtype=np.int32)
    prev = np.zeros(stride, dtype=np.int32)
    for y in range(h):
        row = raw[y * (stride + 1):(y + 1) * (stride + 1)]
        f, line = row[0], np.frombuffer(row[1:], dtype=np.uint8).astype(np.int32)
        if f == 0:
            cur = line
        elif f == 2:
            cur = (line + prev) & 255
        else:  # Sub, Average, Paeth depend on the bytes to the left: byte by byte.
            cur = np.zeros(stride, dtype=np.int32)
            for i in range(stride):
                a = cur[i - bpp] if i >= bpp else 0
                b, c = prev[i], (prev[i - bpp] if i >= bpp else 0)
                if f == 1:
                    p = a
                elif f == 3:
                    p = (a + b) // 2
                else:
                    pa, pb, pc = abs(b - c), abs(a - c), abs(a + b - 2 * c)
                    p = a if pa <= pb and pa <= pc else (b if pb <= pc else c)
                cur[i] = (line[i] + p) & 255
        out[y], prev = cur, cur
    px = out.reshape(h, w, channels)[..., : 3 if channels >= 3 else 1] / 255.0
    lin = np.where(px <= 0.04045, px / 12.92, ((px + 0.055) / 1.055) ** 2.4)
    if lin.shape[-1] == 1:
        return lin[..., 0]
    return lin @ np.array([0.2126, 0.7152, 0.0722])


KS = (2, 3, 5, 10, 20)


def ratios(y, lamps, halo, floor):
    """Each pixel of `y` over its neighbours' median (0 where the mask
    `lamps`, grown by `halo`, leaves it out), and the pixels left out."""
    yf = np.maximum(y, floor)
    foot = np.ones((5, 5), dtype=bool)
    foot[2, 2] = False
    med = ndimage.median_filter(yf, footprint=foot, mode="nearest")
    if halo:
        lamps = ndimage.binary_dilation(lamps, iterations=halo)
    return np.where(lamps, 0.0, yf / med), int(lamps.sum())


def load(path, args):
    """The counted values, the lamp mask and the floor of one image."""
    if path.lower().endswith(".png"):
        y = read_png_luma(path)
        return y, y >= 0.999, 0.01
    y, lum = read_exr(path, args.channel)
    lamps = lum >= args.lamp
    return y, lamps, 1e-6 * np.max(y, where=~lamps, initial=0.0)


def reorder(loaded, halo):
    """`load`'s result as `ratios`' arguments."""
    y, lamps, floor = loaded
    return y, lamps, halo, floor


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("images", nargs="+")
    ap.add_argument("--lamp", type=float, default=1000.0,
                    help="EXR: luminance (cd/m²) from which a pixel is a lamp (default 1000)")
    ap.add_argument("--halo", type=int, default=6,
                    help="pixels around a lamp left out (default 6)")
    ap.add_argument("--channel", default="Y", choices=["X", "Y", "Z", "V"],
                    help="EXR: the channel counted (default Y)")
    ap.add_argument("--structure", metavar="OTHER",
                    help="the same picture with another seed: outliers in both are not counted")
    args = ap.parse_args()
    other = None
    if args.structure:
        other, _ = ratios(*reorder(load(args.structure, args), args.halo))
    for path in args.images:
        r, masked = ratios(*reorder(load(path, args), args.halo))
        if other is not None and other.shape != r.shape:
            sys.exit(f"{path}: {r.shape} pixels, --structure has {other.shape}")
        if other is not None:
            r = np.where(other > KS[0], 0.0, r)
        c = {k: int((r > k).sum()) for k in KS}
        counts = "  ".join(f">{k}x {n}" for k, n in c.items())
        note = ", structure left out" if other is not None else ""
        print(f"{path}: {counts}  (lamp pixels left out: {masked}{note})")


if __name__ == "__main__":
    main()
