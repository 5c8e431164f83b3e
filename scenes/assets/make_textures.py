#!/usr/bin/env python3
"""Makes the procedural textures of scenes/textured_box.ron (standard library only; run from scenes/assets/):
bricks.png (sRGB albedo), bricks_normal.png (tangent-space normal map, raw: x along +u, y along +v, i.e. green
points down the image), tiles.png (sRGB albedo of the floor). 64x64, 8-bit RGB, deterministic."""
import math, struct, zlib

W = H = 64

def png(path, rows):
    raw = b"".join(b"\x00" + bytes(v for px in row for v in px) for row in rows)
    def chunk(t, d):
        c = struct.pack(">I", len(d)) + t + d
        return c + struct.pack(">I", zlib.crc32(t + d) & 0xFFFFFFFF)
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", W, H, 8, 2, 0, 0, 0))
                + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))

def hash01(i, j):
    h = (i * 73856093) ^ (j * 19349663) ^ 0x5bd1e995
    h = (h * 2654435761) & 0xFFFFFFFF
    return (h >> 8) / float(1 << 24)

# Bricks: 4 rows of 2 bricks (16 texels high, 32 wide), every other row offset by half a brick, 2-texel mortar.
def brick_height(x, y):
    row = int(y // 16)
    bx = (x + (16 if row % 2 else 0)) % 32
    by = y % 16
    d = min(bx, 32 - bx, by, 16 - by)  # distance to the mortar line, in texels
    return min(d / 2.5, 1.0)  # 0 in the mortar, 1 on the brick face, a bevel between

def brick_albedo(x, y):
    row = int(y // 16)
    col = int((x + (16 if row % 2 else 0)) // 32)
    if brick_height(x + 0.5, y + 0.5) < 0.35:
        return (200, 195, 185)
    t = hash01(row, col)
    return (int(150 + 50 * t), int(60 + 25 * t), int(40 + 15 * t))

rows = [[brick_albedo(x, y) for x in range(W)] for y in range(H)]
png("bricks.png", rows)

def normal(x, y):
    s = 3.0  # slope scale
    h = lambda a, b: brick_height((a + 0.5) % W, (b + 0.5) % H)
    dx = (h(x + 1, y) - h(x - 1, y)) / 2 * s
    dy = (h(x, y + 1) - h(x, y - 1)) / 2 * s
    n = (-dx, -dy, 1.0)
    l = math.sqrt(sum(c * c for c in n))
    return tuple(int(round(255 * (c / l + 1) / 2)) for c in n)

png("bricks_normal.png", [[normal(x, y) for x in range(W)] for y in range(H)])

def tile(x, y):
    a = (x // 16 + y // 16) % 2
    edge = x % 16 in (0, 15) or y % 16 in (0, 15)
    if edge:
        return (70, 70, 75)
    return (215, 205, 185) if a else (120, 130, 150)

png("tiles.png", [[tile(x, y) for x in range(W)] for y in range(H)])
