#!/usr/bin/env bash
# Issue 24, performance: the overhead of sharding at N = 1 — the unsharded render against
# `--shard 0/1` (the same work, plus the part written), alternating in each of ROUNDS rounds on
# this shared machine; wall times of the whole process, and the merge of the one part.
# Results: docs/results/distributed/overhead.csv and the table printed.
#   bash bench/shard_overhead.sh [rounds (default 3)]
set -euo pipefail
cd "$(dirname "$0")/.."
rounds="${1:-3}"
cargo build --release -q -p caustica-cli
bin=$(pwd)/target/release/caustica
out=docs/results/distributed; mkdir -p "$out"
work=target/bench/shard-overhead; rm -rf "$work"; mkdir -p "$work"
csv="$out/overhead.csv"
# shellcheck source=bench/timing_lib.sh
source bench/timing_lib.sh
renders=(
  "path|cornell-box --integrator path --spp 64 --width 256 --height 256"
  "lighttrace|caustic-box --integrator lighttrace --spp 32 --width 256 --height 256"
  "pm|glass-sphere --integrator pm --spp 16 --photons 200000 --global-photons 100000 --k 300 --global-k 50 --width 256 --height 256"
  "pds|glass-sphere --integrator pds --spp 4 --light-paths 7075083 --smoothing 4 --width 256 --height 256"
  "pppm|caustic-box --integrator pppm --iterations 64 --photons-per-iteration 20000 --width 128 --height 128"
)
echo "round,method,unsharded_seconds,shard_0_of_1_seconds,merge_seconds,identical" > "$csv"
for r in $(seq 1 "$rounds"); do
  for entry in "${renders[@]}"; do
    m="${entry%%|*}"
    # shellcheck disable=SC2086
    set -- ${entry#*|}
    t=$(now); "$bin" render "$@" --threads 2 -q -o "$work/$m.exr" > /dev/null 2>&1; u=$(elapsed "$t")
    rm -rf "$work/$m-parts"
    t=$(now); "$bin" render "$@" --threads 2 -q --shard 0/1 -o "$work/$m-parts/" > /dev/null 2>&1; s=$(elapsed "$t")
    t=$(now); "$bin" merge "$work/$m-parts" -q -o "$work/$m-merged.exr" > /dev/null 2>&1; g=$(elapsed "$t")
    same=no; cmp -s "$work/$m.exr" "$work/$m-merged.exr" && same=yes
    echo "$r,$m,$u,$s,$g,$same" >> "$csv"
  done
done
python3 - "$csv" <<'PY'
import csv, sys
from collections import defaultdict
rows = list(csv.DictReader(open(sys.argv[1])))
by = defaultdict(list)
for r in rows:
    by[r["method"]].append(r)
def med(xs):
    xs = sorted(xs); n = len(xs)
    return xs[n // 2] if n % 2 else 0.5 * (xs[n // 2 - 1] + xs[n // 2])
print("| render | unsharded (median s) | --shard 0/1 (median s) | ratio of medians | shard + merge / unsharded | identical |")
print("|---|---:|---:|---:|---:|---|")
for m, rs in by.items():
    u = med([float(r["unsharded_seconds"]) for r in rs])
    s = med([float(r["shard_0_of_1_seconds"]) for r in rs])
    g = med([float(r["merge_seconds"]) for r in rs])
    same = "yes" if all(r["identical"] == "yes" for r in rs) else "NO"
    print(f"| {m} | {u:.2f} | {s:.2f} | {s / u:.3f} | {(s + g) / u:.3f} | {same} |")
PY
