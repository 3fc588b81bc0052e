#!/usr/bin/env bash
# Participating media, caustica vs Mitsuba 3: fog-box, fog-box-hg and smoke-plume
# (scenes/mitsuba/*.xml, volpath, max depth 64, 128x128) rendered twice each (seeds 1 and 2) by
# Mitsuba's volpath (scalar_rgb, tools/peers/mitsuba_render.py, timing the render call alone) and,
# when the caustica binary renders them (media support), twice by
#   caustica render SCENE.xml --integrator path --spp N --seed S --sampler independent -o OUT.exr
# (timing the whole process), then tools/peers/block_compare.py: per 16x16 block the z-score of
# the difference of the means, the noise measured from the two renders per side, |z| > 4 flagged,
# and the whole-image relative mean difference. One summary line per scene with both times.
# The caustica half is skipped with a message when caustica fails on a scene.
#   bash bench/media_vs_mitsuba.sh [spp (default 256)] [out dir (default ~/.cache/caustica/media-peers)]
# Environment: CAUSTICA_BIN=path (default: cargo build --release, ./target/release/caustica),
# SCENES="fog-box ..." (a subset), SKIP_CAUSTICA=1 (Mitsuba only), NULL_TEST=1 (also two more Mitsuba renders, seeds 3 and 4, and
# a Mitsuba-vs-Mitsuba block test: checks the test's calibration, rms z should be about 1),
# MITSUBA_KAPPA (default 3.13: the noise correlation of Mitsuba's gaussian pixel filter, see
# block_compare.py; caustica's is estimated from its two renders unless CAUSTICA_KAPPA is set),
# SPECTRAL=1 (spectral mode on both sides: caustica --spectral against Mitsuba's scalar_spectral
# volpath; image files get a -spectral suffix. Results: docs/results/spectral/media-vs-mitsuba.md).
set -euo pipefail
cd "$(dirname "$0")/.."
spp="${1:-256}"
out="${2:-$HOME/.cache/caustica/media-peers}"
mkdir -p "$out"
venv=$(bash tools/peers/venv.sh)
mk="${MITSUBA_KAPPA:-3.13}"
ck=(); [ -n "${CAUSTICA_KAPPA:-}" ] && ck=(--kappa-a "$CAUSTICA_KAPPA")
py="$venv/bin/python"
bin="${CAUSTICA_BIN:-./target/release/caustica}"
use_caustica=1
variant=scalar_rgb; cflags=(); sfx=""
if [ "${SPECTRAL:-0}" = 1 ]; then variant=scalar_spectral; cflags=(--spectral); sfx="-spectral"; fi
if [ "${SKIP_CAUSTICA:-0}" = 1 ]; then
  use_caustica=0
elif [ -z "${CAUSTICA_BIN:-}" ] && ! cargo build --release -q --bin caustica; then
  echo "caustica: cargo build failed, the caustica half is skipped"; use_caustica=0
fi
status=0
summary=()
for scene in ${SCENES:-fog-box fog-box-hg smoke-plume}; do
  xml="scenes/mitsuba/$scene.xml"
  echo "== $scene ($spp spp, $variant)"
  mt=()
  seeds="1 2"; [ "${NULL_TEST:-0}" = 1 ] && seeds="1 2 3 4"
  for seed in $seeds; do
    line=$("$py" tools/peers/mitsuba_render.py "$xml" --variant "$variant" --spp "$spp" --seed "$seed" \
      --out "$out/$scene-mitsuba$sfx-$seed.exr")
    echo "$line"
    mt+=("$(echo "$line" | sed -E 's/.*render ([0-9.]+) s.*/\1/')")
  done
  if [ "${NULL_TEST:-0}" = 1 ]; then
    echo "-- null test, Mitsuba seeds 1, 2 vs 3, 4:"
    "$py" tools/peers/block_compare.py --names mitsuba-12 mitsuba-34 --kappa-a "$mk" --kappa-b "$mk" \
      --a "$out/$scene-mitsuba$sfx-1.exr" "$out/$scene-mitsuba$sfx-2.exr" \
      --b "$out/$scene-mitsuba$sfx-3.exr" "$out/$scene-mitsuba$sfx-4.exr" | sed 's/^/   /' || true
  fi
  ct=(); result="caustica skipped"
  if [ "$use_caustica" = 1 ]; then
    ok=1
    for seed in 1 2; do
      s=$(date +%s.%N)
      if ! "$bin" render "$xml" --integrator path "${cflags[@]}" --spp "$spp" --seed "$seed" \
          --sampler independent -o "$out/$scene-caustica$sfx-$seed.exr" -q \
          >"$out/$scene-caustica$sfx-$seed.log" 2>&1; then
        echo "caustica: $scene: render failed (no media support yet?), skipped; its output:"
        sed 's/^/   /' "$out/$scene-caustica$sfx-$seed.log" | tail -5
        ok=0; break
      fi
      e=$(date +%s.%N); ct+=("$(echo "$e - $s" | bc -l)")
      printf 'caustica: %.2f s (whole process), seed %s -> %s\n' "${ct[-1]}" "$seed" "$out/$scene-caustica$sfx-$seed.exr"
    done
    if [ "$ok" = 1 ]; then
      if "$py" tools/peers/block_compare.py --names caustica mitsuba "${ck[@]}" --kappa-b "$mk" \
          --a "$out/$scene-caustica$sfx-1.exr" "$out/$scene-caustica$sfx-2.exr" \
          --b "$out/$scene-mitsuba$sfx-1.exr" "$out/$scene-mitsuba$sfx-2.exr" | tee "$out/$scene-compare$sfx.txt"; then
        result="agree"
      else
        result="DIFFERENT"; status=1
      fi
    fi
  fi
  m="${mt[0]}"
  if [ "${#ct[@]}" -gt 0 ]; then
    c="${ct[0]}"
    summary+=("$(printf '%-12s mitsuba volpath (%s) %7.2f s, caustica path %7.2f s, caustica/mitsuba %.3f, %s' \
      "$scene" "$variant" "$m" "$c" "$(echo "$c / $m" | bc -l)" "$result")")
  else
    summary+=("$(printf '%-12s mitsuba volpath (%s) %7.2f s (seed 1; all: %s), %s' "$scene" "$variant" "$m" "${mt[*]}" "$result")")
  fi
done
echo "== summary ($spp spp, $variant, 128x128, max depth 64; images in $out)"
printf '%s\n' "${summary[@]}"
exit $status
