#!/usr/bin/env python3
"""Render a scene with Mitsuba 3 (variant scalar_rgb, or --variant scalar_spectral) for
comparison with caustica.

  mitsuba_render.py cornell-box --spp 64 --out mitsuba.exr [--integrator path|ptracer]
  mitsuba_render.py cornell-box --variant scalar_spectral ...   (against caustica --spectral)
  mitsuba_render.py scene.xml --spp 64 --out mitsuba.exr [--box]
  mitsuba_render.py scene.xml ... [-D name=value ...]    (XML <default>s, e.g. -D res=64)

`cornell-box` is Mitsuba's own `mi.cornell_box()`. `--box` replaces the pixel filter by a box
(for an XML scene: its `<rfilter type="gaussian"/>`), e.g. to match pbrt-v3's box-filtered BDPT. Prints one line with the wall time of the
render call alone and of scene loading, in seconds.
"""
import argparse
import os
import time

import sys

import mitsuba as mi


def variant_from_argv():
    """The variant must be set before the scene is built; read it ahead of argparse."""
    for i, a in enumerate(sys.argv):
        if a == "--variant" and i + 1 < len(sys.argv):
            return sys.argv[i + 1]
        if a.startswith("--variant="):
            return a.split("=", 1)[1]
    return "scalar_rgb"


mi.set_variant(variant_from_argv())


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--variant", default="scalar_rgb", help="scalar_rgb or scalar_spectral")
    ap.add_argument("scene")
    ap.add_argument("--spp", type=int, default=64)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--integrator", default=None, help="path or ptracer (default: the scene's)")
    ap.add_argument("--max-depth", type=int, default=None)
    ap.add_argument("--box", action="store_true", help="use a box pixel filter")
    ap.add_argument("--threads", type=int, default=None)
    ap.add_argument("--out", required=True)
    ap.add_argument("-D", dest="defines", action="append", default=[], metavar="NAME=VALUE")
    a = ap.parse_args()
    if a.threads:
        mi.Thread.thread().set_thread_count(a.threads) if hasattr(mi.Thread, "set_thread_count") else None
    t0 = time.perf_counter()
    if a.scene == "cornell-box":
        d = mi.cornell_box()
        if a.box:
            d["sensor"]["film"]["rfilter"] = {"type": "box"}
        d["sensor"]["sampler"]["sample_count"] = a.spp
        scene = mi.load_dict(d)
    else:
        params = dict(d.split("=", 1) for d in a.defines)
        if a.box:
            text = open(a.scene).read()
            if '<rfilter type="gaussian"/>' not in text:
                raise SystemExit(f"{a.scene}: no <rfilter type=\"gaussian\"/> to replace")
            text = text.replace('<rfilter type="gaussian"/>', '<rfilter type="box"/>')
            # relative file names (e.g. a .vol grid) resolve against the scene's directory
            fr = mi.file_resolver() if hasattr(mi, "file_resolver") else mi.Thread.thread().file_resolver()
            fr.prepend(os.path.dirname(os.path.abspath(a.scene)))
            scene = mi.load_string(text, **params)
        else:
            scene = mi.load_file(a.scene, **params)
    integrator = scene.integrator()
    if a.integrator:
        spec = {"type": a.integrator}
        if a.max_depth is not None:
            spec["max_depth"] = a.max_depth
        integrator = mi.load_dict(spec)
    t1 = time.perf_counter()
    img = mi.render(scene, integrator=integrator, spp=a.spp, seed=a.seed)
    t2 = time.perf_counter()
    mi.Bitmap(img).write(a.out)
    print(f"mitsuba {mi.variant()}: load {t1 - t0:.3f} s, render {t2 - t1:.3f} s, spp {a.spp} -> {a.out}")


if __name__ == "__main__":
    main()
