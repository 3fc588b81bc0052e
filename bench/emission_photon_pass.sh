#!/usr/bin/env bash
# Issue 23, performance: the caustic photon pass with uniform emission, projection maps and the
# adaptive sampler — 10^6 caustic photons on the glass sphere (pm's caustic map; pds's counting
# pass), alternating the rules in each of REPEAT rounds on this shared machine; the projection
# map's build time; the adaptive sampler's cost per chain step. Results:
# docs/results/emission-photon-pass/README.md.
#   bash bench/emission_photon_pass.sh [photons (default 1000000)] [rounds (default 2)]
set -euo pipefail
cd "$(dirname "$0")/.."
photons="${1:-1000000}"
rounds="${2:-2}"
cargo build --release -q -p caustica-cli
bin=./target/release/caustica
out=docs/results/emission-photon-pass; mkdir -p "$out"
work=target/bench/emission-photon-pass; mkdir -p "$work"
csv="$out/results.csv"
echo "round,scene,integrator,emission,photons,light_paths,pass_seconds,map_build_seconds,total_seconds" > "$csv"
for r in $(seq 1 "$rounds"); do
  for scene in glass-sphere gold-ring; do
    for integrator in pm pds; do
      for e in uniform projection adaptive; do
        log="$work/$scene-$integrator-$e-$r.log"
        start=$(date +%s.%N)
        "$bin" render "$scene" --integrator "$integrator" --photons "$photons" --caustics-only \
          --spp 1 --k 50 --smoothing 4 --no-auto-bandwidth --emission "$e" --seed "$r" \
          -o "$work/$scene-$integrator-$e.exr" > "$log" 2>&1
        total=$(awk -v a="$start" -v b="$(date +%s.%N)" 'BEGIN { printf "%.2f", b - a }')
        python3 - "$log" "$r" "$scene" "$integrator" "$e" "$total" >> "$csv" <<'PY'
import re, sys
log, r, scene, integ, e, total = sys.argv[1:7]
t = open(log).read()
# pm: "photons: caustic N from P paths, ... in S s"; pds: "N caustic photons from P light paths (counted in S s)"
m = re.search(r"photons: caustic (\d+) from (\d+) paths.*? in ([\d.]+) s", t) or \
    re.search(r"(\d+) caustic photons from (\d+) light paths \(counted in ([\d.]+) s\)", t)
b = re.search(r"built in ([\d.]+) s", t)
n, p, s = m.groups() if m else ("", "", "")
print(",".join([r, scene, integ, e, n, p, s, b.group(1) if b else "", total]))
PY
      done
    done
  done
done
python3 - "$csv" "$out" "$photons" "$rounds" <<'PY'
import csv, sys, statistics as st
path, out, photons, rounds = sys.argv[1:5]
rows = list(csv.DictReader(open(path)))
key = lambda r: (r["scene"], r["integrator"], r["emission"])
groups = {}
for r in rows:
    groups.setdefault(key(r), []).append(r)
md = ["# The caustic photon pass: uniform emission, projection maps, adaptive sampler", "",
      f"`bash bench/emission_photon_pass.sh {photons} {rounds}`: {photons} caustic photons "
      f"(`--caustics-only --spp 1`), the rules alternating in each of {rounds} rounds on this "
      "shared 2-core machine; medians. *pass* is pm's caustic photon pass or pds's counting pass "
      "(the render notes' seconds); *speed-up* is uniform's pass time over the rule's, same "
      "scene and integrator. The adaptive sampler traces a uniform replica and, when that is not "
      "visible, a mutation per chain step.", "",
      "| scene | integrator | emission | light paths | yield | pass (s) | speed-up | map build (s) | whole render (s) |",
      "|---|---|---|---:|---:|---:|---:|---:|---:|"]
for (scene, integ, e), rs in sorted(groups.items(), key=lambda kv: (kv[0][0], kv[0][1], ["uniform", "projection", "adaptive"].index(kv[0][2]))):
    sec = st.median(float(r["pass_seconds"]) for r in rs if r["pass_seconds"])
    uni = st.median(float(r["pass_seconds"]) for r in groups[(scene, integ, "uniform")] if r["pass_seconds"])
    n, p = int(rs[0]["photons"]), int(rs[0]["light_paths"])
    build = [float(r["map_build_seconds"]) for r in rs if r["map_build_seconds"]]
    tot = st.median(float(r["total_seconds"]) for r in rs)
    md.append(f"| {scene} | {integ} | {e} | {p} | {100*n/p:.2f} % | {sec:.2f} | {uni/sec:.1f}× | "
              f"{st.median(build):.3f} | {tot:.1f} |" if build else
              f"| {scene} | {integ} | {e} | {p} | {100*n/p:.2f} % | {sec:.2f} | {uni/sec:.1f}× | – | {tot:.1f} |")
open(f"{out}/README.md", "w").write("\n".join(md) + "\n")
print("\n".join(md))
PY
