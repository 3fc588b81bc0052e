#!/usr/bin/env bash
# Volume photon estimates on the built-in `volume-caustic` (a spot light through a glass sphere in
# thin fog, 128x96): ray marching (`--integrator vpm`, seed 000 eq. 8.3) against the beam
# radiance estimate (`--integrator beam`, eq. 8.4). Surfaces are pm's in both (caustic map, global
# map shown directly: --final-gather 0, --no-auto-bandwidth), so with the same --seed both trace the
# same surface and volume photons and the same camera rays; only the volume estimate differs.
#   a. Reduction (seed notes TM4): one photon map, fixed radius R, uniform kernel; vpm with march
#      steps 4R, R, R/4, R/16 compared with the beam image (caustica compare VPM BEAM): the RMSE
#      falls to 0 as the step shrinks.
#   b. Convergence to the light tracer (unbiased reference, REF_SPP light paths per pixel): vpm
#      (default step = half the median photon radius, k = 32) and beam (k = 32, epanechnikov) at
#      25k, 100k, 400k volume photons, RMSE over the whole image and over CROP (the cone of
#      focused light below the sphere, above the floor), and the times.
#   c. Equal error: extra vpm runs with finer steps (default step / 2, / 4) at each photon count,
#      then the time each estimate needs to reach a given crop RMSE (log-log interpolation of the
#      RMSE-time curves, the lower envelope over all runs of a method) and the ratio beam / vpm.
# Every render is a separate process; "wall" is the whole process (date before and after),
# "render" the summary line's time, "photons" the photon line's, "camera" = render - photons.
# Usage:
#   bash bench/volume_estimates.sh [out dir (default ~/.cache/caustica/volume-estimates)]
# Environment: CAUSTICA_BIN (default ./target/fast/caustica), REF_SPP (1024), SPP (camera samples
# of vpm/beam in b and c, 4), TM4_SPP (1), TM4_PHOTONS (100000), TM4_RADIUS (0.1 m),
# COUNTS ("25000 100000 400000"), CROP (x,y,w,h; "50,52,28,20"), SEED (photons and camera, 1),
# REF_SEED (7), PARTS ("a b c"). Results: OUT/results.csv, OUT/tables.md, OUT/*.exr, OUT/*.log;
# existing renders are reused (delete OUT to start over).
set -euo pipefail
cd "$(dirname "$0")/.."
out="${1:-$HOME/.cache/caustica/volume-estimates}"
bin="${CAUSTICA_BIN:-./target/fast/caustica}"
[ -x "$bin" ] || { echo "no caustica binary at $bin (set CAUSTICA_BIN)"; exit 2; }
bin="$(cd "$(dirname "$bin")" && pwd)/$(basename "$bin")"
mkdir -p "$out"
scene=volume-caustic
ref_spp="${REF_SPP:-1024}"
spp="${SPP:-4}"
tm4_spp="${TM4_SPP:-1}"
tm4_n="${TM4_PHOTONS:-100000}"
R="${TM4_RADIUS:-0.1}"
counts="${COUNTS:-25000 100000 400000}"
crop="${CROP:-50,52,28,20}"
seed="${SEED:-1}"
ref_seed="${REF_SEED:-7}"
parts="${PARTS:-a b c}"
csv="$out/results.csv"
[ -f "$csv" ] || echo "part,method,photons,step,radius,spp,wall_s,render_s,photons_s,camera_s,median_radius,rmse_whole,relmean_whole,rmse_crop,relmean_crop,against" >"$csv"
common=(--final-gather 0 --no-auto-bandwidth --seed "$seed" -q)

