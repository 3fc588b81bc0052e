#!/usr/bin/env bash
# Issue 19: the experiments of seed 003 fig. 7-10 (seed 000 ch. 7), which report no numbers, so we
# measure them. Built-in scenes moving-wave (S-T1) and rotating-rod (S-T2), caustics only, 128 px
# wide, seed 1, the shutter opening at frame 0:
#  * references: the motion-blurred light tracer (`--integrator lighttrace --shutter E`), one per
#    exposure, and a second seed at E = 1 for the reference's own noise;
#  * XT1, exposure sweep: TPD (`pds --temporal`, 1 000 photons) at E = 0, 0.25, 0.5, 1, 2, each
#    swept over the smoothing s against its exposure's reference;
#  * XT2, at E = 1: TPD with 1 000 photons (forward and centred alignment; without --temporal as
#    a control) against TDPM (`pm --in-between-frames N`, N = 0, 2, 10) at 1k to 480k photons,
#    each swept over k; the photon count TDPM needs to match TPD;
#  * XT3, the rotating rod: TPD with 5 000 photons against TDPM with 5 000 photons at k = 100
#    and 250 (pixels that see the rod are masked: the light tracer leaves them black);
#  * XT4, the projected D_t x vectors (fig. 10): `cargo run --example dt_vectors`.
# Results: docs/results/temporal/ (README.md, summary.csv, SVG plots, index.html, PNGs).
#   bash bench/temporal.sh [reference light paths per pixel (default 16384)]
# Re-runs reuse finished work (target/bench/temporal; delete it to start over).
set -euo pipefail
cd "$(dirname "$0")/.."
ref_spp="${1:-16384}"
spp=4
work=target/bench/temporal
out=docs/results/temporal
mkdir -p "$work" "$out"
cargo build --profile fast -p caustica-cli -q
cargo build --profile fast -p caustica-render --example dt_vectors -q
# A copy, so rebuilding during the study does not change the binary under it.
bin="$work/caustica"
cp target/fast/caustica "$bin"
# shellcheck source=bench/sweep_lib.sh
. bench/sweep_lib.sh
ss="1,1.5,2,3,4,6,8,12"
ks="5,10,20,40,80,160,320,640,1280,2560"
# Past 80k photons the optimal k of TDPM without in-between frames grows beyond 2560.
ks_many="$ks,5120,10240"
size=(--width 128)
common_of() { echo --caustics-only --spp "$spp" --seed 1 "${size[@]}" --quiet; }

reference() { # scene exposure seed -> path
  local f="$work/$1/reference-e$2-s$3-$ref_spp.exr"
  if [ ! -f "$f" ]; then
    echo "== $1: reference, shutter $2, seed $3, $ref_spp light paths per pixel" >&2
    nice -n 5 "$bin" render "$1" --integrator lighttrace --caustics-only --spp "$ref_spp" \
      --shutter "$2" --seed "$3" "${size[@]}" -q -o "$f" > "$f.txt"
  fi
  echo "$f"
}

sweep() { # scene dir param values reference extra...
  local scene=$1 dir=$2 param=$3 values=$4 ref=$5
  shift 5
  if ! done_sweep "$work/$scene/$dir" "$values"; then
    echo "== $scene: $dir" >&2
    # shellcheck disable=SC2046
    nice -n 5 "$bin" sweep "$scene" --param "$param" --values "$values" --reference "$ref" \
      $(common_of) "$@" -o "$work/$scene/$dir" > "$work/$scene/$dir.txt"
  fi
}

mkdir -p "$work/moving-wave" "$work/rotating-rod"
# XT1: exposure sweep.
for e in 0 0.25 0.5 1 2; do
  ref=$(reference moving-wave "$e" 1)
  sweep moving-wave "tpd-e$e" smoothing "$ss" "$ref" --integrator pds --temporal \
    --photons 1000 --shutter "$e"
done
ref=$(reference moving-wave 1 1)
ref2=$(reference moving-wave 1 2)
"$bin" compare "$ref2" "$ref" > "$work/moving-wave/reference-noise.txt"
# XT2 at E = 1.
sweep moving-wave tpd-centred smoothing "$ss" "$ref" --integrator pds --temporal \
  --shutter-align centred --photons 1000 --shutter 1
sweep moving-wave pd-random-times smoothing "$ss" "$ref" --integrator pds --photons 1000 --shutter 1
for n in 0 2 10; do
  for photons in 1000 5000 10000 20000 40000 80000 160000 480000; do
    k_values=$ks
    [ "$photons" -ge 80000 ] && k_values=$ks_many
    sweep moving-wave "tdpm-b$n-n$photons" k "$k_values" "$ref" --integrator pm --global-photons 0 \
      --in-between-frames "$n" --photons "$photons" --shutter 1
  done
done
# XT3: the rotating rod.
rref=$(reference rotating-rod 1 1)
rref2=$(reference rotating-rod 1 2)
"$bin" compare "$rref2" "$rref" --mask-black > "$work/rotating-rod/reference-noise.txt"
sweep rotating-rod tpd smoothing "$ss" "$rref" --integrator pds --temporal --photons 5000 \
  --shutter 1 --mask-black
for n in 0 2 10; do
  sweep rotating-rod "tdpm-b$n" k "100,250" "$rref" --integrator pm --global-photons 0 \
    --in-between-frames "$n" --photons 5000 --shutter 1 --mask-black
done
# XT4: D_t x vectors.
for scene in moving-wave rotating-rod; do
  target/fast/examples/dt_vectors "$scene" 400 > "$out/$scene-dt-vectors.svg"
done
python3 tools/summarize_temporal.py "$work" "$out" "$ref_spp" "$bin"
