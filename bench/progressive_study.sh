#!/usr/bin/env bash
# Issue 20, item 9: the convergence study of the progressive methods.
#
# On the glass sphere, the water wave and the metal ring (caustics only, against a light-tracer
# reference) and the Cornell box (full global illumination, against a path-tracer reference),
# at 64x64: RMSE against time for pppm, ppds, sppm and ppm, each from four initial bandwidths
# (pppm/sppm/ppm: the first iteration's 50-NN median radius r50 times 1, 1/2, 1/4, 1/8, 1/16 (the
# Cornell box: the global map's, and pppm from its pilot alone); ppds:
# smoothing 0.5, 1, 2, 4, 8, and "ppdsf": ppds at s = 1, 2, 4 with a minimum footprint of r50
# times 1/4, 1/2, 1 on the caustic scenes; ppm with 16 fixed hit points per pixel), alpha 2/3, under one time budget T (the render stops after the
# iteration that crosses T); one render per curve (--save-iterations 1, 2, 4, ...). Then an
# alpha sweep (0.3, 0.5, 0.8, 0.95) of pppm, ppds and sppm at their best initial bandwidth on
# the water wave and the glass sphere, and the one-shot methods at their best bandwidth with
# the light paths the best pppm traced in T (pm: k = 10..1000; pds: s = 0.5..16; Cornell box:
# pm's global k under the time budget T itself). Last, the acceptance's consistency check: every method at its best initial
# bandwidth for exactly 1000 iterations on the glass sphere and the water wave (RMSE after 1,
# 10, 100, 1000 iterations, into iterations.csv).
#   bash bench/progressive_study.sh [T seconds, default 15] [work dir]
# then: python3 tools/summarize_progressive_study.py WORK docs/results/progressive
# About 35 minutes at T = 15 on 2 cores. Re-runs reuse what is done (delete WORK to redo).
set -euo pipefail
cd "$(dirname "$0")/.."
T="${1:-15}"
work="${2:-target/bench/progressive-study}"
cargo build --release -q -p caustica-cli
bin=$PWD/target/release/caustica
# (REF_DIV=N divides the references' samples by N: for a quick check of this script only.)
div="${REF_DIV:-1}"
mkdir -p "$work"
csv="$work/study.csv"
[[ -f $csv ]] || echo "scene,method,alpha,bandwidth,iteration,seconds,rmse" > "$csv"
saves=1,2,4,8,16,32,64,128,256,512,1024,2048,4096,8192,16384,10,100,1000,10000
echo "$T" > "$work/budget.txt"

paths_of() { [[ $1 == glass-sphere ]] && echo 100000 || echo 20000; }
# ppm keeps its camera pass's hit points for good: 16 per pixel (stratified) lower the aliasing
# floor one hit point per pixel leaves (docs/progressive.md); the other methods take 1 camera
# sample per pixel and iteration.
hit_points() { [[ $1 == ppm ]] && echo "--spp 16" || true; }
base_args() { # scene
  local a=(render "$1" --width 64 --height 64 -q)
  [[ $1 == cornell-box ]] || a+=(--caustics-only)
  echo "${a[@]}"
}
metric_args() { # scene
  [[ $1 == cornell-box ]] && echo "" || echo "--mask $work/$1/mask.exr"
}

reference() { # scene
  local s=$1 d="$work/$1"
  mkdir -p "$d"
  [[ -f $d/ref.exr ]] && return
  read -ra b <<< "$(base_args "$s")"
  if [[ $s == cornell-box ]]; then
    "$bin" "${b[@]}" --integrator path --spp $((16384 / div)) --seed 7 -o "$d/ref.exr" > /dev/null
    "$bin" "${b[@]}" --integrator path --spp $((4096 / div)) --seed 8 -o "$d/ref-check.exr" > /dev/null
  else
    "$bin" "${b[@]}" --integrator lighttrace --spp $((65536 / div)) --seed 7 -o "$d/ref.exr" > /dev/null
    "$bin" "${b[@]}" --integrator lighttrace --spp $((16384 / div)) --seed 8 -o "$d/ref-check.exr" > /dev/null
    # Pixels that see glass or a mirror directly are black in every light-tracer image (it cannot
    # connect to a delta surface): the mask is the light tracer's full-light image, non-zero
    # where the camera sees a diffuse surface.
    "$bin" render "$s" --width 64 --height 64 --seed 9 -q --integrator lighttrace --spp 64 \
      -o "$d/mask.exr" > /dev/null
  fi
  # shellcheck disable=SC2046
  "$bin" compare "$d/ref-check.exr" "$d/ref.exr" $(metric_args "$s") > "$d/reference-noise.txt"
}

