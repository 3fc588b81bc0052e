#!/usr/bin/env python3
"""Summarises bench/temporal.sh: seed 003 fig. 7-10 measured (temporal photon differentials, TPD,
against time-dependent photon mapping, TDPM, on the moving wave and the rotating rod).

usage: summarize_temporal.py WORK_DIR OUT_DIR REF_SPP BIN
Reads WORK_DIR/<scene>/<config>/sweep.csv (value = s for TPD, k for TDPM) and the references'
noise (reference-noise.txt), renders the images at the optima with BIN, and writes OUT_DIR/
README.md, summary.csv, index.html, xt1-exposure.svg, xt2-photons.svg and the PNGs.
"""
import csv
import html
import math
import os
import re
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sweep_csv import best, rows  # noqa: E402
import svg_plot  # noqa: E402

work, out, ref_spp, binary = sys.argv[1:5]
os.makedirs(out, exist_ok=True)
EXPOSURES = ["0", "0.25", "0.5", "1", "2"]
BETWEEN = [0, 2, 10]
COUNTS = [1000, 5000, 10000, 20000, 40000, 80000, 160000, 480000]
COMMON = ["--caustics-only", "--spp", "4", "--seed", "1", "--width", "128", "-q"]


def sweep(scene, config):
    p = os.path.join(work, scene, config, "sweep.csv")
    return rows(p) if os.path.exists(p) else None


def opt(scene, config):
    """(RMSE-optimal row, SSIM-optimal row) of a sweep, or None."""
    r = sweep(scene, config)
    return (best(r, "rmse"), best(r, "ssim")) if r else None


def noise(scene):
    p = os.path.join(work, scene, "reference-noise.txt")
    if not os.path.exists(p):
        return None
    m = re.search(r"^RMSE\s+([0-9.eE+-]+)", open(p).read(), re.M)
    return float(m.group(1)) if m else None


def kilo(n):
    return f"{n // 1000}k" if n >= 1000 and n % 1000 == 0 else str(n)


summary = []  # scene, method, config, photons, metric, value, setting


def record(scene, method, config, photons, o, param):
    if o is None:
        return
    for metric, r in zip(("rmse", "ssim"), o):
        summary.append([scene, method, config, photons, metric, f"{r[metric]:.5f}",
                        f"{param}={r['value']}"])


# XT1: exposure sweep of TPD.
xt1 = []
for e in EXPOSURES:
    o = opt("moving-wave", f"tpd-e{e}")
    record("moving-wave", "TPD", f"e={e}", 1000, o, "s")
    xt1.append((e, o))

# XT2 at e = 1.
tpd = opt("moving-wave", "tpd-e1")
tpd_c = opt("moving-wave", "tpd-centred")
pd_random = opt("moving-wave", "pd-random-times")
record("moving-wave", "TPD centred", "e=1", 1000, tpd_c, "s")
record("moving-wave", "PD at random times", "e=1", 1000, pd_random, "s")
tdpm = {}
for n in BETWEEN:
    for c in COUNTS:
        o = opt("moving-wave", f"tdpm-b{n}-n{c}")
        if o:
            tdpm[(n, c)] = o
            record("moving-wave", f"TDPM N={n}", "e=1", c, o, "k")


def photons_to_match(n, target, metric):
    """Photons TDPM with n in-between frames needs for `target` (log-log interpolation between
    the measured counts); None if it never gets there."""
    pts = [(c, tdpm[(n, c)][0 if metric == "rmse" else 1][metric]) for c in COUNTS if (n, c) in tdpm]
    good = (lambda v: v <= target) if metric == "rmse" else (lambda v: v >= target)
    for (c0, v0), (c1, v1) in zip(pts, pts[1:]):
        if good(v0):
            return c0, "at or below the first count"
        if good(v1):
            if metric == "rmse":
                t = (math.log(target) - math.log(v0)) / (math.log(v1) - math.log(v0))
            else:
                t = (target - v0) / (v1 - v0)
            return round(math.exp(math.log(c0) + t * (math.log(c1) - math.log(c0)))), "interpolated"
    if pts and good(pts[0][1]):
        return pts[0][0], "at or below the first count"
    return None, f"more than {kilo(COUNTS[-1])}"


# XT3: the rod.
rod_tpd = opt("rotating-rod", "tpd")
record("rotating-rod", "TPD", "e=1", 5000, rod_tpd, "s")
rod = {}
for n in BETWEEN:
    r = sweep("rotating-rod", f"tdpm-b{n}")
    if r:
        rod[n] = {row["value"]: row for row in r}
        for row in r:
            summary.append(["rotating-rod", f"TDPM N={n}", "e=1", 5000, "rmse", f"{row['rmse']:.5f}", f"k={row['value']}"])
            summary.append(["rotating-rod", f"TDPM N={n}", "e=1", 5000, "ssim", f"{row['ssim']:.5f}", f"k={row['value']}"])

