#!/usr/bin/env python3
"""Render a pbrt-v3 scene (the build of /work/shared/peers/pbrt-v3/build.sh) at a given spp/seed.

  pbrt_render.py SCENE.pbrt --spp 64 --seed 1 --out OUT.pfm [--pbrt PATH] [--threads N]

Substitutes the scene's `"integer pixelsamples" [..]` and `"integer seed" [..]` (the patched
"random" sampler's seed), writes the edited copy next to OUT, runs pbrt with --outfile OUT (pbrt-v3
writes .pfm; its OpenEXR output is stubbed out in that build) and prints one line with the wall
time of the whole pbrt process (parsing is negligible for these scenes), like mitsuba_render.py.
pbrt's own output (statistics) goes to OUT.log; its warnings (e.g. `Parameter "conedelta" not
used`: pbrt-v3 ignores misspelt parameters) are repeated on stderr.
"""
import argparse
import os
import re
import subprocess
import sys
import time


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("scene")
    ap.add_argument("--spp", type=int, default=64)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--out", required=True)
    ap.add_argument("--pbrt", default=os.path.join(os.environ.get("PBRT_BUILD", os.path.expanduser("~/.cache/pbrt-v3")), "pbrt"))
    ap.add_argument("--threads", type=int, default=None)
    a = ap.parse_args()
    text = open(a.scene).read()
    text, n1 = re.subn(r'"integer pixelsamples"\s*\[\s*\d+\s*\]', f'"integer pixelsamples" [{a.spp}]', text)
    text, n2 = re.subn(r'"integer seed"\s*\[\s*-?\d+\s*\]', f'"integer seed" [{a.seed}]', text)
    if n1 != 1 or n2 != 1:
        sys.exit(f"{a.scene}: expected one \"integer pixelsamples\" and one \"integer seed\" (found {n1}, {n2})")
    out = os.path.abspath(a.out)
    edited = out.rsplit(".", 1)[0] + ".pbrt"
    with open(edited, "w") as f:
        f.write(text)
    cmd = [a.pbrt, "--outfile", out]
    if a.threads:
        cmd += ["--nthreads", str(a.threads)]
    t0 = time.perf_counter()
    r = subprocess.run(cmd + [edited], cwd=os.path.dirname(os.path.abspath(a.scene)),
                       stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    t1 = time.perf_counter()
    log = out.rsplit(".", 1)[0] + ".log"
    with open(log, "w") as f:
        f.write(r.stdout)
    # pbrt-v3 only warns about misspelt or unused parameters ("Parameter ... not used"): show them
    for line in r.stdout.splitlines():
        if ("arning" in line or "rror" in line) and "overriding filename" not in line:
            print("pbrt-v3:", line.strip(), file=sys.stderr)
    if r.returncode != 0:
        sys.exit(f"pbrt-v3 failed ({r.returncode}), see {log}")
    print(f"pbrt-v3: render {t1 - t0:.3f} s (whole process), spp {a.spp}, seed {a.seed} -> {a.out}")


if __name__ == "__main__":
    main()
