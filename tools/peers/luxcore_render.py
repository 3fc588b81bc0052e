#!/usr/bin/env python3
"""Renders one of caustica's caustic case scenes with LuxCore 2.11 (pyluxcore) for a time
budget and writes the linear radiance (RGB float) as PFM, top row first like caustica's images.

  luxcore_render.py glass-sphere --engine pgi --time 60 --out lux.pfm [--seed 1]
  luxcore_render.py scenes/gold-ring.toml --engine bidir --time 30 --out lux.pfm

Scenes: glass-sphere, water-wave, metal-ring, gold-ring (read from scenes/NAME.toml, which the
loader's tests keep equal to the built-ins), or a TOML file using the same subset: a look-at
camera with fov along x; materials diffuse (grey or RGB reflectance), dielectric (ior), mirror,
conductor (preset Au, or eta/k); shapes rectangle, sphere and ply (scale/rotate/translate),
`emission` on a shape (one-sided diffuse area light); point (W/sr) and directional (W/m²)
lights. Spheres are tessellated (--sphere-segments, smooth vertex normals); PLY quads are split
into two triangles.

Engines:
  pgi    PATHCPU with the PhotonGI caustic cache (Metropolis photon sampler, Hachisuka & Jensen
         2011's visibility-driven sampler), progressive: the cache is rebuilt every
         --pgi-update-spp passes with the lookup radius shrinking by --pgi-reduction down to
         --pgi-min-radius.
  bidir  BIDIRCPU (bidirectional path tracing with MIS).
  path   PATHCPU alone (for the radiometric checks: direct and diffuse light only).

Conventions matched to caustica / Mitsuba 3 (checked numerically, see
docs/results/emission-equal-time/luxcore-checks.md):
  * point light: with `power` 0, LuxCore's radiant intensity is gain · color / (4π), so
    gain = 4π · intensity [W/sr];
  * directional light: `sharpdistant`, gain = irradiance [W/m²] across the beam; `direction` is
    the direction of travel, as in caustica;
  * area light: a `matte` black material with `emission` = 1 1 1 and emission.gain = radiance
    (a white emission texture keeps LuxCore's normalisation by the texture's luminance inert);
  * camera: LuxCore's `fieldofview` spans the screen window's [-1, 1]; the window is set
    explicitly to x ∈ [-1, 1], so the fov is along x as in caustica (fov_axis x; LuxCore's
    automatic window puts it along the longer axis), and moved down by one pixel, because
    LuxCore otherwise renders the view one pixel row lower than caustica and Mitsuba;
  * film: no reconstruction filter (each sample lands in its pixel, caustica's box filter);
  * gold: `metal2` with caustica's `Au` (n, k); LuxCore's conductor Fresnel is an
    approximation, up to 9 % brighter than the exact one at 60-80° for these n, k.

LuxCore checks halt conditions only inside RenderSession.UpdateStats(), so the budget is
enforced by polling UpdateStats()/HasDone() (never WaitForDone()); the budget counts from just
before RenderSession.Start(), which includes the PhotonGI cache's first build.
This script must not import mitsuba (pyluxcore and mitsuba are never loaded in one process).
"""
import argparse
import json
import math
import os
import sys
import tempfile
import time
import tomllib

import numpy as np

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
CASE_SCENES = ("glass-sphere", "water-wave", "metal-ring", "gold-ring")

# caustica's conductor presets (crates/scene/src/material.rs, conductor_preset): (eta, k) in RGB.
CONDUCTOR_PRESETS = {
    "Au": ((0.14311896, 0.37495704, 1.4424786), (3.9831604, 2.3857207, 1.6032153)),
    "Ag": ((0.15526465, 0.1167233, 0.1383807), (4.8283433, 3.122246, 2.1469504)),
    "Al": ((1.6574599, 0.880369, 0.5212287), (9.223869, 6.269523, 4.837001)),
    "Cu": ((0.2004377, 0.9240334, 1.102212), (3.9129486, 2.4528477, 2.142188)),
}


