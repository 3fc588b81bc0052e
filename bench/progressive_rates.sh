#!/usr/bin/env bash
# Issue 20, performance: iteration rates of the progressive methods against the one-shot methods
# doing the same work, and the fixed cost of an iteration (camera pass, hit-point update).
#   bash bench/progressive_rates.sh [runs per cell, default 3]
#
# 1. Rates. The water wave at 128x128, caustics only: each progressive method runs 100
#    iterations of 100 000 light paths (1 camera sample per pixel and iteration; ppm 1 fixed
#    hit point per pixel), the one-shot pm and pds the same 10^7 light paths with 100 spp in one
#    pass (their bandwidths fixed: pm k = 100, pds s = 4, no automatic choice). The Cornell box
#    at 64x64 with global illumination likewise with 20 iterations of 20 000 light paths
#    (4 final-gather rays for pm and pppm; sppm and ppm gather no rays).
# 2. Fixed cost per iteration: the same renders with 1 light path per iteration, 201 against 1
#    iterations: (T_201 - T_1) / 200 is what an iteration costs besides its photons (sppm: its
#    camera pass and the per-pixel update; ppm: the splat setup over its fixed hit points and
#    the update; pppm/ppds: a camera pass and an empty map).
# Wall times are the minimum over the runs (the machine is shared); the ratios are what counts.
set -euo pipefail
cd "$(dirname "$0")/.."
runs="${1:-3}"
cargo build --release -q -p caustica-cli
bin=$PWD/target/release/caustica
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT

# Minimum wall time (s) of `runs` runs of the given render arguments.
wall() {
  local best=""
  for _ in $(seq "$runs"); do
    /usr/bin/time -f "%e" -o "$out/t" "$bin" "$@" -o "$out/x.exr" -q > /dev/null 2>&1
    local t
    t=$(cat "$out/t")
    best=$(awk -v a="$best" -v b="$t" 'BEGIN {print (a == "" || b < a) ? b : a}')
  done
  echo "$best"
}

rates() { # scene size caustics(0/1) iterations paths extra-options...
  local s=$1 w=$2 c=$3 n=$4 m=$5
  shift 5
  local base=(render "$s" --width "$w" --height "$w" --seed 1)
  ((c)) && base+=(--caustics-only)
  local total=$((n * m))
  echo "### $s, ${w}x${w}$( ((c)) && echo ", caustics only"), $n iterations of $m light paths"
  echo
  echo "| method | wall (s) | iterations/s | light paths/s | time / one-shot pm |"
  echo "|---|---:|---:|---:|---:|"
  local tpm
  tpm=$(wall "${base[@]}" --integrator pm --light-paths "$total" --spp "$n" --k 100 --no-auto-bandwidth "$@")
  echo "| pm (one shot, $n spp) | $tpm | | $(awk -v p="$total" -v t="$tpm" 'BEGIN {printf "%.2f M", p / t / 1e6}') | 1.00 |"
  if ((c)); then
    local tpds
    tpds=$(wall "${base[@]}" --integrator pds --light-paths "$total" --spp "$n" --smoothing 4 --no-auto-bandwidth)
    echo "| pds (one shot, $n spp) | $tpds | | $(awk -v p="$total" -v t="$tpds" 'BEGIN {printf "%.2f M", p / t / 1e6}') | $(awk -v a="$tpds" -v b="$tpm" 'BEGIN {printf "%.2f", a / b}') |"
  fi
  local methods=(pppm ppds sppm ppm)
  ((c)) || methods=(pppm sppm ppm)
  for k in "${methods[@]}"; do
    local t
    t=$(wall "${base[@]}" --integrator "$k" --iterations "$n" --photons-per-iteration "$m" "$@")
    echo "| $k | $t | $(awk -v n="$n" -v t="$t" 'BEGIN {printf "%.1f", n / t}') | $(awk -v p="$total" -v t="$t" 'BEGIN {printf "%.2f M", p / t / 1e6}') | $(awk -v a="$t" -v b="$tpm" 'BEGIN {printf "%.2f", a / b}') |"
  done
  echo
}

overhead() { # scene size caustics(0/1)
  local s=$1 w=$2 c=$3
  local base=(render "$s" --width "$w" --height "$w" --seed 1 --photons-per-iteration 1)
  ((c)) && base+=(--caustics-only)
  echo "### $s, ${w}x${w}$( ((c)) && echo ", caustics only"): fixed cost of an iteration"
  echo
  echo "| method | 1 iteration (s) | 201 iterations (s) | per iteration (ms) |"
  echo "|---|---:|---:|---:|"
  for k in pppm ppds sppm ppm "ppm --spp 16"; do
    read -ra a <<< "$k"
    local r=()
    [[ ${a[0]} == pppm ]] && r=(--radius 0.01) # no pilot to choose a radius from one path
    [[ ${a[0]} == ppds ]] && r=(--smoothing 4)
    local t1 t2
    t1=$(wall "${base[@]}" --integrator "${a[@]}" "${r[@]}" --iterations 1)
    t2=$(wall "${base[@]}" --integrator "${a[@]}" "${r[@]}" --iterations 201)
    echo "| $k | $t1 | $t2 | $(awk -v a="$t1" -v b="$t2" 'BEGIN {printf "%.2f", (b - a) / 200 * 1000}') |"
  done
  echo
}

echo "caustica $(git rev-parse --short HEAD), $(date -u +%Y-%m-%d), minimum of $runs runs"
echo
rates water-wave 128 1 100 100000
rates cornell-box 64 0 20 20000 --final-gather 4
overhead water-wave 128 1
overhead cornell-box 64 0