# render NAME ARGS...: render $out/NAME.exr (and .png) unless present; sets wall, rsec, psec,
# medr (median photon radius), mstep (march step).
render() {
  local name="$1"; shift
  local exr="$out/$name.exr" log="$out/$name.log"
  if [ ! -f "$exr" ] || [ ! -f "$log" ]; then
    local t0 t1
    t0=$(date +%s.%N)
    "$bin" render "$scene" "$@" -o "$exr" --png "$out/$name.png" >"$log.tmp" 2>&1 \
      || { cat "$log.tmp"; echo "render $name failed"; exit 1; }
    t1=$(date +%s.%N)
    { echo "command: caustica render $scene $*"; cat "$log.tmp"
      echo "wall $(echo "$t1 - $t0" | bc -l)"; } >"$log"
    rm -f "$log.tmp"
  fi
  wall=$(sed -nE 's/^wall ([0-9.]+)/\1/p' "$log" | tail -1); wall=$(printf %.3f "$wall")
  rsec=$(sed -nE 's/.* in ([0-9.]+) s: .*/\1/p' "$log" | tail -1)
  psec=$(sed -nE 's/^photons: .* in ([0-9.]+) s \(.*/\1/p' "$log" | tail -1); psec="${psec:-0}"
  medr=$(sed -nE 's/.*median radius ([0-9.]+) m.*/\1/p' "$log" | tail -1); medr="${medr:-}"
  mstep=$(sed -nE 's/.*step ([0-9.]+) m\).*/\1/p' "$log" | tail -1); mstep="${mstep:-}"
  echo "  $name: wall ${wall} s, render ${rsec} s, photons ${psec} s${medr:+, median radius $medr m}${mstep:+, step $mstep m}"
}
# metric IMG REF [crop]: prints "rmse relmean"
metric() {
  local txt
  txt=$("$bin" compare "$1" "$2" ${3:+--crop "$3"})
  echo "$(echo "$txt" | awk '$1=="RMSE"{print $2}') $(echo "$txt" | awk '/^relative mean difference/{print $4}')"
}
# row PART METHOD PHOTONS STEP RADIUS SPP IMG REF
row() {
  local w c cam
  read -r w wm <<<"$(metric "$7" "$8")"
  read -r c cm <<<"$(metric "$7" "$8" "$crop")"
  cam=$(printf %.3f "$(echo "$rsec - $psec" | bc -l)")
  echo "$1,$2,$3,$4,$5,$6,$wall,$rsec,$psec,$cam,$medr,$w,$wm,$c,$cm,$(basename "$8" .exr)" >>"$csv"
  echo "    vs $(basename "$8" .exr): RMSE whole $w (rel. mean $wm), crop $c (rel. mean $cm)"
}

# tm4_step DIV: R / DIV as written in file names (no trailing zeros)
tm4_step() { echo "$R / $1" | bc -l | sed -E 's/0+$//; s/\.$//; s/^\./0./'; }

# ---- a. TM4: the march tends to the beam estimate -------------------------------------------
if [[ " $parts " == *" a "* ]]; then
  echo "== a. TM4: $tm4_n volume photons, fixed radius $R m, uniform kernel, $tm4_spp spp"
  fixed=(--spp "$tm4_spp" --volume-photons "$tm4_n" --volume-radius "$R" "${common[@]}")
  render "tm4-beam" --integrator beam --beam-kernel uniform "${fixed[@]}"
  beam="$out/tm4-beam.exr"
  sed -i '/^a,/d' "$csv"
  echo "a,beam,$tm4_n,,$R,$tm4_spp,$wall,$rsec,$psec,$(printf %.3f "$(echo "$rsec - $psec" | bc -l)"),$medr,0,0,0,0,tm4-beam" >>"$csv"
  for div in 0.25 1 4 16; do
    step=$(tm4_step "$div")
    render "tm4-vpm-step$step" --integrator vpm --march-step "$step" "${fixed[@]}"
    row a vpm "$tm4_n" "$step" "$R" "$tm4_spp" "$out/tm4-vpm-step$step.exr" "$beam"
  done
fi

# ---- b. convergence to the light tracer -----------------------------------------------------
ref="$out/ref-lighttrace-$ref_spp.exr"
if [[ " $parts " == *" b "* || " $parts " == *" c "* ]]; then
  echo "== reference: light tracer, $ref_spp light paths per pixel, seed $ref_seed"
  render "ref-lighttrace-$ref_spp" --integrator lighttrace --spp "$ref_spp" --seed "$ref_seed" -q
  ref_wall=$wall
  # A second, independent light-tracer render at a quarter of the paths: its RMSE against the
  # reference shows the reference's own noise (about half of it: 4x the paths).
  render "ref-lighttrace-$((ref_spp / 4))-check" --integrator lighttrace --spp "$((ref_spp / 4))" \
    --seed "$((ref_seed + 1))" -q
  sed -i '/^ref,/d' "$csv"
  medr=""; row ref lighttrace "" "" "" "$((ref_spp / 4))" "$out/ref-lighttrace-$((ref_spp / 4))-check.exr" "$ref"
  echo "    (reference render: wall $ref_wall s)"
