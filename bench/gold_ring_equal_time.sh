#!/usr/bin/env bash
# Issue 5: equal-time comparison of pm, pdm and pds on the gold ring (Frisvad et al. 2014 fig. 1-2):
# caustics only (paths L S+ D E from the area light via the gold ring), against a long light
# tracer run. Each method first gets its RMSE-optimal bandwidth at 20 000 photons (pm: k; pdm and
# pds: s), then a sweep over the photon count records render time, RMSE and SSIM. The equal-time
# table picks, for a time budget (default: pds's render time with 20 000 photons), the most
# photons each method processes within it.
#   bash bench/gold_ring_equal_time.sh [reference light paths per pixel (default 4096)] [spp (default 4)]
# Results: docs/results/gold-ring-equal-time/ (README.md, results.csv, images).
set -euo pipefail
cd "$(dirname "$0")/.."
ref_spp="${1:-4096}"
spp="${2:-4}"
cargo build --release -q --bin caustica
bin=./target/release/caustica
scene=gold-ring
out=docs/results/gold-ring-equal-time; mkdir -p "$out"
work=target/bench/gold-ring-equal-time; mkdir -p "$work"
ref="$work/reference-$ref_spp.exr"
if [ ! -f "$ref" ]; then
  echo "== reference: light tracer, $ref_spp paths/pixel"
  "$bin" render "$scene" --integrator lighttrace --caustics-only --spp "$ref_spp" --seed 7 -q \
    -o "$ref" --png "$out/reference.png"
fi
common=(--caustics-only --spp "$spp" --seed 1 --reference "$ref" --mask-black --quiet)
counts="5000,10000,20000,40000,80000,160000,320000"
best() { # best value of column 1 by RMSE (column 2) in a sweep.csv
  tail -n +2 "$1" | sort -t, -k2 -g | head -1 | cut -d, -f1
}
echo "== bandwidths at 20000 photons"
"$bin" sweep "$scene" --integrator pm --photons 20000 --param k --values 10,20,40,80,160 \
  "${common[@]}" -o "$work/pm-k" > /dev/null
for i in pdm pds; do
  "$bin" sweep "$scene" --integrator "$i" --photons 20000 --param smoothing --values 1,2,3,4,6,8 \
    "${common[@]}" -o "$work/$i-s" > /dev/null
done
k=$(best "$work/pm-k/sweep.csv"); s_pdm=$(best "$work/pdm-s/sweep.csv"); s_pds=$(best "$work/pds-s/sweep.csv")
echo "== photon sweeps (pm k = $k, pdm s = $s_pdm, pds s = $s_pds)"
"$bin" sweep "$scene" --integrator pm --k "$k" --param photons --values "$counts" "${common[@]}" \
  -o "$work/pm-n" > /dev/null
"$bin" sweep "$scene" --integrator pdm --smoothing "$s_pdm" --param photons --values "$counts" \
  "${common[@]}" -o "$work/pdm-n" > /dev/null
"$bin" sweep "$scene" --integrator pds --smoothing "$s_pds" --param photons --values "$counts" \
  "${common[@]}" -o "$work/pds-n" > /dev/null
python3 - "$work" "$out" "$k" "$s_pdm" "$s_pds" "$ref_spp" "$spp" <<'PY'
import csv, os, sys
work, out, k, s_pdm, s_pds, ref_spp, spp = sys.argv[1:8]
setting = {"pm": f"k = {k}", "pdm": f"s = {s_pdm}", "pds": f"s = {s_pds}"}
rows = {}
for m in ["pm", "pdm", "pds"]:
    with open(os.path.join(work, f"{m}-n", "sweep.csv")) as f:
        rows[m] = [{k2: float(v) for k2, v in r.items()} for r in csv.DictReader(f)]
budget = next(r["seconds"] for r in rows["pds"] if int(r["value"]) == 20000)
with open(os.path.join(out, "results.csv"), "w", newline="") as f:
    w = csv.writer(f)
    w.writerow(["method", "setting", "photons", "seconds", "rmse", "ssim"])
    for m, rs in rows.items():
        for r in rs:
            w.writerow([m, setting[m], int(r["value"]), r["seconds"], r["rmse"], r["ssim"]])
md = [
    "# Equal-time caustics on the gold ring: pm vs pdm vs pds (Frisvad et al. 2014 fig. 1-2)",
    "",
    f"Regenerate: `bash bench/gold_ring_equal_time.sh {ref_spp} {spp}`. Caustics only (L S+ D E: "
    f"the area light via the gold ring onto the table), {spp} spp, seed 1, against the light tracer "
    f"with {ref_spp} light paths per pixel; RMSE on linear radiance and SSIM on the display image "
    "over the pixels that are not black in both images (the light tracer leaves pixels that see "
    "the ring black). Each method at its RMSE-optimal bandwidth with 20 000 photons: "
    f"pm {setting['pm']}, pdm {setting['pdm']}, pds {setting['pds']}. Render time is the whole "
    "render (photon tracing, map or eye-map build, estimates or splats), 2 cores.",
    "",
    f"## Equal time: budget {budget:.2f} s (pds with 20 000 photons)",
    "",
    "| method | setting | photons within the budget | seconds | RMSE | SSIM |",
    "|---|---|---:|---:|---:|---:|",
]
for m, rs in rows.items():
    fit = [r for r in rs if r["seconds"] <= budget * 1.05]
    if not fit:
        md.append(f"| {m} | {setting[m]} | none ≥ 5000 fits | | | |")
        continue
    r = max(fit, key=lambda r: r["value"])
    md.append(f"| {m} | {setting[m]} | {int(r['value'])} | {r['seconds']:.2f} | {r['rmse']:.4f} | {r['ssim']:.4f} |")
md += ["", "## Every run", "", "| method | photons | seconds | RMSE | SSIM |", "|---|---:|---:|---:|---:|"]
for m, rs in rows.items():
    for r in rs:
        md.append(f"| {m} | {int(r['value'])} | {r['seconds']:.2f} | {r['rmse']:.4f} | {r['ssim']:.4f} |")
md += ["", "| reference | pm, 20 000 | pdm, 20 000 | pds, 20 000 |", "|---|---|---|---|",
       "| ![](reference.png) | ![](pm-20000.png) | ![](pdm-20000.png) | ![](pds-20000.png) |", ""]
with open(os.path.join(out, "README.md"), "w") as f:
    f.write("\n".join(md) + "\n")
print("\n".join(md))
PY
"$bin" render "$scene" --integrator pm --k "$k" --photons 20000 --caustics-only --spp "$spp" --seed 1 -q -o "$work/pm.exr" --png "$out/pm-20000.png" > /dev/null
"$bin" render "$scene" --integrator pdm --smoothing "$s_pdm" --photons 20000 --caustics-only --spp "$spp" --seed 1 -q -o "$work/pdm.exr" --png "$out/pdm-20000.png" > /dev/null
"$bin" render "$scene" --integrator pds --smoothing "$s_pds" --photons 20000 --caustics-only --spp "$spp" --seed 1 -q -o "$work/pds.exr" --png "$out/pds-20000.png" > /dev/null
