#!/usr/bin/env python3
"""Summarises bench/case_study_dpm.sh: optimal settings of pm and dpm per case study, their
errors and times, and the photon count pm needs to reach dpm's best RMSE.

usage: summarize_case_study_dpm.py WORK_DIR OUT_DIR PHOTONS REF_SPP SPP
Writes OUT_DIR/summary.csv, OUT_DIR/README.md and OUT_DIR/optima.txt (one line per image to
render at an optimum: scene, png name, caustica arguments).
"""
import csv
import os
import shutil
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sweep_csv import best, rows  # noqa: E402

work, out, photons, ref_spp, spp = sys.argv[1:6]
photons = int(photons)
SCENES = ["water-wave", "metal-ring"]
METRICS = [("rmse", min), ("mise", min), ("ssim", max)]


summary = []
md = [
    "# dpm vs pm on the case studies (Schjøth 2009 ch. 6, Table 6.1 / fig. 6.6-6.9)",
    "",
    f"Regenerate: `bash bench/case_study_dpm.sh {ref_spp} {spp}` (about 15 min on 2 cores). "
    f"Caustics only (L S+ D E), {photons} caustic photons, {spp} spp, seed 1; reference: the light "
    f"tracer with {ref_spp} light paths per pixel. Metrics over the whole image (`caustica sweep`): "
    "RMSE on linear radiance, MISE and SSIM on the display image (Schjøth 2009 ch. 6). "
    "dpm swept over q at each bandwidth h (q = 1e9 is the fixed-bandwidth estimate); "
    "noise scale h/2, α = 1.",
    "",
]
optima = []
for scene in SCENES:
    w = os.path.join(work, scene)
    pm = {}
    for d in sorted(os.listdir(w)):
        if d.startswith("pm-n") and os.path.isdir(os.path.join(w, d)):
            pm[int(d[4:])] = rows(os.path.join(w, d, "sweep.csv"))
    dpm = []
    for d in sorted(os.listdir(w)):
        if d.startswith("dpm-h") and os.path.isdir(os.path.join(w, d)):
            h = d[5:]
            for r in rows(os.path.join(w, d, "sweep.csv")):
                r["h"] = h
                dpm.append(r)
    adaptive = [r for r in dpm if float(r["value"]) < 1e8]
    fixed = [r for r in dpm if float(r["value"]) >= 1e8]
    md += [f"## {scene}", "", f"![reference]({scene}-reference.png) reference", ""]
    md += [
        "| method | optimal for | setting | RMSE | MISE | SSIM | seconds |",
        "|---|---|---|---|---|---|---|",
    ]
    for label, rs, fmt in [
        (f"pm ({photons})", pm[photons], lambda r: f"k = {r['value']}"),
        ("fixed bandwidth", fixed, lambda r: f"h = {r['h']}"),
        (f"dpm ({photons})", adaptive, lambda r: f"h = {r['h']}, q = {r['value']}"),
    ]:
        for metric, _ in METRICS:
            r = best(rs, metric)
            md.append(
                f"| {label} | {metric.upper()} | {fmt(r)} | {r['rmse']:.4f} | {r['mise']:.5f} | "
                f"{r['ssim']:.4f} | {r['seconds']:.2f} |"
            )
            summary.append(
                [scene, label, metric, fmt(r), r["rmse"], r["mise"], r["ssim"], r["seconds"]]
            )
    # Images at the RMSE and SSIM optima.
    for metric in ["rmse", "ssim"]:
        r = best(pm[photons], metric)
        optima.append(
            f"{scene} {scene}-pm-{metric}.png --integrator pm --photons {photons} --k {r['value']}"
        )
        r = best(adaptive, metric)
        optima.append(
            f"{scene} {scene}-dpm-{metric}.png --integrator dpm --photons {photons} "
            f"--bandwidth {r['h']} --q {r['value']}"
        )
    md += [
        "",
        "| | RMSE optimum | SSIM optimum |",
        "|---|---|---|",
        f"| pm | ![]({scene}-pm-rmse.png) | ![]({scene}-pm-ssim.png) |",
        f"| dpm | ![]({scene}-dpm-rmse.png) | ![]({scene}-dpm-ssim.png) |",
        "",
    ]
    # Photons pm needs to reach dpm's best RMSE / MISE.
    for metric in ["rmse", "mise"]:
        target = best(adaptive, metric)[metric]
        need = None
        for n in sorted(pm):
            if best(pm[n], metric)[metric] <= target:
                need = n
                break
        curve = ", ".join(f"{n}: {best(pm[n], metric)[metric]:.5f}" for n in sorted(pm))
        text = f"{need}" if need else f"more than {max(pm)}"
        ratio = f" ({need / photons:.0f}× dpm's photons)" if need else ""
        md.append(
            f"pm needs **{text}** photons{ratio} to reach dpm's best {metric.upper()} "
            f"({target:.5f}); pm's best {metric.upper()} per photon count: {curve}."
        )
        md.append("")
        summary.append([scene, "pm photons to match dpm", metric, text, "", "", "", ""])
    for d in ["pm-n%d" % photons]:
        for ext in ["png", "svg"]:
            src = os.path.join(w, d, "sweep." + ext)
            if os.path.exists(src):
                shutil.copy(src, os.path.join(out, f"{scene}-pm-sweep.{ext}"))
    md.append(f"k sweep of pm: ![]({scene}-pm-sweep.png)")
    md.append("")

with open(os.path.join(out, "summary.csv"), "w", newline="") as f:
    wr = csv.writer(f)
    wr.writerow(["scene", "method", "optimal_for", "setting", "rmse", "mise", "ssim", "seconds"])
    wr.writerows(summary)
with open(os.path.join(out, "README.md"), "w") as f:
    f.write("\n".join(md) + "\n")
with open(os.path.join(out, "optima.txt"), "w") as f:
    f.write("\n".join(optima) + "\n")
print("\n".join(md))
