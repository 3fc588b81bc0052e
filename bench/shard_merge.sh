#!/usr/bin/env bash
# Issue 24, performance: the merge against image size (4 light-tracer parts at 256², 512² and
# 1024², medians of 3) and a tree of merges against one merge (16 light-tracer parts of a 256²
# render: one merge of 16, against four merges of 4 into .cpart groups and one of the groups),
# each checked byte for byte against the unsharded render. Results:
# docs/results/distributed/merge_sizes.csv and tree_merge.csv (summarised in docs/distributed.md).
#   bash bench/shard_merge.sh
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release -q -p caustica-cli
bin=$(pwd)/target/release/caustica
out=docs/results/distributed; mkdir -p "$out"
work=target/bench/shard-merge; rm -rf "$work"; mkdir -p "$work"
# shellcheck source=bench/timing_lib.sh
source bench/timing_lib.sh

echo "size,parts,part_bytes,round,merge_seconds,identical" > "$out/merge_sizes.csv"
for s in 256 512 1024; do
  args=(caustic-box --integrator lighttrace --spp 1 --width "$s" --height "$s" -q)
  "$bin" render "${args[@]}" -o "$work/whole-$s.exr" > /dev/null
  rm -rf "$work/p"
  for i in 0 1 2 3; do "$bin" render "${args[@]}" --shard "$i/4" -o "$work/p/" > /dev/null; done
  bytes=$(du -cb "$work"/p/*.cpart | tail -1 | cut -f1)
  for r in 1 2 3; do
    t=$(now); "$bin" merge "$work/p" -q -o "$work/m.exr" > /dev/null; secs=$(elapsed "$t")
    same=no; cmp -s "$work/m.exr" "$work/whole-$s.exr" && same=yes
    echo "$s,4,$bytes,$r,$secs,$same" >> "$out/merge_sizes.csv"
  done
done

echo "level,merge,parts,seconds,identical" > "$out/tree_merge.csv"
args=(caustic-box --integrator lighttrace --spp 4 --width 256 --height 256 -q --threads 1)
"$bin" render "${args[@]}" -o "$work/whole.exr" > /dev/null
rm -rf "$work/t"; mkdir -p "$work/t"
for i in $(seq 0 15); do "$bin" render "${args[@]}" --shard "$i/16" -o "$work/t/" > /dev/null; done
t=$(now); "$bin" merge "$work/t" -q -o "$work/flat.exr" > /dev/null; secs=$(elapsed "$t")
same=no; cmp -s "$work/flat.exr" "$work/whole.exr" && same=yes
echo "flat,1,16,$secs,$same" >> "$out/tree_merge.csv"
for g in 0 1 2 3; do
  files=()
  for k in 0 1 2 3; do files+=("$work/t/$(printf 'shard-%04d-of-0016.cpart' $((g * 4 + k)))"); done
  t=$(now); "$bin" merge "${files[@]}" -q -o "$work/g$g.cpart" > /dev/null
  echo "groups,$((g + 1)),4,$(elapsed "$t")," >> "$out/tree_merge.csv"
done
t=$(now); "$bin" merge "$work"/g?.cpart -q -o "$work/tree.exr" > /dev/null; secs=$(elapsed "$t")
same=no; cmp -s "$work/tree.exr" "$work/whole.exr" && same=yes
echo "top,1,4,$secs,$same" >> "$out/tree_merge.csv"
cat "$out/merge_sizes.csv" "$out/tree_merge.csv"
