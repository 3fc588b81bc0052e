#!/usr/bin/env python3
"""Summarises bench/pcf_study.sh (issue 21, item 7): photon cone focusing (seed 001 ch. 4-5)
against independent sppm references, at probe points, at equal time, in ablations and sweeps.

usage: summarize_pcf_study.py WORK_DIR OUT_DIR
Reads WORK_DIR/params.txt and the renders' PFM images, summaries and notes; writes OUT_DIR/study.md
(tables), OUT_DIR/*.csv, OUT_DIR/*.svg, OUT_DIR/images/*.png and OUT_DIR/index.html.

The reference of each scene is the mean of two sppm halves (seeds 101 and 102); its own noise is
half the RMSE between the halves (the mean of two independent halves has half the variance of
their difference per pixel... precisely: Var(mean) = Var(a - b) / 4). Probe values are the mean
luminance (Rec. 709) of a 3x3 pixel block; a probe reference's noise is the RMS of (a - b) / 2
over the block divided by 3 (nine independent pixels).
pcf's schedule (seed 001 eq. 3.27, t = theta_1 (sigma / sigma_1)^p): sigma_i solves
sigma^2 (1 - cos t(sigma)) = sigma_1^2 (1 - cos theta_1) Gamma(i + alpha) / (Gamma(1 + alpha) Gamma(i + 1)).
Theory (Lemma 3.1-3.3): variance ~ N^-alpha, bias ~ N^((alpha - 1)/(p + 1)), so the error at a
probe falls like N^-min(alpha/2, (1 - alpha)/(p + 1)) once bias and noise are both shrinking.
"""
import csv
import html
import math
import os
import re
import subprocess
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import svg_plot  # noqa: E402

work, out = sys.argv[1:3]
os.makedirs(os.path.join(out, "images"), exist_ok=True)
BIN = os.path.join(work, "bin", "caustica")
P = dict(kv.split("=", 1) for kv in open(os.path.join(work, "params.txt")).read().split() if "=" in kv)
RES, T = int(P["RES"]), float(P["T"])
S = RES / 128.0
SCENES = ["mirror-caustic-box", "torus-glass", "painting-sheet"]
METHODS = ["pcf", "pcf-nested-off", "pcf-cap", "sppm", "pppm", "ppds", "path", "lighttrace"]
COLOURS = {"pcf": "#d62728", "pcf-nested-off": "#e377c2", "pcf-cap": "#8c564b", "sppm": "#2ca02c", "pppm": "#1f5fd6", "ppds": "#9467bd", "path": "#555555",
           "lighttrace": "#ff7f0e", "A": "#d62728", "B": "#1f5fd6", "C": "#2ca02c"}
# Probe blocks (centre column, row at 128 x 128; scaled with RES), chosen on the reference:
PROBES = {
    "mirror-caustic-box": {"A": (51, 114, "floor caustic of the glass ball (peak)"),
                           "B": (74, 100, "the caustic's reflection in the mirror ball"),
                           "C": (108, 94, "green wall in the mirror ball's shadow (indirect light)")},
    "torus-glass": {"A": (42, 88, "dim part of the glass ball (lower left)"),
                    "B": (80, 102, "bright caustic on the floor"),
                    "C": (45, 62, "the torus seen through the glass")},
}
# Regions (x, y, w, h at 128 x 128): the mirror ball around the reflected caustic; the painting
# (inset 3 px from its edges as seen through the plate).
PAINTING_CENTRE = 0.8150
REGIONS = {"mirror-caustic-box": ("mirror ball (reflected caustic)", (68, 90, 16, 16)),
           "painting-sheet": ("painting (behind the glass)", (35, 43, 58, 42))}


def scaled(r):
    return tuple(max(1, int(round(v * S))) for v in r)


def rpfm(p):
    with open(p, "rb") as f:
        h = f.readline().strip()
        w, hh = map(int, f.readline().split())
        sc = float(f.readline())
        d = np.fromfile(f, "<f4" if sc < 0 else ">f4")
    c = 3 if h == b"PF" else 1
    return np.flipud(d.reshape(hh, w, c)).astype(np.float64)


def wpfm(p, a):
    a = np.flipud(a).astype("<f4")
    with open(p, "wb") as f:
        f.write(b"PF\n%d %d\n-1.0\n" % (a.shape[1], a.shape[0]))
        a.tofile(f)


