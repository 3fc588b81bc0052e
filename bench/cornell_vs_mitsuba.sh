#!/usr/bin/env bash
# Path-traced Cornell box, 256x256, 64 spp, max depth 8: caustica vs Mitsuba 3 (mi.cornell_box())
# in its scalar_rgb variant and in its llvm_ad_rgb variant (Dr.Jit's LLVM backend: JIT-compiled,
# vectorised wavefront over Embree) on this machine, in the same session. The three alternate
# in one loop; prints the wall times, the medians and the ratios of the medians. caustica is
# timed as a whole process; Mitsuba as its render call alone (mitsuba_render.py: no Python
# start-up, import or scene loading, in Mitsuba's favour). All three use $THREADS threads
# (default 2).
#
# llvm_ad_rgb's render time includes tracing the kernels, loading them from Dr.Jit's kernel
# cache (~/.drjit), running them and evaluating the image. The loop uses a WARM kernel cache,
# what a user sees from their second render on: an untimed warm-up render fills ~/.drjit first.
# One render with a cold cache (a fresh, empty HOME, so ~/.drjit is not touched) is timed once
# before the loop, for information. libLLVM: tools/peers/libllvm.sh (Debian's libllvm19,
# unpacked) unless DRJIT_LIBLLVM_PATH is set.
#
# After the loop, the llvm_ad_rgb image is compared with scalar_rgb's (tools/peers/compare_exr.py)
# beside two noise references: each variant with seed 1 against itself with seed 0.
#   bash bench/cornell_vs_mitsuba.sh [runs] [sampler: independent (default) or sobol]
set -euo pipefail
cd "$(dirname "$0")/.."
runs="${1:-3}"
# Mitsuba's mi.cornell_box() uses the independent sampler; compare like with like by default.
sampler="${2:-independent}"
threads="${THREADS:-2}"
venv=$(bash tools/peers/venv.sh)
py="$venv/bin/python"
DRJIT_LIBLLVM_PATH="${DRJIT_LIBLLVM_PATH:-$(bash tools/peers/libllvm.sh)}"
export DRJIT_LIBLLVM_PATH
cargo build --release -q --bin caustica
bin="${CARGO_TARGET_DIR:-target}/release/caustica"
out=target/bench; mkdir -p "$out"
secs() { sed -E 's/.*render ([0-9.]+) s.*/\1/'; }
mitsuba() { # variant, output file, extra arguments
  local v="$1" o="$2"; shift 2
  "$py" tools/peers/mitsuba_render.py cornell-box --variant "$v" --spp 64 --threads "$threads" --out "$o" "$@"
}

echo "date: $(date -u '+%Y-%m-%d %H:%M:%S UTC'); host: $(nproc) cores; threads: $threads; runs: $runs; sampler (caustica): $sampler"
dirty=$(git status --porcelain -- crates Cargo.toml Cargo.lock | awk '{print $NF}' | tr '\n' ' ')
echo "caustica: $(git rev-parse --short HEAD)${dirty:+, built with these files differing from it in the working tree: $dirty}"
echo "rustflags: ${RUSTFLAGS-$(grep -m1 '^rustflags' .cargo/config.toml 2>/dev/null || echo none) (.cargo/config.toml)}"
"$py" -c 'import mitsuba, drjit; print(f"mitsuba {mitsuba.__version__}, drjit {drjit.__version__}")'
echo "libLLVM: $DRJIT_LIBLLVM_PATH$( [ -f "$(dirname "$DRJIT_LIBLLVM_PATH")/../../../VERSION" ] && echo " (Debian libllvm19 $(cat "$(dirname "$DRJIT_LIBLLVM_PATH")/../../../VERSION"))")"

cold_home=$(mktemp -d)
trap 'rm -rf "$cold_home"' EXIT
echo "llvm_ad_rgb, cold kernel cache (empty HOME, once, not in the medians):"
HOME="$cold_home" mitsuba llvm_ad_rgb "$out/cornell-mitsuba-llvm.exr" --jit-stats | sed 's/^/  /'
echo "llvm_ad_rgb, warm-up filling ~/.drjit if needed (not in the medians):"
mitsuba llvm_ad_rgb "$out/cornell-mitsuba-llvm.exr" --jit-stats | sed 's/^/  /'

cts=(); sts=(); lts=()
for i in $(seq "$runs"); do
  s=$(date +%s.%N)
  "$bin" render cornell-box --integrator path --spp 64 --max-depth 8 --sampler "$sampler" \
    --threads "$threads" -o "$out/cornell-caustica.exr" -q >/dev/null
  e=$(date +%s.%N); cts+=("$(echo "$e - $s" | bc -l)")
  sts+=("$(mitsuba scalar_rgb "$out/cornell-mitsuba.exr" | secs)")
  lts+=("$(mitsuba llvm_ad_rgb "$out/cornell-mitsuba-llvm.exr" | secs)")
done
median() { printf '%s\n' "$@" | sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }
c=$(median "${cts[@]}"); m=$(median "${sts[@]}"); l=$(median "${lts[@]}")
echo "caustica (whole process)       runs (s): ${cts[*]}"
echo "mitsuba scalar_rgb (render)    runs (s): ${sts[*]}"
echo "mitsuba llvm_ad_rgb (render, warm kernel cache) runs (s): ${lts[*]}"
printf 'median caustica %.3f s, mitsuba scalar_rgb %.3f s, mitsuba llvm_ad_rgb %.3f s\n' "$c" "$m" "$l"
printf 'ratio caustica/llvm_ad_rgb = %.3f (target <= 1.0)\n' "$(echo "$c / $l" | bc -l)"
printf 'ratio caustica/scalar_rgb  = %.3f (target <= 0.7)\n' "$(echo "$c / $m" | bc -l)"
printf '(llvm_ad_rgb/scalar_rgb    = %.3f)\n' "$(echo "$l / $m" | bc -l)"
# The machine's load moves all three together within a loop iteration: the ratios of each
# iteration's runs, and their medians, are steadier than the ratio of the medians.
rl=(); rs=()
for i in $(seq 0 $((runs - 1))); do
  rl+=("$(printf '%.3f' "$(echo "${cts[$i]} / ${lts[$i]}" | bc -l)")")
  rs+=("$(printf '%.3f' "$(echo "${cts[$i]} / ${sts[$i]}" | bc -l)")")
done
echo "per-iteration caustica/llvm_ad_rgb: ${rl[*]} (median $(median "${rl[@]}"))"
echo "per-iteration caustica/scalar_rgb:  ${rs[*]} (median $(median "${rs[@]}"))"

echo "image check, llvm_ad_rgb (A) vs scalar_rgb (B), both seed 0:"
"$py" tools/peers/compare_exr.py "$out/cornell-mitsuba-llvm.exr" "$out/cornell-mitsuba.exr" | sed 's/^/  /'
mitsuba scalar_rgb "$out/cornell-mitsuba-seed1.exr" --seed 1 >/dev/null
echo "noise reference, scalar_rgb seed 1 (A) vs scalar_rgb seed 0 (B):"
"$py" tools/peers/compare_exr.py "$out/cornell-mitsuba-seed1.exr" "$out/cornell-mitsuba.exr" | sed 's/^/  /'
mitsuba llvm_ad_rgb "$out/cornell-mitsuba-llvm-seed1.exr" --seed 1 >/dev/null
echo "noise reference, llvm_ad_rgb seed 1 (A) vs llvm_ad_rgb seed 0 (B):"
"$py" tools/peers/compare_exr.py "$out/cornell-mitsuba-llvm-seed1.exr" "$out/cornell-mitsuba-llvm.exr" | sed 's/^/  /'
