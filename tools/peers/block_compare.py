#!/usr/bin/env python3
"""Block test between two renderers, with the noise measured from independent renders.

  block_compare.py --a A1.exr A2.exr [A3 ...] --b B1.exr B2.exr [B3 ...]
                   [--block 16] [--z 4] [--check TOL] [--names A B]

Each side is two or more renders of the same scene with different seeds (EXR via Mitsuba's
Bitmap, or PFM, e.g. pbrt-v3's output, read here). For each side the mean image of its renders is
compared with the other's, per block of BLOCKxBLOCK pixels (edge blocks may be smaller) on the
channel mean (R+G+B)/3:

  z = (mean_A - mean_B) / sqrt(var_A + var_B),

where var is the variance of a block mean of the side's averaged image, estimated from its own
renders: per pixel, the sample variance over the n renders; per block, their sum / (n * pixels^2)
(the variance if pixels were independent), times a correlation factor kappa, one per side: pixel
filters wider than a pixel (Mitsuba's gaussian, radius 2) correlate neighbouring pixels.
kappa = sum over lags |dx|, |dy| <= 3 of the autocorrelation of the residuals (render minus
mean of renders, clipped to their 99th percentile of |residual| against fireflies), pooled over
the image and the renders (1 for independent pixels, e.g. a box filter). With two renders that
estimate scatters by about +-30 %; give it when known with --kappa-a/--kappa-b: 1 for a box
filter, 3.13 for Mitsuba's default gaussian (stddev 0.5, radius 2; the square of
sum_d E[w(x) w(x-d)] / E[w(x)^2] for uniform sample positions x, which the estimate scatters
around). Blocks with |z| > Z are flagged. The whole-image relative mean difference is printed
with its own z (block variances summed). Blocks black in every render of both sides are skipped.
With two renders per side each block variance has one degree of freedom per pixel: expect rms z
a little above 1 and heavy tails from fireflies; more renders per side make the test sharper.

Exit status 1 if a block is flagged or (with --check TOL) |relative mean difference| > TOL.
"""
import argparse
import sys

import numpy as np


def read_pfm(path):
    with open(path, "rb") as f:
        kind = f.readline().strip()
        if kind not in (b"PF", b"Pf"):
            raise SystemExit(f"{path}: not a PFM file")
        dims = f.readline().split()
        while not dims:
            dims = f.readline().split()
        w, h = int(dims[0]), int(dims[1])
        scale = float(f.readline().strip())
        ch = 3 if kind == b"PF" else 1
        data = np.frombuffer(f.read(w * h * ch * 4), dtype="<f4" if scale < 0 else ">f4")
    img = data.reshape(h, w, ch)[::-1].astype(np.float64)  # PFM rows run bottom to top
    return np.repeat(img, 3, axis=2) if ch == 1 else img


def read(path):
    if path.lower().endswith(".pfm"):
        return read_pfm(path)
    import mitsuba as mi
    mi.set_variant("scalar_rgb")
    img = np.array(mi.Bitmap(path), dtype=np.float64)
    if img.ndim == 2:
        img = img[..., None].repeat(3, axis=2)
    return img[..., :3]


def blocks(shape, b):
    h, w = shape
    for y0 in range(0, h, b):
        for x0 in range(0, w, b):
            yield y0 // b, x0 // b, slice(y0, min(y0 + b, h)), slice(x0, min(x0 + b, w))


class Side:
    def __init__(self, paths, bsize, kappa=None, mask=None):
        if len(paths) < 2:
            raise SystemExit("each side needs at least two independent renders")
        imgs = np.stack([read(p).mean(axis=2) for p in paths])  # (n, h, w), channel mean
        self.rgb = np.mean([read(p) for p in paths], axis=0)
        if mask is None:
            mask = np.ones(imgs.shape[1:], bool)
        self.mask = mask
        self.n = len(paths)
        self.mean = imgs.mean(axis=0)
        var_pix = imgs.var(axis=0, ddof=1)
        self.shape = self.mean.shape
        self.any_light = (imgs != 0).any(axis=0)
        res = imgs - self.mean
        q = np.quantile(np.abs(res), 0.99)
        self.kappa_est = correlation_factor(np.clip(res, -q, q))
        self.kappa = self.kappa_est if kappa is None else kappa
        self.bmean, self.bvar = {}, {}
        for by, bx, sy, sx in blocks(self.shape, bsize):
            m = mask[sy, sx]
            npix = int(m.sum())
            if npix == 0:
                continue
            self.bmean[by, bx] = self.mean[sy, sx][m].mean()
            # variance of the block mean of the n-render average
            self.bvar[by, bx] = self.kappa * var_pix[sy, sx][m].sum() / npix ** 2 / self.n