# One progressive render under the budget, its saved images compared with the reference.
# ppdsf is ppds with a minimum footprint (--min-footprint, given in EXTRA with the label).
EXTRA=()
integrator_of() { [[ $1 == ppdsf ]] && echo ppds || echo "$1"; }
curve() { # scene method alpha bandwidth-option bandwidth-value label
  local s=$1 m=$2 a=$3 opt=$4 v=$5 label=$6 d="$work/$1/$2-a$3-$6"
  grep -q "^$s,$m,$a,$label," "$csv" && return
  rm -rf "$d" && mkdir -p "$d"
  read -ra b <<< "$(base_args "$s")"
  "$bin" "${b[@]}" --seed 1 --integrator "$(integrator_of "$m")" --time "$T" --photons-per-iteration "$(paths_of "$s")" \
    --ppm-alpha "$a" "$opt" "$v" "${EXTRA[@]}" $(hit_points "$m") --save-iterations "$saves" -o "$d/final.exr" \
    > "$d/summary.txt" 2> "$d/notes.txt"
  local last
  last=$(tail -n 1 "$d/final.exr.iterations.csv" | cut -d, -f1)
  local secs
  secs=$(grep -o 'in [0-9.]* s' "$d/summary.txt" | awk '{print $2}')
  local its
  its=$(grep -o '[0-9]* iterations,' "$d/summary.txt" | awk '{print $1}')
  {
    tail -n +2 "$d/final.exr.iterations.csv" | while IFS=, read -r it sec img; do
      # shellcheck disable=SC2046
      e=$("$bin" compare "$img" "$work/$s/ref.exr" $(metric_args "$s") | awk '/^RMSE/ {print $2}')
      echo "$s,$m,$a,$label,$it,$sec,$e"
    done
    if [[ $its != "$last" ]]; then
      # shellcheck disable=SC2046
      e=$("$bin" compare "$d/final.exr" "$work/$s/ref.exr" $(metric_args "$s") | awk '/^RMSE/ {print $2}')
      echo "$s,$m,$a,$label,$its,$secs,$e"
    fi
  } >> "$csv"
  rm -f "$d"/final-it*.exr "$d/final.exr.state"
}