def lum(a):
    return a[..., 0] * 0.2126 + a[..., 1] * 0.7152 + a[..., 2] * 0.0722


def compare(img, ref, crop=None):
    cmd = [BIN, "compare", img, ref] + (["--crop", ",".join(map(str, crop))] if crop else [])
    o = subprocess.run(cmd, capture_output=True, text=True, check=True).stdout

    def g(k):  # nan where compare prints n/a (SSIM of a region narrower than its window)
        m = re.search(rf"^{k}\s+([-+0-9.eE]+)", o, re.M)
        return float(m.group(1)) if m else float("nan")
    return {"rmse": g("RMSE"), "ssim": g(r"SSIM \(display\)"), "rel": g("relative mean difference")}


def block(a, x, y):
    x, y = int(round(x * S)), int(round(y * S))
    return lum(a)[y - 1:y + 2, x - 1:x + 2]


def iterations(prefix):
    """(iteration, seconds, pfm) of a render's saved images, then its final image."""
    p = prefix + ".exr.iterations.csv"
    rows = []
    if os.path.exists(p):
        with open(p) as f:
            for r in csv.DictReader(f):
                rows.append((int(r["iteration"]), float(r["seconds"]), r["image"][:-4] + ".pfm"))
    s = summary(prefix)
    if s and s.get("iterations") and (not rows or rows[-1][0] != s["iterations"]):
        rows.append((s["iterations"], s["seconds"], prefix + ".pfm"))
    return rows


def summary(prefix):
    p = prefix + ".txt"
    if not os.path.exists(p):
        return None
    t = open(p).read()
    r = {"seconds": float(re.search(r"in ([0-9.]+) s", t).group(1))}
    m = re.search(r"(\d+) iterations", t)
    r["iterations"] = int(m.group(1)) if m else None
    m = re.search(r"([0-9.]+) spp", t)
    r["spp"] = float(m.group(1)) if m else None
    m = re.search(r"(\d+) light paths", t)
    r["paths"] = int(m.group(1)) if m else None
    return r


def notes(prefix):
    p = prefix + ".notes"
    return [l.strip() for l in open(p) if l.startswith("pcf:")] if os.path.exists(p) else []


def pcf_params(prefix):
    t = " ".join(notes(prefix))
    m = re.search(r"sigma ([0-9.]+) -> ([0-9.]+) m, t ([0-9.]+) -> ([0-9.]+) deg \(theta_1 ([0-9.]+), p ([0-9.]+), alpha ([0-9.]+)\)", t)
    c = re.search(r"(\d+) cones per iteration", t)
    sc = re.search(r"([0-9.]+) cones scanned and ([0-9.]+) inside", t)
    if not m:
        return None
    return {"sigma1": float(m.group(1)), "sigmaN": float(m.group(2)), "theta1": float(m.group(5)),
            "p": float(m.group(6)), "alpha": float(m.group(7)), "cones": int(c.group(1)) if c else None,
            "scanned": float(sc.group(1)) if sc else None, "inside": float(sc.group(2)) if sc else None}


def schedule(i, sigma1, theta1_deg, p, alpha):
    """sigma_i and t(sigma_i) (degrees) of eq. 3.27 by bisection on the closed form."""
    th1 = math.radians(theta1_deg)
    g = lambda s: s * s * (1 - math.cos(th1 * (s / sigma1) ** p))  # noqa: E731
    target = g(sigma1) * math.exp(math.lgamma(i + alpha) - math.lgamma(1 + alpha) - math.lgamma(i + 1))
    lo, hi = 0.0, sigma1
    for _ in range(100):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if g(mid) < target else (lo, mid)
    s = 0.5 * (lo + hi)
    return s, math.degrees(th1 * (s / sigma1) ** p)


def fit(xs, ys):
    pts = [(math.log(x), math.log(y)) for x, y in zip(xs, ys) if x > 0 and y > 0]
    if len(pts) < 2:
        return float("nan")
    mx = sum(x for x, _ in pts) / len(pts)
    my = sum(y for _, y in pts) / len(pts)
    sxx = sum((x - mx) ** 2 for x, _ in pts)
    return sum((x - mx) * (y - my) for x, y in pts) / sxx if sxx > 0 else float("nan")


