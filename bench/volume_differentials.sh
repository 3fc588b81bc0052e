#!/usr/bin/env bash
# Volume photon differentials (seed 000 sec. 8.5, spec §2.6 / §3.4 XM1-XM3), measured: for each
# scene, at the seed's volume photon count N, ray-marched volume photon mapping (`vpm`, eq. 8.3,
# k-NN per step), the beam estimate with k-NN pilot radii (`beam`, the ablation "kernel shape vs
# integration scheme") and volume photon differentials (`vpd`, ellipsoidal kernels from each
# photon's differentials) against an unbiased reference, the volumetric light tracer.
#   1. sweeps: vpm's --volume-k, beam's --volume-k, vpd's --volume-smoothing at N (RMSE, SSIM,
#      relative mean difference, times);
#   2. the RMSE- and SSIM-optimal setting of each method;
#   3. how many photons vpm needs to reach vpd's best RMSE: vpm at 2N, 4N, 8N, ... (a small k
#      sweep around k_opt * f^0.57 at each count f N), until it gets there or reaches MATCH_MAX;
#   4. where the estimates lose: relative mean difference over regions (the medium's silhouette
#      edge, its inside, the halo just outside, and inside / outside glass spheres seen directly),
#      error images at the optima;
#   plus vpm with REF_PHOTONS (3 M, the seed's reference) against the light tracer, and a check
#   that camera spp is not what limits the photon methods (the optima again at SPP_CHECK x spp).
# All photon-method renders: --volume-only --no-auto-bandwidth --seed SEED -q --spp SPP.
# --volume-only keeps only light scattered by media straight to the camera along the camera ray's
# first segment; `lighttrace --volume-only` renders the same paths without bias (seed notes Q-M11).
# Every render is its own process: "wall" is measured around it with date, "photons" is the
# photon line's time, "camera" = the summary line's time - photons.
# Usage:
#   bash bench/volume_differentials.sh [out dir (default ~/.cache/caustica/volume-differentials)]
# Environment (defaults in brackets):
#   CAUSTICA_BIN [./target/fast/caustica]
#   SCENES ["facet-smoke:80000 laser-smoke:80000 glass-smoke:10000"]: NAME:N[:WIDTH] (WIDTH
#     renders at --width WIDTH, for large stand-in scenes); scenes the binary lacks are skipped
#   SPP [4], REF_SPP [2048] (light paths per pixel), CHECK_SPP [REF_SPP/4] (the second light
#     tracer render, seed REF_SEED+1: its RMSE against the reference is the noise floor),
#   SEED [1], REF_SEED [7], VPM_KS ["8 16 32 64 128 256"], BEAM_KS [VPM_KS],
#   VPD_SS ["1 2 4 8 16 32"], MATCH_MAX [3000000], REF_PHOTONS [3000000], SPP_CHECK [4] (0: off),
#   DOCS [docs/results/volume-differentials], PY (python with numpy + matplotlib; default
#   tools/peers/.venv/bin/python, else the venv of tools/peers/venv.sh, matplotlib added to it).
# Results: OUT/results.csv (one row per render and region), OUT/SCENE/*.exr|png|log, then
# tools/summarize_volume_differentials.py writes DOCS/{README tables, results.csv, plots, index.html}.
# Existing renders are reused (delete OUT/SCENE to start a scene over).
set -euo pipefail
cd "$(dirname "$0")/.."
t_start=$(date +%s)
out="${1:-$HOME/.cache/caustica/volume-differentials}"
bin="${CAUSTICA_BIN:-./target/fast/caustica}"
[ -x "$bin" ] || { echo "no caustica binary at $bin (set CAUSTICA_BIN)"; exit 2; }
bin="$(cd "$(dirname "$bin")" && pwd)/$(basename "$bin")"
scenes="${SCENES:-facet-smoke:80000 laser-smoke:80000 glass-smoke:10000}"
spp="${SPP:-4}"
ref_spp="${REF_SPP:-2048}"
check_spp="${CHECK_SPP:-$((ref_spp / 4))}"
seed="${SEED:-1}"
ref_seed="${REF_SEED:-7}"
vpm_ks="${VPM_KS:-8 16 32 64 128 256}"
beam_ks="${BEAM_KS:-$vpm_ks}"
vpd_ss="${VPD_SS:-1 2 4 8 16 32}"
match_max="${MATCH_MAX:-3000000}"
ref_photons="${REF_PHOTONS:-3000000}"
spp_check="${SPP_CHECK:-4}"
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
  if [ ! -f "$exr" ] || [ ! -f "$log" ]; then
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

