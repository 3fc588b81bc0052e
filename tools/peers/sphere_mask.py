#!/usr/bin/env python3
"""Writes a PFM mask that is 0 where a pinhole camera sees a sphere (any of 4x4 rays per pixel),
1 elsewhere: light tracers cannot render pixels that see glass directly (L ... S E), so
comparisons with them leave those pixels out (block_compare.py --mask).

  sphere_mask.py --eye 0 1.1 4.5 --target 0 0.8 0 --fov 40 --size 128 96 \
                 --sphere 0 1.2 0 0.5 --out mask.pfm
`--fov` is along x (Mitsuba's fov_axis x); the image's top row is written first in the usual
top-down orientation of caustica and Mitsuba images (PFM stores rows bottom-up).
"""
import argparse
import math
import struct


def sub(a, b):
    return [a[i] - b[i] for i in range(3)]


def norm(a):
    n = math.sqrt(sum(x * x for x in a))
    return [x / n for x in a]


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--eye", nargs=3, type=float, required=True)
    ap.add_argument("--target", nargs=3, type=float, required=True)
    ap.add_argument("--up", nargs=3, type=float, default=[0, 1, 0])
    ap.add_argument("--fov", type=float, required=True)
    ap.add_argument("--size", nargs=2, type=int, required=True)
    ap.add_argument("--sphere", nargs=4, type=float, required=True)
    ap.add_argument("--margin", type=float, default=1.02, help="radius factor")
    ap.add_argument("--out", required=True)
    a = ap.parse_args()
    w, h = a.size
    f = norm(sub(a.target, a.eye))
    r = norm(cross(f, a.up))
    u = cross(r, f)
    t = math.tan(math.radians(a.fov) / 2)
    c, rad = a.sphere[:3], a.sphere[3] * a.margin
    oc = sub(a.eye, c)
    rows = []
    for j in range(h):
        row = []
        for i in range(w):
            hit = False
            for sj in range(4):
                for si in range(4):
                    x = (2 * (i + (si + 0.5) / 4) / w - 1) * t
                    y = (1 - 2 * (j + (sj + 0.5) / 4) / h) * t * h / w
                    d = norm([f[k] + x * r[k] + y * u[k] for k in range(3)])
                    b = sum(oc[k] * d[k] for k in range(3))
                    cc = sum(v * v for v in oc) - rad * rad
                    if b * b - cc >= 0 and -b + math.sqrt(b * b - cc) > 0:
                        hit = True
            row.append(0.0 if hit else 1.0)
        rows.append(row)
    with open(a.out, "wb") as fh:
        fh.write(f"Pf\n{w} {h}\n-1.0\n".encode())
        for row in reversed(rows):
            fh.write(struct.pack(f"<{w}f", *row))


if __name__ == "__main__":
    main()
