#!/usr/bin/env bash
# Issue 6: diffusion-based photon mapping (`dpm`) against k-NN photon mapping (`pm`) on the
# refraction and reflection case studies of seed 000 ch. 6 (built-in scenes water-wave and
# metal-ring), with 20 000 caustic photons as in seed 000 Table 6.1 / fig. 6.6-6.9.
#  * reference: the light tracer, caustics only (paths L S+ D E), run long;
#  * pm: sweep over k; dpm: sweep over q at each bandwidth h (q = 1e9 is the fixed-bandwidth
#    estimate, the thesis' way of choosing h); both caustics only, same spp and seed;
#  * RMSE-, MISE- and SSIM-optimal settings and their errors and times; how many photons pm
#    needs to reach dpm's best RMSE (seed 000 fig. 6.9: 155 000 for MISE).
# Pixels that see the glass or the mirror are black in every image (caustics only).
# Results: docs/results/case-study-dpm/ (README.md, CSVs, plots, images at the optima).
#   bash bench/case_study_dpm.sh [reference light paths per pixel (default 8192)] [spp (default 16)]
set -euo pipefail
cd "$(dirname "$0")/.."
# shellcheck source=bench/sweep_lib.sh
. bench/sweep_lib.sh
ref_spp="${1:-8192}"
spp="${2:-16}"
photons=20000
cargo build --release -q --bin caustica
bin=./target/release/caustica
out=docs/results/case-study-dpm; mkdir -p "$out"
work=target/bench/case-study-dpm; mkdir -p "$work"
ks="5,10,20,40,80,160,320"
qs="0.8,0.4,0.2,0.1,0.05,0.025,1e9"
hs="0.01 0.02 0.035 0.05 0.07 0.1"
pm_counts="20000 40000 80000 160000 320000 640000"
for scene in water-wave metal-ring; do
  w="$work/$scene"; mkdir -p "$w"
  ref="$w/reference-$ref_spp.exr"
  if [ ! -f "$ref" ]; then
    echo "== $scene: reference, light tracer, $ref_spp paths/pixel"
    "$bin" render "$scene" --integrator lighttrace --caustics-only --spp "$ref_spp" --seed 7 -q \
      -o "$ref" --png "$out/$scene-reference.png"
  fi
  common=(--caustics-only --spp "$spp" --seed 1 --reference "$ref" --quiet)
  for n in $pm_counts; do
    # Re-runs reuse finished sweeps of the same values (delete target/bench/case-study-dpm to redo).
    if done_sweep "$w/pm-n$n" "$ks"; then
      continue
    fi
    echo "== $scene: pm, $n photons, sweep k"
    "$bin" sweep "$scene" --integrator pm --photons "$n" --param k --values "$ks" "${common[@]}" \
      -o "$w/pm-n$n" > "$w/pm-n$n.txt"
  done
  for h in $hs; do
    if done_sweep "$w/dpm-h$h" "$qs"; then
      continue
    fi
    echo "== $scene: dpm, $photons photons, h = $h, sweep q"
    "$bin" sweep "$scene" --integrator dpm --photons "$photons" --bandwidth "$h" --param q \
      --values "$qs" "${common[@]}" -o "$w/dpm-h$h" > "$w/dpm-h$h.txt"
  done
done
python3 tools/summarize_case_study_dpm.py "$work" "$out" "$photons" "$ref_spp" "$spp"
# Images at the optima, for the page.
while read -r scene png args; do
  [ -n "$scene" ] || continue
  # shellcheck disable=SC2086
  "$bin" render "$scene" --caustics-only --spp "$spp" --seed 1 -q $args \
    -o "$work/$scene/${png%.png}.exr" --png "$out/$png" > /dev/null
done < "$out/optima.txt"
