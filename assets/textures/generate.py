#!/usr/bin/env python3
"""Generates the default scene's albedo textures in this folder (committed;
re-run to regenerate; deterministic). 8-bit sRGB PNG, written with the
standard library only (zlib).

  pool_tiles.png  256 x 256: 4 x 4 glazed pool tiles (light aqua, each
                  tile a little different) and grey grout
                  lines 4 texels wide -- with "projection": "box" and
                  "scale": 1.25 the image covers 0.8 m, tiles of 0.2 m
  deck_stone.png  256 x 256: 2 x 2 sandstone slabs with fine grain and
                  darker joints
"""
import os
import random
import struct
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))


def write_png(name, w, h, pixel):
    rows = bytearray()
    for y in range(h):
        rows.append(0)  # filter: none
        for x in range(w):
            rows.extend(bytes(max(0, min(255, int(round(c)))) for c in pixel(x, y)))

    def chunk(tag, data):
        return struct.pack(">I", len(data)) + tag + data + struct.pack(">I", zlib.crc32(tag + data) & 0xFFFFFFFF)

    png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
    png += chunk(b"IDAT", zlib.compress(bytes(rows), 9)) + chunk(b"IEND", b"")
    with open(os.path.join(HERE, name), "wb") as f:
        f.write(png)


def value_noise(rng, n):
    """A tileable n x n grid of random values, read bilinearly."""
    g = [[rng.random() for _ in range(n)] for _ in range(n)]

    def at(u, v):
        x, y = u * n, v * n
        i, j = int(x) % n, int(y) % n
        fx, fy = x - int(x), y - int(y)
        a = g[j][i] * (1 - fx) + g[j][(i + 1) % n] * fx
        b = g[(j + 1) % n][i] * (1 - fx) + g[(j + 1) % n][(i + 1) % n] * fx
        return a * (1 - fy) + b * fy

    return at


def pool_tiles():
    rng = random.Random(45)
    size, tiles, grout = 256, 4, 4
    step = size // tiles
    shade = [[0.94 + 0.06 * rng.random() for _ in range(tiles)] for _ in range(tiles)]
    noise = value_noise(rng, 32)

    def pixel(x, y):
        gx, gy = (x + grout // 2) % step, (y + grout // 2) % step
        if gx < grout or gy < grout:
            return (150, 158, 160)
        s = shade[y // step][x // step] * (0.97 + 0.03 * noise(x / size, y / size))
        return (150 * s, 208 * s, 228 * s)

    write_png("pool_tiles.png", size, size, pixel)


def deck_stone():
    rng = random.Random(7)
    size, slabs, joint = 256, 2, 3
    step = size // slabs
    tone = [[0.9 + 0.1 * rng.random() for _ in range(slabs)] for _ in range(slabs)]
    coarse, fine = value_noise(rng, 8), value_noise(rng, 64)

    def pixel(x, y):
        gx, gy = (x + joint // 2) % step, (y + joint // 2) % step
        if gx < joint or gy < joint:
            return (120, 108, 92)
        s = tone[y // step][x // step] * (0.88 + 0.08 * coarse(x / size, y / size) + 0.06 * fine(x / size, y / size))
        return (214 * s, 192 * s, 160 * s)

    write_png("deck_stone.png", size, size, pixel)


if __name__ == "__main__":
    pool_tiles()
    deck_stone()