with open(os.path.join(out, "summary.csv"), "w", newline="") as f:
    w = csv.writer(f)
    w.writerow(["scene", "method", "exposure", "photons", "metric", "value", "at"])
    w.writerows(summary)


# Plots (hand-written SVG: no plotting dependency).
def svg_plot(path, title, xlabel, ylabel, series, logx=False, hlines=()):
    W, H, L, R, T, B = 560, 360, 70, 150, 30, 50
    xs = [x for _, pts, _ in series for x, _ in pts]
    ys = [y for _, pts, _ in series for _, y in pts] + [y for _, y, _ in hlines]
    if not xs:
        return
    fx = (lambda v: math.log10(v)) if logx else (lambda v: v)
    x0, x1 = fx(min(xs)), fx(max(xs))
    y0, y1 = 0.0, max(ys) * 1.1
    if x1 == x0:
        x1 = x0 + 1

    def sx(v):
        return L + (fx(v) - x0) / (x1 - x0) * (W - L - R)

    def sy(v):
        return H - B - (v - y0) / (y1 - y0) * (H - T - B)

    o = svg_plot.frame(W, H, L, R, T, B, title, xlabel, ylabel)
    for i in range(5):
        v = y0 + (y1 - y0) * i / 4
        o.append(f'<text x="{L-6}" y="{sy(v)+4:.1f}" text-anchor="end">{v:.3f}</text>')
    for x in sorted(set(xs)):
        lab = kilo(int(x)) if logx else f"{x:g}"
        o.append(f'<text x="{sx(x):.1f}" y="{H-B+14}" text-anchor="middle">{lab}</text>')
    for k, (name, pts, colour) in enumerate(series):
        d = " ".join(f"{'M' if i == 0 else 'L'}{sx(x):.1f},{sy(y):.1f}" for i, (x, y) in enumerate(pts))
        o.append(f'<path d="{d}" fill="none" stroke="{colour}" stroke-width="1.5"/>')
        for x, y in pts:
            o.append(f'<circle cx="{sx(x):.1f}" cy="{sy(y):.1f}" r="2.5" fill="{colour}"/>')
        o.append(f'<text x="{W-R+8}" y="{T+14*k+10}" fill="{colour}">{html.escape(name)}</text>')
    for k, (name, y, colour) in enumerate(hlines):
        o.append(f'<line x1="{L}" y1="{sy(y):.1f}" x2="{W-R}" y2="{sy(y):.1f}" stroke="{colour}" stroke-dasharray="5,3"/>')
        o.append(f'<text x="{W-R+8}" y="{T+14*(len(series)+k)+10}" fill="{colour}">{html.escape(name)}</text>')
    o.append("</svg>")
    open(path, "w").write("\n".join(o))


svg_plot(os.path.join(out, "xt1-exposure.svg"), "XT1: TPD, 1 000 photons, best RMSE per exposure",
         "exposure e (frames)", "RMSE",
         [("TPD", [(float(e), o[0]["rmse"]) for e, o in xt1 if o], "#1f5fd6")])
colours = {0: "black", 2: "#d62728", 10: "#2ca02c"}
series = []
for n in BETWEEN:
    pts = [(c, tdpm[(n, c)][0]["rmse"]) for c in COUNTS if (n, c) in tdpm]
    if pts:
        series.append((f"TDPM N = {n}", pts, colours[n]))
hl = [("TPD 1k", tpd[0]["rmse"], "#1f5fd6")] if tpd else []
if tpd_c:
    hl.append(("TPD 1k centred", tpd_c[0]["rmse"], "#9467bd"))
svg_plot(os.path.join(out, "xt2-photons.svg"), "XT2: best RMSE against photons, e = 1",
         "photons (total over the in-between frames)", "RMSE", series, logx=True, hlines=hl)


# Images at the optima.
def render(scene, png, args, mask=False):
    dst = os.path.join(out, png)
    exr = os.path.join(work, scene, png.replace(".png", ".exr"))
    if not os.path.exists(dst):
        subprocess.run([binary, "render", scene, *COMMON, *args, "-o", exr, "--png", dst],
                       check=True, stdout=subprocess.DEVNULL)
    return png


images = []  # (section, caption, png)


