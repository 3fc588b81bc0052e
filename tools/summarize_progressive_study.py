#!/usr/bin/env python3
"""Summarises bench/progressive_study.sh (issue 20, item 9): the convergence of pppm, ppds, sppm
and ppm against time, the alpha sweep, and equal time against the one-shot methods.

usage: summarize_progressive_study.py WORK_DIR OUT_DIR
Reads WORK_DIR/study.csv (scene,method,alpha,bandwidth,iteration,seconds,rmse), the references'
noise, the one-shot sweeps and the renders' summaries; writes OUT_DIR/study.md (tables),
OUT_DIR/study-summary.csv and OUT_DIR/convergence-SCENE.svg, alpha-SCENE.svg.

Slopes are least-squares fits of log RMSE against log time over the last decade of time (the
points with t >= t_max / 10); "corrected" subtracts the reference's own noise in quadrature,
sqrt(RMSE^2 - sigma_ref^2), sigma_ref = RMSE(check, ref) / sqrt(5) (the check render has a
quarter of the reference's samples, so its error has 4x the reference's variance).
Theory (Knaus and Zwicker 2011, in time proportional to iterations N): variance ~ N^-alpha,
squared bias ~ r^4 ~ N^-2(1-alpha), so RMSE ~ N^-min(alpha, 2(1-alpha))/2: -1/3 at alpha = 2/3.
"""
import csv
import math
import os
import re
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import svg_plot  # noqa: E402

work, out = sys.argv[1:3]
os.makedirs(out, exist_ok=True)
SCENES = ["glass-sphere", "water-wave", "metal-ring", "cornell-box"]
METHODS = ["pppm", "ppds", "ppdsf", "sppm", "ppm"]
COLOURS = {"pppm": "#1f5fd6", "ppds": "#d62728", "ppdsf": "#e377c2", "sppm": "#2ca02c", "ppm": "#9467bd",
           "pm": "#555555", "pds": "#ff7f0e"}
MAIN = "0.6667"
# ppm keeps 16 fixed hit points per pixel in the study (bench/progressive_study.sh).
SHOWN = {"ppm": "ppm (16 hit points/pixel)", "ppdsf": "ppds + min footprint"}
budget = float(open(os.path.join(work, "budget.txt")).read())

rows = []
with open(os.path.join(work, "study.csv")) as f:
    for r in csv.DictReader(f):
        r["iteration"] = int(r["iteration"])
        r["seconds"] = float(r["seconds"])
        r["rmse"] = float(r["rmse"])
        rows.append(r)


def curve(scene, method, alpha, label):
    pts = sorted((r["seconds"], r["rmse"], r["iteration"]) for r in rows
                 if (r["scene"], r["method"], r["alpha"], r["bandwidth"]) == (scene, method, alpha, label))
    return pts


def labels(scene, method, alpha=MAIN):
    return sorted({r["bandwidth"] for r in rows
                   if (r["scene"], r["method"], r["alpha"]) == (scene, method, alpha)})


def best(scene, method):
    """The initial bandwidth whose curve ends lowest at alpha 2/3, and that curve."""
    cs = [(curve(scene, method, MAIN, l)[-1][1], l) for l in labels(scene, method)
          if curve(scene, method, MAIN, l)]
    if not cs:
        return None, []
    e, l = min(cs)
    return l, curve(scene, method, MAIN, l)


def sigma_ref(scene):
    p = os.path.join(work, scene, "reference-noise.txt")
    m = re.search(r"^RMSE\s+([0-9.eE+-]+)", open(p).read(), re.M) if os.path.exists(p) else None
    return float(m.group(1)) / math.sqrt(5) if m else 0.0