fi
if [[ " $parts " == *" b "* ]]; then
  echo "== b. vpm and beam (defaults) against the light tracer, $spp spp, crop $crop"
  sed -i '/^b,/d' "$csv"
  for n in $counts; do
    render "beam-n$n" --integrator beam --spp "$spp" --volume-photons "$n" "${common[@]}"
    row b beam "$n" "" "$medr" "$spp" "$out/beam-n$n.exr" "$ref"
    render "vpm-n$n" --integrator vpm --spp "$spp" --volume-photons "$n" "${common[@]}"
    row b vpm "$n" "$mstep" "$medr" "$spp" "$out/vpm-n$n.exr" "$ref"
  done
fi

# ---- c. equal error: finer vpm steps -----------------------------------------------------
if [[ " $parts " == *" c "* ]]; then
  echo "== c. vpm with finer steps (default / 2, / 4)"
  sed -i '/^c,/d' "$csv"
  for n in $counts; do
    # the default step is half the median radius, printed by b's render
    base=$(sed -nE 's/.*step ([0-9.]+) m\).*/\1/p' "$out/vpm-n$n.log" | tail -1)
    for div in 2 4; do
      step=$(printf %.5f "$(echo "$base / $div" | bc -l)")
      render "vpm-n$n-step$step" --integrator vpm --spp "$spp" --volume-photons "$n" --march-step "$step" "${common[@]}"
      row c vpm "$n" "$step" "$medr" "$spp" "$out/vpm-n$n-step$step.exr" "$ref"
    done
  done
fi

# ---- tables ------------------------------------------------------------------------------
python3 - "$csv" "$out/tables.md" <<'EOF'
import csv, math, sys
rows = list(csv.DictReader(open(sys.argv[1])))
o = []
def f(x, d=4):
    return "" if x in ("", None) else f"{float(x):.{d}g}"
a = [r for r in rows if r["part"] == "a"]
if a:
    o += ["### a. TM4: vpm against beam, same photons, fixed radius, uniform kernel", "",
          "| estimate | step (m) | step / R | RMSE vs beam (whole) | rel. mean diff. | RMSE vs beam (crop) | wall (s) | camera pass (s) |",
          "|---|---|---|---|---|---|---|---|"]
    for r in a:
        ratio = f"{float(r['step'])/float(r['radius']):.4g}" if r["step"] else ""
        o.append(f"| {r['method']} | {r['step']} | {ratio} | {f(r['rmse_whole'])} | {r['relmean_whole']} | {f(r['rmse_crop'])} | {r['wall_s']} | {r['camera_s']} |")
    o.append("")
ref = [r for r in rows if r["part"] == "ref"]
if ref:
    r = ref[0]
    o += [f"Reference noise: an independent light-tracer render with {r['spp']} paths/pixel against the reference: "
          f"RMSE whole {f(r['rmse_whole'])}, crop {f(r['rmse_crop'])} (wall {r['wall_s']} s).", ""]