def correlation_factor(res, lag=3):
    """Sum of the residuals' spatial autocorrelation over lags |dx|, |dy| <= lag."""
    n, h, w = res.shape
    c0 = (res ** 2).sum()
    if c0 == 0:
        return 1.0
    total = 0.0
    for dy in range(-lag, lag + 1):
        for dx in range(-lag, lag + 1):
            a = res[:, max(0, dy):h + min(0, dy), max(0, dx):w + min(0, dx)]
            b = res[:, max(0, -dy):h + min(0, -dy), max(0, -dx):w + min(0, -dx)]
            total += (a * b).sum() / (a.size / res.size)  # per-pair normalisation of the overlap
    return max(total / c0, 1e-3)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--a", nargs="+", required=True)
    ap.add_argument("--b", nargs="+", required=True)
    ap.add_argument("--names", nargs=2, default=["A", "B"])
    ap.add_argument("--block", type=int, default=16)
    ap.add_argument("--z", type=float, default=4.0)
    ap.add_argument("--kappa-a", type=float, default=None, help="noise correlation factor of A (default: estimated)")
    ap.add_argument("--kappa-b", type=float, default=None, help="noise correlation factor of B (default: estimated)")
    ap.add_argument("--check", type=float, default=None, help="fail if |relative mean difference| > CHECK")
    ap.add_argument("--mask", default=None,
                    help="image (EXR/PFM) of the same size: only pixels where it is non-zero are compared "
                         "(e.g. leave out pixels that see glass directly, which a light tracer cannot render)")
    a = ap.parse_args()
    na, nb = a.names
    mask = None if a.mask is None else read(a.mask).mean(axis=2) != 0
    A, B = Side(a.a, a.block, a.kappa_a, mask), Side(a.b, a.block, a.kappa_b, mask)
    if A.shape != B.shape:
        raise SystemExit(f"size mismatch: {A.shape} vs {B.shape}")
    ma, mb = A.mean[A.mask].mean(), B.mean[B.mask].mean()
    if mask is not None:
        print(f"mask {a.mask}: {int(mask.sum())} of {mask.size} pixels compared")
    nblk = len(A.bmean)
    gvar = (sum(A.bvar.values()) + sum(B.bvar.values())) / nblk ** 2
    gz = (ma - mb) / np.sqrt(gvar) if gvar > 0 else float("inf") * np.sign(ma - mb)
    rel = (ma - mb) / mb if mb != 0 else float("nan")
    print(f"{na}: {A.n} renders, mean RGB {np.round(A.rgb.mean(axis=(0, 1)), 6)}, noise correlation kappa {A.kappa:.2f} (estimate {A.kappa_est:.2f})")
    print(f"{nb}: {B.n} renders, mean RGB {np.round(B.rgb.mean(axis=(0, 1)), 6)}, noise correlation kappa {B.kappa:.2f} (estimate {B.kappa_est:.2f})")
    print(f"relative mean difference {na}/{nb} - 1 = {rel * 100:+.3f} % "
          f"(+- {np.sqrt(gvar) / mb * 100:.3f} % 1 sigma, z = {gz:+.2f})")
    h, w = A.shape
    gy, gx = -(-h // a.block), -(-w // a.block)
    grid = np.full((gy, gx), np.nan)
    flagged = []
    for (by, bx), m in A.bmean.items():
        sy = slice(by * a.block, min((by + 1) * a.block, h))
        sx = slice(bx * a.block, min((bx + 1) * a.block, w))
        valid = A.mask[sy, sx]
        if not (A.any_light[sy, sx][valid].any() or B.any_light[sy, sx][valid].any()):
            continue
        d = m - B.bmean[by, bx]
        v = A.bvar[by, bx] + B.bvar[by, bx]
        z = d / np.sqrt(v) if v > 0 else (0.0 if d == 0 else np.inf * np.sign(d))
        grid[by, bx] = z
        if abs(z) > a.z:
            flagged.append((by, bx, z, m, B.bmean[by, bx]))
    print(f"z per {a.block}x{a.block} block (rows top to bottom, '.' = black in all renders):")
    for row in grid:
        print("  " + " ".join("   .  " if np.isnan(z) else f"{z:+6.1f}" for z in row))
    zs = grid[~np.isnan(grid)]
    print(f"{zs.size} blocks tested, rms z {np.sqrt((zs ** 2).mean()):.2f} (about 1 when both sides agree "
          f"and the noise estimate is right), {len(flagged)} flagged (|z| > {a.z:g})")
    for by, bx, z, m1, m2 in flagged:
        print(f"  block row {by} col {bx} (pixels x {bx * a.block}.., y {by * a.block}..): "
              f"{na} {m1:.5g}, {nb} {m2:.5g}, {(m1 / m2 - 1) * 100 if m2 else float('inf'):+.2f} %, z {z:+.1f}")
    bad = bool(flagged) or (a.check is not None and not abs(rel) <= a.check)
    print("RESULT: " + ("DIFFERENT" if bad else "agree") +
          f" (relative mean difference {rel * 100:+.3f} %, {len(flagged)} flagged blocks)")
    sys.exit(1 if bad else 0)


if __name__ == "__main__":
    main()
