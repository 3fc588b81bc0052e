#!/usr/bin/env bash
# Volume photon differentials (seed 000 sec. 8.5, spec §2.6 / §3.4 XM1-XM3), measured: for each
# scene, at the seed's volume photon count N, ray-marched volume photon mapping (`vpm`, eq. 8.3,
# k-NN per step), the beam estimate with k-NN pilot radii (`beam`, the ablation "kernel shape vs
# integration scheme") and volume photon differentials (`vpd`, ellipsoidal kernels from each
# photon's differentials) against an unbiased reference, the volumetric light tracer.
#   1. stage 1 sweeps at SPP: vpm's --volume-k, beam's --volume-k, vpd's --volume-smoothing at N
#      (ascending; a sweep stops once PAST values in a row are worse than its best in both RMSE
#      and SSIM); RMSE, SSIM, relative mean difference, times;
#   2. stage 2 at FINAL_SPP: each method's stage-1 RMSE- and SSIM-optimal settings again, and the
#      RMSE-optimal one halved while that helps (at SPP the kernels of vpd, thin ellipsoids, alias:
#      its error still falls with camera samples, so the comparison is made at FINAL_SPP); the
#      optima of this stage are the study's;
#   3. how many photons vpm needs to reach vpd's best RMSE: vpm at 2N, 4N, 8N, ... at FINAL_SPP
#      (k around k_opt * f^0.57 at f N), until it gets there, reaches MATCH_MAX or the scene has
#      would pass SCENE_BUDGET seconds (its time so far + 1.7 x the last count's);
#   4. where the estimates lose: relative mean difference over regions (the medium's silhouette
#      edge, its inside, the halo just outside, and inside / outside glass spheres seen directly),
#      error images at the optima;
#   plus vpm with REF_PHOTONS photons (3 M, the seed's reference; k = REF_K, at SPP) against the
#   light tracer.
# All photon-method renders: --volume-only --no-auto-bandwidth --seed SEED -q.
# --volume-only keeps only light scattered by media straight to the camera along the camera ray's
# first segment; `lighttrace --volume-only` renders the same paths without bias (seed notes Q-M11).
# Every render is its own process: "wall" is measured around it with date, "photons" is the
# photon line's time, "camera" = the summary line's time - photons.
# Usage:
#   bash bench/volume_differentials.sh [out dir (default ~/.cache/caustica/volume-differentials)]
# Environment (defaults in brackets):
#   CAUSTICA_BIN [./target/fast/caustica]
#   SCENES ["facet-smoke:80000 laser-smoke:80000 glass-smoke:10000::8192"]: NAME:N[:WIDTH[:RSPP]]
#     (WIDTH renders at --width WIDTH, for large stand-in scenes; RSPP: this scene's REF_SPP, its
#     check at RSPP x CHECK_SPP / REF_SPP); scenes the binary lacks are skipped
#   SPP [4], REF_SPP [2048] (light paths per pixel), CHECK_SPP [REF_SPP/4] (the second light
#     tracer render, seed REF_SEED+1: its RMSE against the reference is the noise floor),
#   SEED [1], REF_SEED [7], VPM_KS ["8 16 32 64 128 256"], BEAM_KS [VPM_KS],
#   VPD_SS ["2 4 8 16 32 64 128 256"; the collimated beam of laser-smoke needs s ≈ 64], PAST [1], FINAL_SPP [16], MATCH_MAX [3000000], REF_PHOTONS
#   [3000000], REF_K [128], SCENE_BUDGET [900] (seconds per scene after which no further photon
#   count is started), CROPS ["glass-smoke=cone:68,64,26,34"]: extra rectangular regions,
#   SCENE=NAME:X,Y,W,H (the volume caustic's cone under glass-smoke's ball),
#   VPD_ARGS, BEAM_ARGS [none]: extra options of every vpd or beam render (e.g. the extensions
#     "--volume-boundary renormalise --spread-collimated 16"; recorded in the summary's command),
#   DOCS [docs/results/volume-differentials], PY (python with numpy + matplotlib; default
#   tools/peers/.venv/bin/python, else the venv of tools/peers/venv.sh, matplotlib added to it).
# Results: OUT/results.csv (one row per render and region), OUT/SCENE/*.exr|png|log, then
# tools/summarize_volume_differentials.py writes DOCS/{README tables, results.csv, plots, index.html}.
# Existing renders are reused when made with the same command (delete OUT/SCENE to start a scene over); so is an earlier photon-count
# scan (OUT/SCENE/match-status.txt; RESCAN=1 continues it).
set -euo pipefail
cd "$(dirname "$0")/.."
t_start=$(date +%s)
out="${1:-$HOME/.cache/caustica/volume-differentials}"
bin="${CAUSTICA_BIN:-./target/fast/caustica}"
[ -x "$bin" ] || { echo "no caustica binary at $bin (set CAUSTICA_BIN)"; exit 2; }
bin="$(cd "$(dirname "$bin")" && pwd)/$(basename "$bin")"
scenes="${SCENES:-facet-smoke:80000 laser-smoke:80000 glass-smoke:10000::8192}"
spp="${SPP:-4}"
ref_spp="${REF_SPP:-2048}"
check_spp="${CHECK_SPP:-$((ref_spp / 4))}"
seed="${SEED:-1}"
ref_seed="${REF_SEED:-7}"
vpm_ks="${VPM_KS:-8 16 32 64 128 256}"
beam_ks="${BEAM_KS:-$vpm_ks}"
vpd_ss="${VPD_SS:-2 4 8 16 32 64 128 256}"
match_max="${MATCH_MAX:-3000000}"
ref_photons="${REF_PHOTONS:-3000000}"
fspp="${FINAL_SPP:-16}"
past="${PAST:-1}"
ref_k="${REF_K:-128}"
scene_budget="${SCENE_BUDGET:-900}"
crops="${CROPS:-glass-smoke=cone:68,64,26,34}"
docs="${DOCS:-docs/results/volume-differentials}"
summ=tools/summarize_volume_differentials.py
if [ -z "${PY:-}" ]; then
  if [ -x tools/peers/.venv/bin/python ]; then PY=tools/peers/.venv/bin/python
  else PY="$(bash tools/peers/venv.sh)/bin/python"; fi
