#!/usr/bin/env bash
# Issue 16 item 3: automatic bandwidths against the sweep optima and today's fixed defaults, on
# the case studies of seed 000 ch. 6 (water-wave, metal-ring: 20 000 caustic photons, 16 spp,
# as docs/results/case-study-dpm and case-study-pds) and the gold ring (20 000 photons, 4 spp,
# pixels black in both images ignored, as docs/results/gold-ring-equal-time). Caustics only
# (L S+ D E), seed 1, against the light tracer (seed 7).
# Per scene and method: the automatic choice (from the render's note) and its RMSE; a small sweep
# at the same settings and its optimum; the fixed defaults (--no-auto-bandwidth: pm k = 50, dpm
# h = median 50-NN radius and q = 0.2, pds s = 1) and, for pds, s = 4 (the shipped scenes'
# smoothing before this change). pdm gives pds's image (1e-5 of the peak), so it is not rerun.
# Results: docs/results/auto-bandwidth/ (README.md, results.csv).
#   bash bench/auto_bandwidth.sh [reference paths/pixel, case studies (8192)] [gold ring (4096)]
set -euo pipefail
cd "$(dirname "$0")/.."
ref_cs="${1:-8192}"
ref_gold="${2:-4096}"
photons=20000
cargo build --release -q --bin caustica
bin=./target/release/caustica
out=docs/results/auto-bandwidth; mkdir -p "$out"
work=target/bench/auto-bandwidth; mkdir -p "$work"
: > "$work/runs.txt"
# run SCENE METHOD LABEL ARGS...: one render through `caustica sweep` (its CSV has the metrics);
# records "scene method label note-or-empty" and leaves DIR/sweep.csv.
run() {
  local scene=$1 method=$2 label=$3; shift 3
  local dir="$work/$scene/$method-$label"
  "$bin" sweep "$scene" --integrator "$method" --photons "$photons" "${common[@]}" "$@" \
    -o "$dir" > /dev/null 2> "$dir.log" || { cat "$dir.log"; exit 1; }
  local note
  note=$(grep -o 'automatic bandwidth: .*' "$dir.log" | head -1 || true)
  printf '%s\t%s\t%s\t%s\n' "$scene" "$method" "$label" "$note" >> "$work/runs.txt"
}
for scene in water-wave metal-ring gold-ring; do
  w="$work/$scene"; mkdir -p "$w"
  if [ "$scene" = gold-ring ]; then ref_spp=$ref_gold spp=4 mask=(--mask-black); methods="pm pds"
  else ref_spp=$ref_cs spp=16 mask=(); methods="pm pds dpm"; fi
  ref="$w/reference-$ref_spp.exr"
  if [ ! -f "$ref" ]; then
    echo "== $scene: reference, light tracer, $ref_spp paths/pixel"
    "$bin" render "$scene" --integrator lighttrace --caustics-only --spp "$ref_spp" --seed 7 -q \
      -o "$ref.tmp.exr"
    mv "$ref.tmp.exr" "$ref"
  fi
  common=(--caustics-only --spp "$spp" --reference "$ref" "${mask[@]}")
  for m in $methods; do
    echo "== $scene: $m"
    run "$scene" "$m" auto --param seed --values 1
    run "$scene" "$m" default --no-auto-bandwidth --param seed --values 1
    case $m in
      pm) run "$scene" pm sweep --seed 1 --param k --values 5,7,10,14,20,28,40,80,160 ;;
      pds)
        run "$scene" pds s4 --smoothing 4 --param seed --values 1
        run "$scene" pds sweep --seed 1 --param smoothing --values 1,2,3,4,5.66,8,11.3,16 ;;
      dpm)
        for h in 0.05 0.07 0.1; do
          run "$scene" dpm "sweep-h$h" --seed 1 --bandwidth "$h" --param q --values 0.025,0.05,0.2
        done ;;
    esac
  done
done
python3 tools/summarize_auto_bandwidth.py "$work" "$out" "$photons" "$ref_cs" "$ref_gold"
