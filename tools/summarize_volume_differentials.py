#!/usr/bin/env python3
"""Region masks and the summary of bench/volume_differentials.sh (seed 000 sec. 8.5 measured:
vpm, the beam ablation and vpd against the volumetric light tracer).

  summarize_volume_differentials.py masks REF.pfm DIR [--toml SCENE.toml] [--width W]
      Writes DIR/mask-REGION.pfm (1 inside the region, 0 elsewhere) and DIR/regions.txt:
      medium regions from the reference's luminance Y, blurred (sigma 1.5 px): "medium" where it
      exceeds 10 % of its 99th percentile; "interior" = medium eroded by EDGE px, "edge" = the
      EDGE-px band inside the medium's silhouette, "halo" = the EDGE-px band just outside it
      (kept only if each has at least 50 pixels and the medium is not the whole frame);
      "sphere-in" / "sphere-out": pixels whose 4x4 sub-rays all / none hit a non-diffuse sphere
      of the scene file (glass or metal seen directly), radius x 0.97 / 1.03.
  summarize_volume_differentials.py summarize WORK DOCS --spp S --ref-spp R --check-spp C
      --ref-photons P --scenes "NAME:N[:W] ..." [--bin PATH]
      Reads WORK/results.csv and the renders in WORK/SCENE/, writes DOCS/results.csv,
      DOCS/README.md (tables; DOCS/notes.md, hand-written, is appended if present),
      DOCS/index.html, DOCS/SCENE-plots.png and small palette PNGs of the images at the optima.
"""
import argparse
import csv
import html
import math
import os
import shutil
import subprocess
import sys

import numpy as np

EDGE = 3
METHODS = ("vpm", "beam", "vpd")
COLOURS = {"vpm": "black", "beam": "#2ca02c", "vpd": "#1f5fd6"}
LABEL = {"vpm": "vpm (ray marching, k-NN)", "beam": "beam (k-NN radii, exact chord)",
         "vpd": "vpd (photon differentials)"}
REGION_TEXT = {
    "interior": "inside the medium's silhouette, ≥ %d px from its edge" % EDGE,
    "edge": "the %d-px band inside the silhouette's edge" % EDGE,
    "halo": "the %d-px band just outside the silhouette" % EDGE,
    "sphere-in": "pixels that see the glass/metal sphere directly",
    "sphere-out": "pixels that do not see it",
}


# ------------------------------------------------------------------ PFM and masks
def read_pfm(path):
    with open(path, "rb") as f:
        kind = f.readline().strip()
        w, h = map(int, f.readline().split())
        scale = float(f.readline())
        ch = 3 if kind == b"PF" else 1
        data = np.frombuffer(f.read(), dtype="<f4" if scale < 0 else ">f4", count=w * h * ch)
    img = data.reshape(h, w, ch)[::-1]  # PFM stores the bottom row first
    return img


def write_pfm(path, mask):
    h, w = mask.shape
    rgb = np.repeat(mask.astype("<f4")[::-1, :, None], 3, axis=2)
    with open(path, "wb") as f:
        f.write(f"PF\n{w} {h}\n-1.0\n".encode())
        f.write(rgb.tobytes())


def blur(y, sigma):
    r = int(3 * sigma + 0.5)
    k = np.exp(-0.5 * (np.arange(-r, r + 1) / sigma) ** 2)
    k /= k.sum()
    p = np.pad(y, r, mode="edge")
    p = np.apply_along_axis(lambda v: np.convolve(v, k, mode="valid"), 0, p)
    return np.apply_along_axis(lambda v: np.convolve(v, k, mode="valid"), 1, p)


def dilate(m, n, pad):
    for _ in range(n):
        p = np.pad(m, 1, constant_values=pad)
        m = p[1:-1, 1:-1] | p[:-2, 1:-1] | p[2:, 1:-1] | p[1:-1, :-2] | p[1:-1, 2:]
    return m


def erode(m, n):
    return ~dilate(~m, n, pad=False)  # the frame's outside counts as medium


