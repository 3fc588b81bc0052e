#!/usr/bin/env bash
# Seed 002 fig. 12 measured: the prism's table caustic (caustics only, spectral) by pm and pds at
# about equal time, against the light tracer; whole image and the streak's close-up (crop).
# Results: docs/results/spectral/prism-equal-time.txt.
#   bash bench/prism_equal_time.sh [reference paths per pixel, default 512]
set -euo pipefail
cd "$(dirname "$0")/.."
ref_lpp="${1:-512}"
cargo build --release -q --bin caustica
B=./target/release/caustica; tmp=target/bench/prism; out=docs/results/spectral; mkdir -p "$tmp" "$out"
crop="190,140,90,50"   # the streak (x, y, w, h in pixels of the 400 x 300 image)
run() {  # name, args...: renders, prints the wall time
  local name="$1"; shift; local s e
  s=$(date +%s.%N); $B render prism --spectral --caustics-only --seed 3 "$@" -o "$tmp/$name.exr" -q >/dev/null 2>&1
  e=$(date +%s.%N); echo "$e - $s" | bc -l
}
[ -f "$tmp/reference.exr" ] || run reference --integrator lighttrace --spp "$ref_lpp" >/dev/null
{
  echo "# prism, spectral, caustics only; reference: light tracer, $ref_lpp paths per pixel (seed 3)"
  for spec in "pds-200k:--integrator pds --spp 4 --photons 200000" \
              "pds-1M:--integrator pds --spp 4 --photons 1000000" \
              "pds-4M:--integrator pds --spp 4 --photons 4000000" \
              "pm-10k:--integrator pm --spp 4 --photons 10000" \
              "pm-25k:--integrator pm --spp 4 --photons 25000" \
              "pm-100k:--integrator pm --spp 4 --photons 100000" \
              "pm-400k:--integrator pm --spp 4 --photons 400000"; do
    name="${spec%%:*}"; args="${spec#*:}"
    t=$(run "$name" $args)
    whole=$($B compare "$tmp/$name.exr" "$tmp/reference.exr" | grep -E "^(RMSE|SSIM)" | awk '{print $NF}' | paste -sd' ')
    close=$($B compare "$tmp/$name.exr" "$tmp/reference.exr" --crop "$crop" | grep -E "^(RMSE|SSIM)" | awk '{print $NF}' | paste -sd' ')
    printf '%-9s time %6.2f s   RMSE SSIM whole: %s   streak close-up: %s\n' "$name" "$t" "$whole" "$close"
  done
} | tee "$out/prism-equal-time.txt"