def fmt(v, d=4):
    if v is None or (isinstance(v, float) and math.isnan(v)):
        return "–"
    return f"{v:.{d}g}" if abs(v) < 1e-3 and v != 0 else f"{v:.{d}f}"


loglog = svg_plot.loglog


def png(src, name):
    subprocess.run([BIN, "convert", src, os.path.join(out, "images", name)], capture_output=True, check=True)
    return f"images/{name}"


md = []
csv_rows = {"probes": [["scene", "probe", "iteration", "seconds", "sigma", "t_deg", "value", "reference", "abs_error", "rel_error"]],
            "equal_time": [["scene", "method", "region", "iterations_or_spp", "seconds", "rmse", "ssim", "rel_mean"]],
            "ablation": [["config", "seed", "rmse", "rmse_region", "mean_lum", "seconds", "cones_per_iteration"]],
            "sweep": [["config", "iteration", "seconds", "rmse", "rmse_region"]]}
md.append(f"Scale {P['SCALE']}: {RES}x{RES} pixels, equal-time budget T = {T:g} s per render (the progressive "
          f"methods stop after the iteration that crosses it), {P['PATHS']} light paths per iteration "
          f"(pcf: and 2 camera samples per pixel per iteration), pcf at its defaults otherwise (sigma_1 = 1.5 % of "
          f"the scene diagonal, theta_1 = 18 deg, p = 1, alpha = 0.5, the cosine aperture at Lambertian lookups, "
          f"techniques from the scene (the BSDF's sampler alone in these three: no glossy material), "
          f"lookup non-delta with NEE there, nesting delta-lights, cone surfaces same); pcf-cap is seed 001's "
          f"kernel at every lookup with its triplet (--cone-diffuse cap --cone-techniques bsdf,camera,importons). "
          f"References: sppm, two halves of {int(P['REFX']) * T:g} s (seeds 101, 102). Every render by the "
          f"binary of commit {P.get('commit', '?')} (params.txt).\n")

# ---- references
refs, ref_noise, ref_halves = {}, {}, {}
md.append("### References\n")
md.append("| scene | sppm iterations per half | seconds per half | reference noise (RMSE of the mean of the halves) | mean luminance |")
md.append("|---|---:|---:|---:|---:|")
for s in SCENES:
    d = os.path.join(work, s)
    if not os.path.exists(os.path.join(d, "ref-b.pfm")):
        continue
    a, b = rpfm(os.path.join(d, "ref-a.pfm")), rpfm(os.path.join(d, "ref-b.pfm"))
    ref = 0.5 * (a + b)
    wpfm(os.path.join(d, "ref.pfm"), ref)
    refs[s], ref_halves[s] = ref, (a, b)
    ref_noise[s] = compare(os.path.join(d, "ref-a.pfm"), os.path.join(d, "ref-b.pfm"))["rmse"] / 2
    sa = summary(os.path.join(d, "ref-a"))
    md.append(f"| {s} | {sa['iterations']} | {sa['seconds']:.1f} | {ref_noise[s]:.5f} | {lum(ref).mean():.4f} |")
md.append("")

# ---- (a) probes
md.append("### (a) Probe points (seed 001 figs. 5.4-5.7)\n")
md.append("pcf's equal-time render (below), its images saved after iterations 1, 2, 4, ...: the absolute and relative "
          "error of the 3x3 block mean luminance at each probe against the sppm reference; sigma_i and t(sigma_i) "
          "from eq. 3.27 (the notes' last sigma is checked against it). Slope: least-squares fit of log |error| against "
          "log i over i >= 4; theory -min(alpha/2, (1 - alpha)/(p + 1)) = -0.25 at alpha 0.5, p 1. A probe's error "
          "cannot be resolved below its reference noise (last column).\n")
