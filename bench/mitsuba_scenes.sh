#!/usr/bin/env bash
# The four comparison scenes of scenes/mitsuba/ rendered by caustica and by Mitsuba 3
# (scalar_rgb, installed into a venv by tools/peers/venv.sh if missing), each with the
# integrator the scene file names (path for the Cornell box and the gold scene, the light tracer
# `lighttrace` vs Mitsuba's `ptracer` for the two caustic scenes), then `caustica compare`:
# relative mean difference, RMSE, SSIM, z-score tests; agreement = |relative mean difference|
# < 1 % and no 16x16 block flagged by the bias test (Bonferroni at 1 %, |difference| >= 1 %).
# Pixels black in both images (light tracers leave pixels that see glass directly black) are
# ignored.
#   bash bench/mitsuba_scenes.sh [path spp (default 256)] [light-tracer spp (default 1024)]
set -euo pipefail
cd "$(dirname "$0")/.."
path_spp="${1:-256}"
lt_spp="${2:-1024}"
venv=$(bash tools/peers/venv.sh)
cargo build --release -q --bin caustica
bin=./target/release/caustica
out=target/bench/mitsuba-scenes; mkdir -p "$out"
status=0
for scene in cornell-box gold-conductors glass-sphere-point directional-glass; do
  xml="scenes/mitsuba/$scene.xml"
  integrator=$(sed -n 's/.*<integrator type="\([a-z]*\)".*/\1/p' "$xml" | head -1)
  spp=$path_spp; [ "$integrator" = ptracer ] && spp=$lt_spp
  echo "== $scene ($integrator, $spp spp)"
  s=$(date +%s.%N)
  "$bin" render "$xml" --spp "$spp" --seed 1 --sampler independent -o "$out/$scene-caustica.exr" -q >/dev/null
  e=$(date +%s.%N)
  printf 'caustica: %.2f s (whole process)\n' "$(echo "$e - $s" | bc -l)"
  "$venv/bin/python" tools/peers/mitsuba_render.py "$xml" --spp "$spp" --seed 7 --out "$out/$scene-mitsuba.exr"
  "$bin" compare "$out/$scene-caustica.exr" "$out/$scene-mitsuba.exr" --mask-black --check 0.01 \
    --error-image "$out/$scene-error.png" || status=1
done
exit $status
