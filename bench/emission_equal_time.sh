#!/usr/bin/env bash
# Issue 23 item 5: equal-time study of caustica's photon methods against LuxCore 2.11 (PATHCPU
# with the PhotonGI caustic cache and its Metropolis photon sampler, and BIDIRCPU) on the four
# caustic case scenes, at several time budgets, against long light-tracer references: RMSE,
# mean absolute error, SSIM and the caustic's energy over the pixels that see a diffuse surface;
# the images side by side.
#   bash bench/emission_equal_time.sh
# Environment (all optional):
#   SCENES       scenes (default "glass-sphere water-wave metal-ring gold-ring")
#   BUDGETS      seconds per render (default "30 60 120")
#   METHODS      caustica methods, ';'-separated entries "INTEGRATOR:EXTRA ARGS" (each run gets
#                --time BUDGET --seed $SEED), e.g.
#                "pds:--spp 4 --emission uniform;pds:--spp 4 --emission projection;ppds"
#                (default: pds with 4 camera samples per pixel and ppds, with
#                --emission uniform when the binary has --emission)
#   LUX_ENGINES  LuxCore engines, pgi and/or bidir (default "pgi bidir")
#   PGI_RADIUS   PhotonGI caustic lookup radius in metres (default 0.02)
#   REF          the reference: "lt" (the light tracer at REF_SPP light paths per pixel, seed 7;
#                pixels that see glass or metal directly are black, hence the mask) or
#                "hybrid:SECONDS" (the hybrid integrator for SECONDS, seed 7: far less noise in
#                the same time). Default "lt"; cached per value.
#   REF_SPP      light paths per pixel of the light-tracer reference (default 8192)
#   REF_CHECK_SPP with a hybrid reference, also render the light tracer at this many light paths
#                per pixel (seed 8) and measure it against the reference: an independent
#                unbiased estimator, whose difference from the reference must be its own noise
#                (default 0: no check)
#   SEED         seed of the timed renders (default 1)
#   OUT, WORK    results (default docs/results/emission-equal-time) and work folders
#                (default target/bench/emission-equal-time)
#   CAUSTICA_BIN a caustica binary to use instead of building one
# Results: $OUT/README.md, results.csv and one PNG strip per scene and budget.
set -euo pipefail
cd "$(dirname "$0")/.."
SCENES="${SCENES:-glass-sphere water-wave metal-ring gold-ring}"
BUDGETS="${BUDGETS:-30 60 120}"
LUX_ENGINES="${LUX_ENGINES:-pgi bidir}"
PGI_RADIUS="${PGI_RADIUS:-0.02}"
REF="${REF:-lt}"
REF_SPP="${REF_SPP:-8192}"
REF_CHECK_SPP="${REF_CHECK_SPP:-0}"
SEED="${SEED:-1}"
OUT="${OUT:-docs/results/emission-equal-time}"
WORK="${WORK:-target/bench/emission-equal-time}"
if [ -n "${CAUSTICA_BIN:-}" ]; then
  bin="$CAUSTICA_BIN"
else
  cargo build --release -q -p caustica-cli
  bin="${CARGO_TARGET_DIR:-target}/release/caustica"
fi
venv="$(bash tools/peers/venv.sh)"
py="$venv/bin/python"
if "$bin" render --help | grep -q -- '--emission'; then em=" --emission uniform"; else em=""; fi
METHODS="${METHODS:-pds:--spp 4$em;ppds:$em}"
IFS=';' read -ra methods <<< "$METHODS"
# caustic crops x,y,w,h (pixels of the 256-px-wide images): the spot beside the sphere, the
# two bands and the region between them, the focal point of the nephroid's branch, the cardioid
declare -A CROP=([glass-sphere]=112,128,56,40 [water-wave]=72,0,112,256
                 [metal-ring]=84,100,64,56 [gold-ring]=60,56,112,72)
