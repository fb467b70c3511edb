#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
# Means of vplrender's EXR images (32-bit float R, G, B; ZIP or no compression; scan lines) over
# pixel sets, standard library only: the whole image, the two image diagonals (x == y and
# x + y == width - 1 on a square image: on the built-in cornell box at 48x48 they run through
# pixel centres on the box's creases) and the rest. Prints one line per file:
#   FILE image MEAN diagonal MEAN off-diagonal MEAN   (luminance-free: the mean of R, G and B)
import struct
import sys
import zlib


def read_exr(path):
    data = open(path, 'rb').read()
    if struct.unpack_from('<I', data, 0)[0] != 20000630:
        raise SystemExit(f'{path}: not an OpenEXR file')
    pos, attrs = 8, {}
    while data[pos] != 0:
        end = data.index(b'\0', pos); name = data[pos:end].decode(); pos = end + 1
        end = data.index(b'\0', pos); typ = data[pos:end].decode(); pos = end + 1
        size = struct.unpack_from('<i', data, pos)[0]; pos += 4
        attrs[name] = (typ, data[pos:pos + size]); pos += size
    pos += 1
    channels, cl = [], attrs['channels'][1]
    q = 0
    while cl[q] != 0:
        end = cl.index(b'\0', q); name = cl[q:end].decode(); q = end + 1
        ptype = struct.unpack_from('<i', cl, q)[0]; q += 16
        channels.append((name, ptype))
    if any(p != 2 for _, p in channels):
        raise SystemExit(f'{path}: only 32-bit float channels are read')
    xmin, ymin, xmax, ymax = struct.unpack('<4i', attrs['dataWindow'][1])
    w, h = xmax - xmin + 1, ymax - ymin + 1
    comp = attrs['compression'][1][0]
    lines = {0: 1, 2: 1, 3: 16}[comp]  # NO, ZIPS, ZIP
    nchunks = (h + lines - 1) // lines
    offsets = struct.unpack_from(f'<{nchunks}Q', data, pos)
    img = {name: [0.0] * (w * h) for name, _ in channels}
    for off in offsets:
        y0, size = struct.unpack_from('<ii', data, off)
        raw = data[off + 8:off + 8 + size]
        n = min(lines, ymax + 1 - y0)
        if comp != 0 and size < n * w * 4 * len(channels):
            t = bytearray(zlib.decompress(raw))
            for i in range(1, len(t)):  # undo the predictor
                t[i] = (t[i - 1] + t[i] - 128) & 0xFF
            half = (len(t) + 1) // 2  # undo the interleave
            u = bytearray(len(t)); u[0::2] = t[:half]; u[1::2] = t[half:]
            raw = bytes(u)
        q = 0
        for yy in range(n):
            y = y0 + yy - ymin
            for name, _ in channels:  # channels are stored in name order
                vals = struct.unpack_from(f'<{w}f', raw, q); q += 4 * w
                img[name][y * w:(y + 1) * w] = vals
    return w, h, img


if __name__ == '__main__':
    for path in sys.argv[1:]:
        w, h, img = read_exr(path)
        v = [(img['R'][i] + img['G'][i] + img['B'][i]) / 3 for i in range(w * h)]
        diag = [y * w + x for y in range(h) for x in range(w) if w == h and (x == y or x + y == w - 1)]
        ds = set(diag)
        rest = [i for i in range(w * h) if i not in ds]
        mean = lambda idx: sum(v[i] for i in idx) / max(1, len(idx))
        print(f'{path} image {mean(range(w * h)):.6e} diagonal {mean(diag):.6e} off-diagonal {mean(rest):.6e}')
