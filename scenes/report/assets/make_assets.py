#!/usr/bin/env python3
"""Writes the small inputs of the report's stability atlas (standard library only; run from this directory):

- planar_stack.obj: a 40 x 40 tessellated square in the plane y = 0 (3200 coplanar triangles sharing vertices and
  edges) and a stack of 64 identical triangles standing on it: planar and degenerate input for the kd-tree.
- sky_nan.exr: a 32 x 16 equirectangular sky (uniform 0.8) with a NaN texel and a negative texel.
- sky_inf.exr: the same sky with one +infinite texel.

The EXR files are uncompressed scanline images with three FLOAT channels (B, G, R), written byte by byte.
"""
import math
import struct


def planar_stack(path):
    n = 40
    lines = [
        "# planar_stack.obj: a 40 x 40 tessellated square in the plane y = 0 (3200 coplanar triangles sharing vertices",
        "# and edges) and a stack of 64 identical triangles standing on it: planar and degenerate input for the kd-tree.",
        "# Written by scenes/report/assets/make_assets.py.",
    ]
    for j in range(n + 1):
        for i in range(n + 1):
            lines.append(f"v {i * 0.25 - 5:g} 0 {j * 0.25 - 5:g}")

    def vid(i, j):
        return j * (n + 1) + i + 1

    for j in range(n):
        for i in range(n):
            a, b, c, d = vid(i, j), vid(i + 1, j), vid(i + 1, j + 1), vid(i, j + 1)
            lines.append(f"f {a} {d} {c}")
            lines.append(f"f {a} {c} {b}")
    base = (n + 1) * (n + 1)
    lines += ["v -1 0 0.5", "v 1 0 0.5", "v 0 1.6 0.5"]
    lines += [f"f {base + 1} {base + 2} {base + 3}"] * 64
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


def attr(name, kind, data):
    return name.encode() + b"\0" + kind.encode() + b"\0" + struct.pack("<i", len(data)) + data


def write_exr(path, w, h, pixel):
    """pixel(x, y) -> (r, g, b) floats; uncompressed, increasing-y scanlines, channels in alphabetical order."""
    channels = b"".join(c.encode() + b"\0" + struct.pack("<iBBBBii", 2, 0, 0, 0, 0, 1, 1) for c in "BGR") + b"\0"
    header = struct.pack("<ii", 20000630, 2)
    header += attr("channels", "chlist", channels)
    header += attr("compression", "compression", b"\0")
    header += attr("dataWindow", "box2i", struct.pack("<iiii", 0, 0, w - 1, h - 1))
    header += attr("displayWindow", "box2i", struct.pack("<iiii", 0, 0, w - 1, h - 1))
    header += attr("lineOrder", "lineOrder", b"\0")
    header += attr("pixelAspectRatio", "float", struct.pack("<f", 1.0))
    header += attr("screenWindowCenter", "v2f", struct.pack("<ff", 0.0, 0.0))
    header += attr("screenWindowWidth", "float", struct.pack("<f", 1.0))
    header += b"\0"
    line_bytes = w * 3 * 4
    first = len(header) + 8 * h
    offsets = b"".join(struct.pack("<Q", first + y * (8 + line_bytes)) for y in range(h))
    lines = b""
    for y in range(h):
        px = [pixel(x, y) for x in range(w)]
        data = b"".join(struct.pack("<f", p[c]) for c in (2, 1, 0) for p in px)
        lines += struct.pack("<ii", y, len(data)) + data
    with open(path, "wb") as f:
        f.write(header + offsets + lines)


def sky(bad):
    def pixel(x, y):
        return bad.get((x, y), (0.8, 0.8, 0.8))

    return pixel


if __name__ == "__main__":
    planar_stack("planar_stack.obj")
    write_exr("sky_nan.exr", 32, 16, sky({(5, 4): (math.nan, math.nan, math.nan), (20, 9): (-3.0, -3.0, -3.0)}))
    write_exr("sky_inf.exr", 32, 16, sky({(12, 6): (math.inf, math.inf, math.inf)}))
