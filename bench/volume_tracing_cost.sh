#!/usr/bin/env bash
# Issue 18: cost of tracing volume photon differentials (vpd, seed 000 sec. 8.4) against plain
# volume photons (target <= 1.3x). Same light paths for both (a test checks the events and fluxes).
#   bash bench/volume_tracing_cost.sh [reps (default 7)]
# 1. Time, one thread (crates/render/examples/tracing_cost.rs, TRACING_COST_MAP=volume): the two
#    tracers alternate in one process `reps` times; ratios of the minimum times, tracing alone
#    and with vpd's kernels built.
# 2. Instructions (valgrind callgrind, one run each, collecting only inside the tracing functions
#    and, for the last column, the kernel build): unaffected by machine load.
set -euo pipefail
cd "$(dirname "$0")/.."
# Valgrind cannot run AVX-512 code: build for any x86-64, as the earlier records were (a set
# RUSTFLAGS, even empty, replaces .cargo/config.toml's target-cpu=native).
export RUSTFLAGS="${RUSTFLAGS-}"
reps="${1:-7}"
cargo build --profile fast -q -p caustica-render --example tracing_cost
ex=./target/fast/examples/tracing_cost
cases=(volume-caustic 100000 smoke-plume 100000 fog-box 100000)

echo "## 1. Time (one thread, min of $reps alternating runs)"
TRACING_COST_MAP=volume "$ex" "$reps" "${cases[@]}"

echo
echo "## 2. Instructions (callgrind)"
echo "| scene | plain (M instr) | with differentials (M instr) | ratio | kernels built too (M instr) | ratio |"
echo "|---|---:|---:|---:|---:|---:|"
instr() { # mode scene photons toggle... -> instructions
  local mode=$1 scene=$2 n=$3; shift 3
  local t=(); for f in "$@"; do t+=(--toggle-collect="$f"); done
  TRACING_COST_MAP=volume TRACING_COST_ONLY="$mode" valgrind --tool=callgrind "${t[@]}" \
    --callgrind-out-file=/dev/null "$ex" 1 "$scene" "$n" 2>&1 | grep -o 'refs: *[0-9,]*' | tr -dc '0-9'
}
for ((i = 0; i < ${#cases[@]}; i += 2)); do
  s=${cases[i]} n=${cases[i + 1]}
  p=$(instr plain "$s" "$n" '*tracer::trace_photons*')
  d=$(instr differential "$s" "$n" '*trace_volume_landings*')
  k=$(instr differential "$s" "$n" '*trace_volume_landings*' '*kernels_from_landings*')
  awk -v s="$s" -v p="$p" -v d="$d" -v k="$k" \
    'BEGIN{printf "| %s | %.1f | %.1f | %.2f | %.1f | %.2f |\n", s, p/1e6, d/1e6, d/p, k/1e6, k/p}'
done

# 3. The whole photon pass as the render notes report it (2 threads, tracing + kernels + the
#    map's build), vpd with open and renormalised kernels (--volume-boundary renormalise adds
#    64 short rays per photon), alternating, min of RUNS runs; the sec. 8.5 scenes at the seed's
#    photon counts and the smoothing of their study optima.
runs="${RUNS:-3}"
cargo build --release -q --bin caustica
bin=./target/release/caustica
echo
echo "## 3. Photon pass of vpd (s), open vs renormalised kernels (min of $runs)"
echo "| scene | volume photons | s | open | renormalised | ratio | kernels cut |"
echo "|---|---:|---:|---:|---:|---:|---|"
pass() { # scene n s [extra] -> seconds of the photon line, and the boundary note
  "$bin" render "$1" --integrator vpd --volume-only --volume-photons "$2" --volume-smoothing "$3" \
    --spp 1 --width 32 --no-auto-bandwidth "${@:4}" -o /tmp/volume_tracing_cost.exr 2>&1
}
for c in facet-smoke:80000:8 laser-smoke:80000:128 glass-smoke:10000:16; do
  IFS=: read -r s n sm <<<"$c"
  o=999; r=999; cut=""
  for ((j = 0; j < runs; j++)); do
    t=$(pass "$s" "$n" "$sm" | sed -nE 's/^photons: .* in ([0-9.]+) s \(.*/\1/p')
    o=$(awk -v a="$o" -v b="$t" 'BEGIN{print (b < a) ? b : a}')
    out=$(pass "$s" "$n" "$sm" --volume-boundary renormalise)
    t=$(echo "$out" | sed -nE 's/^photons: .* in ([0-9.]+) s \(.*/\1/p')
    r=$(awk -v a="$r" -v b="$t" 'BEGIN{print (b < a) ? b : a}')
    cut=$(echo "$out" | sed -nE 's/.*renormalised at surfaces: ([0-9]+ of [0-9]+) cut, keeping ([0-9.]+ %).*/\1, keeping \2/p')
  done
  awk -v s="$s" -v n="$n" -v sm="$sm" -v o="$o" -v r="$r" -v c="$cut" \
    'BEGIN{printf "| %s | %d | %s | %.2f | %.2f | %.2f | %s |\n", s, n, sm, o, r, r/o, c}'
done
