#!/usr/bin/env python3
"""Summarises bench/seed002_scenes.sh: equal-time pm / pdm / pds on cognac-glass, embedded-torus
and swimming-pool (seed 002 figs. 10, 11, 13).

    python3 tools/summarize_seed002_scenes.py WORK OUT CAUSTICA BUDGET_N SCENE=X,Y,W,H ...

Writes OUT/README.md, OUT/results.csv and the images (side by side at equal time, close-ups
magnified 3x). Needs numpy and Pillow for the close-up and side-by-side images (the peers venv
has them); without them it writes the tables only.
"""
import csv
import os
import re
import shutil
import subprocess
import sys

METHODS = ["pm", "pdm", "pds"]
TITLES = {
    "cognac-glass": "Cognac glass (seed 002 fig. 10)",
    "swimming-pool": "Swimming pool (seed 002 fig. 11)",
    "embedded-torus": "Embedded torus (seed 002 fig. 13)",
}


def rows(path):
    with open(path) as f:
        return [{k: float(v) for k, v in r.items()} for r in csv.DictReader(f)]


def compare(caustica, img, ref, crop, mask_black):
    args = [caustica, "compare", img, ref, "--crop", crop]
    if mask_black:
        args.append("--mask-black")
    out = subprocess.run(args, capture_output=True, text=True).stdout
    rmse = float(re.search(r"^RMSE\s+(\S+)", out, re.M).group(1))
    ssim = float(re.search(r"^SSIM \(display\)\s+(\S+)", out, re.M).group(1))
    return rmse, ssim


def fmt_count(n):
    return f"{int(n):,}".replace(",", " ")


def images(work, out, scene, picks, crop):
    try:
        import numpy as np
        from PIL import Image
    except ImportError:
        return False
    d = os.path.join(work, scene)
    x, y, w, h = map(int, crop.split(","))
    tiles = [("reference", os.path.join(d, "reference.png"))]
    for m in METHODS:
        if picks.get(m):
            tiles.append((m, os.path.join(d, f"{m}-n", f"photons-{int(picks[m]['value'])}.png")))
    full, close = [], []
    for name, p in tiles:
        im = Image.open(p).convert("RGB")
        a = np.array(im)
        # The close-up's frame in red on the full image.
        framed = a.copy()
        for t in range(2):
            framed[max(y - 1 - t, 0), max(x - 1, 0):x + w + 1] = (255, 0, 0)
            framed[min(y + h + t, a.shape[0] - 1), max(x - 1, 0):x + w + 1] = (255, 0, 0)
            framed[y - 1:y + h + 1, max(x - 1 - t, 0)] = (255, 0, 0)
            framed[y - 1:y + h + 1, min(x + w + t, a.shape[1] - 1)] = (255, 0, 0)
        full.append(framed)
        c = Image.fromarray(a[y:y + h, x:x + w]).resize((3 * w, 3 * h), Image.NEAREST)
        close.append(np.array(c))
        Image.fromarray(a).save(os.path.join(out, f"{scene}-{name}.png"))
        c.save(os.path.join(out, f"{scene}-{name}-closeup.png"))
    gap = lambda arr: np.full((arr.shape[0], 4, 3), 255, np.uint8)
    row = lambda ims: np.concatenate(sum([[i, gap(i)] for i in ims], [])[:-1], axis=1)
    Image.fromarray(row(full)).save(os.path.join(out, f"{scene}-side-by-side.png"))
    Image.fromarray(row(close)).save(os.path.join(out, f"{scene}-closeups.png"))
    return True