bc = [r for r in rows if r["part"] in ("b", "c")]
if bc:
    o += ["### b/c. vpm and beam against the light tracer", "",
          "| part | estimate | volume photons | median radius (m) | step (m) | RMSE whole | rel. mean whole | RMSE crop | rel. mean crop | wall (s) | photons (s) | camera pass (s) |",
          "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in sorted(bc, key=lambda r: (int(r["photons"]), r["method"], r["part"], -float(r["step"] or 0))):
        o.append(f"| {r['part']} | {r['method']} | {r['photons']} | {r['radius']} | {r['step'] or '—'} | {f(r['rmse_whole'])} | {r['relmean_whole']} | {f(r['rmse_crop'])} | {r['relmean_crop']} | {r['wall_s']} | {r['photons_s']} | {r['camera_s']} |")
    o.append("")
    # equal error: lower envelope of (time, crop RMSE) per method, log-log interpolation
    def curve(method, tkey):
        pts = sorted((float(r[tkey]), float(r["rmse_crop"])) for r in bc if r["method"] == method)
        env, best = [], math.inf
        for t, e in pts:           # Pareto front: keep a run only if it beats every faster one
            if e < best:
                env.append((t, e)); best = e
        return env
    def time_for(env, e):
        for (t0, e0), (t1, e1) in zip(env, env[1:]):
            if e1 <= e <= e0:
                if e0 == e1: return t0
                s = (math.log(e) - math.log(e0)) / (math.log(e1) - math.log(e0))
                return math.exp(math.log(t0) + s * (math.log(t1) - math.log(t0)))
        if env and abs(env[0][1] - e) < 1e-12: return env[0][0]
        return None
    for tkey, label in (("wall_s", "wall time of the whole process"), ("camera_s", "camera pass (render - photon tracing)")):
        bv, vv = curve("beam", tkey), curve("vpm", tkey)
        o += [f"### c. Equal crop RMSE, {label}", "",
              "Pareto fronts (time s, crop RMSE): beam " + ", ".join(f"({t:.3g}, {e:.4g})" for t, e in bv)
              + "; vpm " + ", ".join(f"({t:.3g}, {e:.4g})" for t, e in vv), "",
              "| target crop RMSE | beam time (s) | vpm time (s) | beam / vpm |", "|---|---|---|---|"]
        targets = sorted({e for _, e in bv} | {e for _, e in vv}, reverse=True)
        for e in targets:
            tb, tv = time_for(bv, e), time_for(vv, e)
            ratio = f"{tb/tv:.3g}" if tb and tv else "—"
            o.append(f"| {e:.4g} | {f'{tb:.3g}' if tb else 'not reached'} | {f'{tv:.3g}' if tv else 'not reached'} | {ratio} |")
        o.append("")
open(sys.argv[2], "w").write("\n".join(o) + "\n")
print("\n".join(o))
EOF
# ---- side-by-side PNGs (python3 stdlib: a minimal 8-bit RGB PNG reader and writer) ---------
montage() {  # montage OUT.png IN.png...
  python3 - "$@" <<'PY'
import struct, sys, zlib
def read(path):
    data = open(path, "rb").read(); pos = 8; idat = b""
    while pos < len(data):
        n, = struct.unpack(">I", data[pos:pos + 4]); t = data[pos + 4:pos + 8]; c = data[pos + 8:pos + 8 + n]
        pos += 12 + n
        if t == b"IHDR":
            w, h, bd, ct, _, _, il = struct.unpack(">IIBBBBB", c); assert bd == 8 and il == 0; ch = {2: 3, 6: 4}[ct]
        elif t == b"IDAT":
            idat += c
    raw = zlib.decompress(idat); st = w * ch; prev = bytearray(st); rows = []; i = 0
    for _ in range(h):
        f = raw[i]; ln = bytearray(raw[i + 1:i + 1 + st]); i += 1 + st
        for x in range(st):
            a = ln[x - ch] if x >= ch else 0; b = prev[x]; c = prev[x - ch] if x >= ch else 0
            if f == 1: ln[x] = (ln[x] + a) & 255
            elif f == 2: ln[x] = (ln[x] + b) & 255
            elif f == 3: ln[x] = (ln[x] + (a + b) // 2) & 255
            elif f == 4:
                q = a + b - c; pa, pb, pc = abs(q - a), abs(q - b), abs(q - c)
                ln[x] = (ln[x] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(b"".join(bytes(ln[x * ch:x * ch + 3]) for x in range(w))); prev = ln
    return w, h, rows
ims = [read(p) for p in sys.argv[2:]]
h = ims[0][1]; gap = b"\xff\xff\xff" * 2
rows = [gap.join(im[2][y] for im in ims) for y in range(h)]
w = len(rows[0]) // 3
chunk = lambda t, c: struct.pack(">I", len(c)) + t + c + struct.pack(">I", zlib.crc32(t + c) & 0xffffffff)
open(sys.argv[1], "wb").write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
    + chunk(b"IDAT", zlib.compress(b"".join(b"\x00" + r for r in rows), 9)) + chunk(b"IEND", b""))
PY
}
pngs() { local f; for f in "$@"; do if [ -f "$out/$f.png" ]; then echo "$out/$f.png"; fi; done; }
mapfile -t a_png < <(pngs "tm4-vpm-step$(tm4_step 0.25)" "tm4-vpm-step$(tm4_step 1)" \
  "tm4-vpm-step$(tm4_step 4)" tm4-beam)
if [ "${#a_png[@]}" -gt 1 ]; then montage "$out/montage-tm4.png" "${a_png[@]}"; fi
first=${counts%% *}; last=${counts##* }
mapfile -t b_png < <(pngs "ref-lighttrace-$ref_spp" "vpm-n$first" "beam-n$first" "vpm-n$last" "beam-n$last")
if [ "${#b_png[@]}" -gt 1 ]; then montage "$out/montage-convergence.png" "${b_png[@]}"; fi
echo "results: $csv, $out/tables.md, $out/montage-*.png"
