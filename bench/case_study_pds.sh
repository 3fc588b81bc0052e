#!/usr/bin/env bash
# Issue 5: seed 002 Table 1 and fig. 6-8 on our refraction and reflection case studies (built-in
# scenes water-wave and metal-ring) with 20 000 caustic photons:
#  * reference: the light tracer, caustics only (paths L S+ D E), run long;
#  * pm swept over k, pds swept over the smoothing parameter s, dpm over (h, q) (the dpm study's
#    sweeps), all caustics only, same spp and seed;
#  * RMSE- and SSIM-optimal settings, their errors and render times, and how many photons pm
#    needs to reach pds's best RMSE and SSIM (seed 002: ~10x and ~100x on the refraction case).
# Shares its work folder with bench/case_study_dpm.sh (reference, pm and dpm sweeps are reused,
# finished sweeps are not redone; delete target/bench/case-study-dpm to start over).
# Results: docs/results/case-study-pds/ (README.md, index.html, summary.csv, fig. 6/8 SVGs, images).
#   bash bench/case_study_pds.sh [reference light paths per pixel (default 8192)] [spp (default 16)]
set -euo pipefail
cd "$(dirname "$0")/.."
ref_spp="${1:-8192}"
spp="${2:-16}"
photons=20000
# The dpm study: reference, pm over k at 20k-640k photons, dpm over (h, q).
bash bench/case_study_dpm.sh "$ref_spp" "$spp" > /dev/null
bin=./target/release/caustica
out=docs/results/case-study-pds; mkdir -p "$out"
work=target/bench/case-study-dpm
ks="5,10,20,40,80,160,320"
ss="0.5,1,1.5,2,3,4,6,8,12"
pm_more="1280000 2560000 5120000"
# Re-runs reuse finished sweeps of the same values.
# shellcheck source=bench/sweep_lib.sh
. bench/sweep_lib.sh
for scene in water-wave metal-ring; do
  w="$work/$scene"
  common=(--caustics-only --spp "$spp" --seed 1 --reference "$w/reference-$ref_spp.exr" --quiet)
  if ! done_sweep "$w/pds-n$photons" "$ss"; then
    echo "== $scene: pds, $photons photons, sweep s"
    "$bin" sweep "$scene" --integrator pds --photons "$photons" --param smoothing --values "$ss" \
      "${common[@]}" -o "$w/pds-n$photons" > "$w/pds-n$photons.txt"
  fi
  for n in $pm_more; do
    if ! done_sweep "$w/pm-n$n" "$ks"; then
      echo "== $scene: pm, $n photons, sweep k"
      "$bin" sweep "$scene" --integrator pm --photons "$n" --param k --values "$ks" "${common[@]}" \
        -o "$w/pm-n$n" > "$w/pm-n$n.txt"
    fi
  done
  cp "docs/results/case-study-dpm/$scene-reference.png" "$out/$scene-reference.png"
done
python3 tools/summarize_case_study_pds.py "$work" "$out" "$photons" "$ref_spp" "$spp"
# Images at the optima, for the page.
while read -r scene png args; do
  [ -n "$scene" ] || continue
  # shellcheck disable=SC2086
  "$bin" render "$scene" --caustics-only --spp "$spp" --seed 1 -q $args \
    -o "$work/$scene/${png%.png}.exr" --png "$out/$png" > /dev/null
done < "$out/optima.txt"
