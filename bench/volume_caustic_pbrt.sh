#!/usr/bin/env bash
# Volume caustic vs pbrt-v3: scenes/pbrt/volume-caustic.pbrt (a spot light through a glass sphere
# onto a floor, all in thin fog; 128x96, BDPT, max depth 64, box filter) rendered twice (seeds 1
# and 2) by pbrt-v3, built by /work/shared/peers/pbrt-v3/build.sh if missing, and, when caustica
# renders media, twice by caustica's light tracer on scenes/mitsuba/volume-caustic.xml (the same
# scene; rendered from a copy with the pixel filter switched to box, as pbrt's):
#   caustica render volume-caustic.xml --integrator light --spp N --seed S -o OUT.exr
# then tools/peers/block_compare.py over the pixels that do not see the glass sphere directly
# (tools/peers/sphere_mask.py; 16x16 blocks, z from the two renders per side, |z| > 4
# flagged, whole-image relative mean difference). The caustica half is skipped with a message when
# caustica fails on the scene. Mitsuba cannot render this scene (volpath does not reach the spot
# light through the glass), so it takes no part.
# With CHECK=1 first the two sanity checks of the pbrt scene conventions (camera, fov axis,
# handedness, units, medium parameters) against Mitsuba, 2 renders each side:
#   spot-floor-check: no fog, diffuse off-centre sphere; pbrt BDPT vs Mitsuba path (box filter)
#   spot-fog-check:   fog, diffuse off-centre sphere;   pbrt BDPT vs Mitsuba volpath (box filter)
#   bash bench/volume_caustic_pbrt.sh [pbrt spp (default 256)] [caustica light paths per pixel
#        (default 4 x pbrt spp)] [out dir (default ~/.cache/caustica/media-peers/volume-caustic)]
# Environment: PBRT_BUILD (default ~/.cache/pbrt-v3), PBRT_V3_GIT (a git dir of mmp/pbrt-v3 for the
# build, e.g. the `fetch github:mmp/pbrt-v3` mirror), CAUSTICA_BIN, SKIP_CAUSTICA=1, CHECK=1,
# CHECK_MITSUBA_SPP (default 16 x pbrt spp), CAUSTICA_KAPPA (noise correlation factor of caustica's
# renders for block_compare.py, default estimated; pbrt's and Mitsuba's box-filtered renders: 1).
set -euo pipefail
cd "$(dirname "$0")/.."
spp="${1:-256}"
lt_spp="${2:-$((4 * spp))}"
out="${3:-$HOME/.cache/caustica/media-peers/volume-caustic}"
mkdir -p "$out"
venv=$(bash tools/peers/venv.sh)
py="$venv/bin/python"
pbrt_build="${PBRT_BUILD:-$HOME/.cache/pbrt-v3}"
if [ ! -x "$pbrt_build/pbrt" ]; then
  shared=/work/shared; [ -d "$shared" ] || shared="$(cd .. && pwd)/shared"
  git_dir="${PBRT_V3_GIT:-/work/.mirror/mmp+pbrt-v3/repo}"
  [ -e "$git_dir" ] || { echo "pbrt-v3 missing: set PBRT_V3_GIT to a git dir or clone of github.com/mmp/pbrt-v3"; exit 2; }
  echo "building pbrt-v3 into $pbrt_build (about 3 min on 2 cores)"
  PBRT_BUILD="$pbrt_build" bash "$shared/peers/pbrt-v3/build.sh" "$git_dir" >"$out/pbrt-build.log" 2>&1 \
    || { tail -20 "$out/pbrt-build.log"; exit 2; }
fi
pbrt() { python3 tools/peers/pbrt_render.py "$@" --pbrt "$pbrt_build/pbrt"; }
status=0
summary=()
secs() { sed -E 's/.*render ([0-9.]+) s.*/\1/'; }