mkdir -p "$OUT" "$WORK"
csv="$WORK/results.csv"
echo "scene,budget,method,seconds,rmse,mae,ssim,caustic_energy_ratio,mean_ratio,note" > "$csv"
# shellcheck source=bench/timing_lib.sh
source bench/timing_lib.sh
label() { # "pds:--spp 4 --emission uniform" -> "pds --spp 4 --emission uniform" (display)
  local i="${1%%:*}" a="${1#*:}"
  [ "$a" = "$1" ] && a=""
  echo "$i${a:+ $(echo "$a" | xargs)}"
}
slug() { echo "$1" | sed -e 's/--//g' -e 's/[^A-Za-z0-9.]\+/-/g' -e 's/-$//'; }
measure() { # scene budget method seconds image reference mask crop note
  local cmp ssim m
  cmp=$("$bin" compare "$5" "$6" --mask "$7")
  ssim=$(echo "$cmp" | awk '/^SSIM/ { print $NF }')
  m=$("$py" tools/peers/equal_time_metrics.py metrics "$5" "$6" "$7" --crop "$8")
  "$py" - "$1" "$2" "$3" "$4" "$ssim" "$m" "$9" >> "$csv" <<'PY'
import csv, json, sys
scene, budget, method, seconds, ssim, m, note = sys.argv[1:8]
m = json.loads(m)
csv.writer(sys.stdout).writerow([scene, budget, method, seconds, m["rmse"], m["mae"], ssim,
                                 m["caustic_energy_ratio"], m["mean_ratio"], note])
PY
  tail -n 1 "$csv"
}
for scene in $SCENES; do
  w="$WORK/$scene"; mkdir -p "$w"
  crop="${CROP[$scene]:-0,0,100000,100000}"
  case "$REF" in
    lt) ref="$w/reference-lt-$REF_SPP.pfm"
        ref_args=(--integrator lighttrace --spp "$REF_SPP") ;;
    hybrid:*) ref="$w/reference-hybrid-${REF#hybrid:}s.pfm"
        ref_args=(--integrator hybrid --time "${REF#hybrid:}") ;;
    *) echo "REF must be lt or hybrid:SECONDS, got '$REF'" >&2; exit 2 ;;
  esac
  if [ ! -f "$ref" ]; then
    echo "== $scene: reference, ${ref_args[*]}"
    t0=$(now)
    "$bin" render "$scene" "${ref_args[@]}" --seed 7 -q -o "$ref.tmp.pfm" > "${ref%.pfm}.log" 2>&1
    mv "$ref.tmp.pfm" "$ref"
    echo "   $(elapsed "$t0") s" | tee -a "${ref%.pfm}.log"
  fi
  mask="$w/mask.pfm"
  if [ ! -f "$mask" ]; then
    python3 tools/peers/specular_mask.py toml "scenes/$scene.toml" "$w/cover.toml"
    "$bin" render "$w/cover.toml" --integrator path --spp 64 --seed 1 -q -o "$w/cover.pfm" > /dev/null
    "$py" tools/peers/specular_mask.py mask "$w/cover.pfm" "$mask"
  fi
  if [ "$REF" != lt ] && [ "$REF_CHECK_SPP" -gt 0 ]; then
    check="$w/check-lt-$REF_CHECK_SPP.pfm"
    echo "== $scene: reference check, light tracer with $REF_CHECK_SPP light paths per pixel"
    t0=$(now)
    "$bin" render "$scene" --integrator lighttrace --spp "$REF_CHECK_SPP" --seed 8 -q -o "$check" \
      > "${check%.pfm}.log" 2>&1
    measure "$scene" 0 "lighttrace --spp $REF_CHECK_SPP (reference check)" "$(elapsed "$t0")" \
      "$check" "$ref" "$mask" "$crop" "independent unbiased estimator"
  fi
  for budget in $BUDGETS; do
    imgs=("$ref")
    for e in $LUX_ENGINES; do
      img="$w/luxcore-$e-${budget}s.pfm"
      echo "== $scene, $budget s: LuxCore $e"
      t0=$(now)
      "$py" tools/peers/luxcore_render.py "$scene" --engine "$e" --time "$budget" --seed "$SEED" \
        --pgi-radius "$PGI_RADIUS" --out "$img" --stats "$w/luxcore-$e-${budget}s.json" \
        > /dev/null 2> "$w/luxcore-$e-${budget}s.log"
      secs=$(elapsed "$t0")
      note=$("$py" -c 'import json, sys; s = json.load(open(sys.argv[1]))
print("%d passes, Start() %.1f s" % (s["passes"], s["start_seconds"]))' "$w/luxcore-$e-${budget}s.json")
      measure "$scene" "$budget" "luxcore-$e" "$secs" "$img" "$ref" "$mask" "$crop" "$note"
      imgs+=("$img")
    done
    for entry in "${methods[@]}"; do
      integ="${entry%%:*}"; extra=""
      [ "$integ" != "$entry" ] && extra="${entry#*:}"
      name="$(label "$entry")"
      img="$w/$(slug "$name")-${budget}s.pfm"
      echo "== $scene, $budget s: caustica $name"
      t0=$(now)
      # shellcheck disable=SC2086 # the extra arguments are split on purpose
      "$bin" render "$scene" --integrator "$integ" $extra --time "$budget" --seed "$SEED" -q \
        -o "$img" > "${img%.pfm}.log" 2>&1
      secs=$(elapsed "$t0")
      note=$(grep -- ' -> ' "${img%.pfm}.log" | tail -n 1 | sed -e 's/ -> .*//' -e 's/^[^:]*: //' | head -c 200 || true)
      measure "$scene" "$budget" "$name" "$secs" "$img" "$ref" "$mask" "$crop" "$note"
      imgs+=("$img")
    done
    "$py" tools/peers/equal_time_metrics.py strip "$w/strip-${budget}s.pfm" "${imgs[@]}"
    "$bin" convert "$w/strip-${budget}s.pfm" "$OUT/$scene-${budget}s.png" > /dev/null
  done
done
cp "$csv" "$OUT/results.csv"
n_budget=$(echo "$BUDGETS" | wc -w); n_scene=$(echo "$SCENES" | wc -w)
total=$(awk -v b="$BUDGETS" 'BEGIN { n = split(b, a, " "); s = 0; for (i = 1; i <= n; i++) s += a[i]; print s }')
runs=$(( $(echo "$LUX_ENGINES" | wc -w) + ${#methods[@]} ))
dirty=""; [ -n "$(git status --porcelain -- crates)" ] && dirty=" (crates/ modified)"
export M_COMMAND="SCENES=\"$SCENES\" BUDGETS=\"$BUDGETS\" METHODS=\"$METHODS\" REF=$REF REF_SPP=$REF_SPP REF_CHECK_SPP=$REF_CHECK_SPP OUT=$OUT bash bench/emission_equal_time.sh"
export M_DATE="$(date +%F)" M_COMMIT="$(git rev-parse --short HEAD)$dirty"
export M_MACHINE="$(nproc) cores ($(lscpu | sed -n 's/^Model name: *//p')), $(free -g | awk '/Mem:/ {print $2}') GiB"
export M_LUXCORE="$("$py" -c 'import importlib.metadata as m; print(m.version("pyluxcore"))')"
case "$REF" in
  lt) M_REFERENCE="caustica's light tracer at $REF_SPP light paths per pixel (\`caustica render SCENE --integrator lighttrace --spp $REF_SPP --seed 7\`)" ;;
  *) M_REFERENCE="caustica's hybrid integrator run for ${REF#hybrid:} s (\`caustica render SCENE --integrator hybrid --time ${REF#hybrid:} --seed 7\`; checked against an independent light tracer, budget 0 in the tables)" ;;
esac
export M_REFERENCE M_REF_SPP="$REF_SPP" M_METHODS="$METHODS" M_PGI_RADIUS="$PGI_RADIUS"
ref_min=4; [ "$REF" != lt ] && ref_min=$(( ${REF#hybrid:} / 60 + 2 ))
export M_MINUTES=$(( total * runs * n_scene / 60 + ref_min * n_scene ))
export M_CROPS="glass-sphere=${CROP[glass-sphere]} water-wave=${CROP[water-wave]} metal-ring=${CROP[metal-ring]} gold-ring=${CROP[gold-ring]}"
"$py" - "$WORK/meta.json" <<'PY'
import json, os, sys
e = os.environ
meta = {
    "command": e["M_COMMAND"], "date": e["M_DATE"], "commit": e["M_COMMIT"],
    "machine": e["M_MACHINE"], "luxcore": e["M_LUXCORE"], "ref_spp": e["M_REF_SPP"],
    "methods": [m.replace(":", " ", 1).strip() for m in e["M_METHODS"].split(";")],
    "pgi_radius": e["M_PGI_RADIUS"], "estimate_minutes": e["M_MINUTES"],
    "crops": dict(kv.split("=") for kv in e["M_CROPS"].split()),
    "reference": e["M_REFERENCE"],
}
json.dump(meta, open(sys.argv[1], "w"), indent=1)
PY
"$py" tools/peers/equal_time_metrics.py report "$OUT/results.csv" "$WORK/meta.json" \
  docs/results/emission-equal-time/luxcore-checks.md "$OUT/README.md"
echo "== written $OUT/README.md, $OUT/results.csv and $((n_scene * n_budget)) image strips"
