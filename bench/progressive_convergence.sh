#!/usr/bin/env bash
# Issue 20: convergence of the progressive methods on a caustic: RMSE against the light tracer
# after 1, 4, 16, 64, 256 iterations (caustics only, 64x64, 1 spp and 20000 light paths per
# iteration, alpha 2/3), with the log-log slope of RMSE over iterations fitted on the last
# three points (PPPM's theory: MSE ~ N^-2/3 at alpha = 2/3, i.e. RMSE slope -1/3).
#   bash bench/progressive_convergence.sh [scene (default water-wave)] [max iterations (256)]
set -euo pipefail
cd "$(dirname "$0")/.."
scene="${1:-water-wave}"
max="${2:-256}"
cargo build --release -q -p caustica-cli
bin=./target/release/caustica
dir=target/bench/progressive/$scene
mkdir -p "$dir"
common=(render "$scene" --width 64 --height 64 --caustics-only -q)
ref="$dir/reference.exr"
[[ -f $ref ]] || "$bin" "${common[@]}" --integrator lighttrace --spp 8192 --seed 7 -o "$ref" > /dev/null
"$bin" "${common[@]}" --integrator lighttrace --spp 2048 --seed 8 -o "$dir/ref-check.exr" > /dev/null
noise=$("$bin" compare "$dir/ref-check.exr" "$ref" | awk '/^RMSE/ {print $2}')
echo "Reference: light tracer 8192 paths/pixel; an independent 2048-path render is at RMSE $noise."
echo
echo "| method | iterations | RMSE | wall (s) |"
echo "|---|---:|---:|---:|"
for kind in pppm ppds sppm ppm; do
  extra=()
  [[ $kind == ppds ]] && extra=(--smoothing 4)
  pts=""
  for n in 1 4 16 64 256 1024; do
    ((n > max)) && continue
    out="$dir/$kind-$n.exr"
    start=$(date +%s.%N)
    "$bin" "${common[@]}" --integrator "$kind" --iterations "$n" --photons-per-iteration 20000 --seed 1 \
      "${extra[@]}" -o "$out" > /dev/null 2>&1
    secs=$(awk -v a="$start" -v b="$(date +%s.%N)" 'BEGIN {printf "%.2f", b - a}')
    e=$("$bin" compare "$out" "$ref" | awk '/^RMSE/ {print $2}')
    echo "| $kind | $n | $e | $secs |"
    pts="$pts $n $e"
  done
  echo "$pts" | awk -v k="$kind" '{
    m = NF / 2; s = (m >= 3) ? m - 2 : 1; n = 0; sx = 0; sy = 0; sxx = 0; sxy = 0
    for (i = s; i <= m; i++) { x = log($(2*i-1)); y = log($(2*i)); n++; sx += x; sy += y; sxx += x*x; sxy += x*y }
    if (n >= 2) printf "| %s | log-log slope of the last %d points | %.3f | |\n", k, n, (n*sxy - sx*sy) / (n*sxx - sx*sx)
  }'
done