def die(msg):
    raise SystemExit(f"luxcore_render.py: {msg}")


def rgb(v, what):
    if isinstance(v, (int, float)):
        return (float(v),) * 3
    if isinstance(v, list) and len(v) == 3:
        return tuple(float(x) for x in v)
    die(f"{what}: expected a number or [r, g, b], got {v!r}")


def fmt(v):
    return " ".join(f"{float(x):.9g}" for x in v)


# ---------------------------------------------------------------- transforms


def rotation(axis, deg):
    a = np.asarray(axis, float)
    a = a / np.linalg.norm(a)
    t = math.radians(deg)
    c, s = math.cos(t), math.sin(t)
    x, y, z = a
    r = np.array([
        [c + x * x * (1 - c), x * y * (1 - c) - z * s, x * z * (1 - c) + y * s],
        [y * x * (1 - c) + z * s, c + y * y * (1 - c), y * z * (1 - c) - x * s],
        [z * x * (1 - c) - y * s, z * y * (1 - c) + x * s, c + z * z * (1 - c)],
    ])
    m = np.eye(4)
    m[:3, :3] = r
    return m


def shape_transform(sh):
    """translate · rotate · scale · matrix (docs/scene-format.md)."""
    m = np.eye(4)
    if "matrix" in sh:
        m = np.array(sh["matrix"], float)
    if "scale" in sh:
        s = sh["scale"]
        s = [s] * 3 if isinstance(s, (int, float)) else s
        m = np.diag([float(s[0]), float(s[1]), float(s[2]), 1.0]) @ m
    rots = sh.get("rotate", [])
    if isinstance(rots, dict):
        rots = [rots]
    for r in rots:  # applied in order: the first one acts first
        m = rotation(r["axis"], float(r["angle"])) @ m
    if "translate" in sh:
        t = np.eye(4)
        t[:3, 3] = sh["translate"]
        m = t @ m
    return m


def apply(m, p, n):
    p2 = p @ m[:3, :3].T + m[:3, 3]
    n2 = None
    if n is not None:
        n2 = n @ np.linalg.inv(m[:3, :3])  # inverse transpose
        n2 /= np.linalg.norm(n2, axis=1, keepdims=True)
    return p2, n2


# ---------------------------------------------------------------- meshes


def rectangle_mesh():
    p = np.array([[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]], float)
    n = np.tile([0.0, 0.0, 1.0], (4, 1))
    f = np.array([[0, 1, 2], [0, 2, 3]], np.int32)  # counter-clockwise seen from +z
    return p, n, f


