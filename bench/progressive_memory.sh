#!/usr/bin/env bash
# Issue 20: peak memory of the progressive methods is flat in the number of iterations (only
# one iteration's photons or footprints alive, plus the pooled film), and their iteration rate.
#   bash bench/progressive_memory.sh [max iterations (default 10000)]
#   KINDS="pcf" bash bench/progressive_memory.sh   # some methods only (default: all)
# Each method on the water wave at 32x32, 1 spp and 2000 light paths per iteration, at
# 10, 100, 1000 and 10000 iterations: peak RSS (GNU time's "Maximum resident set size") and
# wall time. The one-shot pm/pds at the same per-iteration work is the baseline of the rate.
set -euo pipefail
cd "$(dirname "$0")/.."
max="${1:-10000}"
cargo build --release -q -p caustica-cli
bin=./target/release/caustica
out=$(mktemp -d)
common=(render water-wave --width 32 --height 32 --caustics-only --seed 1 -q)
echo "| method | iterations | peak RSS (MB) | wall (s) | iterations/s |"
echo "|---|---:|---:|---:|---:|"
for kind in ${KINDS:-pppm ppds sppm ppm pcf}; do
  for n in 10 100 1000 10000; do
    ((n > max)) && continue
    args=("${common[@]}")
    # pcf's cones do not separate caustic paths: it renders everything.
    [[ $kind == pcf ]] && args=(render water-wave --width 32 --height 32 --seed 1 -q)
    /usr/bin/time -f "%M %e" -o "$out/t" "$bin" "${args[@]}" --integrator "$kind" \
      --iterations "$n" --photons-per-iteration 2000 --spp 1 -o "$out/$kind.exr" > /dev/null 2>&1
    read -r kb secs < "$out/t"
    awk -v k="$kind" -v n="$n" -v kb="$kb" -v s="$secs" \
      'BEGIN {printf "| %s | %d | %.1f | %.2f | %.0f |\n", k, n, kb / 1024, s, n / (s > 0 ? s : 1e-9)}'
  done
done
echo
echo "One-shot baseline (one iteration's work as a single render, 1 spp, 2000 light paths):"
for kind in pm pds; do
  /usr/bin/time -f "%M %e" -o "$out/t" "$bin" "${common[@]}" --integrator "$kind" \
    --light-paths 2000 --spp 1 --no-auto-bandwidth -o "$out/$kind.exr" > /dev/null 2>&1
  read -r kb secs < "$out/t"
  echo "$kind: peak RSS $(awk -v kb="$kb" 'BEGIN {printf "%.1f", kb / 1024}') MB, wall $secs s"
done
rm -rf "$out"
