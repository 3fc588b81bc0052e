#!/usr/bin/env python3
"""Write scenes/mitsuba/smoke-plume.vol, the density grid of the smoke-plume scene.

  make_plume_vol.py [OUT.vol] [--res 32]

Mitsuba .vol format (little endian): bytes 'V','O','L', version byte 3, int32 encoding 1
(float32), int32 xres, yres, zres, int32 channels (1), six float32 bbox (xmin, ymin, zmin, xmax,
ymax, zmax), then the float32 data x-fastest: data[(z*yres + y)*xres + x].

Voxel (i, j, k) holds the density evaluated at the voxel centre
  u = (i+0.5)/32, v = (j+0.5)/32, w = (k+0.5)/32      (u along x, v along y = up, w along z)
  cx  = 0.5 + 0.08*sin(6v),  cz = 0.5 + 0.08*cos(5v),  rad = 0.12 + 0.25*v
  r2  = (u-cx)^2 + (w-cz)^2
  density = exp(-r2 / (2*rad^2)) * (1 - v) * (1 - 0.3*sin(11u)*sin(13w)),  clamped to >= 0.
The values are computed in float64 and stored as float32. The bbox written into the header is
the medium's box in the scene, x in [-0.6, 0.6], y in [-0.999, 0.6], z in [-0.6, 0.6]; Mitsuba 3
ignores it (gridvolume uses it only with use_grid_bbox=true), the scene's to_world does the
mapping of the unit cube instead.
"""
import argparse
import os
import struct

import numpy as np

BBOX = (-0.6, -0.999, -0.6, 0.6, 0.6, 0.6)


def density(u, v, w):
    cx = 0.5 + 0.08 * np.sin(6 * v)
    cz = 0.5 + 0.08 * np.cos(5 * v)
    rad = 0.12 + 0.25 * v
    r2 = (u - cx) ** 2 + (w - cz) ** 2
    d = np.exp(-r2 / (2 * rad ** 2)) * (1 - v) * (1 - 0.3 * np.sin(11 * u) * np.sin(13 * w))
    return np.maximum(d, 0.0)


def grid(res):
    c = (np.arange(res) + 0.5) / res
    # axes ordered (z, y, x) so that C order is x-fastest: index ((z*yres + y)*xres + x)
    w, v, u = np.meshgrid(c, c, c, indexing="ij")
    return density(u, v, w).astype("<f4")


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    default = os.path.join(here, "..", "..", "scenes", "mitsuba", "smoke-plume.vol")
    ap = argparse.ArgumentParser()
    ap.add_argument("out", nargs="?", default=os.path.normpath(default))
    ap.add_argument("--res", type=int, default=32)
    a = ap.parse_args()
    d = grid(a.res)
    with open(a.out, "wb") as f:
        f.write(b"VOL" + bytes([3]))
        f.write(struct.pack("<iiiii", 1, a.res, a.res, a.res, 1))
        f.write(struct.pack("<6f", *BBOX))
        f.write(d.tobytes(order="C"))
    print(f"{a.out}: {a.res}^3, min {d.min():.6f}, max {d.max():.6f}, mean {d.mean():.6f}")


if __name__ == "__main__":
    main()