# The best initial bandwidth (label) of a method at alpha 2/3: lowest RMSE at its last row.
best_label() { # scene method
  awk -F, -v s="$1" -v m="$2" '$1 == s && $2 == m && $3 == "0.6667" {
      if (!($4 in it) || $5 + 0 > it[$4]) { it[$4] = $5 + 0; e[$4] = $7 + 0 } }
    END { b = ""; for (l in e) if (b == "" || e[l] < e[b]) b = l; print b }' "$csv"
}
option_of() { # scene method label -> "--radius R", "--smoothing S [--min-footprint R]"
  case $2 in
    ppds) echo "--smoothing ${3#s}" ;;
    ppdsf)
      local sm=${3#s}
      echo "--smoothing ${sm%%f*} --min-footprint $(awk -v f="${3##*f}" '{printf "%.6g", $1 * f}' "$work/$1/r50.txt")"
      ;;
    *) echo "--radius $(awk -v f="${3#r}" '{printf "%.6g", $1 * f}' "$work/$1/r50.txt")" ;;
  esac
}

scenes=(glass-sphere water-wave metal-ring cornell-box)
for s in "${scenes[@]}"; do
  echo "== $s: reference"
  reference "$s"
  read -ra b <<< "$(base_args "$s")"
  if [[ ! -f $work/$s/r50.txt ]]; then
    "$bin" "${b[@]}" --seed 1 --integrator pppm --iterations 1 --photons-per-iteration "$(paths_of "$s")" \
      -o "$work/$s/pilot.exr" 2>&1 >/dev/null | grep -o 'radius [0-9.]* ->' | awk '{print $2}' | tail -n 1 \
      > "$work/$s/r50.txt"
    rm -f "$work/$s/pilot.exr" "$work/$s/pilot.exr.state"
  fi
  echo "   r50 = $(cat "$work/$s/r50.txt")"
  for m in pppm sppm ppm; do
    fs=(1 0.5 0.25 0.125 0.0625)
    # The Cornell box has no caustic photons: pppm's --radius (the caustic map's) changes
    # nothing; its global radius comes from the pilot (r50 is that one, for sppm and ppm).
    [[ $s == cornell-box && $m == pppm ]] && fs=(1)
    for f in "${fs[@]}"; do
      echo "   $m r50*$f"
      curve "$s" "$m" 0.6667 --radius "$(awk -v f="$f" '{printf "%.6g", $1 * f}' "$work/$s/r50.txt")" "r$f"
    done
  done
  for sm in 0.5 1 2 4 8; do
    echo "   ppds s=$sm"
    curve "$s" ppds 0.6667 --smoothing "$sm" "s$sm"
  done
  # ppds with a minimum footprint of r50 times 1/4, 1/2, 1 (shrinking with the smoothing).
  [[ $s == cornell-box ]] && continue
  for sm in 1 2 4; do
    for f in 0.25 0.5 1; do
      echo "   ppds s=$sm min footprint r50*$f"
      EXTRA=(--min-footprint "$(awk -v f="$f" '{printf "%.6g", $1 * f}' "$work/$s/r50.txt")")
      curve "$s" ppdsf 0.6667 --smoothing "$sm" "s${sm}f$f"
      EXTRA=()
    done
  done
done

echo "== alpha sweep"
for s in water-wave glass-sphere; do
  for m in pppm ppds sppm; do
    l=$(best_label "$s" "$m")
    read -ra o <<< "$(option_of "$s" "$m" "$l")"
    for a in 0.3 0.5 0.8 0.95; do
      echo "   $s $m $l alpha $a"
      curve "$s" "$m" "$a" "${o[0]}" "${o[1]}" "$l"
    done
  done
done

echo "== one-shot methods at the light paths of the best pppm"
for s in "${scenes[@]}"; do
  l=$(best_label "$s" pppm)
  its=$(awk -F, -v s="$s" -v l="$l" '$1 == s && $2 == "pppm" && $3 == "0.6667" && $4 == l {if ($5 + 0 > n) n = $5 + 0} END {print n}' "$csv")
  n=$((its * $(paths_of "$s")))
  echo "$n" > "$work/$s/one-shot-paths.txt"
  read -ra b <<< "$(base_args "$s")"
  b=("${b[@]:1}" --seed 1) # without "render"
  read -ra mk <<< "$(metric_args "$s")"
  if [[ $s == cornell-box ]]; then
    # Equal time rather than equal light paths: pm's final gather makes a render of pppm's
    # light paths take minutes. Under --time T the photon pass has a fifth of T and stops
    # there (the global photon count below is a cap it does not reach).
    [[ -d $work/$s/one-shot-pm ]] || "$bin" sweep "${b[@]}" --integrator pm --time "$T" \
      --global-photons 50000000 --param global-k --values 50,200,800 \
      --reference "$work/$s/ref.exr" -o "$work/$s/one-shot-pm" > /dev/null
  else
    [[ -d $work/$s/one-shot-pm ]] || "$bin" sweep "${b[@]}" "${mk[@]}" --integrator pm --light-paths "$n" \
      --param k --values 10,30,100,300,1000 --reference "$work/$s/ref.exr" -o "$work/$s/one-shot-pm" > /dev/null
    [[ -d $work/$s/one-shot-pds ]] || "$bin" sweep "${b[@]}" "${mk[@]}" --integrator pds --light-paths "$n" \
      --param smoothing --values 0.5,1,2,4,8,16 --reference "$work/$s/ref.exr" -o "$work/$s/one-shot-pds" > /dev/null
  fi
  echo "   $s: $n light paths"
done
echo "== 1000 iterations at the best initial bandwidths"
icsv="$work/iterations.csv"
[[ -f $icsv ]] || echo "scene,method,bandwidth,iteration,seconds,rmse" > "$icsv"
for s in glass-sphere water-wave; do
  read -ra b <<< "$(base_args "$s")"
  read -ra mk <<< "$(metric_args "$s")"
  for m in pppm ppds ppdsf sppm ppm; do
    l=$(best_label "$s" "$m")
    grep -q "^$s,$m,$l," "$icsv" && continue
    read -ra o <<< "$(option_of "$s" "$m" "$l")"
    d="$work/$s/$m-1000"
    rm -rf "$d" && mkdir -p "$d"
    echo "   $s $m $l"
    # shellcheck disable=SC2046
    "$bin" "${b[@]}" --seed 1 --integrator "$(integrator_of "$m")" --iterations 1000 --photons-per-iteration "$(paths_of "$s")" \
      "${o[@]}" $(hit_points "$m") --save-iterations 1,10,100,1000 -o "$d/final.exr" > /dev/null 2>&1
    tail -n +2 "$d/final.exr.iterations.csv" | while IFS=, read -r it sec img; do
      e=$("$bin" compare "$img" "$work/$s/ref.exr" "${mk[@]}" | awk '/^RMSE/ {print $2}')
      echo "$s,$m,$l,$it,$sec,$e"
    done >> "$icsv"
    rm -f "$d"/final-it*.exr "$d/final.exr.state"
  done
done
echo "done: $csv $icsv"
