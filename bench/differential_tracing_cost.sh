#!/usr/bin/env bash
# Issue 5: cost of tracing caustic photons with photon differentials against plain photons
# (target <= 1.3x). Same light paths for both (pdm's landings are pm's caustic photons); the
# photon-pass time is the one the render notes report ("... in X s"), alternating pm and pdm
# runs so that machine load affects both alike.
#   bash bench/differential_tracing_cost.sh [runs per integrator (default 3)]
set -euo pipefail
cd "$(dirname "$0")/.."
runs="${1:-3}"
cargo build --release -q --bin caustica
bin=./target/release/caustica
pass() { # scene photons integrator -> photon-pass seconds
  "$bin" render "$1" --integrator "$3" --caustics-only --photons "$2" --global-photons 0 --spp 1 \
    -o /tmp/caustica-tracing-cost.pfm 2>&1 >/dev/null | grep -o 'paths, in [0-9.]* s' | head -1 | grep -o '[0-9.]*'
}
echo "| scene | caustic photons | pm photon pass (s) | pdm photon pass (s) | pdm / pm (median) |"
echo "|---|---:|---|---|---:|"
for spec in "glass-sphere 200000" "water-wave 2000000" "metal-ring 1000000"; do
  read -r scene n <<< "$spec"
  pm=(); pdm=()
  for _ in $(seq "$runs"); do
    pm+=("$(pass "$scene" "$n" pm)"); pdm+=("$(pass "$scene" "$n" pdm)")
  done
  med() { printf '%s\n' "$@" | sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }
  mp=$(med "${pm[@]}"); md=$(med "${pdm[@]}")
  echo "| $scene | $n | ${pm[*]} | ${pdm[*]} | $(awk -v a="$md" -v b="$mp" 'BEGIN {printf "%.2f", a / b}') |"
done