fi
"$PY" -c "import numpy, matplotlib" 2>/dev/null || "$PY" -m pip install -q numpy matplotlib
mkdir -p "$out"
csv="$out/results.csv"
header="scene,part,method,photons,param,value,spp,seed,wall_s,render_s,photons_s,camera_s,median_radius,step,region,pixels,rmse,ssim,relmean,against,image"
[ -f "$csv" ] && [ "$(head -1 "$csv")" = "$header" ] || echo "$header" >"$csv"
echo "caustica: $bin ($("$bin" --version 2>/dev/null || true)); $(nproc) cores; spp $spp, reference $ref_spp light paths/pixel"
"$bin" scenes >"$out/scenes.txt"

# render NAME ARGS...: $dir/NAME.exr (and .png) unless present; sets wall rsec psec csec medr mstep
render() {
  local name="$1"; shift
  local exr="$dir/$name.exr" log="$dir/$name.log"
  # reuse a render made with the same command (a bare `render NAME` reuses whatever is there)
  if [ ! -f "$exr" ] || [ ! -f "$log" ] || \
     { [ $# -gt 0 ] && [ "$(head -1 "$log")" != "command: caustica render $scene ${size[*]} $*" ]; }; then
    local t0 t1
    t0=$(date +%s.%N)
    "$bin" render "$scene" "${size[@]}" "$@" -o "$exr" --png "$dir/$name.png" >"$log.tmp" 2>&1 \
      || { cat "$log.tmp"; echo "render $name failed"; exit 1; }
    t1=$(date +%s.%N)
    { echo "command: caustica render $scene ${size[*]} $*"; cat "$log.tmp"
      echo "wall $(echo "$t1 - $t0" | bc -l)"; } >"$log"
    rm -f "$log.tmp"
  fi
  wall=$(printf %.3f "$(sed -nE 's/^wall ([0-9.]+)/\1/p' "$log" | tail -1)")
  rsec=$(sed -nE 's/.* in ([0-9.]+) s: .*/\1/p' "$log" | tail -1)
  psec=$(sed -nE 's/^photons: .* in ([0-9.]+) s \(.*/\1/p' "$log" | tail -1); psec="${psec:-0}"
  csec=$(printf %.3f "$(echo "$rsec - $psec" | bc -l)")
  medr=$(sed -nE 's/.*median radius ([0-9.]+) m.*/\1/p' "$log" | tail -1); medr="${medr:-}"
  mstep=$(sed -nE 's/.*step ([0-9.]+) m\).*/\1/p' "$log" | tail -1); mstep="${mstep:-}"
  echo "  $name: wall ${wall} s (photons ${psec} s, camera ${csec} s)${medr:+, median radius $medr m}${mstep:+, step $mstep m}"
}
# metric IMG REF [compare options]: sets m_rmse m_ssim m_rel m_px
metric() {
  local txt
  txt=$("$bin" compare "$@")
  m_rmse=$(echo "$txt" | awk '$1=="RMSE"{print $2}')
  m_ssim=$(echo "$txt" | awk '/^SSIM \(display\)/{print $3}')
  m_rel=$(echo "$txt" | awk '/^relative mean difference/{print $4}')
  m_px=$(echo "$txt" | awk '$1=="pixels"{print $2}')
}
# row PART METHOD PHOTONS PARAM VALUE SPP NAME [REFNAME (default ref)] [REGION (default whole)]
# appends one csv line (replacing an earlier one with the same scene,part,image,against,region)
row() {
  local part=$1 method=$2 n=$3 param=$4 value=$5 rspp=$6 name=$7 against=${8:-ref} region=${9:-whole}
  local opts=()
  [ "$region" = whole ] || opts=(--mask "$dir/mask-$region.pfm")
  metric "$dir/$name.exr" "$dir/$against.exr" "${opts[@]}"
  local key="$scene,$part,"
  awk -F, -v s="$scene" -v p="$part" -v i="$name" -v a="$against" -v r="$region" \
    '!($1==s && $2==p && $21==i && $20==a && $15==r)' "$csv" >"$csv.tmp" && mv "$csv.tmp" "$csv"
  echo "$key$method,$n,$param,$value,$rspp,$seed,$wall,$rsec,$psec,$csec,$medr,$mstep,$region,$m_px,$m_rmse,$m_ssim,$m_rel,$against,$name" >>"$csv"
  [ "$region" = whole ] && echo "    vs $against: RMSE $m_rmse, SSIM $m_ssim, rel. mean $m_rel" || true
}
# best PART METHOD rmse|ssim [PHOTONS]: "value rmse ssim" of the optimal row (whole image vs ref)
best() {
  awk -F, -v s="$scene" -v p="$1" -v m="$2" -v k="$3" -v n="${4:-}" '
    $1==s && $2==p && $3==m && $15=="whole" && $20=="ref" && (n=="" || $4==n) {
      v = (k=="rmse") ? -$17 : $18
      if (!seen || v > bv) { bv = v; b = $6 " " $17 " " $18; seen = 1 } }
    END { if (seen) print b }' "$csv"
}
lt() { awk -v a="$1" -v b="$2" 'BEGIN{exit !(a < b)}'; }
half() { awk -v v="$1" -v p="$2" 'BEGIN{ if (p=="k") printf "%d", v / 2; else printf "%g", v / 2 }'; }

# extra METHOD: the extra options of METHOD's renders (VPD_ARGS, BEAM_ARGS)
extra() { case "$1" in vpd) echo "${VPD_ARGS:-}" ;; beam) echo "${BEAM_ARGS:-}" ;; esac; }

