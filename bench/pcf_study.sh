#!/usr/bin/env bash
# Issue 21, item 7: the photon cone focusing (pcf) study (seed 001 ch. 4-5; the reading notes
# /work/shared/notes/spec-progressive-pcf.md sec. 4.4, R-1, R-2, R-4 (in part), R-5, R-6, R-7).
#
#   bash bench/pcf_study.sh [work dir]        SCALE=small|full (default full), DOCS=docs/results/pcf
#
# On mirror-caustic-box (a glass and a mirror ball, a point light: a caustic and its reflection),
# torus-glass (a torus inside a glass ball, a point light) and painting-sheet (a grey sheet behind
# a glass plate, a point light: L S D S E only), at RES x RES:
#  (ref) an INDEPENDENT reference per scene: sppm, two halves of REFX * T seconds each (seeds 101,
#        102; 2 * REFX >= 10 times pcf's budget); their mean is the reference, and half their RMSE
#        to each other is its own noise.
#  (a+b) equal time: pcf (defaults; without nesting; with seed 001's cap kernel and triplet at
#        every lookup, pcf-cap), sppm, pppm, ppds, path and lighttrace, each --time T (the
#        progressive ones stop after the iteration that crosses T), seed 1; pcf (and the
#        progressive peers) save the image after iterations 1, 2, 4, 8, ... (the probe curves of
#        seed 001 figs. 5.4 to 5.7 come from pcf's saved images: probe blocks of 3x3 pixels,
#        chosen in the summariser). On mirror-caustic-box pcf and sppm also with seeds
#        2..ET_SEEDS, alternating (the reflected caustic's RMSE over seeds).
#  (c) ablations at equal cone count on mirror-caustic-box with seed 001's kernel (--cone-diffuse
#        cap): --iterations ABL_IT, PATHS/2 light paths, seeds 1..SEEDS: --cone-techniques uniform
#        | bsdf | bsdf,camera | bsdf,camera,importons | the last with --no-mis; and bsdf,camera vs
#        bsdf,camera,importons with the lookup at the second bounce (--cone-lookup bounce:2; seed
#        001 fig. 4.8); and the default, bsdf with the cosine aperture at Lambertian lookups.
#  (d) sweeps on mirror-caustic-box with seed 001's kernel and triplet: --ppm-alpha 0.2, 0.5, 0.8
#        at --cone-order 1, and --cone-order 2 at alpha 0.2 and 0.5, each SWEEP_IT iterations of
#        PATHS/2 light paths, saved at powers of 2.
# Every render's command line goes to WORK/commands.log (copied to DOCS). Then
# tools/summarize_pcf_study.py WORK OUT writes the tables, SVG plots and index.html.
# Re-runs reuse what is done (delete WORK to redo). SCALE=small: about 5 minutes (64x64, T = 4 s);
# full: about 25 minutes on 2 cores (128x128, T = 20 s; 23 minutes on 2026-12-06).
set -euo pipefail
cd "$(dirname "$0")/.."
SCALE="${SCALE:-full}"
work="${1:-target/bench/pcf-study-$SCALE}"
DOCS="${DOCS:-}"
case $SCALE in
  small) T=4 REFX=3 RES=64 PATHS=10000 ABL_IT=8 SWEEP_IT=16 SEEDS=2 ET_SEEDS=3 ;;
  full) T=20 REFX=5 RES=128 PATHS=20000 ABL_IT=32 SWEEP_IT=128 SEEDS=3 ET_SEEDS=5 ;;
  *) echo "SCALE must be small or full" >&2; exit 1 ;;
