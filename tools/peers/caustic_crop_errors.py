#!/usr/bin/env python3
"""The caustic's own errors in bench/emission_equal_time.sh's renders (numpy only; PFM in).

  caustic_crop_errors.py WORK_DIR SCENE=X,Y,W,H [SCENE=X,Y,W,H ...]

For every render the study left in WORK_DIR/SCENE/ (LuxCore's and caustica's PFMs, named
ENGINE-or-METHOD-BUDGETs.pfm), the mean absolute error and RMSE against the scene's reference
over the caustic crop's pixels that see a diffuse surface (the study's mask), where the photon
methods differ from the path-traced rest of the image. Prints a markdown table.
"""
import glob
import os
import re
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(__file__))
from equal_time_metrics import read_pfm  # noqa: E402


def main():
    work = sys.argv[1]
    rows = ["| scene | budget (s) | renderer | caustic MAE | caustic RMSE | MAE / best LuxCore |",
            "|---|---:|---|---:|---:|---:|"]
    for arg in sys.argv[2:]:
        scene, crop = arg.split("=")
        x, y, w, h = (int(v) for v in crop.split(","))
        d = os.path.join(work, scene)
        refs = sorted(glob.glob(os.path.join(d, "reference-lt-*.pfm")))
        if not refs:
            continue
        ref = read_pfm(refs[-1])
        mask = read_pfm(os.path.join(d, "mask.pfm"))[..., 0] > 0.5
        sel = np.zeros_like(mask)
        sel[y:y + h, x:x + w] = True
        sel &= mask
        found = {}
        for p in glob.glob(os.path.join(d, "*-*s.pfm")):
            name = os.path.basename(p)[:-4]
            m = re.match(r"(.+)-(\d+)s$", name)
            if not m or name.startswith(("reference", "strip", "cover", "mask")):
                continue
            img = read_pfm(p)
            if img.shape != ref.shape:
                continue
            e = (img - ref)[sel]
            found.setdefault(int(m.group(2)), []).append(
                (m.group(1), float(np.abs(e).mean()), float(np.sqrt((e ** 2).mean()))))
        for budget in sorted(found):
            lux = [mae for n, mae, _ in found[budget] if n.startswith("luxcore")]
            best = min(lux) if lux else float("nan")
            for n, mae, rmse in sorted(found[budget]):
                rows.append(f"| {scene} | {budget} | {n} | {mae:.5f} | {rmse:.5f} | {mae / best:.2f} |")
    print("\n".join(rows))


if __name__ == "__main__":
    main()
