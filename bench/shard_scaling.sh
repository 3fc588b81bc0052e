#!/usr/bin/env bash
# Issue 24, performance and the scaling model of docs/distributed.md: for eight renders, the
# unsharded render, then N = 1, 2, 4, 8, 16 (and 64 for two methods) shards rendered one after
# another on this machine (each as a 2-core machine would run it), each shard's wall time and
# render time, the merge's time and bytes, and a byte comparison with the unsharded image; then
# 2 local workers (two 1-thread shard processes at once, plus the merge) against one 1-thread
# process and one 2-thread process. Results: docs/results/distributed/ (results.csv,
# workers.csv, README.md written by tools/summarize_shard_scaling.py).
#   bash bench/shard_scaling.sh [quick]     # METHODS="pm pds" reruns some methods into the same tables
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release -q -p caustica-cli
bin=$(pwd)/target/release/caustica
out=docs/results/distributed; mkdir -p "$out"
work=target/bench/shard-scaling; rm -rf "$work"; mkdir -p "$work"
csv="$out/results.csv"
# shellcheck source=bench/timing_lib.sh
source bench/timing_lib.sh
# The render's own seconds, from its one-line summary ("... in 1.23 s ...").
render_secs() { sed -n 's/.* in \([0-9.]*\) s[:, ].*/\1/p' "$1" | tail -1; }

declare -A ARGS
ARGS[path]="cornell-box --integrator path --spp 64 --width 256 --height 256"
ARGS[lighttrace]="caustic-box --integrator lighttrace --spp 32 --width 256 --height 256"
# The photon methods with their bandwidths given (k, s): a shard would otherwise repeat the
# automatic choice (2.8 s of pm's 16 s here); pm-auto keeps it, to measure that cost.
ARGS[pm]="glass-sphere --integrator pm --spp 16 --photons 200000 --global-photons 100000 --k 300 --global-k 50 --width 256 --height 256"
ARGS[pm-auto]="glass-sphere --integrator pm --spp 16 --photons 200000 --global-photons 100000 --width 256 --height 256"
ARGS[pds]="glass-sphere --integrator pds --spp 4 --photons 4000000 --smoothing 4 --width 256 --height 256"
# pds with the light-path budget the photon count needed: no counting pass for every shard to repeat.
ARGS[pds-paths]="glass-sphere --integrator pds --spp 4 --light-paths 7075083 --smoothing 4 --width 256 --height 256"
ARGS[pppm]="caustic-box --integrator pppm --iterations 64 --photons-per-iteration 20000 --width 128 --height 128"
ARGS[ppds]="caustic-box --integrator ppds --iterations 64 --photons-per-iteration 20000 --width 128 --height 128"
methods="${METHODS:-path lighttrace pm pm-auto pds pds-paths pppm ppds}"
mode="${1:-}"
counts="1 2 4 8 16"
if [[ "$mode" == quick ]]; then counts="1 2 4"; fi

# METHODS=… appends to the table of an earlier run (its rows for those methods replaced).
if [[ -n "${METHODS:-}" && -f "$csv" ]]; then
  grep -v -E "^($(echo "$methods" | tr ' ' '|')),[0-9]" "$csv" > "$csv.keep" || true
  mv "$csv.keep" "$csv"
else
  echo "method,shards,shard,wall_seconds,render_seconds,part_bytes,merge_seconds,identical" > "$csv"
fi
for m in $methods; do
  # shellcheck disable=SC2086
  set -- ${ARGS[$m]}
  t=$(now)
  "$bin" render "$@" --threads 2 -q -o "$work/$m-whole.exr" > "$work/$m-whole.log" 2>&1
  wall=$(elapsed "$t")
  echo "$m,0,,$wall,$(render_secs "$work/$m-whole.log"),,," >> "$csv"
  extra=""
  if [[ "$m" == path || "$m" == pppm ]] && [[ "$mode" != quick ]]; then extra=64; fi
  for n in $counts $extra; do
    parts="$work/$m-$n"; mkdir -p "$parts"
    for i in $(seq 0 $((n - 1))); do
      t=$(now)
      "$bin" render "$@" --threads 2 -q --shard "$i/$n" -o "$parts/" > "$parts/$i.log" 2>&1
      wall=$(elapsed "$t")
      bytes=$(stat -c %s "$parts/$(printf 'shard-%04d-of-%04d.cpart' "$i" "$n")")
      echo "$m,$n,$i,$wall,$(render_secs "$parts/$i.log"),$bytes,," >> "$csv"
    done
    t=$(now)
    "$bin" merge "$parts" -q -o "$parts/merged.exr" > "$parts/merge.log" 2>&1
    msecs=$(elapsed "$t")
    same=no; cmp -s "$parts/merged.exr" "$work/$m-whole.exr" && same=yes
    echo "$m,$n,merge,,,$(du -cb "$parts"/*.cpart | tail -1 | cut -f1),$msecs,$same" >> "$csv"
    rm -f "$parts"/*.cpart
  done
done

# Two local workers against one process.
wcsv="$out/workers.csv"
if [[ -n "${METHODS:-}" && -f "$wcsv" ]]; then
  grep -v -E "^($(echo "$methods" | tr ' ' '|')),[a-z0-9]" "$wcsv" > "$wcsv.keep" || true
  mv "$wcsv.keep" "$wcsv"
else
  echo "method,setup,seconds,identical" > "$wcsv"
fi
for m in path pds pppm; do
  [[ " $methods " == *" $m "* ]] || continue
  # shellcheck disable=SC2086
  set -- ${ARGS[$m]}
  for _ in 1 2; do
    t=$(now); "$bin" render "$@" --threads 1 -q -o "$work/w-$m-1.exr" > /dev/null 2>&1
    echo "$m,one process 1 thread,$(elapsed "$t")," >> "$wcsv"
    t=$(now); "$bin" render "$@" --threads 2 -q -o "$work/w-$m-2.exr" > /dev/null 2>&1
    echo "$m,one process 2 threads,$(elapsed "$t")," >> "$wcsv"
    rm -rf "$work/w-$m-parts"; mkdir -p "$work/w-$m-parts"
    t=$(now)
    "$bin" render "$@" --threads 1 -q --shard 0/2 -o "$work/w-$m-parts/" > /dev/null 2>&1 &
    "$bin" render "$@" --threads 1 -q --shard 1/2 -o "$work/w-$m-parts/" > /dev/null 2>&1
    wait
    "$bin" merge "$work/w-$m-parts" -q -o "$work/w-$m-merged.exr" > /dev/null 2>&1
    same=no; cmp -s "$work/w-$m-merged.exr" "$work/w-$m-1.exr" && same=yes
    echo "$m,2 shard processes x 1 thread + merge,$(elapsed "$t"),$same" >> "$wcsv"
  done
done
python3 tools/summarize_shard_scaling.py "$out"