# sweep METHOD FLAG PARAM "VALUES" (ascending): stage 1 at SPP; stops once PAST values in a row are
# worse than the best so far in both RMSE and SSIM (the larger bandwidths are the costly renders)
sweep() {
  local m=$1 flag=$2 p=$3 v br="" bs="" worse=0 improved name
  for v in $4; do
    name="$m-n$N-$p$v"
    # shellcheck disable=SC2046
    render "$name" --integrator "$m" --volume-photons "$N" "$flag" "$v" --spp "$spp" "${common[@]}" $(extra "$m")
    row sweep "$m" "$N" "$p" "$v" "$spp" "$name"
    improved=0
    if [ -z "$br" ] || lt "$m_rmse" "$br"; then br=$m_rmse; improved=1; fi
    if [ -z "$bs" ] || lt "$bs" "$m_ssim"; then bs=$m_ssim; improved=1; fi
    if [ "$improved" = 1 ]; then worse=0; else worse=$((worse + 1)); fi
    [ "$worse" -lt "$past" ] || { echo "  ($m: stopped after $p = $v)"; break; }
  done
}
# refine METHOD FLAG PARAM: stage 2 at FINAL_SPP: stage 1's RMSE- and SSIM-optimal values, then
# halving the RMSE-optimal one while that lowers the RMSE (more camera samples remove aliasing
# noise, so the optimum can only move to less smoothing; at most 3 halvings)
refine() {
  local m=$1 flag=$2 p=$3 vr vs v lo name prev i
  read -r vr _ <<<"$(best sweep "$m" rmse)"; read -r vs _ <<<"$(best sweep "$m" ssim)"
  for v in $vr $([ "$vs" = "$vr" ] || echo "$vs"); do
    name="$m-n$N-$p$v-spp$fspp"
    # shellcheck disable=SC2046
    render "$name" --integrator "$m" --volume-photons "$N" "$flag" "$v" --spp "$fspp" "${common[@]}" $(extra "$m")
    row final "$m" "$N" "$p" "$v" "$fspp" "$name"
    [ "$v" = "$vr" ] && prev=$m_rmse
  done
  v=$vr
  for i in 1 2 3; do
    lo=$(half "$v" "$p"); { [ "$p" = k ] && [ "$lo" -lt 2 ]; } && break
    name="$m-n$N-$p$lo-spp$fspp"
    # shellcheck disable=SC2046
    render "$name" --integrator "$m" --volume-photons "$N" "$flag" "$lo" --spp "$fspp" "${common[@]}" $(extra "$m")
    row final "$m" "$N" "$p" "$lo" "$fspp" "$name"
    lt "$m_rmse" "$prev" || break
    prev=$m_rmse; v=$lo
  done
}