for s in ["mirror-caustic-box", "torus-glass"]:
    prefix = os.path.join(work, s, "et-pcf")
    pp = pcf_params(prefix)
    if s not in refs or not pp:
        continue
    its = iterations(prefix)
    ref = refs[s]
    a, b = ref_halves[s]
    sN = schedule(its[-1][0], pp["sigma1"], pp["theta1"], pp["p"], pp["alpha"])
    md.append(f"#### {s}\n")
    md.append(f"sigma_1 = {pp['sigma1']} m, theta_1 = {pp['theta1']:g} deg, p = {pp['p']:g}, alpha = {pp['alpha']:g}; "
              f"{its[-1][0]} iterations in {its[-1][1]:.1f} s; sigma_N = {sN[0]:.4f} m, t = {sN[1]:.2f} deg from eq. 3.27 "
              f"(the notes: {pp['sigmaN']} m); {pp['cones']} cones per iteration, {pp['scanned']} cones scanned "
              f"and {pp['inside']} inside the kernel per lookup.\n")
    md.append("| probe | where | reference | ref. noise | " + " | ".join(f"i={i}" for i, _, _ in its) + " | slope |")
    md.append("|---|---|---:|---:|" + "---:|" * len(its) + "---:|")
    series, rel_series = [], []
    for name, (x, y, where) in PROBES[s].items():
        rv = block(ref, x, y).mean()
        rn = math.sqrt((((block(a, x, y) - block(b, x, y)) / 2) ** 2).mean()) / 3
        errs = []
        for i, sec, img in its:
            v = block(rpfm(img), x, y).mean()
            sg, tt = schedule(i, pp["sigma1"], pp["theta1"], pp["p"], pp["alpha"])
            errs.append((i, abs(v - rv)))
            csv_rows["probes"].append([s, name, i, sec, f"{sg:.5f}", f"{tt:.3f}", f"{v:.5f}", f"{rv:.5f}",
                                       f"{abs(v - rv):.5f}", f"{abs(v - rv) / rv if rv else float('nan'):.5f}"])
        sl = fit([i for i, _ in errs if i >= 4], [e for i, e in errs if i >= 4])
        md.append(f"| {name} | {where} | {rv:.4f} | {rn:.4f} | " +
                  " | ".join(f"{e:.4f} ({100 * e / rv:.0f} %)" for _, e in errs) + f" | {fmt(sl, 2)} |")
        series.append((f"{name}: |error|", [(i, e) for i, e in errs], COLOURS[name]))
        rel_series.append((name, rn, COLOURS[name]))
    md.append("")
    n = its[-1][0]
    sched = [(i,) + schedule(i, pp["sigma1"], pp["theta1"], pp["p"], pp["alpha"]) for i in
             sorted({1, 2, 4, 8, 16, 32, 64, 128, 256, 512, 1024, 2048, 4096, n}) if i <= n]
    series.append(("sigma_i (m)", [(i, sg) for i, sg, _ in sched], "#000000"))
    series.append(("t(sigma_i) (rad)", [(i, math.radians(tt)) for i, _, tt in sched], "#888888"))
    loglog(os.path.join(out, f"probes-{s}.svg"), f"{s}: pcf probe error and bandwidths against iterations",
           "iteration", "|error| (luminance); sigma (m); t (rad)", series,
           guides=[("slope -1/4 (theory)", (n, min(e for _, pts, _ in series[:3] for _, e in pts if e > 0) or 1e-3), -0.25, "black")],
           dashed=[(f"{nm}: ref. noise", y, c) for nm, y, c in rel_series])
    md.append(f"![probe errors on {s}](probes-{s}.svg)\n")

# ---- (b) equal time
md.append("### (b) Equal time\n")
md.append(f"Every method --time {T:g}, seed 1, against the sppm reference (note: sppm is also the reference's "
          "method, so its bias is shared and its RMSE here is noise only; the other methods pay for any bias sppm and "
          "they do not share). RMSE, SSIM (display) and the relative mean difference from caustica compare, over the "
          "whole image and over the scene's region.\n")
