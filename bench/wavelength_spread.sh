#!/usr/bin/env bash
# Wavelength photon differentials (issue 22, deliverable 3) measured on the prism's rainbow: pds in
# spectral mode at equal photons, without wavelength differentials and with
# --wavelength-spread K (each footprint swept along the dispersion fan over K s / (N_e p(λ)) nm).
# Per K: the noise (RMSE between two seeds / √2) and the error against the light tracer's
# reference (RMSE, SSIM), on the whole image and on the streak's close-up (crop).
# Results: docs/results/spectral/wavelength-spread-PHOTONS.txt.
#   bash bench/wavelength_spread.sh [photons, default 100000] [reference paths per pixel, default 512]
set -euo pipefail
cd "$(dirname "$0")/.."
photons="${1:-100000}"
ref_lpp="${2:-512}"
# Environment: CAUSTICA_BIN=path (default: cargo build --release, ./target/release/caustica).
[ -n "${CAUSTICA_BIN:-}" ] || cargo build --release -q --bin caustica
B="${CAUSTICA_BIN:-./target/release/caustica}"; tmp=target/bench/prism; out=docs/results/spectral; mkdir -p "$tmp" "$out"
crop="190,140,90,50"   # the streak (x, y, w, h in pixels of the 400 x 300 image), as prism_equal_time.sh
common=(render prism --spectral --caustics-only --integrator pds --spp 4 --photons "$photons" --smoothing 23 -q)
[ -f "$tmp/reference.exr" ] || $B render prism --spectral --caustics-only --seed 3 --integrator lighttrace \
  --spp "$ref_lpp" -o "$tmp/reference.exr" -q >/dev/null 2>&1
{
  echo "# prism, spectral, caustics only, pds --spp 4 --photons $photons --smoothing 23 (the CV choice)"
  echo "# reference: light tracer, $ref_lpp paths per pixel (seed 3); noise = RMSE(seed 1, seed 2)/sqrt 2"
  printf '%-8s %9s %9s %9s %8s | %9s %9s %9s %8s\n' K noise RMSE-ref '' SSIM streak-noise RMSE-ref '' SSIM
  for k in ${KS:-off 1 10 100 300 1000 3000}; do
    extra=(); [ "$k" != off ] && extra=(--wavelength-spread "$k")
    for seed in 1 2; do
      $B "${common[@]}" --seed "$seed" "${extra[@]}" -o "$tmp/ws-$k-$seed.exr" >/dev/null 2>&1
    done
    a="$tmp/ws-$k-1.exr"; b="$tmp/ws-$k-2.exr"; r="$tmp/reference.exr"
    n=$($B compare "$a" "$b" | grep -E "^RMSE" | awk '{print $NF}')
    e=$($B compare "$a" "$r" | grep -E "^RMSE" | awk '{print $NF}')
    s=$($B compare "$a" "$r" | grep -E "^SSIM" | awk '{print $NF}')
    cn=$($B compare "$a" "$b" --crop "$crop" | grep -E "^RMSE" | awk '{print $NF}')
    ce=$($B compare "$a" "$r" --crop "$crop" | grep -E "^RMSE" | awk '{print $NF}')
    cs=$($B compare "$a" "$r" --crop "$crop" | grep -E "^SSIM" | awk '{print $NF}')
    printf '%-8s %9.6f %9.6f %9s %8s | %9.6f %9.6f %9s %8s\n' "$k" \
      "$(echo "$n / sqrt(2)" | bc -l)" "$e" '' "$s" "$(echo "$cn / sqrt(2)" | bc -l)" "$ce" '' "$cs"
  done
} | tee "$out/wavelength-spread-$photons.txt"
