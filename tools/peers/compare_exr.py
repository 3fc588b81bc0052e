#!/usr/bin/env python3
"""Quick numeric comparison of two EXR images (relative mean difference, per-region means).

  compare_exr.py A.exr B.exr [--blocks N] [--mask-zero]
Uses Mitsuba's Bitmap reader (the peers venv) and numpy. `--mask-zero` ignores pixels that are
black in B (Mitsuba's ptracer leaves pixels that see glass or mirrors directly black).
"""
import argparse

import numpy as np
import mitsuba as mi

mi.set_variant("scalar_rgb")


def load(p):
    return np.array(mi.Bitmap(p), dtype=np.float64)[..., :3]


ap = argparse.ArgumentParser()
ap.add_argument("a")
ap.add_argument("b")
ap.add_argument("--blocks", type=int, default=4)
ap.add_argument("--mask-zero", action="store_true")
args = ap.parse_args()
a, b = load(args.a), load(args.b)
if a.shape != b.shape:
    raise SystemExit(f"size mismatch: {a.shape} vs {b.shape}")
mask = np.ones(a.shape[:2], bool)
if args.mask_zero:
    mask = b.sum(-1) > 0
ma, mb = a[mask].mean(0), b[mask].mean(0)
print(f"mean A {ma}, mean B {mb}, relative difference {(ma - mb) / mb}")
rmse = np.sqrt(((a - b)[mask] ** 2).mean())
print(f"RMSE {rmse:.5f}, relative RMSE {rmse / b[mask].mean():.4f}")
n = args.blocks
h, w = a.shape[0] // n, a.shape[1] // n
print(f"{n}x{n} block relative differences of the channel mean (A/B - 1):")
for by in range(n):
    row = []
    for bx in range(n):
        sa = a[by * h:(by + 1) * h, bx * w:(bx + 1) * w].mean()
        sb = b[by * h:(by + 1) * h, bx * w:(bx + 1) * w].mean()
        row.append(f"{(sa / sb - 1) * 100:+6.1f}%" if sb > 0 else "   n/a ")
    print("  " + " ".join(row))