for entry in $scenes; do
  IFS=: read -r scene N width rspp <<<"$entry"
  rspp="${rspp:-$ref_spp}"; cspp=$((rspp * check_spp / ref_spp))
  if ! grep -qx "$scene" "$out/scenes.txt"; then
    echo "== $scene: not a built-in scene of $bin; skipped"; continue
  fi
  t_scene=$(date +%s)
  dir="$out/$scene"; mkdir -p "$dir"
  size=(); [ -z "$width" ] || size=(--width "$width")
  common=(--volume-only --no-auto-bandwidth --seed "$seed" -q)
  echo "== $scene: $N volume photons, sweeps at $spp spp, optima at $fspp spp${width:+, width $width}"

  # ---- references ---------------------------------------------------------------------------
  render "ref" --integrator lighttrace --volume-only --spp "$rspp" --seed "$ref_seed" -q
  row ref lighttrace "" spp "$rspp" "$rspp" ref ref
  render "ref-check" --integrator lighttrace --volume-only --spp "$cspp" --seed "$((ref_seed + 1))" -q
  row ref-check lighttrace "" spp "$cspp" "$cspp" ref-check
  # region masks from the reference (and glass spheres of scenes/SCENE.toml, if any)
  "$bin" convert "$dir/ref.exr" "$dir/ref.pfm" >/dev/null
  crop_args=()
  for c in $crops; do [ "${c%%=*}" != "$scene" ] || crop_args+=(--crop "${c#*=}"); done
  "$PY" "$summ" masks "$dir/ref.pfm" "$dir" "${crop_args[@]}" \
    $([ -f "scenes/$scene.toml" ] && echo "--toml scenes/$scene.toml") | sed 's/^/  /'
  regions=$(cat "$dir/regions.txt")

  # ---- 1. stage 1: sweeps at N, SPP ---------------------------------------------------------
  sweep vpm --volume-k k "$vpm_ks"
  sweep beam --volume-k k "$beam_ks"
  sweep vpd --volume-smoothing s "$vpd_ss"
  # ---- 2. stage 2: the optima at FINAL_SPP ---------------------------------------------------
  refine vpm --volume-k k
  refine beam --volume-k k
  refine vpd --volume-smoothing s
  read -r kv_r rv_r _ <<<"$(best final vpm rmse)"; read -r kv_s _ sv_s <<<"$(best final vpm ssim)"
  read -r kb_r rb_r _ <<<"$(best final beam rmse)"; read -r kb_s _ sb_s <<<"$(best final beam ssim)"
  read -r sd_r rd_r _ <<<"$(best final vpd rmse)"; read -r sd_s _ sd_ssim <<<"$(best final vpd ssim)"
  echo "  optima at $fspp spp (RMSE; SSIM): vpm k=$kv_r $rv_r; k=$kv_s $sv_s | beam k=$kb_r $rb_r; k=$kb_s $sb_s | vpd s=$sd_r $rd_r; s=$sd_s $sd_ssim"

  # ---- secondary reference: vpm with REF_PHOTONS, k = REF_K, at SPP -------------------------
  vpmref="vpm-n$ref_photons-k$ref_k"
  render "$vpmref" --integrator vpm --volume-photons "$ref_photons" --volume-k "$ref_k" --spp "$spp" "${common[@]}"
  row vpmref vpm "$ref_photons" k "$ref_k" "$spp" "$vpmref"

  # ---- regions, error images, against the vpm reference, at the optima ----------------------
  optima=("vpm:vpm-n$N-k$kv_r-spp$fspp:k:$kv_r" "beam:beam-n$N-k$kb_r-spp$fspp:k:$kb_r" "vpd:vpd-n$N-s$sd_r-spp$fspp:s:$sd_r")
  [ "$kv_s" = "$kv_r" ] || optima+=("vpm:vpm-n$N-k$kv_s-spp$fspp:k:$kv_s")
  [ "$sd_s" = "$sd_r" ] || optima+=("vpd:vpd-n$N-s$sd_s-spp$fspp:s:$sd_s")
  escale=$(awk -v r="$rv_r" 'BEGIN{printf "%.6g", 3 * r}')   # one colour scale per scene: 3 x vpm's best RMSE
  for o in "${optima[@]}" "vpm:$vpmref:k:$ref_k"; do
    IFS=: read -r m name p v <<<"$o"
    render "$name"   # present: sets the times for the rows
    n=$(echo "$name" | sed -E 's/^[a-z]+-n([0-9]+)-.*/\1/')
    ospp=$(sed -nE 's/.*--spp ([0-9]+).*/\1/p' "$dir/$name.log" | head -1)
    for region in $regions; do row region "$m" "$n" "$p" "$v" "$ospp" "$name" ref "$region"; done
    [ "$name" = "$vpmref" ] || row vs-vpmref "$m" "$n" "$p" "$v" "$ospp" "$name" "$vpmref"
    "$bin" compare "$dir/$name.exr" "$dir/ref.exr" --error-image "$dir/err-$name.png" --error-scale "$escale" >/dev/null
  done
  "$bin" compare "$dir/ref-check.exr" "$dir/ref.exr" --error-image "$dir/err-ref-check.png" --error-scale "$escale" >/dev/null

  # ---- 3. photons vpm needs to reach vpd's best RMSE (at FINAL_SPP) --------------------------
  # at f N: k in {kc/2, kc} (kc = k_opt f^0.57: the AMISE-optimal k of a 3-D k-NN estimate grows
  # as N^(4/7)), then once more halved or doubled toward the better one; the scan stops at the
  # first count whose best RMSE <= vpd's, at MATCH_MAX, or when the scene has used SCENE_BUDGET s
  status=none; t_count=0
  if [ -f "$dir/match-status.txt" ] && [ -z "${RESCAN:-}" ]; then
    status=$(cat "$dir/match-status.txt")
    echo "  photon-count scan: kept from the earlier run ($status; RESCAN=1 scans again)"
  elif lt "$rd_r" "$rv_r"; then
    f=1; status=max
    while :; do
      # no new count once the scene's time plus 1.7x the last count's would pass SCENE_BUDGET
      if [ $(( $(date +%s) - t_scene + 17 * ${t_count:-0} / 10 )) -ge "$scene_budget" ]; then status=time; break; fi
      t_c0=$(date +%s)
      f=$((f * 2)); n=$((N * f)); [ "$n" -lt "$match_max" ] || n=$match_max
      kc=$(awk -v k="$kv_r" -v f="$(echo "$n / $N" | bc -l)" 'BEGIN{printf "%d", k * f^0.57 + 0.5}')
      k1=$(( (kc + 1) / 2 )); [ "$k1" -ge 2 ] || k1=2
      for k in "$k1" "$kc"; do
        render "vpm-n$n-k$k-spp$fspp" --integrator vpm --volume-photons "$n" --volume-k "$k" --spp "$fspp" "${common[@]}"
        row match vpm "$n" k "$k" "$fspp" "vpm-n$n-k$k-spp$fspp"
      done
      read -r kb _ <<<"$(best match vpm rmse "$n")"
      if [ "$kb" = "$k1" ]; then k=$(( (k1 + 1) / 2 )); else k=$((kc * 2)); fi
      if [ "$k" -ge 2 ] && [ "$k" != "$k1" ]; then
        render "vpm-n$n-k$k-spp$fspp" --integrator vpm --volume-photons "$n" --volume-k "$k" --spp "$fspp" "${common[@]}"
        row match vpm "$n" k "$k" "$fspp" "vpm-n$n-k$k-spp$fspp"
      fi
      t_count=$(( $(date +%s) - t_c0 ))
      read -r kb rb _ <<<"$(best match vpm rmse "$n")"
      echo "  vpm at $n photons: best RMSE $rb (k = $kb; vpd's best $rd_r)"
      if ! lt "$rd_r" "$rb"; then status=reached; break; fi
      [ "$n" -lt "$match_max" ] || break
    done
  else
    echo "  vpm's best RMSE ($rv_r) is already at or below vpd's ($rd_r): no photon-count scan"
  fi
  echo "$status" >"$dir/match-status.txt"
  echo "  ($scene: $(( $(date +%s) - t_scene )) s; $(( $(date +%s) - t_start )) s since start)"
done

# ---- summary: tables, plots, HTML page -----------------------------------------------------
cmdline="bash bench/volume_differentials.sh${1:+ $1}"
for v in SPP FINAL_SPP REF_SPP CHECK_SPP SEED REF_SEED VPM_KS BEAM_KS VPD_SS PAST MATCH_MAX REF_PHOTONS REF_K SCENE_BUDGET CROPS SCENES VPD_ARGS BEAM_ARGS DOCS; do
  [ -z "${!v:-}" ] || cmdline="$v=\"${!v}\" $cmdline"
done
cmdline="CAUSTICA_BIN=$bin $cmdline"
"$PY" "$summ" summarize "$out" "$docs" --command "$cmdline" --spp "$spp" --ref-spp "$ref_spp" --check-spp "$check_spp" \
  --ref-photons "$ref_photons" --final-spp "$fspp" --ref-k "$ref_k" --scenes "$scenes" --bin "$bin"
echo "total wall time $(( $(date +%s) - t_start )) s; results: $csv, $docs/"
