#!/usr/bin/env bash
# Issue 21 / spec notes T-16: the glint of a point light in a glass plate (L S E, a delta that no
# other method renders) has a closed form: the front face mirrors the light, and the irradiance
# the glint puts on the pinhole is I F / |L' - eye|^2 = 0.03593 W/m^2 on painting-sheet; the back
# face adds (1 - F)^2 F I through the slab, 0.2 % dimmer (docs/scenes.md): 0.0717 W/m^2 in all.
# pcf with nesting (default) renders the glints as a blurred spot; without (--nested off) not.
# With the same seed both renders share every light path and camera sample, so their difference
# is the glints' radiance alone; the image's sum of that difference times each pixel's solid
# angle must tend to the closed form as the kernel shrinks.
#   bash bench/pcf_glint.sh [iterations (default 256)]    DOCS=docs/results/pcf-glint
set -euo pipefail
cd "$(dirname "$0")/.."
n="${1:-256}"
res=128
[[ -n ${NO_BUILD:-} ]] || cargo build --release -q -p caustica-cli
bin=./target/release/caustica
work=target/bench/pcf-glint
out="${DOCS:-$work/results}"
mkdir -p "$work" "$out"
saves=$(awk -v n="$n" 'BEGIN { for (i = 1; i <= n; i *= 2) printf "%s%d", (i > 1 ? "," : ""), i }')
log="$out/commands.log"
: > "$log"
for mode in delta-lights off; do
  cmd=(render painting-sheet --integrator pcf --nested "$mode" --iterations "$n" --photons-per-iteration 50000
    --spp 1 --seed 1 --width $res --height $res --save-iterations "$saves" -o "$work/$mode.exr")
  echo "caustica ${cmd[*]}" >> "$log"
  "$bin" "${cmd[@]}" 2> "$work/$mode.notes" > /dev/null
  for i in ${saves//,/ }; do "$bin" convert "$work/$mode-it$i.exr" "$work/$mode-it$i.pfm" > /dev/null; done
done
/root/.cache/caustica/peers-venv/bin/python - "$work" "$out" "$saves" $res <<'PY'
import sys, math, numpy as np
work, out, saves, res = sys.argv[1], sys.argv[2], [int(s) for s in sys.argv[3].split(",")], int(sys.argv[4])
def read(p):
    with open(p, "rb") as f:
        f.readline(); w, h = map(int, f.readline().split()); sc = float(f.readline())
        d = np.fromfile(f, dtype="<f4" if sc < 0 else ">f4")
    return d.reshape(h, w, 3)[::-1]
# Pixel solid angles of the pinhole (fov 40 deg across, square film at distance 1).
half = math.tan(math.radians(20.0))
s = 2 * half / res
c = (np.arange(res) + 0.5) * s - half
u, v = np.meshgrid(c, c)
omega = s * s / (1 + u * u + v * v) ** 1.5
want = 0.03593 + 0.03593 * 0.998  # front + back face (docs/scenes.md)
rows = ["| iteration | sum of (nested - off) x pixel solid angle (W/m^2), luminance | / closed form | spot radius (pixels, 90 % of the energy) |", "|---:|---:|---:|---:|"]
csv = ["iteration,irradiance,ratio,radius90"]
for i in saves:
    a = read(f"{work}/delta-lights-it{i}.pfm"); b = read(f"{work}/off-it{i}.pfm")
    d = (a - b) @ np.array([0.2126, 0.7152, 0.0722])
    e = float((d * omega).sum())
    # Radius around the peak holding 90 % of the summed energy.
    y0, x0 = np.unravel_index(np.argmax(d), d.shape)
    yy, xx = np.mgrid[0:res, 0:res]
    r = np.hypot(yy - y0, xx - x0).ravel(); w = (d * omega).ravel()
    o = np.argsort(r); cum = np.cumsum(w[o]); r90 = float(r[o][np.searchsorted(cum, 0.9 * cum[-1])])
    rows.append(f"| {i} | {e:.5f} | {e / want:.3f} | {r90:.1f} |")
    csv.append(f"{i},{e:.6f},{e / want:.4f},{r90:.1f}")
md = ["# The glint of a point light in glass (spec notes T-16)", "",
      "`bash bench/pcf_glint.sh` (commands in commands.log): painting-sheet, pcf with nesting (`delta-lights`) minus pcf without (`off`), same seed;",
      f"closed form {want:.5f} W/m² (front face 0.03593, back face 0.2 % dimmer; docs/scenes.md).", ""] + rows
open(f"{out}/README.md", "w").write("\n".join(md) + "\n")
open(f"{out}/glint.csv", "w").write("\n".join(csv) + "\n")
print("\n".join(md))
PY