for s in SCENES:
    if s not in refs:
        continue
    rp = os.path.join(work, s, "ref.pfm")
    reg = REGIONS.get(s)
    md.append(f"#### {s}\n")
    md.append(f"Reference noise {ref_noise[s]:.5f} (whole image)." + (f" Region: {reg[0]}, pixels {scaled(reg[1])} (x, y, w, h)." if reg else "") + "\n")
    head = "| method | iterations / spp | seconds | RMSE | SSIM | rel. mean |"
    if reg:
        head += " region RMSE | region SSIM | region rel. mean |"
    md.append(head)
    md.append("|---|---:|---:|---:|---:|---:|" + ("---:|---:|---:|" if reg else ""))
    curves = []
    for m in METHODS:
        prefix = os.path.join(work, s, f"et-{m}")
        if not os.path.exists(prefix + ".pfm"):
            continue
        sm = summary(prefix)
        c = compare(prefix + ".pfm", rp)
        what = f"{sm['iterations']} it" if sm["iterations"] else (f"{sm['spp']:g} spp" if sm["spp"] else f"{sm['paths']} paths")
        row = f"| {m} | {what} | {sm['seconds']:.1f} | {c['rmse']:.4f} | {c['ssim']:.4f} | {c['rel']:+.4f} |"
        csv_rows["equal_time"].append([s, m, "whole", what, sm["seconds"], c["rmse"], c["ssim"], c["rel"]])
        if reg:
            cr = compare(prefix + ".pfm", rp, scaled(reg[1]))
            row += f" {cr['rmse']:.4f} | {cr['ssim']:.4f} | {cr['rel']:+.4f} |"
            csv_rows["equal_time"].append([s, m, "region", what, sm["seconds"], cr["rmse"], cr["ssim"], cr["rel"]])
        md.append(row)
        its = iterations(prefix)
        if its and m in ("pcf", "pcf-nested-off", "pcf-cap", "sppm", "pppm", "ppds"):
            pts = [(sec, compare(img, rp, scaled(reg[1]) if reg else None)["rmse"]) for _, sec, img in its]
            curves.append((m, pts, COLOURS[m]))
        else:
            curves.append((m, [(sm["seconds"], (cr if reg else c)["rmse"])], COLOURS[m]))
        png(prefix + ".pfm", f"{s}-{m}.png")
    png(rp, f"{s}-reference.png")
    md.append("")
    if s == "painting-sheet":
        # docs/scenes.md, "The closed form of painting-sheet": the image centre's radiance, with the
        # sheet-plate interreflections (first order, without them: 0.7517).
        md.append(f"Image centre against the closed form of docs/scenes.md (L = {PAINTING_CENTRE} W/m²/sr with the "
                  "sheet-plate interreflections; 0.7517 without): mean luminance of the centre 4x4 pixels (grey scene), "
                  "and of every 4x4 block of the central 16x16 pixels (spread = their standard deviation: the radiance's own gradient plus noise).\n")
        md.append("| method | centre 4x4 | / closed form | central 16x16 mean | / closed form | spread of 4x4 blocks |")
        md.append("|---|---:|---:|---:|---:|---:|")
        c0 = RES // 2
        for m in ["reference (sppm)"] + METHODS:
            f = rp if m.startswith("reference") else os.path.join(work, s, f"et-{m}.pfm")
            if not os.path.exists(f):
                continue
            L = lum(rpfm(f))
            v4 = L[c0 - 2:c0 + 2, c0 - 2:c0 + 2].mean()
            big = L[c0 - 8:c0 + 8, c0 - 8:c0 + 8]
            blocks = big.reshape(4, 4, 4, 4).mean(axis=(1, 3))
            md.append(f"| {m} | {v4:.4f} | {v4 / PAINTING_CENTRE:.3f} | {big.mean():.4f} | {big.mean() / PAINTING_CENTRE:.3f} | "
                      f"{blocks.std(ddof=1):.4f} |")
            csv_rows["equal_time"].append([s, m, "centre4x4_vs_closed_form", "", "", "", "", v4 / PAINTING_CENTRE - 1])
        md.append("")
    loglog(os.path.join(out, f"equal-time-{s}.svg"), f"{s}: RMSE ({'region' if reg else 'whole image'}) against time",
           "seconds", "RMSE", curves, dashed=[("reference noise (whole)", ref_noise[s], "black")])
    md.append(f"![equal time on {s}](equal-time-{s}.svg)\n")
    md.append(" ".join(f"![{m}](images/{s}-{m}.png)" for m in ["reference"] + METHODS) + "\n")
    md.append("(images: reference, " + ", ".join(METHODS) + "; 0 EV, sRGB)\n")

