#!/usr/bin/env bash
# The cost of spectral mode: alternating runs of the same render in RGB and spectral mode
# (whole process wall time, median of N), on the Cornell box (path tracer, 64 spp), the glass
# sphere (pds, 200 000 photons) and the prism (light tracer, 16 paths per pixel); and the cost
# of dispersion: the prism in spectral mode with its F2 glass against the same glass without
# dispersion (ior = n_d).
#   bash bench/spectral_cost.sh [runs, default 3]
set -euo pipefail
cd "$(dirname "$0")/.."
runs="${1:-3}"
cargo build --release -q --bin caustica
tmp=target/bench; mkdir -p "$tmp"
sed 's/^dispersion = "F2".*/ior = 1.62/' scenes/prism.toml > scenes/.prism-nodispersion.toml
trap 'rm -f scenes/.prism-nodispersion.toml' EXIT
median() { printf '%s\n' "$@" | sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }
time_of() { local s e; s=$(date +%s.%N); "$@" -q >/dev/null 2>&1; e=$(date +%s.%N); echo "$e - $s" | bc -l; }
compare() {  # name, then the render arguments; A = RGB, B = --spectral (or the 2nd form)
  local name="$1" a="$2" b="$3"; local ta=() tb=()
  for _ in $(seq "$runs"); do
    ta+=("$(time_of ./target/release/caustica render $a -o "$tmp/spectral-cost.exr")")
    tb+=("$(time_of ./target/release/caustica render $b -o "$tmp/spectral-cost.exr")")
  done
  local ma mb; ma=$(median "${ta[@]}"); mb=$(median "${tb[@]}")
  printf '%-34s A %7.2f s  B %7.2f s  B/A %.3f   (A: %s | B: %s)\n' "$name" "$ma" "$mb" "$(echo "$mb / $ma" | bc -l)" "${ta[*]}" "${tb[*]}"
}
compare "cornell-box path 64 spp" "cornell-box --integrator path --spp 64" "cornell-box --integrator path --spp 64 --spectral"
compare "glass-sphere pds 200k photons" "glass-sphere --integrator pds --spp 4 --photons 200000 --smoothing 8" "glass-sphere --integrator pds --spp 4 --photons 200000 --smoothing 8 --spectral"
compare "prism lighttrace 16 lpp" "prism --integrator lighttrace --spp 16" "prism --integrator lighttrace --spp 16 --spectral"
compare "prism spectral: no dispersion/F2" "scenes/.prism-nodispersion.toml --integrator lighttrace --spp 16 --spectral" "prism --integrator lighttrace --spp 16 --spectral"