def slope(pts, sigma=0.0):
    if len(pts) < 2:
        return float("nan")
    tmax = pts[-1][0]
    sel = [(t, e) for t, e, _ in pts if t >= tmax / 10 and e * e > sigma * sigma]
    if len(sel) < 2:
        return float("nan")
    xs = [math.log(t) for t, _ in sel]
    ys = [0.5 * math.log(e * e - sigma * sigma) for _, e in sel]
    n = len(xs)
    mx, my = sum(xs) / n, sum(ys) / n
    sxx = sum((x - mx) ** 2 for x in xs)
    return sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sxx if sxx > 0 else float("nan")


def theory(alpha):
    a = float(alpha)
    return -min(a, 2 * (1 - a)) / 2


def at_iteration(pts, n):
    for t, e, i in pts:
        if i == n:
            return e
    return None


def describe(method, label):
    if label is None:
        return ""
    if method == "ppds":
        return f"s = {label[1:]}"
    if method == "ppdsf":
        sm, f = label[1:].split("f")
        return f"s = {sm}, min footprint {f} r50"
    return f"r = {label[1:]} r50"


def oneshot(scene, method):
    p = os.path.join(work, scene, f"one-shot-{method}", "sweep.csv")
    if not os.path.exists(p):
        return None
    with open(p) as f:
        rs = list(csv.DictReader(f))
    for r in rs:
        r["rmse"] = float(r["rmse"])
        r["seconds"] = float(r["seconds"])
    return rs


def fmt(v, d=4):
    return "–" if v is None or (isinstance(v, float) and math.isnan(v)) else f"{v:.{d}f}"


def loglog(path, title, xlabel, ylabel, series, guides=()):
    """The shared log-log plot (tools/svg_plot.py) at this study's size."""
    svg_plot.loglog(path, title, xlabel, ylabel, series, guides, width=620, legend=190)


md = []
summary = [["scene", "method", "alpha", "initial", "iterations", "seconds", "rmse", "slope", "slope_corrected", "theory"]]
md.append(f"Time budget T = {budget:g} s per render (the render stops after the iteration that crosses it); "
          "64x64, seed 1, alpha = 0.6667 unless stated. Slopes: log RMSE against log time over the last "
          "decade of time; corrected: the reference's noise removed in quadrature.\n")
for scene in SCENES:
    sig = sigma_ref(scene)
    md.append(f"### {scene}\n")
    md.append(f"Reference noise sigma_ref = {sig:.5f}.\n")
    md.append("| method | initial bandwidth (best of) | RMSE at 1 / 10 / 100 / 1000 iterations | iterations in T | RMSE at T | slope | corrected | theory |")
    md.append("|---|---|---|---:|---:|---:|---:|---:|")
    series, guides = [], []
    for m in METHODS:
        l, pts = best(scene, m)
        if not pts:
            continue
        others = ", ".join(describe(m, x) for x in labels(scene, m))
        marks = " / ".join(fmt(at_iteration(pts, n)) for n in (1, 10, 100, 1000))
        s, sc = slope(pts), slope(pts, sig)
        md.append(f"| {SHOWN.get(m, m)} | {describe(m, l)} ({others}) | {marks} | {pts[-1][2]} | {pts[-1][1]:.4f} | "
                  f"{fmt(s, 3)} | {fmt(sc, 3)} | {theory(MAIN):.3f} |")
        summary.append([scene, m, MAIN, l, pts[-1][2], pts[-1][0], pts[-1][1], s, sc, theory(MAIN)])
        series.append((f"{m} ({describe(m, l)})", [(t, e) for t, e, _ in pts], COLOURS[m]))
    if series:
        # the theory slope drawn through the lowest end point
        end = min((pts[-1] for _, pts, _ in series), key=lambda p: p[1])
        guides.append(("slope -1/3 (theory)", end, theory(MAIN), "black"))
        loglog(os.path.join(out, f"convergence-{scene}.svg"),
               f"{scene}: RMSE against time, best initial bandwidth, alpha 2/3",
               "seconds", "RMSE", series, guides)
    md.append(f"\n![RMSE against time on {scene}](convergence-{scene}.svg)\n")
    # every initial bandwidth
    md.append("<details><summary>every initial bandwidth</summary>\n")
    md.append("| method | initial | RMSE at T | iterations | slope |")
    md.append("|---|---|---:|---:|---:|")
    for m in METHODS:
        for l in labels(scene, m):
            pts = curve(scene, m, MAIN, l)
            md.append(f"| {m} | {describe(m, l)} | {pts[-1][1]:.4f} | {pts[-1][2]} | {fmt(slope(pts), 3)} |")
    md.append("\n</details>\n")