esac
py=/root/.cache/caustica/peers-venv/bin/python
[[ -x $py ]] || py=python3
# (NO_BUILD=1: skip the build, e.g. while another cargo holds the lock; WORK/bin/caustica, if
# present, is used as it is.)
[[ -n ${NO_BUILD:-} ]] || cargo build --release -q -p caustica-cli
mkdir -p "$work/bin"
# A private copy of the binary: another build in target/ must not change it mid-study.
[[ -x $work/bin/caustica ]] || cp target/release/caustica "$work/bin/caustica"
bin=$PWD/$work/bin/caustica
log="$work/commands.log"
[[ -f $work/params.txt ]] || {
  echo "SCALE=$SCALE T=$T REFX=$REFX RES=$RES PATHS=$PATHS ABL_IT=$ABL_IT SWEEP_IT=$SWEEP_IT SEEDS=$SEEDS ET_SEEDS=$ET_SEEDS"
  echo "commit=$(git rev-parse --short HEAD) dirty_files=$(git status --porcelain crates | wc -l)"
  echo "started=$(date -u +%FT%TZ)"
} > "$work/params.txt"
saves=1,2,4,8,16,32,64,128,256,512,1024,2048,4096
half_paths=$((PATHS / 2))

# Run a render, logging its command line; stdout to OUT.txt, stderr (the notes) to OUT.notes.
run() { # output.exr args...
  local o=$1
  shift
  echo "caustica $* -o $o    # load $(cut -d' ' -f1 /proc/loadavg), $(date -u +%T)" >> "$log"
  "$bin" "$@" -o "$o" > "${o%.exr}.txt" 2> "${o%.exr}.notes"
}
topfm() { "$bin" convert "$1" "${1%.exr}.pfm" > /dev/null; }
# Convert a render's saved iterations and its final image to PFM (the summariser reads them).
pfms() { # output.exr
  local o=$1
  if [[ -f $o.iterations.csv ]]; then
    tail -n +2 "$o.iterations.csv" | while IFS=, read -r _ _ img; do topfm "$img"; rm -f "$img"; done
  fi
  topfm "$o"
  rm -f "$o.state"
}

scenes=(mirror-caustic-box torus-glass painting-sheet)
base=(--width "$RES" --height "$RES" -q)

for s in "${scenes[@]}"; do
  d="$work/$s"
  mkdir -p "$d"
  echo "== $s: reference (sppm, 2 x $((REFX * T)) s)"
  for h in a b; do
    seed=$([[ $h == a ]] && echo 101 || echo 102)
    [[ -f $d/ref-$h.pfm ]] && continue
    run "$d/ref-$h.exr" render "$s" "${base[@]}" --integrator sppm --photons-per-iteration "$PATHS" \
      --time $((REFX * T)) --seed "$seed"
    pfms "$d/ref-$h.exr"
  done
  echo "== $s: equal time, T = $T s"
  for m in pcf pcf-nested-off pcf-cap sppm pppm ppds path lighttrace; do
    o="$d/et-$m.exr"
    [[ -f ${o%.exr}.pfm ]] && continue
    echo "   $m"
    case $m in
      pcf) run "$o" render "$s" "${base[@]}" --integrator pcf --time "$T" --photons-per-iteration "$PATHS" \
             --spp 2 --seed 1 --save-iterations "$saves" ;;
      # Without nesting: no point-light glints in glass and mirrors, which sppm (the
      # reference) cannot render either; the like-for-like comparison.
      pcf-nested-off) run "$o" render "$s" "${base[@]}" --integrator pcf --nested off --time "$T" \
             --photons-per-iteration "$PATHS" --spp 2 --seed 1 --save-iterations "$saves" ;;
      # The seed's kernel everywhere (a cap also at Lambertian lookups) with its triplet of
      # techniques: pcf's defaults before the cosine aperture (docs/pcf.md, "Lambertian lookups").
      pcf-cap) run "$o" render "$s" "${base[@]}" --integrator pcf --cone-diffuse cap \
             --cone-techniques bsdf,camera,importons --time "$T" --photons-per-iteration "$PATHS" \
             --spp 2 --seed 1 --save-iterations "$saves" ;;
      sppm | pppm | ppds) run "$o" render "$s" "${base[@]}" --integrator "$m" --time "$T" \
             --photons-per-iteration "$PATHS" --seed 1 --save-iterations "$saves" ;;
      *) run "$o" render "$s" "${base[@]}" --integrator "$m" --time "$T" --seed 1 ;;
    esac
    pfms "$o"
  done