def ref_png(scene, e):
    exr = os.path.join(work, scene, f"reference-e{e}-s1-{ref_spp}.exr")
    png = f"{scene}-reference-e{e}.png"
    if os.path.exists(exr) and not os.path.exists(os.path.join(out, png)):
        subprocess.run([binary, "convert", exr, os.path.join(out, png)], check=False,
                       stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return png


for e, o in xt1:
    if o:
        images.append(("XT1", f"e = {e}: reference", ref_png("moving-wave", e)))
        s = o[0]["value"]
        images.append(("XT1", f"e = {e}: TPD 1k, s = {s}, RMSE {o[0]['rmse']:.4f}",
                       render("moving-wave", f"wave-tpd-e{e}.png",
                              ["--integrator", "pds", "--temporal", "--photons", "1000",
                               "--smoothing", s, "--shutter", e])))
if tpd:
    images.append(("XT2", "reference (e = 1)", ref_png("moving-wave", "1")))
    images.append(("XT2", f"TPD 1k, s = {tpd[0]['value']}, RMSE {tpd[0]['rmse']:.4f}",
                   os.path.basename(f"wave-tpd-e1.png")))
for n in BETWEEN:
    for c in (1000, 40000, 480000):
        o = tdpm.get((n, c))
        if o:
            k = o[0]["value"]
            images.append(("XT2", f"TDPM N = {n}, {kilo(c)}, k = {k}, RMSE {o[0]['rmse']:.4f}",
                           render("moving-wave", f"wave-tdpm-b{n}-n{c}.png",
                                  ["--integrator", "pm", "--global-photons", "0",
                                   "--in-between-frames", str(n), "--photons", str(c), "--k", k,
                                   "--shutter", "1"])))
if rod_tpd:
    images.append(("XT3", "reference", ref_png("rotating-rod", "1")))
    images.append(("XT3", f"TPD 5k, s = {rod_tpd[0]['value']}, RMSE {rod_tpd[0]['rmse']:.4f}",
                   render("rotating-rod", "rod-tpd.png",
                          ["--integrator", "pds", "--temporal", "--photons", "5000",
                           "--smoothing", rod_tpd[0]["value"], "--shutter", "1"])))
    for n in BETWEEN:
        for k in ("100", "250"):
            row = rod.get(n, {}).get(k)
            if row:
                images.append(("XT3", f"TDPM N = {n}, 5k, k = {k}, RMSE {row['rmse']:.4f}",
                               render("rotating-rod", f"rod-tdpm-b{n}-k{k}.png",
                                      ["--integrator", "pm", "--global-photons", "0",
                                       "--in-between-frames", str(n), "--photons", "5000",
                                       "--k", k, "--shutter", "1"])))
for scene in ("moving-wave", "rotating-rod"):
    if os.path.exists(os.path.join(out, f"{scene}-dt-vectors.svg")):
        images.append(("XT4", f"{scene}: projected D_t x", f"{scene}-dt-vectors.svg"))

# README.
md = ["# Temporal photon differentials against time-dependent photon mapping (issue 19)", "",
      "Seed 003 fig. 7-10 (seed 000 ch. 7) measured: the seeds report no numbers. Regenerate with "
      "`bash bench/temporal.sh` (about 40 minutes on 2 cores; re-runs reuse finished work in "
      "`target/bench/temporal`). Images side by side: [index.html](index.html).", "",
      "Setup: built-in scenes `moving-wave` (S-T1) and `rotating-rod` (S-T2), 128 x 128, "
      "`--caustics-only --spp 4 --seed 1`, shutter opening at frame 0. References: the "
      f"motion-blurred light tracer with {ref_spp} light paths per pixel (`--integrator lighttrace "
      "--shutter E`). TPD = `--integrator pds --temporal` (forward alignment unless said), "
      "TDPM = `--integrator pm --global-photons 0 --in-between-frames N` (photon counts are totals "
      "over the N + 1 times, Q-T13). Every method at its optimal bandwidth: TPD swept over "
      "s in {1, 1.5, 2, 3, 4, 6, 8, 12}, TDPM over k in {5, 10, 20, 40, 80, 160, 320, 640, 1280, 2560} (and 5120, 10240 from 80k photons on); "
      "RMSE-optimal and SSIM-optimal settings reported separately.", ""]
nw, nr = noise("moving-wave"), noise("rotating-rod")
md += [f"Reference noise (RMSE between seeds 1 and 2 of the reference; an image's RMSE against "
       f"the reference includes about this much of the reference's own noise): moving wave "
       f"{nw if nw is not None else 'n/a'}, rotating rod {nr if nr is not None else 'n/a'} "
       "(rod: pixels black in both masked).", ""]
md += ["## XT1: exposure sweep (TPD, 1 000 photons, moving wave)", "",
       "| exposure e (frames) | best RMSE (s) | best SSIM (s) |", "|---|---|---|"]
for e, o in xt1:
    if o:
        md.append(f"| {e} | {o[0]['rmse']:.4f} ({o[0]['value']}) | {o[1]['ssim']:.4f} ({o[1]['value']}) |")
md += ["", "![XT1](xt1-exposure.svg)", ""]
md += ["## XT2: TPD 1 000 photons against TDPM at e = 1 (moving wave)", "",
       "Each cell: best RMSE (k) / best SSIM (k).", "",
       "| N in-between | " + " | ".join(kilo(c) for c in COUNTS) + " |",
       "|---|" + "---|" * len(COUNTS)]
for n in BETWEEN:
    cells = []
    for c in COUNTS:
        o = tdpm.get((n, c))
        cells.append(f"{o[0]['rmse']:.4f} ({o[0]['value']}) / {o[1]['ssim']:.3f} ({o[1]['value']})" if o else "-")
    md.append(f"| {n} | " + " | ".join(cells) + " |")
md.append("")
for name, o in (("TPD 1k (forward)", tpd), ("TPD 1k centred", tpd_c),
                ("PD 1k, photons at random times (no --temporal)", pd_random)):
    if o:
        md.append(f"* {name}: RMSE {o[0]['rmse']:.4f} (s = {o[0]['value']}), "
                  f"SSIM {o[1]['ssim']:.4f} (s = {o[1]['value']})")
md.append("")
verdict = []
if tpd:
    md += ["Photons TDPM needs to match TPD 1k:", "",
           "| N | to match TPD's RMSE | to match TPD's SSIM |", "|---|---|---|"]
    for n in BETWEEN:
        a, how_a = photons_to_match(n, tpd[0]["rmse"], "rmse")
        b, how_b = photons_to_match(n, tpd[1]["ssim"], "ssim")
        fa = f"{a} ({how_a})" if a else how_a
        fb = f"{b} ({how_b})" if b else how_b
        md.append(f"| {n} | {fa} | {fb} |")
    md.append("")
    for n in (0, 2):
        o = tdpm.get((n, 40000))
        if o:
            ok = tpd[0]["rmse"] < o[0]["rmse"]
            verdict.append(f"N = {n}: TPD 1k {tpd[0]['rmse']:.4f} vs TDPM 40k {o[0]['rmse']:.4f} — "
                           f"{'TPD lower' if ok else 'TPD NOT lower'}")
    md += ["**Acceptance** (TPD with 1 000 photons has lower RMSE than TDPM with 40 000 at 0 and 2 "
           "in-between frames): " + "; ".join(verdict) + ".", ""]
md += ["![XT2](xt2-photons.svg)", ""]
md += ["## XT3: the rotating rod (5 000 photons, e = 1)", "",
       "| method | RMSE | SSIM |", "|---|---|---|"]
if rod_tpd:
    md.append(f"| TPD (best s: {rod_tpd[0]['value']} / {rod_tpd[1]['value']}) | {rod_tpd[0]['rmse']:.4f} | {rod_tpd[1]['ssim']:.4f} |")
for n in BETWEEN:
    for k in ("100", "250"):
        row = rod.get(n, {}).get(k)
        if row:
            md.append(f"| TDPM N = {n}, k = {k} | {row['rmse']:.4f} | {row['ssim']:.4f} |")
md += ["", "## XT4: projected time differentials (fig. 10)", "",
       "`target/fast/examples/dt_vectors SCENE 400` (exposure 4 frames to make them visible): "
       "arrows from each caustic photon's landing x to x + D_t x.", "",
       "![wave](moving-wave-dt-vectors.svg) ![rod](rotating-rod-dt-vectors.svg)", ""]
open(os.path.join(out, "README.md"), "w").write("\n".join(md))

# index.html.
h = ["<!doctype html><meta charset=utf-8><title>caustica: temporal photon differentials</title>",
     "<style>body{font-family:sans-serif} figure{display:inline-block;margin:4px;text-align:center}"
     " img{width:256px;image-rendering:pixelated} figcaption{font-size:12px;width:256px}</style>",
     "<h1>Temporal photon differentials vs time-dependent photon mapping</h1>",
     "<p>See <a href=README.md>README.md</a> for the tables and commands.</p>"]
section = None
for sec, cap, png in images:
    if sec != section:
        h.append(f"<h2>{sec}</h2>")
        section = sec
    h.append(f"<figure><img src='{html.escape(png)}'><figcaption>{html.escape(cap)}</figcaption></figure>")
open(os.path.join(out, "index.html"), "w").write("\n".join(h))
print("\n".join(verdict))
