#!/usr/bin/env bash
# Issue 19: cost of tracing temporal photon differentials (three parameters) against ordinary
# ones (two) on the same light paths of the moving scenes (target <= 1.15x), the memory per
# photon, and BVH queries at a time against a static BVH.
#   bash bench/temporal_tracing_cost.sh [reps (default 15)]
# 1. Tracing alone, one thread (crates/render/examples/temporal_tracing_cost.rs): N = 2 and
#    N = 3 alternately in one process, `reps` times each; ratio of the minimum times.
# 2. The same in instructions (valgrind callgrind, one run each): unaffected by machine load.
# 3. BVH closest-hit queries, static vs moving (criterion, crates/scene/benches/motion_bvh.rs).
set -euo pipefail
cd "$(dirname "$0")/.."
# Valgrind cannot run AVX-512 code: build for any x86-64, as the earlier records were (a set
# RUSTFLAGS, even empty, replaces .cargo/config.toml's target-cpu=native).
export RUSTFLAGS="${RUSTFLAGS-}"
reps="${1:-15}"
cargo build --release -q -p caustica-render --example temporal_tracing_cost
ex=./target/release/examples/temporal_tracing_cost
cases=(moving-wave 200000 rotating-rod 2000000)

echo "## 1. Tracing alone (one thread, min of $reps alternating runs)"
"$ex" "$reps" "${cases[@]}"

if command -v valgrind > /dev/null; then
  echo
  echo "## 2. Instructions (callgrind; start-up, measured with 0 paths, subtracted)"
  echo "| scene | light paths | two parameters (M instr) | three (M instr) | ratio |"
  echo "|---|---:|---:|---:|---:|"
  instr() { # columns scene paths -> instructions
    TRACING_COST_ONLY="$1" valgrind --tool=callgrind --callgrind-out-file=/dev/null "$ex" 1 "$2" "$3" 2>&1 \
      | grep -o 'refs: *[0-9,]*' | tr -dc '0-9'
  }
  for ((i = 0; i < ${#cases[@]}; i += 2)); do
    scene=${cases[i]}; n=$((cases[i+1] / 10))
    z=$(instr 2 "$scene" 0); a=$(instr 2 "$scene" "$n"); b=$(instr 3 "$scene" "$n")
    awk -v s="$scene" -v n="$n" -v z="$z" -v a="$a" -v b="$b" \
      'BEGIN {printf "| %s | %d | %.1f | %.1f | %.3f |\n", s, n, (a - z) / 1e6, (b - z) / 1e6, (b - z) / (a - z)}'
  done
fi

echo
echo "## 3. BVH queries at a time (criterion)"
cargo bench -q -p caustica-scene --bench motion_bvh 2>&1 | grep -E "^motion_bvh|time:|thrpt:|agrees|triangles"