if [ "${CHECK:-0}" = 1 ]; then
  mspp="${CHECK_MITSUBA_SPP:-$((16 * spp))}"
  for check in spot-floor-check spot-fog-check; do
    echo "== $check: pbrt-v3 BDPT $spp spp vs Mitsuba $mspp spp (box filter)"
    pt=(); mt=()
    for seed in 1 2; do
      line=$(pbrt "scenes/pbrt/$check.pbrt" --spp "$spp" --seed "$seed" --out "$out/$check-pbrt-$seed.pfm"); echo "$line"
      pt+=("$(echo "$line" | secs)")
      line=$("$py" tools/peers/mitsuba_render.py "scenes/mitsuba/$check.xml" --box --spp "$mspp" --seed "$seed" \
        --out "$out/$check-mitsuba-$seed.exr"); echo "$line"
      mt+=("$(echo "$line" | secs)")
    done
    if "$py" tools/peers/block_compare.py --names pbrt mitsuba --kappa-a 1 --kappa-b 1 \
        --a "$out/$check-pbrt-1.pfm" "$out/$check-pbrt-2.pfm" \
        --b "$out/$check-mitsuba-1.exr" "$out/$check-mitsuba-2.exr" | tee "$out/$check-compare.txt"; then
      r=agree
    else
      r=DIFFERENT; status=1
    fi
    summary+=("$(printf '%-17s pbrt bdpt %s spp %7.2f s, mitsuba %s spp %7.2f s, %s' "$check" "$spp" "${pt[0]}" "$mspp" "${mt[0]}" "$r")")
  done
fi

echo "== volume-caustic: pbrt-v3 BDPT $spp spp"
pt=()
for seed in 1 2; do
  line=$(pbrt scenes/pbrt/volume-caustic.pbrt --spp "$spp" --seed "$seed" --out "$out/volume-caustic-pbrt-$seed.pfm"); echo "$line"
  pt+=("$(echo "$line" | secs)")
done
result="caustica skipped"
ct=()
bin="${CAUSTICA_BIN:-./target/release/caustica}"
use_caustica=1
if [ "${SKIP_CAUSTICA:-0}" = 1 ]; then
  use_caustica=0
elif [ -z "${CAUSTICA_BIN:-}" ] && ! cargo build --release -q --bin caustica; then
  echo "caustica: cargo build failed, the caustica half is skipped"; use_caustica=0
fi
if [ "$use_caustica" = 1 ]; then
  xml="$out/volume-caustic-box.xml"
  sed 's|<rfilter type="gaussian"/>|<rfilter type="box"/>|' scenes/mitsuba/volume-caustic.xml >"$xml"
  ok=1
  for seed in 1 2; do
    s=$(date +%s.%N)
    if ! "$bin" render "$xml" --integrator light --spp "$lt_spp" --seed "$seed" \
        -o "$out/volume-caustic-caustica-$seed.exr" -q >"$out/volume-caustic-caustica-$seed.log" 2>&1; then
      echo "caustica: volume-caustic: render failed (no media support yet?), skipped; its output:"
      sed 's/^/   /' "$out/volume-caustic-caustica-$seed.log" | tail -5
      ok=0; break
    fi
    e=$(date +%s.%N); ct+=("$(echo "$e - $s" | bc -l)")
    printf 'caustica light tracer: %.2f s (whole process), %s paths/pixel, seed %s\n' "${ct[-1]}" "$lt_spp" "$seed"
  done
  if [ "$ok" = 1 ]; then
    ck=(); [ -n "${CAUSTICA_KAPPA:-}" ] && ck=(--kappa-a "$CAUSTICA_KAPPA")
    # Pixels that see the glass sphere directly are left out: a light tracer cannot render them
    # (L ... S E paths), pbrt's BDPT can.
    python3 tools/peers/sphere_mask.py --eye 0 1.1 4.5 --target 0 0.8 0 --fov 40 --size 128 96 \
      --sphere 0 1.2 0 0.5 --out "$out/volume-caustic-glass-mask.pfm"
    if "$py" tools/peers/block_compare.py --names caustica pbrt "${ck[@]}" --kappa-b 1 \
        --mask "$out/volume-caustic-glass-mask.pfm" \
        --a "$out/volume-caustic-caustica-1.exr" "$out/volume-caustic-caustica-2.exr" \
        --b "$out/volume-caustic-pbrt-1.pfm" "$out/volume-caustic-pbrt-2.pfm" | tee "$out/volume-caustic-compare.txt"; then
      result=agree
    else
      result=DIFFERENT; status=1
    fi
  fi
fi
if [ "${#ct[@]}" -gt 0 ]; then
  summary+=("$(printf '%-17s pbrt bdpt %s spp %7.2f s, caustica light %s paths/px %7.2f s, caustica/pbrt %.3f, %s' \
    volume-caustic "$spp" "${pt[0]}" "$lt_spp" "${ct[0]}" "$(echo "${ct[0]} / ${pt[0]}" | bc -l)" "$result")")
else
  summary+=("$(printf '%-17s pbrt bdpt %s spp %7.2f s (seed 1; both: %s), %s' volume-caustic "$spp" "${pt[0]}" "${pt[*]}" "$result")")
fi
echo "== summary (128x96; images in $out)"
printf '%s\n' "${summary[@]}"
exit $status