done

# The reflected caustic over seeds: pcf and sppm at equal time, alternating (seed 1 is (b)'s).
s=mirror-caustic-box
d="$work/$s"
echo "== $s: equal time over seeds 2..$ET_SEEDS, pcf and sppm alternating"
for seed in $(seq 2 "$ET_SEEDS"); do
  for m in pcf sppm; do
    o="$d/et-$m-s$seed.exr"
    [[ -f ${o%.exr}.pfm ]] && continue
    case $m in
      pcf) run "$o" render "$s" "${base[@]}" --integrator pcf --time "$T" --photons-per-iteration "$PATHS" \
             --spp 2 --seed "$seed" ;;
      sppm) run "$o" render "$s" "${base[@]}" --integrator sppm --time "$T" --photons-per-iteration "$PATHS" \
             --seed "$seed" ;;
    esac
    pfms "$o"
  done
done

d="$work/$s/ablation"
mkdir -p "$d"
echo "== $s: ablations, $ABL_IT iterations of $half_paths light paths, seeds 1..$SEEDS"
# Seed 001's kernel (a cap at every lookup: --cone-diffuse cap), where the techniques matter,
# and the default cosine aperture at Lambertian lookups with the BSDF's sampler alone.
configs=("uniform" "bsdf" "bsdf,camera" "bsdf,camera,importons" "bsdf,camera,importons:no-mis"
  "bsdf,camera:bounce2" "bsdf,camera,importons:bounce2" "bsdf:cosine")
for c in "${configs[@]}"; do
  tech=${c%%:*}
  extra=(--cone-diffuse cap)
  [[ $c == *:no-mis ]] && extra+=(--no-mis)
  [[ $c == *:bounce2 ]] && extra+=(--cone-lookup bounce:2)
  [[ $c == *:cosine ]] && extra=(--cone-diffuse cosine)
  label=${c//,/+}
  label=${label//:/-}
  for seed in $(seq 1 "$SEEDS"); do
    o="$d/$label-s$seed.exr"
    [[ -f ${o%.exr}.pfm ]] && continue
    echo "   $c seed $seed"
    run "$o" render "$s" "${base[@]}" --integrator pcf --iterations "$ABL_IT" --photons-per-iteration "$half_paths" \
      --spp 2 --seed "$seed" --cone-techniques "$tech" "${extra[@]}"
    pfms "$o"
  done
done

d="$work/$s/sweep"
mkdir -p "$d"
echo "== $s: alpha and order sweeps, $SWEEP_IT iterations of $half_paths light paths"
for c in a0.2-p1 a0.5-p1 a0.8-p1 a0.2-p2 a0.5-p2; do
  a=${c%-p*}
  a=${a#a}
  p=${c##*-p}
  o="$d/$c.exr"
  [[ -f ${o%.exr}.pfm ]] && continue
  echo "   alpha $a, p $p"
  run "$o" render "$s" "${base[@]}" --integrator pcf --iterations "$SWEEP_IT" --photons-per-iteration "$half_paths" \
    --spp 2 --seed 1 --ppm-alpha "$a" --cone-order "$p" --save-iterations "$saves" \
    --cone-diffuse cap --cone-techniques bsdf,camera,importons
  pfms "$o"
done
echo "finished=$(date -u +%FT%TZ)" >> "$work/params.txt"

out="${DOCS:-$work/results}"
"$py" tools/summarize_pcf_study.py "$work" "$out"
cp "$log" "$out/commands.log"
cp "$work/params.txt" "$out/params.txt"
echo "results in $out"