def sphere_coverage(toml_path, w, h):
    """[(name, fraction of 4x4 sub-rays hitting the sphere, r*0.97), (..., r*1.03)] per sphere."""
    import tomllib
    sc = tomllib.load(open(toml_path, "rb"))
    cam = sc["camera"]
    eye, target = np.array(cam["eye"], float), np.array(cam["target"], float)
    up = np.array(cam.get("up", [0, 1, 0]), float)
    mats = {m["name"]: m.get("type", "") for m in sc.get("material", [])}
    f = target - eye; f /= np.linalg.norm(f)
    r = np.cross(f, up); r /= np.linalg.norm(r)
    u = np.cross(r, f)
    t = math.tan(math.radians(cam["fov"]) / 2)  # along x
    out = []
    for s in sc.get("shape", []):
        if s.get("type") != "sphere" or mats.get(s.get("material"), "diffuse") in ("diffuse", "null"):
            continue
        c = np.array(s.get("center", [0, 0, 0]), float) + np.array(s.get("translate", [0, 0, 0]), float)
        rad = float(s.get("radius", 1.0)) * float(s.get("scale", 1.0) if not isinstance(s.get("scale"), list) else 1.0)
        cover = []
        for margin in (0.97, 1.03):
            hits = np.zeros((h, w))
            for sj in range(4):
                for si in range(4):
                    x = (2 * (np.arange(w)[None, :] + (si + 0.5) / 4) / w - 1) * t
                    y = (1 - 2 * (np.arange(h)[:, None] + (sj + 0.5) / 4) / h) * t * h / w
                    d = f[None, None, :] + x[..., None] * r + y[..., None] * u
                    d /= np.linalg.norm(d, axis=2, keepdims=True)
                    oc = eye - c
                    b = d @ oc
                    cc = oc @ oc - (rad * margin) ** 2
                    disc = b * b - cc
                    hit = (disc >= 0) & (-b + np.sqrt(np.maximum(disc, 0)) > 0)
                    hits += hit
            cover.append(hits / 16)
        out.append(cover)
    return out


def cmd_masks(a):
    img = read_pfm(a.ref)
    y = img[..., 0] if img.shape[2] == 1 else img @ np.array([0.2126, 0.7152, 0.0722])
    h, w = y.shape
    yb = blur(y, 1.5)
    p99 = np.percentile(yb, 99)
    medium = yb > 0.1 * p99
    regions = {}
    if medium.mean() < 0.97:
        interior = erode(medium, EDGE)
        regions["interior"] = interior
        regions["edge"] = medium & ~interior
        regions["halo"] = dilate(medium, EDGE, pad=False) & ~medium
    if a.toml and os.path.isfile(a.toml):
        try:
            covers = sphere_coverage(a.toml, w, h)
        except Exception as e:  # a scene file this reader does not understand: no sphere regions
            print(f"sphere masks skipped: {e}")
            covers = []
        if covers:
            inside = np.zeros((h, w), bool); anyhit = np.zeros((h, w), bool)
            for small, big in covers:
                inside |= small >= 1.0
                anyhit |= big > 0
            regions["sphere-in"] = inside
            regions["sphere-out"] = ~anyhit
    notes = []
    for c in a.crop or []:
        name, rect = c.split(":")
        x, y0, cw, ch = map(int, rect.split(","))
        m = np.zeros((h, w), bool); m[y0:y0 + ch, x:x + cw] = True
        regions[name] = m
        notes.append(f"{name}=the rectangle x,y,w,h = {rect} (CROPS)")
    open(os.path.join(a.dir, "region-notes.txt"), "w").write("".join(n + "\n" for n in notes))
    kept = []
    for name, m in regions.items():
        if m.sum() >= 50:
            write_pfm(os.path.join(a.dir, f"mask-{name}.pfm"), m)
            kept.append(name)
    open(os.path.join(a.dir, "regions.txt"), "w").write(" ".join(kept) + "\n")
    print(f"masks: medium {medium.mean():.0%} of the frame; regions "
          + ", ".join(f"{k} {int(regions[k].sum())} px" for k in kept))


# ------------------------------------------------------------------ summary
def num(x):
    return float(x) if x not in ("", None) else None


def load(work):
    rows = list(csv.DictReader(open(os.path.join(work, "results.csv"))))
    for r in rows:
        for k in ("photons", "wall_s", "render_s", "photons_s", "camera_s", "median_radius", "step",
                  "rmse", "ssim", "relmean", "spp", "pixels"):
            r[k] = num(r[k])
    return rows


def f4(x, d=4):
    return "—" if x is None else f"{x:.{d}g}"


def pct(x):
    return "—" if x is None else f"{100 * x:+.1f} %"


def setting(r):
    return f"{r['param']} = {r['value']}"


def denoise(d, e):
    """RMSE against a noiseless reference: sqrt(RMSE^2 - sigma_ref^2) (independent noise)."""
    s = d.get("ref_noise") or 0.0
    return math.sqrt(max(e * e - s * s, 0.0))


def edge(d, m, r):
    """' (edge of the sweep)' if r's value is the largest or smallest rendered for method m."""
    vals = [float(x["value"]) for x in d["sweep"][m] + d["final"][m]]
    v = float(r["value"])
    return " (largest swept)" if v >= max(vals) else " (smallest swept)" if v <= min(vals) else ""


def loglog(n0, e0, n1, e1, e):
    if e0 == e1:
        return n0
    s = (math.log(e) - math.log(e0)) / (math.log(e1) - math.log(e0))
    return math.exp(math.log(n0) + s * (math.log(n1) - math.log(n0)))


