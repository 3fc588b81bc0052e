#!/usr/bin/env bash
# Issue 5: cost of tracing caustic photons with photon differentials against plain photons
# (target <= 1.3x). Same light paths for both (pdm's landings are pm's caustic photons).
#   bash bench/differential_tracing_cost.sh [reps (default 15)] [whole-pass runs (default 3)]
# 1. Tracing alone, one thread (crates/render/examples/tracing_cost.rs): the two tracers run
#    alternately in one process, `reps` times each; ratio of the minimum times.
# 2. The same in instructions (valgrind callgrind, one run each): unaffected by machine load.
# 3. The whole photon pass as the render notes report it ("... in X s": tracing on 2 threads
#    plus each map's build), alternating pm and pdm runs.
set -euo pipefail
cd "$(dirname "$0")/.."
# Valgrind cannot run AVX-512 code: build for any x86-64, as the earlier records were (a set
# RUSTFLAGS, even empty, replaces .cargo/config.toml's target-cpu=native).
export RUSTFLAGS="${RUSTFLAGS-}"
reps="${1:-15}"
runs="${2:-3}"
cargo build --release -q --bin caustica
cargo build --release -q -p caustica-render --example tracing_cost
ex=./target/release/examples/tracing_cost
cases=(glass-sphere 10000 water-wave 100000 metal-ring 50000)

echo "## 1. Tracing alone (one thread, min of $reps alternating runs)"
"$ex" "$reps" "${cases[@]}"

echo
echo "## 2. Instructions (callgrind)"
echo "| scene | caustic photons | plain (M instr) | with differentials (M instr) | ratio |"
echo "|---|---:|---:|---:|---:|"
instr() { # mode scene photons -> instructions
  TRACING_COST_ONLY="$1" valgrind --tool=callgrind --callgrind-out-file=/dev/null "$ex" 1 "$2" "$3" 2>&1 \
    | grep -o 'refs: *[0-9,]*' | tr -dc '0-9'
}
for ((i = 0; i < ${#cases[@]}; i += 2)); do
  scene=${cases[i]}; n=${cases[i+1]}
  p=$(instr plain "$scene" "$n"); d=$(instr differential "$scene" "$n")
  awk -v s="$scene" -v n="$n" -v p="$p" -v d="$d" \
    'BEGIN {printf "| %s | %d | %.0f | %.0f | %.2f |\n", s, n, p / 1e6, d / 1e6, d / p}'
done

echo
echo "## 3. Whole photon pass (2 threads, incl. map build)"
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
