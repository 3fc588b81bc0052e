#!/usr/bin/env bash
# Path-traced Cornell box, 256x256, 64 spp, max depth 8: caustica vs Mitsuba 3 (scalar_rgb,
# mi.cornell_box()) on this machine, in the same session. Three runs each, alternating; prints
# the wall times and the ratio of the medians (whole caustica process vs Mitsuba's render call,
# which excludes Python start-up and scene loading, in Mitsuba's favour).
#   bash bench/cornell_vs_mitsuba.sh [runs] [sampler: independent (default) or sobol]
set -euo pipefail
cd "$(dirname "$0")/.."
runs="${1:-3}"
# Mitsuba's mi.cornell_box() uses the independent sampler; compare like with like by default.
sampler="${2:-independent}"
venv=$(bash tools/peers/venv.sh)
cargo build --release -q --bin caustica
out=target/bench; mkdir -p "$out"
cts=(); mts=()
for i in $(seq "$runs"); do
  s=$(date +%s.%N)
  ./target/release/caustica render cornell-box --integrator path --spp 64 --max-depth 8 --sampler "$sampler" -o "$out/cornell-caustica.exr" -q >/dev/null
  e=$(date +%s.%N); cts+=("$(echo "$e - $s" | bc -l)")
  m=$("$venv/bin/python" tools/peers/mitsuba_render.py cornell-box --spp 64 --out "$out/cornell-mitsuba.exr" | sed -E 's/.*render ([0-9.]+) s.*/\1/')
  mts+=("$m")
done
median() { printf '%s\n' "$@" | sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }
c=$(median "${cts[@]}"); m=$(median "${mts[@]}")
echo "caustica runs (s): ${cts[*]}"
echo "mitsuba  runs (s): ${mts[*]}"
printf 'median caustica %.3f s, mitsuba %.3f s, ratio caustica/mitsuba = %.3f (target <= 0.7)\n' "$c" "$m" "$(echo "$c / $m" | bc -l)"