# ---- (b') the reflected caustic over seeds
s = "mirror-caustic-box"
if s in refs:
    rp = os.path.join(work, s, "ref.pfm")
    reg = scaled(REGIONS[s][1])
    per = {}
    for m in ("pcf", "sppm"):
        for seed in range(1, int(P.get("ET_SEEDS", "1")) + 1):
            prefix = os.path.join(work, s, f"et-{m}" if seed == 1 else f"et-{m}-s{seed}")
            if not os.path.exists(prefix + ".pfm"):
                continue
            sm = summary(prefix)
            per.setdefault(m, []).append((seed, sm["iterations"], sm["seconds"], compare(prefix + ".pfm", rp, reg)["rmse"],
                                          compare(prefix + ".pfm", rp)["rmse"]))
    if all(len(per.get(m, [])) > 1 for m in ("pcf", "sppm")):
        md.append(f"#### {s}: the reflected caustic over seeds\n")
        md.append(f"pcf (defaults, --spp 2) and sppm, --time {T:g}, seeds 1..{P['ET_SEEDS']} (seed 1 is the table above's; "
                  "the others alternate pcf and sppm). RMSE over the mirror-ball region "
                  f"{reg} and the whole image against the sppm reference.\n")
        md.append("| method | seed | iterations | seconds | region RMSE | whole RMSE |")
        md.append("|---|---:|---:|---:|---:|---:|")
        for m in ("pcf", "sppm"):
            for seed, it, sec, rr, rw in per[m]:
                md.append(f"| {m} | {seed} | {it} | {sec:.1f} | {rr:.4f} | {rw:.4f} |")
                csv_rows["equal_time"].append([s, m, f"region_seed{seed}", f"{it} it", sec, rr, "", ""])
        stats = {}
        for m in ("pcf", "sppm"):
            v = np.array([r[3] for r in per[m]])
            stats[m] = (v.mean(), v.std(ddof=1) / math.sqrt(len(v)), len(v))
        md.append("")
        md.append("Mean region RMSE ± standard error over the seeds: " + "; ".join(
            f"{m} {mu:.4f} ± {se:.4f} ({n} seeds)" for m, (mu, se, n) in stats.items())
            + f"; ratio pcf / sppm {stats['pcf'][0] / stats['sppm'][0]:.2f}.\n")