def sphere_mesh(center, radius, segments):
    nu, nv = segments, max(segments // 2, 4)
    th = np.linspace(0, math.pi, nv + 1)
    ph = np.linspace(0, 2 * math.pi, nu + 1)
    T, P = np.meshgrid(th, ph, indexing="ij")
    d = np.stack([np.sin(T) * np.cos(P), np.cos(T), -np.sin(T) * np.sin(P)], -1).reshape(-1, 3)
    p = np.asarray(center, float) + radius * d
    idx = np.arange((nv + 1) * (nu + 1)).reshape(nv + 1, nu + 1)
    a, b = idx[:-1, :-1].ravel(), idx[:-1, 1:].ravel()
    c, e = idx[1:, 1:].ravel(), idx[1:, :-1].ravel()
    f = np.concatenate([np.stack([a, e, c], 1), np.stack([a, c, b], 1)])
    # drop the degenerate triangles at the poles
    pa, pb, pc = p[f[:, 0]], p[f[:, 1]], p[f[:, 2]]
    area = np.linalg.norm(np.cross(pb - pa, pc - pa), axis=1)
    f = f[area > 1e-12 * radius * radius]
    # outward winding check
    pa, pb, pc = p[f[:, 0]], p[f[:, 1]], p[f[:, 2]]
    ng = np.cross(pb - pa, pc - pa)
    if np.mean(np.sum(ng * (pa - center), 1) > 0) < 0.5:
        f = f[:, ::-1]
    return p, d.copy(), f.astype(np.int32)


def read_ply(path):
    with open(path, "rb") as fh:
        if fh.readline().strip() != b"ply":
            die(f"{path}: not a PLY file")
        fmt_line = fh.readline().split()
        if fmt_line[1] != b"ascii":
            die(f"{path}: only ASCII PLY is supported here")
        nv = nf = 0
        vprops = []
        cur = None
        while True:
            line = fh.readline()
            if not line:
                die(f"{path}: no end_header")
            w = line.split()
            if not w or w[0] == b"comment":
                continue
            if w[0] == b"end_header":
                break
            if w[0] == b"element":
                cur = w[1]
                if cur == b"vertex":
                    nv = int(w[2])
                elif cur == b"face":
                    nf = int(w[2])
            elif w[0] == b"property" and cur == b"vertex":
                vprops.append(w[-1].decode())
        data = fh.read().split(b"\n")
    vert = np.array([[float(x) for x in data[i].split()] for i in range(nv)])
    col = {name: i for i, name in enumerate(vprops)}
    p = vert[:, [col["x"], col["y"], col["z"]]]
    n = vert[:, [col["nx"], col["ny"], col["nz"]]] if "nx" in col else None
    tris = []
    for i in range(nv, nv + nf):
        w = [int(x) for x in data[i].split()]
        k, ids = w[0], w[1:]
        for j in range(1, k - 1):  # fan, as caustica's loader
            tris.append((ids[0], ids[j], ids[j + 1]))
    return p, n, np.array(tris, np.int32)


def write_ply(path, p, n, f):
    with open(path, "wb") as fh:
        has_n = n is not None
        hdr = ["ply", "format binary_little_endian 1.0", f"element vertex {len(p)}",
               "property float x", "property float y", "property float z"]
        if has_n:
            hdr += ["property float nx", "property float ny", "property float nz"]
        hdr += [f"element face {len(f)}", "property list uchar int vertex_indices", "end_header"]
        fh.write(("\n".join(hdr) + "\n").encode())
        v = np.hstack([p, n]) if has_n else p
        fh.write(v.astype("<f4").tobytes())
        fr = np.zeros(len(f), dtype=[("n", "u1"), ("i", "<i4", 3)])
        fr["n"] = 3
        fr["i"] = f
        fh.write(fr.tobytes())


# ---------------------------------------------------------------- the scene


def build(scene_path, args, work):
    with open(scene_path, "rb") as fh:
        sc = tomllib.load(fh)
    base = os.path.dirname(os.path.abspath(scene_path))
    lines = []

    def put(k, v):
        lines.append(f"{k} = {v}")

    cam = sc["camera"]
    for k in cam:
        if k not in ("eye", "target", "up", "fov", "fov_axis", "width", "height"):
            die(f"camera key {k!r} is not supported")
    if cam.get("fov_axis", "x") != "x":
        die("only fov_axis = x is supported")
    w = args.width or int(cam["width"])
    h = args.height or (int(cam["height"]) * w // int(cam["width"]))
    put("scene.camera.type", '"perspective"')
    put("scene.camera.lookat.orig", fmt(cam["eye"]))
    put("scene.camera.lookat.target", fmt(cam["target"]))
    put("scene.camera.up", fmt(cam.get("up", [0, 1, 0])))
    put("scene.camera.fieldofview", f"{float(cam['fov']):.9g}")
    # fov along x: the screen window spans [-1, 1] horizontally
    # LuxCore's perspective camera renders the window one pixel lower than caustica and Mitsuba
    # (measured: the sharp shadow edges of a point light land one row below); a window moved
    # down by one pixel (2/w in screen units) lines them up
    dy = -2.0 / w
    put("scene.camera.screenwindow", fmt([-1, 1, -h / w + dy, h / w + dy]))
    put("scene.camera.lensradius", "0")

    mats = {}
    for m in sc.get("material", []):
        name, t = m["name"], m["type"]
        pre = f"scene.materials.{name}"
        if t == "diffuse":
            put(pre + ".type", '"matte"')
            put(pre + ".kd", fmt(rgb(m.get("reflectance", 0.5), name)))
        elif t == "dielectric":
            if m.get("dispersion") or m.get("absorption"):
                die(f"material {name}: dispersion/absorption not supported")
            put(pre + ".type", '"glass"')
            put(pre + ".kr", "1 1 1")
            put(pre + ".kt", "1 1 1")
            put(pre + ".interiorior", f"{float(m.get('ior', 1.5)):.9g}")
            put(pre + ".exteriorior", "1")
        elif t == "mirror":
            put(pre + ".type", '"mirror"')
            put(pre + ".kr", fmt(rgb(m.get("reflectance", 1), name)))
        elif t == "conductor":
            if "preset" in m:
                eta, k = CONDUCTOR_PRESETS[m["preset"]]
            else:
                eta, k = rgb(m["eta"], name), rgb(m["k"], name)
            if m.get("roughness", 0):
                die(f"material {name}: rough conductors not supported")
            put(pre + ".type", '"metal2"')
            put(pre + ".n", fmt(eta))
            put(pre + ".k", fmt(k))
            put(pre + ".uroughness", f"{args.metal_roughness:.9g}")
            put(pre + ".vroughness", f"{args.metal_roughness:.9g}")
        else:
            die(f"material type {t!r} not supported")
        mats[name] = t

    for i, sh in enumerate(sc.get("shape", [])):
        t = sh["type"]
        m = shape_transform(sh)
        if t == "rectangle":
            p, n, f = rectangle_mesh()
            p, n = apply(m, p, n)
        elif t == "sphere":
            if any(k in sh for k in ("matrix", "scale", "rotate")):
                die("transformed spheres are not supported")
            c = np.asarray(sh.get("center", [0, 0, 0]), float)
            p, n, f = sphere_mesh(c, float(sh.get("radius", 1)), args.sphere_segments)
            p, n = apply(m, p, n)
        elif t == "ply":
            p, n, f = read_ply(os.path.join(base, sh["filename"]))
            p, n = apply(m, p, n)
        else:
            die(f"shape type {t!r} not supported")
        if sh.get("flip_normals"):
            f = f[:, ::-1]
            n = -n if n is not None else None
        ply = os.path.join(work, f"shape{i}.ply")
        write_ply(ply, p, n, f)
        put(f"scene.shapes.shape{i}.type", '"mesh"')
        put(f"scene.shapes.shape{i}.ply", json.dumps(ply))
        mat = sh["material"]
        if "emission" in sh:
            # an emitting copy of the shape's material: LuxCore puts emission on materials
            mname = f"{mat}_emit{i}"
            if mats[mat] != "diffuse":
                die("emission on a non-diffuse material is not supported")
            src = [ln for ln in lines if ln.startswith(f"scene.materials.{mat}.")]
            for ln in src:
                lines.append(ln.replace(f"scene.materials.{mat}.", f"scene.materials.{mname}.", 1))
            put(f"scene.materials.{mname}.emission", "1 1 1")
            put(f"scene.materials.{mname}.emission.gain", fmt(rgb(sh["emission"], "emission")))
            put(f"scene.materials.{mname}.emission.power", "0")
            put(f"scene.materials.{mname}.emission.efficency", "0")
            mat = mname
        put(f"scene.objects.shape{i}.shape", f'"shape{i}"')
        put(f"scene.objects.shape{i}.material", f'"{mat}"')

    for i, li in enumerate(sc.get("light", [])):
        t = li["type"]
        pre = f"scene.lights.light{i}"
        if t == "point":
            put(pre + ".type", '"point"')
            put(pre + ".position", fmt(li["position"]))
            put(pre + ".color", "1 1 1")
            put(pre + ".power", "0")
            put(pre + ".efficency", "0")
            i_rgb = rgb(li.get("intensity", 1), "intensity")
            put(pre + ".gain", fmt([4 * math.pi * x for x in i_rgb]))
        elif t == "directional":
            put(pre + ".type", '"sharpdistant"')
            d = np.asarray(li["direction"], float)
            put(pre + ".direction", fmt(d / np.linalg.norm(d)))
            put(pre + ".color", "1 1 1")
            put(pre + ".gain", fmt(rgb(li.get("irradiance", 1), "irradiance")))
        else:
            die(f"light type {t!r} not supported")
    return "\n".join(lines) + "\n", w, h


def config_props(args, w, h, budget):
    depth = args.max_depth
    c = [
        f"renderengine.type = {'BIDIRCPU' if args.engine == 'bidir' else 'PATHCPU'}",
        f"renderengine.seed = {args.seed}",
        f"native.threads.count = {args.threads}",
        "sampler.type = SOBOL",
        f"film.width = {w}",
        f"film.height = {h}",
        "film.filter.type = NONE",
        "film.outputs.0.type = RGB",
        "film.outputs.0.filename = unused.exr",
        "film.imagepipelines.0.0.type = TONEMAP_LINEAR",
        "film.imagepipelines.0.0.scale = 1",
        "path.forceblackbackground.enable = 1",
        f"path.maxdepth = {depth}",
        f"light.maxdepth = {depth}",
        f"path.pathdepth.total = {depth}",
        f"path.pathdepth.diffuse = {depth}",
        f"path.pathdepth.glossy = {depth}",
        f"path.pathdepth.specular = {depth}",
        "path.clamping.variance.maxvalue = 0",
        "path.hybridbackforward.enable = 0",
    ]
    if budget:
        c.append(f"batch.halttime = {budget:.9g}")
    if args.spp:
        c.append(f"batch.haltspp = {args.spp}")
    if args.engine == "pgi":
        c += [
            "path.photongi.sampler.type = METROPOLIS",
            "path.photongi.indirect.enabled = 0",
            "path.photongi.caustic.enabled = 1",
            f"path.photongi.photon.maxdepth = {depth}",
            f"path.photongi.caustic.maxsize = {args.pgi_photons}",
            f"path.photongi.caustic.lookup.radius = {args.pgi_radius:.9g}",
            f"path.photongi.caustic.updatespp = {args.pgi_update_spp}",
            f"path.photongi.caustic.updatespp.radiusreduction = {args.pgi_reduction:.9g}",
            f"path.photongi.caustic.updatespp.minradius = {args.pgi_min_radius:.9g}",
        ]
    return "\n".join(c) + "\n"


def write_pfm(path, img):
    h, w, _ = img.shape
    with open(path, "wb") as fh:
        fh.write(f"PF\n{w} {h}\n-1.0\n".encode())
        fh.write(np.ascontiguousarray(img[::-1], dtype="<f4").tobytes())  # PFM: bottom row first


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("scene", help="glass-sphere, water-wave, metal-ring, gold-ring or a .toml")
    ap.add_argument("--engine", choices=["pgi", "bidir", "path"], required=True)
    ap.add_argument("--time", type=float, help="budget in seconds (wall clock from Start())")
    ap.add_argument("--spp", type=int, help="halt after this many samples per pixel instead")
    ap.add_argument("--out", required=True, help="output .pfm (linear RGB, top row first)")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--threads", type=int, default=os.cpu_count() or 2)
    ap.add_argument("--width", type=int)
    ap.add_argument("--height", type=int)
    ap.add_argument("--max-depth", type=int, default=16)
    ap.add_argument("--sphere-segments", type=int, default=512,
                    help="segments around a tessellated sphere (half as many rings)")
    ap.add_argument("--metal-roughness", type=float, default=0.0,
                    help="metal2 u/v roughness of conductors (0: LuxCore clamps to its minimum)")
    ap.add_argument("--pgi-radius", type=float, default=0.02,
                    help="PhotonGI caustic lookup radius (m) of the first cache (LuxCore's default 0.15)")
    ap.add_argument("--pgi-min-radius", type=float, default=0.003)
    ap.add_argument("--pgi-reduction", type=float, default=0.96)
    ap.add_argument("--pgi-update-spp", type=int, default=8)
    ap.add_argument("--pgi-photons", type=int, default=100000,
                    help="caustic photons stored per cache build (LuxCore's caustic.maxsize)")
    ap.add_argument("--stats", help="write the run's statistics as JSON here")
    ap.add_argument("--keep", help="keep the generated LuxCore scene/config in this folder")
    ap.add_argument("--verbose", action="store_true", help="show LuxCore's log")
    args = ap.parse_args()
    if not args.time and not args.spp:
        die("give --time or --spp")

    scene_path = args.scene
    if args.scene in CASE_SCENES:
        scene_path = os.path.join(ROOT, "scenes", args.scene + ".toml")
    if not os.path.isfile(scene_path):
        die(f"no scene {args.scene!r}")

    work = args.keep or tempfile.mkdtemp(prefix="luxcore-")
    os.makedirs(work, exist_ok=True)
    scn, w, h = build(scene_path, args, work)
    cfg = config_props(args, w, h, args.time)
    with open(os.path.join(work, "scene.scn"), "w") as fh:
        fh.write(scn)
    with open(os.path.join(work, "render.cfg"), "w") as fh:
        fh.write(cfg + f"scene.file = {os.path.join(work, 'scene.scn')}\n")

    # pyluxcore prints its library check on stdout at import: keep our stdout for the summary
    saved = os.dup(1)
    os.dup2(2, 1)
    try:
        import pyluxcore
    finally:
        os.dup2(saved, 1)
        os.close(saved)
    log = []
    pyluxcore.Init(lambda msg: (log.append(msg), args.verbose and print(msg, file=sys.stderr)))

    t_setup = time.monotonic()
    scene_props = pyluxcore.Properties()
    scene_props.SetFromString(scn)
    scene = pyluxcore.Scene()
    scene.Parse(scene_props)
    cfg_props = pyluxcore.Properties()
    cfg_props.SetFromString(cfg)
    config = pyluxcore.RenderConfig(cfg_props, scene)
    session = pyluxcore.RenderSession(config)
    t0 = time.monotonic()
    session.Start()
    t_started = time.monotonic() - t0
    budget = args.time or float("inf")
    while True:
        left = budget - (time.monotonic() - t0)
        time.sleep(max(0.0, min(0.1, left)))
        session.UpdateStats()  # halt conditions are checked here
        if session.HasDone() or time.monotonic() - t0 >= budget:
            break
    stats = session.GetStats()
    session.Stop()
    wall = time.monotonic() - t0
    film = session.GetFilm()
    buf = np.zeros(w * h * 3, np.float32)
    film.GetOutputFloat(pyluxcore.FilmOutputType.RGB, buf)
    # LuxCore's film buffers start at the bottom row (OpenGL convention)
    img = buf.reshape(h, w, 3)[::-1]
    if not np.all(np.isfinite(img)):
        print("warning: non-finite pixels set to 0", file=sys.stderr)
        img = np.nan_to_num(img, nan=0.0, posinf=0.0, neginf=0.0)
    write_pfm(args.out, img)

    def stat(k, default=0.0):
        try:
            return stats.Get(k).GetFloat()
        except Exception:
            return default

    summary = {
        "engine": args.engine,
        "scene": args.scene,
        "seconds": round(wall, 3),
        "start_seconds": round(t_started, 3),
        "setup_seconds": round(t0 - t_setup, 3),
        "luxcore_seconds": round(stat("stats.renderengine.time"), 3),
        "passes": int(stat("stats.renderengine.pass")),
        "samples_per_second": stat("stats.renderengine.total.samplesec"),
        "width": w,
        "height": h,
        "mean": [float(x) for x in img.reshape(-1, 3).mean(0)],
    }
    if args.stats:
        with open(args.stats, "w") as fh:
            json.dump(summary, fh, indent=1)
    print(json.dumps(summary), flush=True)
    sys.stderr.flush()
    # pyluxcore 2.11 aborts at interpreter shutdown ("PyThreadState_Get: ... GIL is released")
    # while its static objects log through the Python handler: leave without finalising
    os._exit(0)


if __name__ == "__main__":
    main()
