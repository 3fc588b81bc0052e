#!/usr/bin/env bash
# Spectral mode against Mitsuba 3's scalar_spectral on its own Cornell box (mi.cornell_box(),
# 256x256, path tracer, max depth 8), and caustica's RGB mode beside it: the mean linear sRGB of
# each and caustica compare's z-test. Writes docs/results/spectral/cornell-*.exr and the
# compare output to docs/results/spectral/cornell-vs-mitsuba.txt.
#   bash bench/spectral_vs_mitsuba.sh [caustica spp, default 512] [mitsuba spp, default 1024]
set -euo pipefail
cd "$(dirname "$0")/.."
spp="${1:-512}"; mspp="${2:-1024}"
venv=$(bash tools/peers/venv.sh)
cargo build --release -q --bin caustica
out=docs/results/spectral; tmp=target/bench; mkdir -p "$out" "$tmp"
./target/release/caustica render cornell-box --integrator path --spp "$spp" --max-depth 8 --spectral -o "$tmp/cornell-spectral.exr" -q
./target/release/caustica render cornell-box --integrator path --spp "$spp" --max-depth 8 -o "$tmp/cornell-rgb.exr" -q
"$venv/bin/python" tools/peers/mitsuba_render.py cornell-box --variant scalar_spectral --spp "$mspp" --out "$tmp/cornell-mitsuba-spectral.exr"
{
  echo "# caustica --spectral ($spp spp) against Mitsuba 3 scalar_spectral ($mspp spp)"
  ./target/release/caustica compare "$tmp/cornell-spectral.exr" "$tmp/cornell-mitsuba-spectral.exr"
  echo
  echo "# caustica RGB mode ($spp spp) against Mitsuba 3 scalar_spectral ($mspp spp)"
  ./target/release/caustica compare "$tmp/cornell-rgb.exr" "$tmp/cornell-mitsuba-spectral.exr"
} | tee "$out/cornell-vs-mitsuba.txt"