def main():
    work, out, caustica, budget_n = sys.argv[1:5]
    crops = dict(a.split("=", 1) for a in sys.argv[5:])
    budget_n = int(budget_n)
    os.makedirs(out, exist_ok=True)
    params = open(os.path.join(work, "params.txt")).read().strip()
    md = [
        "# Seed 002's cognac glass, swimming pool and embedded torus: pm, pdm and pds at equal time",
        "",
        "Regenerate: `bash bench/seed002_scenes.sh` (then this page: "
        "`tools/summarize_seed002_scenes.py`, called by the script). Every render's command line is "
        "in [commands.log](commands.log); the study's parameters:",
        "",
        "```",
        params,
        "```",
        "",
        "**Method.** Seed 002 compares methods at equal time by the photons each processes in the "
        "budget (figs. 10-11: RMSE and SSIM against a reference). Here each method first gets its "
        "RMSE-optimal bandwidth at N0 photons (pm: k; pdm and pds: s), then renders a ladder of "
        "photon counts at it; the budget is pds's render time at BUDGET_N photons and each method "
        "is shown with the largest count whose whole render (photon tracing, map or eye map, "
        "estimates or splats, camera pass) fits in 1.05 x the budget. Times are wall-clock on two "
        "cores **shared with another engineer's builds and renders** (load 4-6 during the study), "
        "so they carry maybe ±30 % noise; the photon counts are a ladder of factors of 2, so equal "
        "time is equal within that factor.",
        "",
        "* `cognac-glass`, `embedded-torus`: caustics only (L S+ D E, `--caustics-only`: the "
        "caustic seen directly on the table and floor), against the light tracer (unbiased) with "
        "REF_LT light paths per pixel; pixels black in both (the glass seen directly) are left out "
        "(`--mask-black`).",
        "* `swimming-pool`: the floor and walls are seen only through the water (L S D S E), which "
        "the light tracer cannot render, so, as seed 002 did for its pool, the reference is `pm` "
        "with REF_PM photons (k = REF_K, REF_SPP spp, its own seed); indirect light is off in every "
        "render (`--global-photons 0`), so the images are direct light plus "
        "caustics. A pm reference favours pm's kernel shape somewhat; its own blur is a k-NN radius "
        "of a few millimetres, under a pixel (about 1.5 cm of floor).",
        "",
    ]
    table = []
    for scene in ["cognac-glass", "swimming-pool", "embedded-torus"]:
        d = os.path.join(work, scene)
        if not os.path.exists(os.path.join(d, "pds-n", "sweep.csv")):
            continue
        k, s_pdm, s_pds = open(os.path.join(d, "bandwidths.txt")).read().split()
        setting = {"pm": f"k = {k}", "pdm": f"s = {s_pdm}", "pds": f"s = {s_pds}"}
        lad = {m: rows(os.path.join(d, f"{m}-n", "sweep.csv")) for m in METHODS}
        bws = {
            "pm": rows(os.path.join(d, "pm-k", "sweep.csv")),
            "pdm": rows(os.path.join(d, "pdm-s", "sweep.csv")),
            "pds": rows(os.path.join(d, "pds-s", "sweep.csv")),
        }
        budget = next(r["seconds"] for r in lad["pds"] if int(r["value"]) == budget_n)
        ref = [f for f in os.listdir(d) if f.startswith("reference-") and f.endswith(".exr")][0]
        ref_path = os.path.join(d, ref)
        ref_s = open(os.path.join(d, "reference.seconds")).read().strip()
        mask_black = scene != "swimming-pool"
        crop = crops[scene]
        picks = {}
        md += [f"## {TITLES[scene]}", "", f"Reference: `{ref[:-4]}` ({ref_s} s). Bandwidths "
               f"(RMSE-optimal at N0 photons): pm {setting['pm']}, pdm {setting['pdm']}, pds "
               f"{setting['pds']}. Budget: {budget:.1f} s (pds with {fmt_count(budget_n)} photons). "
               f"Close-up: the {crop.split(',')[2]} x {crop.split(',')[3]} pixels at "
               f"({crop.split(',')[0]}, {crop.split(',')[1]}) (red frame).", "",
               "| method | setting | photons in the budget | seconds | RMSE | SSIM | close-up RMSE | close-up SSIM |",
               "|---|---|---:|---:|---:|---:|---:|---:|"]
        for m in METHODS:
            fit = [r for r in lad[m] if r["seconds"] <= 1.05 * budget]
            if not fit:
                md.append(f"| {m} | {setting[m]} | none of the ladder fits | | | | | |")
                continue
            r = max(fit, key=lambda r: r["value"])
            picks[m] = r
            img = os.path.join(d, f"{m}-n", f"photons-{int(r['value'])}.exr")
            cr, cs = compare(caustica, img, ref_path, crop, mask_black)
            md.append(f"| {m} | {setting[m]} | {fmt_count(r['value'])} | {r['seconds']:.1f} | "
                      f"{r['rmse']:.4f} | {r['ssim']:.4f} | {cr:.4f} | {cs:.4f} |")
            table.append([scene, m, setting[m], "equal-time", int(r["value"]), r["seconds"],
                          r["rmse"], r["ssim"], cr, cs])
        if "pm" in picks and "pds" in picks:
            a, b = picks["pm"]["rmse"], picks["pds"]["rmse"]
            verdict = "lower" if b < a else "higher"
            ratio = f", ratio {b / a:.2f}" if a > 0 else ""
            md += ["", f"At equal time pds's RMSE is **{verdict}** than pm's ({b:.4f} against "
                   f"{a:.4f}{ratio}); SSIM {picks['pds']['ssim']:.4f} against "
                   f"{picks['pm']['ssim']:.4f}."]
        if images(work, out, scene, picks, crop):
            names = ["reference"] + [m for m in METHODS if m in picks]
            md += ["", "| " + " | ".join(names) + " |", "|" + "---|" * len(names),
                   "| " + " | ".join(f"![]({scene}-{n}.png)" for n in names) + " |",
                   "| " + " | ".join(f"![]({scene}-{n}-closeup.png)" for n in names) + " |"]
        shutil.copy(os.path.join(d, "reference.png"), os.path.join(out, f"{scene}-reference.png"))
        md += ["", "Every run (bandwidths at N0, then the photon ladders):", "",
               "| method | parameter | value | seconds | RMSE | SSIM |", "|---|---|---:|---:|---:|---:|"]
        for m, rs in bws.items():
            p = "k" if m == "pm" else "s"
            for r in rs:
                md.append(f"| {m} | {p} | {r['value']:g} | {r['seconds']:.1f} | {r['rmse']:.4f} | {r['ssim']:.4f} |")
                table.append([scene, m, f"{p} = {r['value']:g}", "bandwidth", "", r["seconds"],
                              r["rmse"], r["ssim"], "", ""])
        for m, rs in lad.items():
            for r in rs:
                md.append(f"| {m} | photons ({setting[m]}) | {fmt_count(r['value'])} | {r['seconds']:.1f} | {r['rmse']:.4f} | {r['ssim']:.4f} |")
                table.append([scene, m, setting[m], "ladder", int(r["value"]), r["seconds"],
                              r["rmse"], r["ssim"], "", ""])
        md.append("")
    with open(os.path.join(out, "results.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["scene", "method", "setting", "kind", "photons", "seconds", "rmse", "ssim",
                    "closeup_rmse", "closeup_ssim"])
        w.writerows(table)
    with open(os.path.join(out, "README.md"), "w") as f:
        f.write("\n".join(md) + "\n")
    print("\n".join(md))


if __name__ == "__main__":
    main()