def small_png(src, dst, colours=128):
    """Copies a PNG as an adaptive-palette PNG (keeps the committed images small)."""
    from PIL import Image
    im = Image.open(src).convert("RGB")
    im.quantize(colours, method=Image.Quantize.MEDIANCUT, dither=Image.Dither.NONE).save(dst, optimize=True)


def scene_summary(scene, N, rows, work, docs, a):
    S = [r for r in rows if r["scene"] == scene]
    if not S:
        return None
    d = {"scene": scene, "N": N}
    whole = lambda r: r["region"] == "whole" and r["against"] == "ref"  # noqa: E731
    ref = [r for r in S if r["part"] == "ref"]
    chk = [r for r in S if r["part"] == "ref-check" and whole(r)]
    d["ref_wall"] = ref[0]["wall_s"] if ref else None
    d["check"] = chk[0] if chk else None
    d["ref_spp"] = int(ref[0]["spp"]) if ref else a.ref_spp
    if chk:
        # independent renders: RMSE(check, ref)^2 = s_c^2 + s_r^2, s_c^2 = s_r^2 * R / C
        d["ref_noise"] = chk[0]["rmse"] / math.sqrt(1 + d["ref_spp"] / chk[0]["spp"])
    sw = {m: sorted([r for r in S if r["part"] == "sweep" and r["method"] == m and whole(r)],
                    key=lambda r: float(r["value"])) for m in METHODS}
    d["sweep"] = sw
    fin = {m: sorted([r for r in S if r["part"] == "final" and r["method"] == m and whole(r)],
                     key=lambda r: float(r["value"])) for m in METHODS}
    d["final"] = fin
    opt = {}
    for m in METHODS:
        if fin[m]:
            opt[m] = {"rmse": min(fin[m], key=lambda r: r["rmse"]), "ssim": max(fin[m], key=lambda r: r["ssim"])}
    d["opt"] = opt
    d["opt1"] = {m: {"rmse": min(sw[m], key=lambda r: r["rmse"]), "ssim": max(sw[m], key=lambda r: r["ssim"])}
                 for m in METHODS if sw[m]}
    st = os.path.join(work, scene, "match-status.txt")
    d["status"] = open(st).read().strip() if os.path.isfile(st) else "none"
    vr = [r for r in S if r["part"] == "vpmref" and whole(r)]
    d["vpmref"] = vr[0] if vr else None
    d["vs_vpmref"] = {r["image"]: r for r in S if r["part"] == "vs-vpmref"}
    reg = {}
    for r in S:
        if r["part"] == "region":
            reg.setdefault(r["image"], {})[r["region"]] = r
    d["regions"] = reg
    rn = os.path.join(work, scene, "region-notes.txt")
    d["region_text"] = dict(REGION_TEXT)
    if os.path.isfile(rn):
        for line in open(rn):
            if "=" in line:
                k, v = line.strip().split("=", 1)
                d["region_text"][k] = v
    # photon-count scan: best vpm RMSE / SSIM per count (N from the sweep)
    scan = {}
    for r in S:
        if (r["part"] == "match" or (r["part"] == "final" and r["method"] == "vpm")) and whole(r):
            scan.setdefault(int(r["photons"]), []).append(r)
    d["scan"] = {n: (min(rs, key=lambda r: r["rmse"]), max(rs, key=lambda r: r["ssim"]))
                 for n, rs in sorted(scan.items())}
    for metric in ("rmse", "ssim"):
        key = "match_" + metric
        if "vpd" not in opt or "vpm" not in opt:
            continue
        target = opt["vpd"][metric][metric]
        pts = [(n, (b[0] if metric == "rmse" else b[1])[metric]) for n, b in d["scan"].items()]
        good = (lambda e: e <= target) if metric == "rmse" else (lambda e: e >= target)
        if good(pts[0][1]):
            d[key] = ("already", pts[0][0])
            continue
        d[key] = ("more", pts[-1][0], d["status"])
        for (n0, e0), (n1, e1) in zip(pts, pts[1:]):
            if not good(e0) and good(e1):
                if metric == "rmse":
                    d[key] = ("at", loglog(n0, e0, n1, e1, target))
                else:  # SSIM: interpolate linearly in log N
                    s = (target - e0) / (e1 - e0)
                    d[key] = ("at", math.exp(math.log(n0) + s * (math.log(n1) - math.log(n0))))
                break
    # images
    sd = os.path.join(work, scene)
    imgs = {}
    def put(key, name, src):
        p = os.path.join(sd, src)
        if os.path.isfile(p):
            small_png(p, os.path.join(docs, f"{scene}-{name}.png"))
            imgs[key] = f"{scene}-{name}.png"
    put("ref", "reference", "ref.png")
    for m in opt:
        put(m, m, opt[m]["rmse"]["image"] + ".png")
        put("err-" + m, m + "-error", "err-" + opt[m]["rmse"]["image"] + ".png")
        if opt[m]["ssim"]["image"] != opt[m]["rmse"]["image"]:
            put(m + "-ssim", m + "-ssim", opt[m]["ssim"]["image"] + ".png")
    if d["vpmref"]:
        put("vpmref", "vpm-ref", d["vpmref"]["image"] + ".png")
        put("err-vpmref", "vpm-ref-error", "err-" + d["vpmref"]["image"] + ".png")
    put("err-ref-check", "ref-check-error", "err-ref-check.png")
    d["imgs"] = imgs
    plots(d, os.path.join(docs, f"{scene}-plots.png"))
    d["plot"] = f"{scene}-plots.png"
    return d