# ---- (c) ablations
d = os.path.join(work, "mirror-caustic-box", "ablation")
if os.path.isdir(d) and "mirror-caustic-box" in refs:
    rp = os.path.join(work, "mirror-caustic-box", "ref.pfm")
    reg = scaled(REGIONS["mirror-caustic-box"][1])
    labels = ["uniform", "bsdf", "bsdf+camera", "bsdf+camera+importons", "bsdf+camera+importons-no-mis",
              "bsdf+camera-bounce2", "bsdf+camera+importons-bounce2", "bsdf-cosine"]
    res = {}
    for lb in labels:
        fs = sorted(f for f in os.listdir(d) if f.startswith(lb + "-s") and f.endswith(".pfm"))
        if not fs:
            continue
        imgs, rows = [], []
        for f in fs:
            pre = os.path.join(d, f[:-4])
            c, cr = compare(pre + ".pfm", rp), compare(pre + ".pfm", rp, reg)
            im = rpfm(pre + ".pfm")
            imgs.append(lum(im))
            pp = pcf_params(pre)
            rows.append((c["rmse"], cr["rmse"], lum(im).mean(), summary(pre)["seconds"], pp["cones"] if pp else None))
            csv_rows["ablation"].append([lb, f[len(lb) + 2:-4]] + list(rows[-1]))
        st = np.array(imgs)
        var = st.var(axis=0, ddof=1).mean() if len(imgs) > 1 else float("nan")
        x, y, w, h = reg
        var_r = st[:, y:y + h, x:x + w].var(axis=0, ddof=1).mean() if len(imgs) > 1 else float("nan")
        res[lb] = {"n": len(imgs), "rmse": np.mean([r[0] for r in rows]), "rmse_r": np.mean([r[1] for r in rows]),
                   "mean": np.mean([r[2] for r in rows]), "sec": np.mean([r[3] for r in rows]),
                   "cones": rows[0][4], "var": var, "var_r": var_r}
    base_lb = "bsdf+camera+importons"
    ref_mean = lum(refs["mirror-caustic-box"]).mean()
    md.append("### (c) Ablations at equal cone budget (mirror-caustic-box)\n")
    md.append(f"Fixed --iterations {P['ABL_IT']} and --photons-per-iteration {int(P['PATHS']) // 2}, --spp 2, seeds 1..{P['SEEDS']}; "
              "every configuration but the last with seed 001's kernel at every lookup (--cone-diffuse cap), where the "
              "techniques matter; the last is the default, the cosine aperture at Lambertian lookups with the BSDF's "
              "sampler alone. \"cones\" is per iteration (each technique adds one cone per light vertex). Variance: per-pixel luminance "
              "variance across the seeds, averaged over the image (and the mirror-ball region). Mean ratio: mean "
              f"luminance over the MIS triplet's ({base_lb}) and over the reference's ({ref_mean:.4f}).\n")
    md.append("| techniques | lookup | seeds | cones / iteration | seconds | RMSE | region RMSE | variance | region variance | mean / triplet | mean / reference |")
    md.append("|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for lb, r in res.items():
        tech = lb.replace("-bounce2", "").replace("-no-mis", " (no MIS)").replace("-cosine", "").replace("+", ",")
        look = ("bounce:2" if lb.endswith("bounce2") else "non-delta") + (", cosine" if lb.endswith("cosine") else ", cap")
        md.append(f"| {tech} | {look} | {r['n']} | {r['cones']} | {r['sec']:.1f} | {r['rmse']:.4f} | {r['rmse_r']:.4f} | "
                  f"{fmt(r['var'], 4)} | {fmt(r['var_r'], 4)} | {r['mean'] / res[base_lb]['mean'] if base_lb in res else float('nan'):.3f} | "
                  f"{r['mean'] / ref_mean:.3f} |")
    md.append("")

# ---- (d) sweeps
d = os.path.join(work, "mirror-caustic-box", "sweep")
if os.path.isdir(d) and "mirror-caustic-box" in refs:
    rp = os.path.join(work, "mirror-caustic-box", "ref.pfm")
    reg = scaled(REGIONS["mirror-caustic-box"][1])
    md.append("### (d) Sweeps of alpha and p (mirror-caustic-box)\n")
    md.append(f"--iterations {P['SWEEP_IT']}, --photons-per-iteration {int(P['PATHS']) // 2}, --spp 2, seed 1, seed 001's kernel "
              "and triplet (--cone-diffuse cap --cone-techniques bsdf,camera,importons: p acts only through caps). RMSE against "
              "the reference over the whole image and the mirror-ball region after 1, 4, 16, 64, ... iterations; slope "
              "fitted over i >= 4 (whole image); theory for the error -min(alpha/2, (1 - alpha)/(p + 1)) (valid only "
              "while the error is above the reference noise "
              f"{ref_noise['mirror-caustic-box']:.4f}).\n")
    cfgs = ["a0.2-p1", "a0.5-p1", "a0.8-p1", "a0.2-p2", "a0.5-p2"]
    shade = {"a0.2-p1": "#9ecae1", "a0.5-p1": "#4292c6", "a0.8-p1": "#08519c", "a0.2-p2": "#fc9272", "a0.5-p2": "#de2d26"}
    marks = [1, 4, 16, 32, 64, 128, 512, 1024]
    md.append("| alpha | p | sigma_N (m) | t_N (deg) | seconds | " + " | ".join(f"RMSE i={i}" for i in marks) +
              " | region RMSE at N | slope | theory |")
    md.append("|---:|---:|---:|---:|---:|" + "---:|" * len(marks) + "---:|---:|---:|")
    series, series_r, sch_s, sch_t = [], [], [], []
    for cf in cfgs:
        pre = os.path.join(d, cf)
        if not os.path.exists(pre + ".pfm"):
            continue
        pp = pcf_params(pre)
        its = iterations(pre)
        pts, pts_r = [], []
        for i, sec, img in its:
            e, er = compare(img, rp)["rmse"], compare(img, rp, reg)["rmse"]
            pts.append((i, e))
            pts_r.append((i, er))
            csv_rows["sweep"].append([cf, i, sec, e, er])
        al, p = pp["alpha"], pp["p"]
        sl = fit([i for i, _ in pts if i >= 4], [e for i, e in pts if i >= 4])
        th = -min(al / 2, (1 - al) / (p + 1))
        byi = dict(pts)
        sN = schedule(its[-1][0], pp["sigma1"], pp["theta1"], p, al)
        md.append(f"| {al:g} | {p:g} | {sN[0]:.4f} | {sN[1]:.2f} | {its[-1][1]:.1f} | " +
                  " | ".join(fmt(byi.get(i)) for i in marks) + f" | {pts_r[-1][1]:.4f} | {fmt(sl, 3)} | {th:.3f} |")
        series.append((f"alpha {al:g}, p {p:g}", pts, shade[cf]))
        series_r.append((f"alpha {al:g}, p {p:g}", pts_r, shade[cf]))
        ii = [i for i in [1, 2, 4, 8, 16, 32, 64, 128, 256, 512, 1024, 2048, 4096] if i <= its[-1][0]]
        sch_s.append((f"alpha {al:g}, p {p:g}", [(i, schedule(i, pp["sigma1"], pp["theta1"], p, al)[0]) for i in ii], shade[cf]))
        sch_t.append((f"alpha {al:g}, p {p:g}", [(i, schedule(i, pp["sigma1"], pp["theta1"], p, al)[1]) for i in ii], shade[cf]))
    md.append("")
    nf = [("reference noise", ref_noise["mirror-caustic-box"], "black")]
    loglog(os.path.join(out, "sweep-rmse.svg"), "mirror-caustic-box: pcf RMSE (whole image) against iterations",
           "iteration", "RMSE", series, dashed=nf)
    loglog(os.path.join(out, "sweep-rmse-region.svg"), "mirror-caustic-box: pcf RMSE (mirror ball) against iterations",
           "iteration", "RMSE", series_r)
    loglog(os.path.join(out, "schedule-sigma.svg"), "eq. 3.27: sigma_i", "iteration", "sigma (m)", sch_s)
    loglog(os.path.join(out, "schedule-t.svg"), "eq. 3.27: t(sigma_i)", "iteration", "t (deg)", sch_t)
    md.append("![sweep, whole image](sweep-rmse.svg) ![sweep, mirror ball](sweep-rmse-region.svg)\n")
    md.append("![sigma_i](schedule-sigma.svg) ![t(sigma_i)](schedule-t.svg)\n")

open(os.path.join(out, "study.md"), "w").write("\n".join(md) + "\n")
for k, rows in csv_rows.items():
    with open(os.path.join(out, f"{k}.csv"), "w", newline="") as f:
        csv.writer(f).writerows(rows)


# ---- index.html: study.md with its tables and images, rendered by a small markdown subset
def inline(t):
    t = html.escape(t)
    t = re.sub(r"!\[([^\]]*)\]\(([^)]+)\)", r'<img alt="\1" src="\2">', t)
    return re.sub(r"`([^`]+)`", r"<code>\1</code>", t)


h = ["<!doctype html><html><head><meta charset='utf-8'><title>pcf study</title><style>"
     "body{font-family:sans-serif;max-width:1400px;margin:auto}table{border-collapse:collapse;font-size:12px}"
     "td,th{border:1px solid #bbb;padding:2px 5px;text-align:right}img{vertical-align:top}"
     "img[src^=images]{width:192px;image-rendering:pixelated}</style></head><body>",
     "<h1>Photon cone focusing study (bench/pcf_study.sh)</h1><p>See README.md for the method, the commands "
     "(commands.log) and the findings.</p>"]
in_table = False
for line in md + [""]:
    if line.startswith("|"):
        cells = [c.strip() for c in line.strip("|").split("|")]
        if set("".join(cells)) <= set("-:"):
            continue
        if not in_table:
            h.append("<table>")
            in_table, tag = True, "th"
        else:
            tag = "td"
        h.append("<tr>" + "".join(f"<{tag}>{inline(c)}</{tag}>" for c in cells) + "</tr>")
        continue
    if in_table:
        h.append("</table>")
        in_table = False
    if line.startswith("#"):
        n = len(line) - len(line.lstrip("#"))
        h.append(f"<h{n}>{inline(line.lstrip('#').strip())}</h{n}>")
    elif line.strip():
        h.append(f"<p>{inline(line)}</p>")
h.append("</body></html>")
open(os.path.join(out, "index.html"), "w").write("\n".join(h))
print("\n".join(md))
