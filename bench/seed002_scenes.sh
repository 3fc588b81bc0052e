#!/usr/bin/env bash
# Issue 22, item 5 for three scenes: seed 002's equal-time comparisons on the cognac glass
# (fig. 10), the swimming pool (fig. 11) and the embedded torus (fig. 13): pm against pdm and pds.
#
#   bash bench/seed002_scenes.sh [work dir]      (NO_BUILD=1: use the binary already built)
#
# At W px wide (the scenes' 4:3), SPP camera samples per pixel, seed 1:
#  (ref) cognac-glass and embedded-torus: caustics only (L S+ D E, --caustics-only) against the
#        light tracer with REF_LT light paths per pixel (unbiased; pixels black in both, e.g.
#        the glass seen directly, are left out: --mask-black). swimming-pool: the floor and walls
#        are seen only through the water, which the light tracer cannot render, so, as the seed
#        did, the reference is pm with REF_PM photons (k = REF_K), and every render has indirect
#        light off (--global-photons 0; with --final-gather 0 too, pm is refused: it would show the empty global map): direct light
#        plus the caustics.
#  (a) bandwidths at N0 photons: pm over k, pdm and pds over s; the RMSE-optimal value is kept.
#  (b) photon ladder at that bandwidth: pm, pdm, pds at COUNTS photons; times are whole renders.
#  (c) equal time (tools/summarize_seed002_scenes.py): the budget is pds's render time at
#      BUDGET_N photons; each method's image is its largest count within 1.05 x the budget.
#      Close-ups (CROP_*) are compared on their own.
# Every command goes to WORK/commands.log. Re-runs reuse finished sweeps (delete WORK to redo).
set -euo pipefail
cd "$(dirname "$0")/.."
work="${1:-target/bench/seed002-scenes}"
out="${DOCS:-docs/results/seed002-scenes}"
W=${W:-256} SPP=${SPP:-4} N0=${N0:-50000} BUDGET_N=${BUDGET_N:-100000}
REF_LT=${REF_LT:-1024} REF_PM=${REF_PM:-10000000} REF_K=${REF_K:-100} REF_SPP=${REF_SPP:-16}
COUNTS=${COUNTS:-25000,50000,100000,200000,400000}
KS=${KS:-20,40,80,160,320,640}
SS=${SS:-1,2,4,8,16,32}
# Close-ups at W = 256: x,y,w,h (the caustic in the glass's shadow; the floor's caustic net;
# the bright band at the block's foot).
CROP_cognac_glass=${CROP_cognac_glass:-96,112,80,60}
CROP_swimming_pool=${CROP_swimming_pool:-80,72,80,60}
CROP_embedded_torus=${CROP_embedded_torus:-64,112,96,48}
target_dir="${CARGO_TARGET_DIR:-target}"
[[ -n ${NO_BUILD:-} ]] || cargo build --release -q -p caustica-cli
mkdir -p "$work/bin" "$out"
# A private copy of the binary: another build must not change it mid-study.
[[ -x $work/bin/caustica ]] || cp "$target_dir/release/caustica" "$work/bin/caustica"
bin=$PWD/$work/bin/caustica
log="$work/commands.log"
[[ -f $work/params.txt ]] || {
  echo "W=$W SPP=$SPP N0=$N0 BUDGET_N=$BUDGET_N REF_LT=$REF_LT REF_PM=$REF_PM REF_K=$REF_K REF_SPP=$REF_SPP"
  echo "COUNTS=$COUNTS KS=$KS SS=$SS"
  echo "commit=$(git rev-parse --short HEAD) started=$(date -u +%FT%TZ) cores=$(nproc)"
} > "$work/params.txt"
# shellcheck source=bench/sweep_lib.sh
. bench/sweep_lib.sh
run() { # logs and runs caustica ARGS...
  echo "caustica $*    # load $(cut -d' ' -f1 /proc/loadavg), $(date -u +%T)" >> "$log"
  "$bin" "$@"
}
best() { tail -n +2 "$1" | sort -t, -k2 -g | head -1 | cut -d, -f1; } # lowest RMSE of a sweep.csv

for scene in cognac-glass embedded-torus swimming-pool; do
  d="$work/$scene"
  mkdir -p "$d"
  if [[ $scene == swimming-pool ]]; then
    mode=(--global-photons 0)
    ref="$d/reference-pm-$REF_PM.exr"
    [[ -f $ref ]] || {
      echo "== $scene: reference, pm with $REF_PM photons, k = $REF_K"
      t0=$SECONDS
      run render "$scene" --integrator pm \
        --photons "$REF_PM" --k "$REF_K" --spp "$REF_SPP" --width "$W" --seed 7 "${mode[@]}" -q \
        -o "$ref" --png "$d/reference.png" > "$d/reference.txt" 2>&1
      echo "$((SECONDS - t0))" > "$d/reference.seconds"
    }
    mask=()
  else
    mode=(--caustics-only)
    ref="$d/reference-lt-$REF_LT.exr"
    [[ -f $ref ]] || {
      echo "== $scene: reference, light tracer, $REF_LT light paths per pixel"
      t0=$SECONDS
      run render "$scene" --integrator lighttrace \
        --spp "$REF_LT" --width "$W" --seed 7 "${mode[@]}" -q \
        -o "$ref" --png "$d/reference.png" > "$d/reference.txt" 2>&1
      echo "$((SECONDS - t0))" > "$d/reference.seconds"
    }
    mask=(--mask-black)
  fi
  common=(--width "$W" --spp "$SPP" --seed 1 "${mode[@]}" --reference "$ref" "${mask[@]}" --quiet)
  # (a) bandwidths
  if ! done_sweep "$d/pm-k" "$KS"; then
    echo "== $scene: pm, $N0 photons, k over $KS"
    run sweep "$scene" --integrator pm --photons "$N0" --param k --values "$KS" "${common[@]}" \
      -o "$d/pm-k" > /dev/null
  fi
  for m in pdm pds; do
    if ! done_sweep "$d/$m-s" "$SS"; then
      echo "== $scene: $m, $N0 photons, s over $SS"
      run sweep "$scene" --integrator "$m" --photons "$N0" --param smoothing --values "$SS" \
        "${common[@]}" -o "$d/$m-s" > /dev/null
    fi
  done
  k=$(best "$d/pm-k/sweep.csv")
  s_pdm=$(best "$d/pdm-s/sweep.csv")
  s_pds=$(best "$d/pds-s/sweep.csv")
  echo "$k $s_pdm $s_pds" > "$d/bandwidths.txt"
  # (b) photon ladders
  for m in pm pdm pds; do
    case $m in
      pm) bw=(--k "$k") ;;
      pdm) bw=(--smoothing "$s_pdm") ;;
      pds) bw=(--smoothing "$s_pds") ;;
    esac
    if ! done_sweep "$d/$m-n" "$COUNTS"; then
      echo "== $scene: $m (${bw[*]}), photons over $COUNTS"
      run sweep "$scene" --integrator "$m" "${bw[@]}" --param photons --values "$COUNTS" \
        "${common[@]}" --png -o "$d/$m-n" > /dev/null
    fi
  done
done
echo "finished=$(date -u +%FT%TZ)" >> "$work/params.txt"
cp "$log" "$work/params.txt" "$out/"
py=/root/.cache/caustica/peers-venv/bin/python
[[ -x $py ]] || py=python3
"$py" tools/summarize_seed002_scenes.py "$work" "$out" "$bin" "$BUDGET_N" \
  "cognac-glass=$CROP_cognac_glass" "embedded-torus=$CROP_embedded_torus" \
  "swimming-pool=$CROP_swimming_pool"
