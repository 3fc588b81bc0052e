#!/usr/bin/env bash
# Issue 24, performance and the scaling model of docs/distributed.md: for six methods, the
# unsharded render, then N = 1, 2, 4, 8, 16 (and 64 for two methods) shards rendered one after
# another on this machine (each as a 2-core machine would run it), each shard's wall time and
# render time, the merge's time and bytes, and a byte comparison with the unsharded image; then
# 2 local workers (two 1-thread shard processes at once, plus the merge) against one 1-thread
# process and one 2-thread process. Results: docs/results/distributed/ (results.csv,
# workers.csv, README.md written by tools/summarize_shard_scaling.py).
#   bash bench/shard_scaling.sh [quick]
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release -q -p caustica-cli
bin=$(pwd)/target/release/caustica
out=docs/results/distributed; mkdir -p "$out"
work=target/bench/shard-scaling; rm -rf "$work"; mkdir -p "$work"
csv="$out/results.csv"
now() { date +%s.%N; }
elapsed() { awk -v a="$1" -v b="$(now)" 'BEGIN { printf "%.3f", b - a }'; }
# The render's own seconds, from its one-line summary ("... in 1.23 s ...").
render_secs() { sed -n 's/.* in \([0-9.]*\) s[:, ].*/\1/p' "$1" | tail -1; }

declare -A ARGS
ARGS[path]="cornell-box --integrator path --spp 64 --width 256 --height 256"
ARGS[lighttrace]="caustic-box --integrator lighttrace --spp 32 --width 256 --height 256"
ARGS[pm]="glass-sphere --integrator pm --spp 16 --photons 200000 --global-photons 100000 --width 256 --height 256"
ARGS[pds]="glass-sphere --integrator pds --spp 4 --photons 200000 --width 256 --height 256"
ARGS[pppm]="caustic-box --integrator pppm --iterations 64 --photons-per-iteration 20000 --width 128 --height 128"
ARGS[ppds]="caustic-box --integrator ppds --iterations 64 --photons-per-iteration 20000 --width 128 --height 128"
methods="path lighttrace pm pds pppm ppds"
mode="${1:-}"
counts="1 2 4 8 16"
if [[ "$mode" == quick ]]; then counts="1 2 4"; fi

echo "method,shards,shard,wall_seconds,render_seconds,part_bytes,merge_seconds,identical" > "$csv"
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
echo "method,setup,seconds,identical" > "$wcsv"
for m in path pds pppm; do
  # shellcheck disable=SC2086
  set -- ${ARGS[$m]}
  for round in 1 2; do
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