def plots(d, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(1, 3, figsize=(12.5, 4.0))
    handles = ([], []), ([], [])
    sw = d["sweep"]
    for i, metric in enumerate(("rmse", "ssim")):
        a = ax[i]
        for m in ("vpm", "beam"):
            if sw[m]:
                a.plot([float(r["value"]) for r in sw[m]], [r[metric] for r in sw[m]], "o-",
                       color=COLOURS[m], label=f"{m} at {a_spp} spp (k, bottom axis)")
        for m in ("vpm", "beam"):
            if d["final"][m]:
                a.plot([float(r["value"]) for r in d["final"][m]], [r[metric] for r in d["final"][m]], "o",
                       mfc="none", ms=9, color=COLOURS[m], label=f"{m} at {a_fspp} spp")
        a.set_xscale("log", base=2); a.set_xlabel("k (vpm, beam)")
        if sw["vpd"]:
            b = a.twiny()
            b.plot([float(r["value"]) for r in sw["vpd"]], [r[metric] for r in sw["vpd"]], "s--",
                   color=COLOURS["vpd"], label="vpd (s, top axis)")
            if d["final"]["vpd"]:
                b.plot([float(r["value"]) for r in d["final"]["vpd"]], [r[metric] for r in d["final"]["vpd"]], "s",
                       mfc="none", ms=9, color=COLOURS["vpd"], label=f"vpd at {a_fspp} spp")
            b.set_xscale("log", base=2); b.set_xlabel("s (vpd)", color=COLOURS["vpd"])
            if metric == "rmse":
                handles = a.get_legend_handles_labels(), b.get_legend_handles_labels()
        if metric == "rmse" and d.get("ref_noise"):
            a.axhline(d["ref_noise"], color="grey", lw=0.8, ls=":", label="reference noise")
        if metric == "rmse":
            a.set_yscale("log")
        a.set_ylabel(metric.upper()); a.grid(alpha=0.3)
    a = ax[2]
    ns = list(d["scan"])
    a.plot(ns, [d["scan"][n][0]["rmse"] for n in ns], "o-", color=COLOURS["vpm"], label="vpm, best k per count")
    if "vpd" in d["opt"]:
        a.axhline(d["opt"]["vpd"]["rmse"]["rmse"], color=COLOURS["vpd"], ls="--",
                  label=f"vpd at {d['N']} photons, best s")
        a.axvline(d["N"], color="grey", lw=0.6)
    mr = d.get("match_rmse")
    if mr and mr[0] == "at":
        a.plot([mr[1]], [d["opt"]["vpd"]["rmse"]["rmse"]], "x", color="red", ms=9, mew=2,
               label=f"match: {mr[1] / d['N']:.3g}× N")
    if "beam" in d["opt"]:
        a.axhline(d["opt"]["beam"]["rmse"]["rmse"], color=COLOURS["beam"], ls=":", label="beam at N, best k")
    a.set_xscale("log"); a.set_yscale("log"); a.set_xlabel("volume photons"); a.set_ylabel("RMSE")
    a.legend(fontsize=7); a.grid(alpha=0.3, which="both")
    fig.suptitle(f"{d['scene']}: error against the light tracer (--volume-only)", fontsize=10)
    (h1, l1), (h2, l2) = handles
    fig.legend(h1 + h2, l1 + l2, loc="lower center", ncol=4, fontsize=7, frameon=False)
    fig.tight_layout(rect=(0, 0.1, 1, 1))
    fig.savefig(path + ".tmp.png", dpi=72)
    plt.close(fig)
    small_png(path + ".tmp.png", path, 64)
    os.remove(path + ".tmp.png")


def t(x):
    return "—" if x is None else f"{x:.2f}"


def match_text(d, metric):
    mr = d.get("match_" + metric)
    if not mr:
        return "—"
    kind, n = mr[:2]
    if kind == "already":
        return f"vpm already matches at N = {d['N']}"
    if kind == "more":
        why = {"time": "scan stopped by the time budget", "max": "not reached up to MATCH_MAX"}.get(
            mr[2] if len(mr) > 2 else "", "not reached in the scan")
        if len(d["scan"]) == 1:
            why = "no scan: vpm is not behind in RMSE" if metric == "ssim" else why
        extra = ""
        pts = [(k, v[0]["rmse"]) for k, v in d["scan"].items()]
        if metric == "rmse" and len(pts) >= 2 and pts[-1][1] < pts[-2][1]:
            (n0, e0), (n1, e1) = pts[-2], pts[-1]
            x = loglog(n0, e0, n1, e1, d["opt"]["vpd"]["rmse"]["rmse"])
            extra = f"; extrapolating the last two counts log-log: ≈ {x / d['N']:.3g}× N"
        return f"> {int(n)} photons (> {n / d['N']:.3g}× N; {why}{extra})"
    return f"≈ {n:,.0f} photons = {n / d['N']:.3g}× N (log-log between the bracketing counts)"


def scene_md(d):
    o = []
    sc, N, opt = d["scene"], d["N"], d["opt"]
    o += [f"## {sc} ({N} volume photons)", ""]
    if d.get("check"):
        c = d["check"]
        o += [f"Reference: light tracer `--volume-only`, {d['ref_spp']} light paths/pixel "
              f"(wall {t(d['ref_wall'])} s). Noise floor: an independent render with {int(c['spp'])} "
              f"paths/pixel (seed + 1) against it: RMSE {f4(c['rmse'])}, SSIM {f4(c['ssim'])}, "
              f"rel. mean {pct(c['relmean'])}; the reference's own RMSE is then ≈ {f4(d['ref_noise'])}.", ""]
    o1 = d["opt1"]
    o += [f"**Stage 1: sweeps at {a_spp} spp** (whole image against the reference; times in s: wall of the "
          "process, photon pass, camera pass = summary time − photon pass; bold: RMSE-optimal, italic: "
          "SSIM-optimal; a sweep stops once a value is worse than its best in both RMSE and SSIM):", "",
          "| method | setting | RMSE | SSIM | rel. mean diff. | median radius (m) | march step (m) | wall | photons | camera |",
          "|---|---|---|---|---|---|---|---|---|---|"]
    for m in METHODS:
        for r in d["sweep"][m]:
            e, s = f4(r["rmse"]), f4(r["ssim"])
            if m in o1 and r is o1[m]["rmse"]:
                e = f"**{e}**"
            if m in o1 and r is o1[m]["ssim"]:
                s = f"*{s}*"
            o.append(f"| {m} | {setting(r)} | {e} | {s} | {pct(r['relmean'])} | {f4(r['median_radius'])} | "
                     f"{f4(r['step'])} | {t(r['wall_s'])} | {t(r['photons_s'])} | {t(r['camera_s'])} |")
    o.append("")
    o += [f"**Stage 2: at {a_fspp} spp** (stage 1's optima, then the RMSE-optimal bandwidth halved while "
          f"the RMSE falls; the columns at {a_spp} spp repeat stage 1 for the same setting):", "",
          f"| method | setting | RMSE | SSIM | rel. mean diff. | RMSE at {a_spp} spp | SSIM at {a_spp} spp | wall | photons | camera |",
          "|---|---|---|---|---|---|---|---|---|---|"]
    for m in METHODS:
        lo = {r["value"]: r for r in d["sweep"][m]}
        for r in d["final"][m]:
            e, s = f4(r["rmse"]), f4(r["ssim"])
            if m in opt and r is opt[m]["rmse"]:
                e = f"**{e}**"
            if m in opt and r is opt[m]["ssim"]:
                s = f"*{s}*"
            r0 = lo.get(r["value"])
            o.append(f"| {m} | {setting(r)} | {e} | {s} | {pct(r['relmean'])} | {f4(r0['rmse']) if r0 else '—'} | "
                     f"{f4(r0['ssim']) if r0 else '—'} | {t(r['wall_s'])} | {t(r['photons_s'])} | {t(r['camera_s'])} |")
    o.append("")
    if "vpm" in opt and "vpd" in opt:
        v, p, b = opt["vpm"], opt["vpd"], opt.get("beam")
        o += [f"**At the optima** (stage 2, {a_fspp} spp):", "",
              "| method | RMSE-optimal | RMSE | RMSE less the reference's noise | SSIM there | rel. mean diff. | wall (s) | photons (s) | camera (s) | SSIM-optimal | SSIM | RMSE there |",
              "|---|---|---|---|---|---|---|---|---|---|---|---|"]
        for m in METHODS:
            if m in opt:
                r, s = opt[m]["rmse"], opt[m]["ssim"]
                o.append(f"| {m} | {setting(r)}{edge(d, m, r)} | {f4(r['rmse'])} | {f4(denoise(d, r['rmse']))} | {f4(r['ssim'])} | {pct(r['relmean'])} | "
                         f"{t(r['wall_s'])} | {t(r['photons_s'])} | {t(r['camera_s'])} | {setting(s)}{edge(d, m, s)} | {f4(s['ssim'])} | {f4(s['rmse'])} |")
        vr = d.get("vpmref")
        if vr:
            o.append(f"| vpm {int(vr['photons'])} photons, {int(vr['spp'])} spp (secondary reference) | {setting(vr)} | {f4(vr['rmse'])} | {f4(denoise(d, vr['rmse']))} | "
                     f"{f4(vr['ssim'])} | {pct(vr['relmean'])} | {t(vr['wall_s'])} | {t(vr['photons_s'])} | {t(vr['camera_s'])} | | | |")
        o.append("")
        o += [f"* RMSE ratio vpd / vpm at the RMSE optima: **{p['rmse']['rmse'] / v['rmse']['rmse']:.3g}** "
              f"({f4(p['rmse']['rmse'])} / {f4(v['rmse']['rmse'])})"
              + (f"; beam / vpm {b['rmse']['rmse'] / v['rmse']['rmse']:.3g}, vpd / beam "
                 f"{p['rmse']['rmse'] / b['rmse']['rmse']:.3g}." if b else "."),
              f"* The same with the reference's own noise taken out (√(RMSE² − σ_ref²), σ_ref = {f4(d.get('ref_noise'))}): "
              f"vpd / vpm {denoise(d, p['rmse']['rmse']) / denoise(d, v['rmse']['rmse']):.3g}.",
              f"* SSIM at the SSIM optima: vpm {f4(v['ssim']['ssim'])}, "
              + (f"beam {f4(b['ssim']['ssim'])}, " if b else "") + f"vpd {f4(p['ssim']['ssim'])}.",
              f"* Photons vpm needs to reach vpd's best RMSE ({f4(p['rmse']['rmse'])}): {match_text(d, 'rmse')}; "
              f"vpd's best SSIM ({f4(p['ssim']['ssim'])}): {match_text(d, 'ssim')}.", ""]
    if len(d["scan"]) > 1:
        o += [f"**vpm by photon count** ({a_fspp} spp; best of its k values at each count; N's row is stage 2):", "",
              "| volume photons | × N | best RMSE | its k | best SSIM | its k | wall of the RMSE-best (s) |", "|---|---|---|---|---|---|---|"]
        for n, (br, bs) in d["scan"].items():
            ks = sorted({r["value"] for r in [br, bs]})
            o.append(f"| {n} | {n / N:.3g} | {f4(br['rmse'])} | {br['value']} | {f4(bs['ssim'])} | {bs['value']} | {t(br['wall_s'])} |")
        o.append("")
    if d["regions"]:
        names = []
        for reg in d["regions"].values():
            names += [k for k in reg if k not in names]
        o += ["**Where the estimates differ from the reference** (relative mean difference and RMSE "
              "per region, at the RMSE optima; regions: " + "; ".join(f"{k}: {d['region_text'].get(k, k)}" for k in names) + "):", "",
              "| image | " + " | ".join(f"{k} rel. mean | {k} RMSE" for k in names) + " |",
              "|---|" + "---|---|" * len(names)]
        for img, reg in d["regions"].items():
            any_r = next(iter(reg.values()))
            label = f"{any_r['method']} {int(any_r['photons'])}, {setting(any_r)}"
            px = ""
            o.append(f"| {label} | " + " | ".join(
                (f"{pct(reg[k]['relmean'])} | {f4(reg[k]['rmse'])}" if k in reg else "— | —") for k in names) + " |")
        pxs = next(iter(d["regions"].values()))
        o.append("")
        o.append("Region sizes (pixels): " + ", ".join(f"{k} {int(pxs[k]['pixels'])}" for k in names if k in pxs) + ".")
        o.append("")
    vs = d["vs_vpmref"]
    if vs and d.get("vpmref"):
        o += [f"Against the secondary reference (vpm with {int(d['vpmref']['photons'])} photons, "
              f"{setting(d['vpmref'])}), as the seed compared: " + "; ".join(
                  f"{r['method']} {setting(r)} RMSE {f4(r['rmse'])}, SSIM {f4(r['ssim'])}, rel. mean {pct(r['relmean'])}"
                  for r in vs.values()) + ".", ""]
    if "vpm" in opt and "vpd" in opt:
        pv, pd_ = opt["vpm"]["rmse"], opt["vpd"]["rmse"]
        o += [f"Photon pass at N (includes building the volume map: k-NN radii for vpm/beam, differentials "
              f"for vpd): vpm {t(pv['photons_s'])} s, vpd {t(pd_['photons_s'])} s"
              + (f", beam {t(opt['beam']['rmse']['photons_s'])} s" if "beam" in opt else "") + ".", ""]
    o += [f"![{sc} plots]({d['plot']})", ""]
    return o


def html_page(ds, a):
    css = ("body{font-family:Helvetica,Arial,sans-serif;max-width:1400px;margin:1em auto;padding:0 1em;color:#222}"
           ".row{display:flex;flex-wrap:wrap;gap:10px}figure{margin:0;width:%dpx}figure img{width:100%%;"
           "image-rendering:pixelated;background:#000}figcaption{font-size:12px}code{background:#f4f4f4}"
           "img.plot{max-width:100%%}") % 260
    o = ["<!DOCTYPE html>", '<html lang="en"><head><meta charset="utf-8"><title>Volume photon differentials, measured</title>'
         f"<style>{css}</style></head><body>",
         "<h1>Volume photon differentials vs ray-marched volume photon mapping (seed 000 sec. 8.5), measured</h1>",
         f"<p>Regenerate: <code>{html.escape(a.command)}</code>. Media only (<code>--volume-only</code>: light scattered "
         f"by media straight to the camera along the first segment), sweeps at {a.spp} spp, optima at {a.final_spp} spp, seed 1, <code>--no-auto-bandwidth</code>; "
         f"reference: the light tracer <code>--volume-only</code> (light paths per pixel per scene below). Each "
         f"method at its RMSE-optimal setting ({a.final_spp} spp); error images: signed luminance difference against the reference "
         "(blue: darker, red: brighter), one colour scale per scene (3 × vpm's best RMSE). See README.md for the tables.</p>"]
    for d in ds:
        opt, im = d["opt"], d["imgs"]
        o.append(f"<h2>{html.escape(d['scene'])} ({d['N']} volume photons)</h2>")
        figs = []
        def fig(key, cap):
            if key in im:
                figs.append(f'<figure><img src="{im[key]}" alt="{html.escape(cap)}"><figcaption>{html.escape(cap)}</figcaption></figure>')
        ref_cap = f"reference: light tracer, {d['ref_spp']} paths/pixel, {t(d['ref_wall'])} s"
        if d.get("ref_noise"):
            ref_cap += f"; its noise ≈ RMSE {f4(d['ref_noise'])}"
        fig("ref", ref_cap)
        for m in METHODS:
            if m in opt:
                r = opt[m]["rmse"]
                fig(m, f"{m}, {setting(r)} (RMSE-optimal): RMSE {f4(r['rmse'])}, SSIM {f4(r['ssim'])}, "
                       f"rel. mean {pct(r['relmean'])}, {t(r['wall_s'])} s")
        vr = d.get("vpmref")
        if vr:
            fig("vpmref", f"vpm, {int(vr['photons'])} photons, {setting(vr)}: RMSE {f4(vr['rmse'])}, "
                          f"SSIM {f4(vr['ssim'])}, rel. mean {pct(vr['relmean'])}, {t(vr['wall_s'])} s")
        o.append('<div class="row">' + "".join(figs) + "</div>")
        figs = []
        c = d.get("check")
        if c:
            fig("err-ref-check", f"error: light tracer {int(c['spp'])} paths/pixel, other seed (noise floor), RMSE {f4(c['rmse'])}")
        for m in METHODS:
            if m in opt:
                fig("err-" + m, f"error: {m} {setting(opt[m]['rmse'])}")
        if vr:
            fig("err-vpmref", f"error: vpm {int(vr['photons'])}")
        o.append('<div class="row">' + "".join(figs) + "</div>")
        figs = []
        for m in METHODS:
            if m in opt and m + "-ssim" in im:
                r = opt[m]["ssim"]
                fig(m + "-ssim", f"{m}, {setting(r)} (SSIM-optimal): SSIM {f4(r['ssim'])}, RMSE {f4(r['rmse'])}")
        if figs:
            o.append('<div class="row">' + "".join(figs) + "</div>")
        if "vpm" in opt and "vpd" in opt:
            v, p = opt["vpm"], opt["vpd"]
            o.append(f"<p>RMSE vpd / vpm at the optima: <b>{p['rmse']['rmse'] / v['rmse']['rmse']:.3g}</b>; "
                     f"SSIM at the SSIM optima: vpm {f4(v['ssim']['ssim'])}"
                     + (f", beam {f4(opt['beam']['ssim']['ssim'])}" if "beam" in opt else "")
                     + f", vpd {f4(p['ssim']['ssim'])}. Photons vpm needs to reach vpd's RMSE: "
                     f"{html.escape(match_text(d, 'rmse'))}.</p>")
        o.append(f'<p><img class="plot" src="{d["plot"]}" alt="sweeps and photon count"></p>')
    o.append("</body></html>")
    return "\n".join(o) + "\n"


a_ref_spp = a_spp = a_fspp = 0


def cmd_summarize(a):
    global a_ref_spp, a_spp, a_fspp
    a_ref_spp, a_spp, a_fspp = a.ref_spp, a.spp, a.final_spp
    os.makedirs(a.docs, exist_ok=True)
    rows = load(a.work)
    shutil.copy(os.path.join(a.work, "results.csv"), os.path.join(a.docs, "results.csv"))
    ds = []
    for e in a.scenes.split():
        parts = e.split(":")
        d = scene_summary(parts[0], int(parts[1]), rows, a.work, a.docs, a)
        if d:
            ds.append(d)
    o = ["# Volume photon differentials, measured (seed 000 sec. 8.5; spec §2.6, §3.4 XM1–XM3)", "",
         "Regenerate everything (renders in `~/.cache/caustica/volume-differentials/`, reused when present):", "",
         f"    {a.command}", "",
         "Every image is media only (`--volume-only`: light scattered by media straight to the camera along the "
         "camera ray's first segment, seed notes Q-M11), so the volume estimators of ch. 8 are compared alone. "
         f"The photon methods use `--no-auto-bandwidth --seed 1 -q`, bandwidth sweeps at `--spp {a.spp}` and the "
         f"optima (and the photon-count scan) at `--spp {a.final_spp}`; the reference is "
         "`lighttrace --volume-only --seed 7` (unbiased for these paths; light paths per pixel per scene below). "
         "Metrics (`caustica compare IMG REF`) are over the whole image unless a region is named: RMSE on linear "
         "radiance, SSIM on the display image, relative mean difference (image mean / reference mean − 1).", "",
         "Methods: `vpm` ray marching with k-NN per step (eq. 8.3; `--volume-k k`, step half the median radius); "
         "`beam` k-NN pilot radii with the exact chord integral (`--volume-k k`; the ablation: vpm's kernel shape, "
         "vpd's integration); `vpd` photon differentials in media, ellipsoidal kernels (`--volume-smoothing s`).", "",
         "**Machine:** a shared 2-core machine; other engineers built and rendered alongside. Times are wall "
         "times of single processes and are only good as ratios within this session.", ""]
    if ds:
        o += ["## Summary", "",
              "| scene | N | RMSE vpd / vpm (RMSE optima) | beam / vpm | SSIM vpm / beam / vpd (SSIM optima) | vpm photons to reach vpd's RMSE | vpd rel. mean diff. | vpm rel. mean diff. |",
              "|---|---|---|---|---|---|---|---|"]
        for d in ds:
            opt = d["opt"]
            if "vpm" in opt and "vpd" in opt:
                v, p, b = opt["vpm"], opt["vpd"], opt.get("beam")
                o.append(f"| {d['scene']} | {d['N']} | {p['rmse']['rmse'] / v['rmse']['rmse']:.3g} | "
                         f"{(b['rmse']['rmse'] / v['rmse']['rmse']) if b else float('nan'):.3g} | "
                         f"{f4(v['ssim']['ssim'])} / {f4(b['ssim']['ssim']) if b else '—'} / {f4(p['ssim']['ssim'])} | "
                         f"{match_text(d, 'rmse')} | {pct(p['rmse']['relmean'])} | {pct(v['rmse']['relmean'])} |")
        o.append("")
    for d in ds:
        o += scene_md(d)
    notes = os.path.join(a.docs, "notes.md")
    if os.path.isfile(notes):
        o += [open(notes).read().rstrip(), ""]
    o += ["See `index.html` for the images side by side; `results.csv` holds every render and region "
          "(columns: scene, part, method, photons, param, value, spp, seed, times, median radius, step, region, "
          "pixels, rmse, ssim, relmean, against, image).", ""]
    open(os.path.join(a.docs, "README.md"), "w").write("\n".join(o))
    open(os.path.join(a.docs, "index.html"), "w").write(html_page(ds, a))
    print("\n".join(o))


def main():
    ap = argparse.ArgumentParser()
    sub = ap.add_subparsers(dest="cmd", required=True)
    m = sub.add_parser("masks")
    m.add_argument("ref"); m.add_argument("dir")
    m.add_argument("--toml"); m.add_argument("--width", type=int)
    m.add_argument("--crop", action="append", help="NAME:X,Y,W,H, an extra rectangular region")
    s = sub.add_parser("summarize")
    s.add_argument("work"); s.add_argument("docs")
    s.add_argument("--spp", type=int, required=True); s.add_argument("--ref-spp", type=int, required=True)
    s.add_argument("--check-spp", type=int, required=True); s.add_argument("--ref-photons", type=int, required=True)
    s.add_argument("--final-spp", type=int, required=True); s.add_argument("--ref-k", type=int, default=128)
    s.add_argument("--scenes", required=True); s.add_argument("--bin", default="")
    s.add_argument("--command", default="bash bench/volume_differentials.sh")
    a = ap.parse_args()
    (cmd_masks if a.cmd == "masks" else cmd_summarize)(a)


if __name__ == "__main__":
    main()
