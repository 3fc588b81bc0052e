#!/usr/bin/env bash
# Seed 002 figs. 10-11 revisited (issue 22): pds with a minimum footprint (--min-footprint R:
# footprints collapsed at caustic folds widened to R, against fireflies) against pm at its
# RMSE-optimal k, at about equal time on a quiet machine, with the references, bandwidths and
# binary of bench/seed002_scenes.sh (run that first). Prints one line per render (whole-process
# wall time, RMSE, SSIM) and writes docs/results/seed002-scenes/min-footprint.txt.
#   bash bench/seed002_min_footprint.sh [work dir of seed002_scenes.sh]
set -euo pipefail
cd "$(dirname "$0")/.."
work="${1:-target/bench/seed002-scenes}"
bin="$work/bin/caustica"
[[ -x $bin ]] || { echo "run bench/seed002_scenes.sh first ($bin missing)" >&2; exit 1; }
out=docs/results/seed002-scenes/min-footprint.txt
one() {  # scene ref mask mode method bandwidth photons min_footprint
  local scene=$1 ref=$2 mask=$3 mode=$4 m=$5 bw=$6 n=$7 mf=$8 extra=() s e
  [[ $mf != 0 ]] && extra=(--min-footprint "$mf")
  s=$(date +%s.%N)
  "$bin" render "$scene" --integrator "$m" $bw --photons "$n" --width 256 --spp 4 --seed 1 $mode \
    "${extra[@]}" -o "$work/mf.exr" -q >/dev/null 2>&1
  e=$(date +%s.%N)
  printf '%-14s %-4s %-14s %8s photons  min-footprint %-6s %6.2f s  RMSE %s  SSIM %s\n' \
    "$scene" "$m" "$bw" "$n" "$mf" "$(echo "$e - $s" | bc -l)" \
    $("$bin" compare "$work/mf.exr" "$ref" $mask | grep -E '^(RMSE|SSIM)' | awk '{print $NF}')
}
{
  echo "# $(date -u +%FT%TZ), $(nproc) cores, load $(cut -d' ' -f1 /proc/loadavg); 256 px wide, 4 spp, seed 1"
  pool=("swimming-pool" "$work/swimming-pool/reference-pm-10000000.exr" "" "--global-photons 0")
  for n in 25000 50000 100000; do one "${pool[@]}" pm "--k 40" "$n" 0; done
  for mf in 0 0.003 0.01; do one "${pool[@]}" pds "--smoothing 16" 100000 "$mf"; done
  cognac=("cognac-glass" "$work/cognac-glass/reference-lt-1024.exr" "--mask-black" "--caustics-only")
  for n in 100000 200000 400000; do one "${cognac[@]}" pm "--k 160" "$n" 0; done
  for n in 100000 200000; do for mf in 0 0.003; do one "${cognac[@]}" pds "--smoothing 16" "$n" "$mf"; done; done
} | tee "$out"
