"""Writes scenes/textures/showcase-sky.png: a small procedural
equirectangular sky (Mitsuba's envmap mapping: top row +y) for the material
showcase — a blue gradient overhead, a warm glow near the horizon, a bright
sun disc, and a neutral grey ground. sRGB-encoded 8-bit, made with the
standard library only. Run from the repository root."""

import math
import struct
import zlib

W, H = 256, 128
SUN_THETA, SUN_PHI, SUN_RADIUS = math.radians(55.0), math.radians(140.0), math.radians(3.0)


def encode(v):
    v = max(0.0, min(1.0, v))
    s = 12.92 * v if v <= 0.0031308 else 1.055 * v ** (1 / 2.4) - 0.055
    return int(round(255 * s))


def radiance(theta, phi):
    d = (math.sin(theta) * math.sin(phi), math.cos(theta), -math.sin(theta) * math.cos(phi))
    s = (math.sin(SUN_THETA) * math.sin(SUN_PHI), math.cos(SUN_THETA),
         -math.sin(SUN_THETA) * math.cos(SUN_PHI))
    cos_sun = sum(a * b for a, b in zip(d, s))
    if d[1] < 0.0:
        return (0.18, 0.17, 0.16)
    up = d[1]
    sky = (0.25 + 0.35 * (1 - up), 0.35 + 0.3 * (1 - up), 0.85)
    glow = math.exp(-up * 6.0) * 0.25
    if math.acos(max(-1.0, min(1.0, cos_sun))) < SUN_RADIUS:
        return (1.0, 1.0, 0.95)
    halo = max(0.0, cos_sun) ** 64 * 0.5
    return tuple(min(1.0, c + glow * w + halo) for c, w in zip(sky, (1.0, 0.7, 0.3)))


def main():
    rows = []
    for y in range(H):
        theta = y / (H - 1) * math.pi
        row = bytearray([0])
        for x in range(W):
            phi = (x + 0.5) / W * 2 * math.pi
            row += bytes(encode(c) for c in radiance(theta, phi))
        rows.append(bytes(row))
    raw = zlib.compress(b"".join(rows), 9)

    def chunk(tag, data):
        return struct.pack(">I", len(data)) + tag + data + struct.pack(">I", zlib.crc32(tag + data))

    png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", W, H, 8, 2, 0, 0, 0))
    png += chunk(b"sRGB", b"\x00") + chunk(b"IDAT", raw) + chunk(b"IEND", b"")
    with open("scenes/textures/showcase-sky.png", "wb") as f:
        f.write(png)


if __name__ == "__main__":
    main()