for entry in $scenes; do
  IFS=: read -r scene N width <<<"$entry"
  if ! grep -qx "$scene" "$out/scenes.txt"; then
    echo "== $scene: not a built-in scene of $bin; skipped"; continue
  fi
  dir="$out/$scene"; mkdir -p "$dir"
  size=(); [ -z "$width" ] || size=(--width "$width")
  common=(--volume-only --no-auto-bandwidth --seed "$seed" -q)
  echo "== $scene: $N volume photons, $spp spp${width:+, width $width}"

  # ---- references ---------------------------------------------------------------------------
  render "ref" --integrator lighttrace --volume-only --spp "$ref_spp" --seed "$ref_seed" -q
  row ref lighttrace "" spp "$ref_spp" "$ref_spp" ref ref
  render "ref-check" --integrator lighttrace --volume-only --spp "$check_spp" --seed "$((ref_seed + 1))" -q
  row ref-check lighttrace "" spp "$check_spp" "$check_spp" ref-check
  # region masks from the reference (and glass spheres of scenes/SCENE.toml, if any)
  "$bin" convert "$dir/ref.exr" "$dir/ref.pfm"
  "$PY" "$summ" masks "$dir/ref.pfm" "$dir" ${width:+--width "$width"} \
    $([ -f "scenes/$scene.toml" ] && echo "--toml scenes/$scene.toml") | sed 's/^/  /'
  regions=$(cat "$dir/regions.txt")

  # ---- 1. sweeps at N -----------------------------------------------------------------------
  for k in $vpm_ks; do
    render "vpm-n$N-k$k" --integrator vpm --volume-photons "$N" --volume-k "$k" --spp "$spp" "${common[@]}"
    row sweep vpm "$N" k "$k" "$spp" "vpm-n$N-k$k"
  done
  for k in $beam_ks; do
    render "beam-n$N-k$k" --integrator beam --volume-photons "$N" --volume-k "$k" --spp "$spp" "${common[@]}"
    row sweep beam "$N" k "$k" "$spp" "beam-n$N-k$k"
  done
  for s in $vpd_ss; do
    render "vpd-n$N-s$s" --integrator vpd --volume-photons "$N" --volume-smoothing "$s" --spp "$spp" "${common[@]}"
    row sweep vpd "$N" s "$s" "$spp" "vpd-n$N-s$s"
  done
  read -r kv_r rv_r _ <<<"$(best sweep vpm rmse)"; read -r kv_s _ sv_s <<<"$(best sweep vpm ssim)"
  read -r kb_r rb_r _ <<<"$(best sweep beam rmse)"; read -r kb_s _ sb_s <<<"$(best sweep beam ssim)"
  read -r sd_r rd_r _ <<<"$(best sweep vpd rmse)"; read -r sd_s _ sd_ssim <<<"$(best sweep vpd ssim)"
  echo "  optima (RMSE; SSIM): vpm k=$kv_r $rv_r; k=$kv_s $sv_s | beam k=$kb_r $rb_r; k=$kb_s $sb_s | vpd s=$sd_r $rd_r; s=$sd_s $sd_ssim"

  # ---- secondary reference: vpm with REF_PHOTONS (k scaled like the match scan's centre) ------
  kref=$(awk -v k="$kv_r" -v f="$(echo "$ref_photons / $N" | bc -l)" 'BEGIN{printf "%d", k * f^0.57 + 0.5}')
  render "vpm-n$ref_photons-k$kref" --integrator vpm --volume-photons "$ref_photons" --volume-k "$kref" --spp "$spp" "${common[@]}"
  row vpmref vpm "$ref_photons" k "$kref" "$spp" "vpm-n$ref_photons-k$kref"
  vpmref="vpm-n$ref_photons-k$kref"

  # ---- 2. optima: regions, error images, against the vpm reference --------------------------
  optima=("vpm:vpm-n$N-k$kv_r:k:$kv_r" "beam:beam-n$N-k$kb_r:k:$kb_r" "vpd:vpd-n$N-s$sd_r:s:$sd_r")
  [ "$kv_s" = "$kv_r" ] || optima+=("vpm:vpm-n$N-k$kv_s:k:$kv_s")
  [ "$kb_s" = "$kb_r" ] || optima+=("beam:beam-n$N-k$kb_s:k:$kb_s")
  [ "$sd_s" = "$sd_r" ] || optima+=("vpd:vpd-n$N-s$sd_s:s:$sd_s")
  escale=$(awk -v r="$rv_r" 'BEGIN{printf "%.6g", 3 * r}')   # one colour scale per scene: 3 x vpm's best RMSE
  for o in "${optima[@]}" "vpm:$vpmref:k:$kref"; do
    IFS=: read -r m name p v <<<"$o"
    render "$name"   # reuse: sets the times for the row
    n=$(echo "$name" | sed -E 's/^[a-z]+-n([0-9]+)-.*/\1/')
    for region in $regions; do row region "$m" "$n" "$p" "$v" "$spp" "$name" ref "$region"; done
    [ "$name" = "$vpmref" ] || row vs-vpmref "$m" "$n" "$p" "$v" "$spp" "$name" "$vpmref"
    "$bin" compare "$dir/$name.exr" "$dir/ref.exr" --error-image "$dir/err-$name.png" --error-scale "$escale" >/dev/null
  done
  "$bin" compare "$dir/ref-check.exr" "$dir/ref.exr" --error-image "$dir/err-ref-check.png" --error-scale "$escale" >/dev/null

  # ---- camera spp check: the RMSE optima at SPP_CHECK x spp ---------------------------------
  if [ "$spp_check" -gt 1 ]; then
    hs=$((spp * spp_check))
    render "vpm-n$N-k$kv_r-spp$hs" --integrator vpm --volume-photons "$N" --volume-k "$kv_r" --spp "$hs" "${common[@]}"
    row sppcheck vpm "$N" k "$kv_r" "$hs" "vpm-n$N-k$kv_r-spp$hs"
    render "beam-n$N-k$kb_r-spp$hs" --integrator beam --volume-photons "$N" --volume-k "$kb_r" --spp "$hs" "${common[@]}"
    row sppcheck beam "$N" k "$kb_r" "$hs" "beam-n$N-k$kb_r-spp$hs"
    render "vpd-n$N-s$sd_r-spp$hs" --integrator vpd --volume-photons "$N" --volume-smoothing "$sd_r" --spp "$hs" "${common[@]}"
    row sppcheck vpd "$N" s "$sd_r" "$hs" "vpd-n$N-s$sd_r-spp$hs"
  fi

  # ---- 3. photons vpm needs to reach vpd's best RMSE ----------------------------------------
  # at f N: k in {kc/2, kc, 2 kc}, kc = k_opt f^0.57 (the AMISE-optimal k of a 3-D k-NN estimate
  # grows as N^(4/7)); the scan stops at the first count whose best RMSE <= vpd's, or at MATCH_MAX
  if lt "$rd_r" "$rv_r"; then
    f=1
    while :; do
      f=$((f * 2)); n=$((N * f))
      if [ "$n" -ge "$match_max" ]; then n=$match_max; fi
      fr=$(echo "$n / $N" | bc -l)
      kc=$(awk -v k="$kv_r" -v f="$fr" 'BEGIN{printf "%d", k * f^0.57 + 0.5}')
      for k in $(( (kc + 1) / 2 )) "$kc" $((kc * 2)); do
        render "vpm-n$n-k$k" --integrator vpm --volume-photons "$n" --volume-k "$k" --spp "$spp" "${common[@]}"
        row match vpm "$n" k "$k" "$spp" "vpm-n$n-k$k"
      done
      read -r _ rb _ <<<"$(best match vpm rmse "$n")"
      echo "  vpm at $n photons: best RMSE $rb (vpd's best $rd_r)"
      if ! lt "$rd_r" "$rb" || [ "$n" -ge "$match_max" ]; then break; fi
    done
  else
    echo "  vpm's best RMSE ($rv_r) is already at or below vpd's ($rd_r): no photon-count scan"
  fi
  echo "  ($scene done, $(( $(date +%s) - t_start )) s since start)"
done

# ---- summary: tables, plots, HTML page -----------------------------------------------------
cmdline="bash bench/volume_differentials.sh${1:+ $1}"
for v in SPP REF_SPP CHECK_SPP SEED REF_SEED VPM_KS BEAM_KS VPD_SS MATCH_MAX REF_PHOTONS SPP_CHECK SCENES; do
  [ -z "${!v:-}" ] || cmdline="$v=\"${!v}\" $cmdline"
done
cmdline="CAUSTICA_BIN=$bin $cmdline"
"$PY" "$summ" summarize "$out" "$docs" --command "$cmdline" --spp "$spp" --ref-spp "$ref_spp" --check-spp "$check_spp" \
  --ref-photons "$ref_photons" --scenes "$scenes" --bin "$bin"
echo "total wall time $(( $(date +%s) - t_start )) s; results: $csv, $docs/"