# Alpha sweep
md.append("### Alpha sweep\n")
md.append("Each method at its best initial bandwidth (alpha 2/3); theory: RMSE slope -min(alpha, 2(1 - alpha))/2.\n")
md.append("| scene | method | alpha | iterations in T | RMSE at T | slope | corrected | theory |")
md.append("|---|---|---:|---:|---:|---:|---:|---:|")
for scene in ["water-wave", "glass-sphere"]:
    sig = sigma_ref(scene)
    for m in ["pppm", "ppds", "sppm"]:
        l, _ = best(scene, m)
        series = []
        alphas = sorted({r["alpha"] for r in rows if r["scene"] == scene and r["method"] == m
                         and r["bandwidth"] == l}, key=float)
        for a in alphas:
            pts = curve(scene, m, a, l)
            if not pts:
                continue
            md.append(f"| {scene} | {m} ({describe(m, l)}) | {a} | {pts[-1][2]} | {pts[-1][1]:.4f} | "
                      f"{fmt(slope(pts), 3)} | {fmt(slope(pts, sig), 3)} | {theory(a):.3f} |")
            summary.append([scene, m, a, l, pts[-1][2], pts[-1][0], pts[-1][1], slope(pts), slope(pts, sig), theory(a)])
            shade = {"0.3": "#9ecae1", "0.5": "#4292c6", "0.6667": "#08519c", "0.8": "#fc9272", "0.95": "#de2d26"}
            series.append((f"alpha {a}", [(t, e) for t, e, _ in pts], shade.get(a, "black")))
        if series:
            loglog(os.path.join(out, f"alpha-{scene}-{m}.svg"), f"{scene}, {m}: RMSE against time per alpha",
                   "seconds", "RMSE", series)
md.append("")
for scene in ["water-wave", "glass-sphere"]:
    md.append(" ".join(f"![alpha sweep {scene} {m}](alpha-{scene}-{m}.svg)" for m in ["pppm", "ppds", "sppm"]))
md.append("")

# Equal time
md.append("### Equal time: progressive against one-shot\n")
md.append("One-shot methods with the light paths the best pppm traced in T (about the same time), each at "
          "its best bandwidth of the sweep (pm: k nearest; pds: smoothing s; Cornell box: pm's global k).\n")
