#!/usr/bin/env python3
"""Colour copies of 8-bit grey PNG frames, for the CLI test (standard library only).

    png_colour.py rgb|rgba IN.png OUT.png

Each grey value g becomes (R, G, B) = (g + 5, g, g - 13) where that stays in
0..255, else (g, g, g). With the ITU-R BT.601 weights of OpenCV's BGR2GRAY,
0.299 * 5 - 0.114 * 13 = 0.013, so the grey conversion gives g back exactly,
while swapped red and blue channels would give about g - 3.3. rgba adds an
opaque alpha channel.
"""
import struct
import sys
import zlib


def chunks(data):
    pos = 8
    while pos < len(data):
        (length,) = struct.unpack(">I", data[pos:pos + 4])
        kind = data[pos + 4:pos + 8]
        yield kind, data[pos + 8:pos + 8 + length]
        pos += 12 + length


def read_grey(path):
    with open(path, "rb") as f:
        data = f.read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise SystemExit(path + ": not a PNG")
    idat = b""
    for kind, body in chunks(data):
        if kind == b"IHDR":
            width, height, depth, colour, _, _, interlace = struct.unpack(">IIBBBBB", body)
            if depth != 8 or colour != 0 or interlace != 0:
                raise SystemExit(path + ": not an 8-bit grey non-interlaced PNG")
        elif kind == b"IDAT":
            idat += body
    raw = zlib.decompress(idat)
    rows, prev, pos = [], bytearray(width), 0
    for _ in range(height):
        kind, line = raw[pos], bytearray(raw[pos + 1:pos + 1 + width])
        pos += 1 + width
        for i in range(width):
            a = line[i - 1] if i > 0 else 0
            b = prev[i]
            c = prev[i - 1] if i > 0 else 0
            if kind == 1:
                line[i] = (line[i] + a) & 255
            elif kind == 2:
                line[i] = (line[i] + b) & 255
            elif kind == 3:
                line[i] = (line[i] + (a + b) // 2) & 255
            elif kind == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                pred = a if pa <= pb and pa <= pc else (b if pb <= pc else c)
                line[i] = (line[i] + pred) & 255
        rows.append(line)
        prev = line
    return width, height, rows


def write_colour(path, width, height, rows, alpha):
    raw = bytearray()
    for line in rows:
        raw.append(0)
        for g in line:
            r, b = (g + 5, g - 13) if 13 <= g <= 250 else (g, g)
            raw += bytes((r, g, b, 255) if alpha else (r, g, b))

    def chunk(kind, body):
        return (struct.pack(">I", len(body)) + kind + body +
                struct.pack(">I", zlib.crc32(kind + body) & 0xFFFFFFFF))

    header = struct.pack(">IIBBBBB", width, height, 8, 6 if alpha else 2, 0, 0, 0)
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) +
                chunk(b"IDAT", zlib.compress(bytes(raw), 6)) + chunk(b"IEND", b""))


def main():
    if len(sys.argv) != 4 or sys.argv[1] not in ("rgb", "rgba"):
        raise SystemExit(__doc__)
    width, height, rows = read_grey(sys.argv[2])
    write_colour(sys.argv[3], width, height, rows, sys.argv[1] == "rgba")


if __name__ == "__main__":
    main()
