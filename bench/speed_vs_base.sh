#!/usr/bin/env bash
# Render times of two builds side by side: the Cornell box (path tracer), the light tracer and
# pm/pds renders of docs/performance.md, each run alternately REPS times with both binaries
# (the machine is shared and noisy, so only ratios within one session mean anything).
#
#   BASE_BIN=a NEW_BIN=b bench/speed_vs_base.sh [REPS]      # default 5
#
# Prints a Markdown table (median and range of each binary's wall time, ratio of medians,
# whether the outputs are byte-identical) and writes it to docs/results/speed-vs-base/.
set -euo pipefail
cd "$(dirname "$0")/.."
reps=${1:-5}
: "${BASE_BIN:?set BASE_BIN}" "${NEW_BIN:?set NEW_BIN}"
out=${OUT:-docs/results/speed-vs-base}
work=${WORK:-target/speed-vs-base}
mkdir -p "$out" "$work"

renders=(
    "cornell-box --integrator path --spp 64 --max-depth 8 --sampler independent"
    "glass-sphere --integrator lighttrace --spp 256"
    "glass-sphere --integrator pm --photons 1000000 --global-photons 100000 --spp 1"
    "water-wave --integrator pm --photons 200000 --spp 4"
    "water-wave --integrator pds --photons 200000 --spp 4"
)

# Wall time of one run in seconds.
wall() {
    local t0 t1
    t0=$(date +%s.%N)
    "$@" >/dev/null 2>&1
    t1=$(date +%s.%N)
    echo "$t1 - $t0" | bc -l
}
# median, min and max of the numbers on stdin.
stats() { sort -g | awk '{a[NR]=$1} END {m = (NR % 2) ? a[(NR+1)/2] : (a[NR/2]+a[NR/2+1])/2; printf "%.3f %.3f %.3f\n", m, a[1], a[NR]}'; }

table=$out/table.md
{
    echo "| render | base median (range) | new median (range) | new / base | output |"
    echo "|---|---:|---:|---:|---|"
} >"$table"
for r in "${renders[@]}"; do
    tb=() tn=()
    for i in $(seq "$reps"); do
        # shellcheck disable=SC2086
        tb+=("$(wall "$BASE_BIN" render $r -q -o "$work/base.exr")")
        # shellcheck disable=SC2086
        tn+=("$(wall "$NEW_BIN" render $r -q -o "$work/new.exr")")
    done
    read -r mb lb hb < <(printf '%s\n' "${tb[@]}" | stats)
    read -r mn ln hn < <(printf '%s\n' "${tn[@]}" | stats)
    ratio=$(echo "$mn / $mb" | bc -l)
    same=$(cmp -s "$work/base.exr" "$work/new.exr" && echo byte-identical || echo "**differs**")
    printf '| `render %s` | %.2f s (%.2f–%.2f) | %.2f s (%.2f–%.2f) | %.3f | %s |\n' \
        "$r" "$mb" "$lb" "$hb" "$mn" "$ln" "$hn" "$ratio" "$same" | tee -a "$table"
done
echo "($reps alternating runs each, $(nproc) threads, $(date -u +%F))" >>"$table"
echo "table: $table"
