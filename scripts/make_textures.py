#!/usr/bin/env python3
"""Writes the bundled procedural textures (PNG, standard library only):

  scenes/textures/mortar_height.png  Figure 6's block wall: a height map, 1 on the block faces,
                                     0 in the mortar grooves, bevelled edges. 512 x 512 texels
                                     for one 1.6 x 1.6 m repeat (uv_tile = 1.6): 40 x 20 cm
                                     blocks in running bond, 1.2 cm joints with 1.2 cm bevels.
  scenes/textures/studs_normal.png   The studded wall (scenes/studded_wall.toml): a tangent-space
                                     normal map (glTF convention) of one rounded stud per repeat,
                                     128 x 128 texels: height H (1 - (r/R)^2)^2 inside R = 0.4 of
                                     the repeat, H = 0.38 R (slopes up to 30 degrees), flat around.
  tests/data/scene/srgb_levels.png   4 x 1 RGB texels with known 8-bit values for the sRGB
                                     decoding test: (0,0,0) (128,128,128) (188,64,255) (255,255,255).

Run from anywhere: python3 scripts/make_textures.py
"""
import os
import struct
import zlib

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def write_png(path, width, height, channels, rows):
    """rows: list of bytes objects, each width * channels long (8-bit)."""
    colour_type = {1: 0, 3: 2, 4: 6}[channels]

    def chunk(tag, data):
        body = tag + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body) & 0xFFFFFFFF)

    raw = b"".join(b"\x00" + row for row in rows)  # filter type 0 on every row
    png = b"\x89PNG\r\n\x1a\n"
    png += chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, colour_type, 0, 0, 0))
    png += chunk(b"IDAT", zlib.compress(raw, 9))
    png += chunk(b"IEND", b"")
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "wb") as f:
        f.write(png)


def smoothstep(e0, e1, x):
    t = min(max((x - e0) / (e1 - e0), 0.0), 1.0)
    return t * t * (3.0 - 2.0 * t)


def mortar_height(size=512, repeat_m=1.6, block_w=0.4, block_h=0.2, half_joint=0.006, bevel=0.012):
    rows = []
    for j in range(size):
        # Texture row 0 is the top of the image; v runs upwards on the wall.
        y = (size - 0.5 - j) / size * repeat_m
        course = int(y // block_h)
        dy = min(y - course * block_h, (course + 1) * block_h - y)
        offset = 0.5 * block_w if course % 2 else 0.0  # running bond
        row = bytearray()
        for i in range(size):
            x = (i + 0.5) / size * repeat_m + offset
            dx = min(x % block_w, block_w - x % block_w)
            d = min(dx, dy)  # distance to the nearest joint's centre line
            h = smoothstep(half_joint, half_joint + bevel, d)
            row.append(int(round(255 * h)))
        rows.append(bytes(row))
    return rows


def studs_normal(size=128, radius=0.4, height_over_radius=0.38):
    """Rows of RGB bytes: n = normalize(-dh/dx, -dh/dy, 1) encoded as 0.5 n + 0.5 (x right, y up,
    in units of the repeat; the dome is symmetric, so the image's row order does not matter)."""
    rows = []
    h0 = height_over_radius * radius
    for j in range(size):
        y = (size - 0.5 - j) / size - 0.5
        row = bytearray()
        for i in range(size):
            x = (i + 0.5) / size - 0.5
            s2 = (x * x + y * y) / (radius * radius)
            # h = h0 (1 - s2)^2: dh/dx = -4 h0 (1 - s2) x / R^2, likewise y.
            g = -4.0 * h0 * (1.0 - s2) / (radius * radius) if s2 < 1.0 else 0.0
            nx, ny, nz = -g * x, -g * y, 1.0
            norm = (nx * nx + ny * ny + nz * nz) ** 0.5
            row.extend(int(round(255 * (0.5 * c / norm + 0.5))) for c in (nx, ny, nz))
        rows.append(bytes(row))
    return rows


def main():
    write_png(os.path.join(ROOT, "scenes/textures/mortar_height.png"), 512, 512, 1, mortar_height())
    write_png(os.path.join(ROOT, "scenes/textures/studs_normal.png"), 128, 128, 3, studs_normal())
    levels = bytes([0, 0, 0, 128, 128, 128, 188, 64, 255, 255, 255, 255])
    write_png(os.path.join(ROOT, "tests/data/scene/srgb_levels.png"), 4, 1, 3, [levels])


if __name__ == "__main__":
    main()
