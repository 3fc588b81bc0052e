#!/usr/bin/env bash
# The hybrid integrator's time split (--light-share): for each share, two renders with different
# seeds at the same time budget; since the method is unbiased its error is its noise, and the
# difference of two independent renders has twice its variance, so RMSE ≈ RMS(a − b)/√2 and
# MAE ≈ mean|a − b|/√2 (exact for Gaussian noise), no reference needed. Over the pixels that
# see a diffuse surface (the mask of bench/emission_equal_time.sh), whole and in its caustic crop. About 2 × 2 × |SHARES| × BUDGET s.
#   bash bench/hybrid_share.sh
# Environment: SCENES (default "glass-sphere gold-ring"), SHARES (default "0.1 0.25 0.5"),
#   BUDGET seconds (default 20), OUT (default docs/results/hybrid), WORK (default
#   target/bench/hybrid-share), CAUSTICA_BIN.
set -euo pipefail
cd "$(dirname "$0")/.."
SCENES="${SCENES:-glass-sphere gold-ring}"
SHARES="${SHARES:-0.1 0.25 0.5}"
BUDGET="${BUDGET:-20}"
OUT="${OUT:-docs/results/hybrid}"
WORK="${WORK:-target/bench/hybrid-share}"
if [ -n "${CAUSTICA_BIN:-}" ]; then
  bin="$CAUSTICA_BIN"
else
  cargo build --release -q -p caustica-cli
  bin="${CARGO_TARGET_DIR:-target}/release/caustica"
fi
py="$(bash tools/peers/venv.sh)/bin/python"
declare -A CROP=([glass-sphere]=112,128,56,40 [water-wave]=72,0,112,256
                 [metal-ring]=84,100,64,56 [gold-ring]=60,56,112,72)
mkdir -p "$OUT" "$WORK"
md="$OUT/share.md"
{
  echo "# The hybrid's time split (--light-share)"
  echo
  echo "Measured $(date +%F) at $(git rev-parse --short HEAD) on $(nproc) cores; machine otherwise idle."
  echo "Command: \`SCENES=\"$SCENES\" SHARES=\"$SHARES\" BUDGET=$BUDGET bash bench/hybrid_share.sh\`."
  echo "Each cell: two renders (seeds 1 and 2) of \`caustica render SCENE --integrator hybrid --time $BUDGET --light-share F\`;"
  echo "noise RMSE = RMS(a − b)/√2 and MAE = mean|a − b|/√2 over the linear RGB values of the pixels that see a diffuse surface (the equal-time study's mask), whole image and caustic crop."
  echo
  echo "| scene | share | light paths | spp | whole RMSE | whole MAE | crop RMSE | crop MAE |"
  echo "|---|---:|---:|---:|---:|---:|---:|---:|"
} > "$md"
for scene in $SCENES; do
  # The study's mask: the pixels that see a diffuse surface (bench/emission_equal_time.sh).
  mask="$WORK/$scene-mask.pfm"
  if [ ! -f "$mask" ]; then
    python3 tools/peers/specular_mask.py toml "scenes/$scene.toml" "$WORK/$scene-cover.toml"
    "$bin" render "$WORK/$scene-cover.toml" --integrator path --spp 64 --seed 1 -q \
      -o "$WORK/$scene-cover.pfm" > /dev/null
    "$py" tools/peers/specular_mask.py mask "$WORK/$scene-cover.pfm" "$mask"
  fi
  for share in $SHARES; do
    for seed in 1 2; do
      "$bin" render "$scene" --integrator hybrid --time "$BUDGET" --light-share "$share" \
        --seed "$seed" -q -o "$WORK/$scene-$share-$seed.pfm" > "$WORK/$scene-$share-$seed.log" 2>&1
    done
    work=$(grep -- ' -> ' "$WORK/$scene-$share-1.log" | sed -e 's/.*, \([0-9]*\) caustic light paths, \([0-9.]*\) spp in.*/\1 \2/')
    "$py" - "$WORK/$scene-$share-1.pfm" "$WORK/$scene-$share-2.pfm" "$mask" "${CROP[$scene]}" "$scene" "$share" $work >> "$md" <<'PY'
import sys
sys.path.insert(0, "tools/peers")
import numpy as np
from equal_time_metrics import read_pfm
a, b = read_pfm(sys.argv[1]), read_pfm(sys.argv[2])
mask = read_pfm(sys.argv[3])[..., 0] > 0.5
x, y, w, h = (int(v) for v in sys.argv[4].split(","))
crop = np.zeros_like(mask)
crop[y:y + h, x:x + w] = True
d = a - b
c = d[crop & mask]
d = d[mask]
r = lambda e: np.sqrt((e ** 2).mean() / 2)
m = lambda e: np.abs(e).mean() / np.sqrt(2)
scene, share, paths, spp = sys.argv[5:9]
print(f"| {scene} | {share} | {int(paths) / 1e6:.1f} M | {float(spp):.0f} | {r(d):.4g} | {m(d):.4g} | {r(c):.4g} | {m(c):.4g} |")
PY
    tail -n 1 "$md"
  done
done