md.append("| scene | pppm | ppds | ppds + min footprint | sppm | ppm | best pm (k) | best pds (s) | ppds / pppm | ppds / sppm | ppds + min footprint / pppm | / sppm |")
md.append("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
for scene in SCENES:
    end = {m: best(scene, m)[1] for m in METHODS}
    e = {m: (v[-1][1] if v else None) for m, v in end.items()}
    t = {m: (v[-1][0] if v else None) for m, v in end.items()}
    cells = [f"{fmt(e[m])} ({fmt(t[m], 1)} s)" if e[m] is not None else "–" for m in METHODS]
    for one in ["pm", "pds"]:
        rs = oneshot(scene, one)
        if rs:
            b = min(rs, key=lambda r: r["rmse"])
            cells.append(f"{b['rmse']:.4f} ({b['value']}, {b['seconds']:.1f} s)")
            summary.append([scene, one, "", b["value"], "", b["seconds"], b["rmse"], "", "", ""])
        else:
            cells.append("–")
    def ratio(a, b):
        return e[a] / e[b] if e[a] and e[b] else None
    md.append(f"| {scene} | " + " | ".join(cells) + f" | {fmt(ratio('ppds', 'pppm'), 2)} | "
              f"{fmt(ratio('ppds', 'sppm'), 2)} | {fmt(ratio('ppdsf', 'pppm'), 2)} | {fmt(ratio('ppdsf', 'sppm'), 2)} |")
md.append("")

# Rates
md.append("### Rates\n")
md.append("Light paths per second of the progressive renders (best bandwidth, whole render incl. camera passes) "
          "and of the one-shot renders of the equal-time table (their sweep's mean time per render).\n")
md.append("| scene | light paths per iteration | " + " | ".join(f"{m} it/s" for m in METHODS) + " | "
          + " | ".join(f"{m} paths/s" for m in METHODS) + " | pm paths/s | pds paths/s |")
md.append("|---|---:|" + "---:|" * (2 * len(METHODS) + 2))
for scene in SCENES:
    m_paths = 100000 if scene == "glass-sphere" else 20000
    its, pps = [], []
    for m in METHODS:
        _, pts = best(scene, m)
        if pts:
            its.append(f"{pts[-1][2] / pts[-1][0]:.1f}")
            pps.append(f"{pts[-1][2] * m_paths / pts[-1][0] / 1e6:.2f} M")
        else:
            its.append("–")
            pps.append("–")
    p = os.path.join(work, scene, "one-shot-paths.txt")
    n = int(open(p).read()) if os.path.exists(p) else None
    for one in ["pm", "pds"]:
        rs = oneshot(scene, one)
        if rs and n:
            mean = sum(r["seconds"] for r in rs) / len(rs)
            pps.append(f"{n / mean / 1e6:.2f} M")
        else:
            pps.append("–")
    md.append(f"| {scene} | {m_paths} | " + " | ".join(its + pps) + " |")
md.append("")

# Consistency: exactly 1000 iterations at the best initial bandwidths
ipath = os.path.join(work, "iterations.csv")
if os.path.exists(ipath):
    with open(ipath) as f:
        irows = list(csv.DictReader(f))
    md.append("### Consistency: 1, 10, 100, 1000 iterations\n")
    md.append("Each method at its best initial bandwidth of the time study, run for exactly 1000 iterations "
              "(no time budget); RMSE against the reference after 1, 10, 100 and 1000 iterations. "
              "\"Falls\" checks each step against the reference noise floor: a step may rise by at most "
              "2 sigma_ref (the noise of the comparison itself).\n")
    md.append("| scene | method | initial | 1 | 10 | 100 | 1000 | falls | seconds for 1000 |")
    md.append("|---|---|---|---:|---:|---:|---:|---|---:|")
    for scene in ["glass-sphere", "water-wave"]:
        sig = sigma_ref(scene)
        for m in METHODS:
            rs = sorted((int(r["iteration"]), float(r["rmse"]), float(r["seconds"]), r["bandwidth"])
                        for r in irows if r["scene"] == scene and r["method"] == m)
            if not rs:
                continue
            es = [e for _, e, _, _ in rs]
            falls = all(b <= a + 2 * sig for a, b in zip(es, es[1:]))
            strict = all(b < a for a, b in zip(es, es[1:]))
            verdict = "yes" if strict else ("within noise" if falls else "NO")
            md.append(f"| {scene} | {SHOWN.get(m, m)} | {describe(m, rs[0][3])} | " + " | ".join(f"{e:.4f}" for e in es)
                      + f" | {verdict} | {rs[-1][2]:.1f} |")
            summary.append([scene, m, MAIN, rs[0][3], rs[-1][0], rs[-1][2], rs[-1][1], "", "", ""])
    md.append("")

open(os.path.join(out, "study.md"), "w").write("\n".join(md) + "\n")
with open(os.path.join(out, "study-summary.csv"), "w", newline="") as f:
    csv.writer(f).writerows(summary)
print("\n".join(md))
