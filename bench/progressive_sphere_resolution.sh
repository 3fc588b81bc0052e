#!/usr/bin/env bash
# Issue 20: why ppds loses to pppm and sppm on the glass sphere at 64x64 (docs/results/progressive).
# The sphere's caustic covers about 30 pixels at 64x64, with structure below a pixel; this
# renders it at 64, 128 and 256 pixels square under the same time budget (caustics only, 100 000
# light paths per iteration, alpha 2/3, seed 1), ppds at s = 2, 4, 8 and pppm at 1/4, 1/2 and 1
# times the 50-NN median radius r50, and reports each one's best RMSE against a light-tracer
# reference (65536, 16384, 4096 paths/pixel: about 4.3 G light paths each) over the pixels that
# see a diffuse surface, and the ratio ppds/pppm. Then the noise/bias split at 64x64: two more
# seeds of each best setting give the noise (RMSE between seeds / sqrt 2) and the bias
# (sqrt(MSE - noise^2)).
#   bash bench/progressive_sphere_resolution.sh [T seconds, default 15] [work dir]
set -euo pipefail
cd "$(dirname "$0")/.."
T="${1:-15}"
work="${2:-target/bench/progressive-sphere-resolution}"
cargo build --release -q -p caustica-cli
bin=$PWD/target/release/caustica
mkdir -p "$work"
rmse() { "$bin" compare "$1" "$2" --mask "$3" | awk '/^RMSE/ {print $2}'; }
mean_diff() { "$bin" compare "$1" "$2" --mask "$3" | awk '/^relative mean/ {print $4}'; }
out="$work/resolution.md"
{
  echo "| pixels | ppds best (s) | RMSE | pppm best (r/r50) | RMSE | ppds / pppm | iterations ppds / pppm |"
  echo "|---:|---|---:|---|---:|---:|---:|"
} > "$out"
for w in 64 128 256; do
  d="$work/$w"
  mkdir -p "$d"
  loud=(render glass-sphere --width "$w" --height "$w" --caustics-only)
  base=("${loud[@]}" -q)
  lpp=$((65536 * 64 * 64 / (w * w)))
  [[ -f $d/ref.exr ]] || "$bin" "${base[@]}" --integrator lighttrace --spp "$lpp" --seed 7 -o "$d/ref.exr" > /dev/null
  [[ -f $d/mask.exr ]] || "$bin" render glass-sphere --width "$w" --height "$w" -q --integrator lighttrace \
    --spp 64 --seed 9 -o "$d/mask.exr" > /dev/null
  r50=$("$bin" "${loud[@]}" --integrator pppm --iterations 1 --photons-per-iteration 100000 --seed 1 \
    -o "$d/pilot.exr" 2>&1 >/dev/null | grep -o 'radius [0-9.]* ->' | awk '{print $2}' | tail -n 1)
  best() { # method option values... -> "value rmse iterations"
    local m=$1 opt=$2
    shift 2
    for v in "$@"; do
      local val=$v
      [[ $m == pppm ]] && val=$(awk -v r="$r50" -v f="$v" 'BEGIN {printf "%.6g", r * f}')
      local f="$d/$m-$v.exr"
      [[ -f $f ]] || "$bin" "${base[@]}" --integrator "$m" --time "$T" --photons-per-iteration 100000 \
        --seed 1 "$opt" "$val" -o "$f" > "$f.txt" 2> /dev/null
      echo "$v $(rmse "$f" "$d/ref.exr" "$d/mask.exr") $(grep -o '[0-9]* iterations' "$f.txt" | awk '{print $1}')"
    done | sort -k2 -g | head -n 1
  }
  read -r sv se si <<< "$(best ppds --smoothing 2 4 8)"
  read -r rv re ri <<< "$(best pppm --radius 0.25 0.5 1)"
  awk -v w="$w" -v sv="$sv" -v se="$se" -v rv="$rv" -v re="$re" -v si="$si" -v ri="$ri" \
    'BEGIN {printf "| %d² | s = %s | %.4f | %s | %.4f | %.2f | %s / %s |\n", w, sv, se, rv, re, se / re, si, ri}' >> "$out"
  if [[ $w == 64 ]]; then
    split=$work/split.md
    echo "| method (64²) | RMSE | noise | bias | mean vs reference |" > "$split"
    echo "|---|---:|---:|---:|---:|" >> "$split"
    for mv in "ppds --smoothing $sv" "pppm --radius $(awk -v r="$r50" -v f="$rv" 'BEGIN {printf "%.6g", r * f}')"; do
      read -ra a <<< "$mv"
      its=$([[ ${a[0]} == ppds ]] && echo "$si" || echo "$ri")
      for seed in 2 3; do
        f="$d/${a[0]}-seed$seed.exr"
        [[ -f $f ]] || "$bin" "${base[@]}" --integrator "${a[0]}" --iterations "$its" \
          --photons-per-iteration 100000 --seed "$seed" "${a[1]}" "${a[2]}" -o "$f" > /dev/null 2>&1
      done
      e=$(rmse "$d/${a[0]}-seed2.exr" "$d/ref.exr" "$d/mask.exr")
      n=$(rmse "$d/${a[0]}-seed2.exr" "$d/${a[0]}-seed3.exr" "$d/mask.exr")
      m=$(mean_diff "$d/${a[0]}-seed2.exr" "$d/ref.exr" "$d/mask.exr")
      awk -v k="${a[0]} ${a[1]} ${a[2]}, $its iterations" -v e="$e" -v n="$n" -v m="$m" \
        'BEGIN {s = n / sqrt(2); b = e * e - s * s; printf "| %s | %.4f | %.4f | %.4f | %+.1f %% |\n", k, e, s, (b > 0 ? sqrt(b) : 0), 100 * m}' >> "$split"
    done
  fi
done
cat "$out"
echo
cat "$work/split.md"
