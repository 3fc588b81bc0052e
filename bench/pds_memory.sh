#!/usr/bin/env bash
# Issue 5: photon differential splatting keeps no photon map, so its peak memory must not grow
# with the photon count. Renders the water wave's caustic with pds and pdm at 10^5, 10^6 and
# 10^7 caustic photons (4 spp, 256x256 = 262 144 eye vertices) and records peak RSS (GNU time),
# wall time and the splat rate from the render notes.
#   bash bench/pds_memory.sh [scene (default water-wave)]
# Output: a Markdown table on stdout (copied into docs/performance.md).
set -euo pipefail
cd "$(dirname "$0")/.."
scene="${1:-water-wave}"
cargo build --release -q --bin caustica
bin=./target/release/caustica
work=target/bench/pds-memory; mkdir -p "$work"
echo "| integrator | caustic photons | peak RSS (MB) | wall (s) | splat pass |"
echo "|---|---:|---:|---:|---|"
for n in 100000 1000000 10000000; do
  for i in pds pdm; do
    log="$work/$i-$n.log"
    /usr/bin/time -f "%M %e" -o "$work/$i-$n.time" "$bin" render "$scene" --integrator "$i" \
      --caustics-only --spp 4 --photons "$n" --seed 1 -q -o "$work/$i-$n.exr" 2> "$log" > /dev/null
    read -r kb secs < "$work/$i-$n.time"
    rate=$(grep -o '[0-9.]* M splats/s' "$log" || true)
    echo "| $i | $n | $((kb / 1024)) | $secs | ${rate:--} |"
  done
done
