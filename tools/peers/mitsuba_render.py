#!/usr/bin/env python3
"""Render a scene with Mitsuba 3 (variant scalar_rgb, or --variant scalar_spectral or
llvm_ad_rgb) for comparison with caustica.

  mitsuba_render.py cornell-box --spp 64 --out mitsuba.exr [--integrator path|ptracer]
  mitsuba_render.py cornell-box --variant scalar_spectral ...   (against caustica --spectral)
  mitsuba_render.py cornell-box --variant llvm_ad_rgb --threads 2 ...   (Dr.Jit's LLVM backend)
  mitsuba_render.py scene.xml --spp 64 --out mitsuba.exr [--box]
  mitsuba_render.py scene.xml ... [-D name=value ...]    (XML <default>s, e.g. -D res=64)

`cornell-box` is Mitsuba's own `mi.cornell_box()`. `--box` replaces the pixel filter by a box
(for an XML scene: its `<rfilter type="gaussian"/>`), e.g. to match pbrt-v3's box-filtered BDPT. Prints one line with the wall time of the
render call alone and of scene loading, in seconds.

The llvm_* variants need a libLLVM that Dr.Jit 1.5 accepts (the system's LLVM 14/15 makes it
abort): DRJIT_LIBLLVM_PATH from the environment, else the one tools/peers/libllvm.sh unpacks
(Debian's libllvm19), set before mitsuba (and so drjit) is imported. Their render time includes
the JIT compilation of the kernels (or the load from Dr.Jit's kernel cache in ~/.drjit when it
is warm: a first render on a machine compiles, later ones with the same kernels reuse it) and
the evaluation of the image; see main().

--threads N sets the size of Dr.Jit's thread pool (dr.set_thread_count), which both the scalar
variants' block-parallel renderer and the LLVM backend's kernels run on; without it, the pool
has one thread per core.
"""
import argparse
import os
import subprocess
import time

import sys


def variant_from_argv():
    """The variant must be set before the scene is built; read it ahead of argparse."""
    for i, a in enumerate(sys.argv):
        if a == "--variant" and i + 1 < len(sys.argv):
            return sys.argv[i + 1]
        if a.startswith("--variant="):
            return a.split("=", 1)[1]
    return "scalar_rgb"


VARIANT = variant_from_argv()
JIT = VARIANT.startswith("llvm_") or VARIANT.startswith("cuda_")
if VARIANT.startswith("llvm_") and not os.environ.get("DRJIT_LIBLLVM_PATH"):
    # Dr.Jit reads DRJIT_LIBLLVM_PATH when its LLVM backend starts: set it before the import.
    here = os.path.dirname(os.path.abspath(__file__))
    os.environ["DRJIT_LIBLLVM_PATH"] = subprocess.run(
        ["bash", os.path.join(here, "libllvm.sh")], check=True, stdout=subprocess.PIPE, text=True
    ).stdout.strip()

import drjit as dr  # noqa: E402
import mitsuba as mi  # noqa: E402

mi.set_variant(VARIANT)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--variant", default="scalar_rgb", help="scalar_rgb, scalar_spectral or llvm_ad_rgb")
    ap.add_argument("scene")
    ap.add_argument("--spp", type=int, default=64)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--integrator", default=None, help="path or ptracer (default: the scene's)")
    ap.add_argument("--max-depth", type=int, default=None)
    ap.add_argument("--box", action="store_true", help="use a box pixel filter")
    ap.add_argument("--threads", type=int, default=None)
    ap.add_argument("--out", required=True)
    ap.add_argument("--jit-stats", action="store_true",
                    help="JIT variants: print a second line summing Dr.Jit's kernel history of the render "
                    "(kernels, cache hits, code generation, LLVM compile and execution times; "
                    "the history makes Dr.Jit time each kernel, so leave it out of timed runs)")
    ap.add_argument("-D", dest="defines", action="append", default=[], metavar="NAME=VALUE")
    a = ap.parse_args()
    pool = dr.thread_count()
    if a.threads:
        # Mitsuba 3.9's Thread has no set_thread_count (the former call here did nothing); the
        # render threads are Dr.Jit's pool for the scalar and the LLVM variants alike.
        dr.set_thread_count(a.threads)
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
    if JIT:
        # Evaluate what loading left pending so that it does not count as rendering.
        dr.eval()
        dr.sync_thread()
    if JIT and a.jit_stats:
        dr.kernel_history()  # drop what loading launched
        dr.set_flag(dr.JitFlag.KernelHistory, True)
    t1 = time.perf_counter()
    img = mi.render(scene, integrator=integrator, spp=a.spp, seed=a.seed)
    if JIT:
        # Inside the timer for the JIT variants: tracing and compiling the kernels (or loading
        # them from the kernel cache ~/.drjit when it is warm), running them, and the image's
        # evaluation: mi.render returns with kernels possibly still running on the thread pool,
        # so wait for them. The image is complete in memory at t2, as the scalar variants' is.
        dr.eval(img)
        dr.sync_thread()
    t2 = time.perf_counter()
    threads = f", threads {dr.thread_count()}"
    # Writing the EXR with a pool of one thread hangs (Mitsuba 3.9.1, Dr.Jit 1.5): write with the
    # pool's original size.
    dr.set_thread_count(pool)
    mi.Bitmap(img).write(a.out)
    print(f"mitsuba {mi.variant()}: load {t1 - t0:.3f} s, render {t2 - t1:.3f} s, spp {a.spp}{threads} -> {a.out}")
    if JIT and a.jit_stats:
        h = [k for k in dr.kernel_history() if str(k.get("type", "")).endswith("JIT")]
        ms = lambda key: sum(k.get(key, 0.0) for k in h) / 1000.0  # noqa: E731 (Dr.Jit reports ms)
        hits = sum(1 for k in h if k.get("cache_hit"))
        disk = sum(1 for k in h if k.get("cache_disk"))  # a subset of the hits
        print(f"  jit: {len(h)} kernel launches, {len(h) - hits} compiled, {disk} loaded from the kernel "
              f"cache ~/.drjit, {hits - disk} reused in-process; code generation {ms('codegen_time'):.3f} s, "
              f"LLVM compile {ms('backend_time'):.3f} s, execution {ms('execution_time'):.3f} s")


if __name__ == "__main__":
    main()
