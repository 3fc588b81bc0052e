#!/usr/bin/env python3
"""Masks of the pixels that see a diffuse surface, for comparing full images with a light tracer
(which leaves pixels that see glass, mirrors or smooth metal directly black).

Two steps, so that caustica renders the coverage with its own camera and exact shapes:

  specular_mask.py toml SCENE.toml COVER.toml
      writes a copy of the scene in which every specular shape (dielectric, mirror, conductor
      materials) is a black diffuse surface emitting radiance 1 and everything else is black
      (no other emission): a path-traced render of it is, per pixel, the fraction of the pixel
      that sees a specular surface;
  specular_mask.py mask COVER.pfm MASK.pfm [--threshold 1e-3]
      turns that coverage image into a mask: 1 where the coverage is below the threshold (the
      pixel sees only diffuse surfaces or nothing), 0 elsewhere.

  caustica render COVER.toml --integrator path --spp 64 -o COVER.pfm
Uses numpy for the second step only; reads and writes PFM (caustica writes PFM with -o x.pfm).
Handles the TOML subset of the case scenes (scenes/*.toml); relative file names are made absolute.
"""
import argparse
import json
import os
import sys
import tomllib

SPECULAR = {"dielectric", "mirror", "conductor"}


def tv(v):
    """A TOML value."""
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (int, float)):
        return repr(v)
    if isinstance(v, str):
        return json.dumps(v)
    if isinstance(v, list):
        return "[" + ", ".join(tv(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{ " + ", ".join(f"{k} = {tv(x)}" for k, x in v.items()) + " }"
    raise SystemExit(f"specular_mask.py: cannot write {v!r}")


def cover_toml(src, dst):
    with open(src, "rb") as fh:
        sc = tomllib.load(fh)
    base = os.path.dirname(os.path.abspath(src))
    mats = {m["name"]: m for m in sc.get("material", [])}
    out = [f"name = {tv(sc.get('name', 'scene') + '-specular-cover')}", ""]
    for table in ("camera", "film", "animation"):
        if table in sc:
            out.append(f"[{table}]")
            out += [f"{k} = {tv(v)}" for k, v in sc[table].items()]
            out.append("")
    out += ["[render]", "max_depth = 1", "", "[[material]]", 'name = "black"', 'type = "diffuse"',
            "reflectance = 0", ""]
    specular = 0
    for sh in sc.get("shape", []):
        sh = dict(sh)
        is_spec = mats[sh["material"]]["type"] in SPECULAR
        sh["material"] = "black"
        sh.pop("emission", None)
        sh.pop("emission_spectrum", None)
        sh.pop("interior", None)
        sh.pop("exterior", None)
        if is_spec:
            sh["emission"] = 1
            specular += 1
        for k in ("filename",):
            if k in sh and not os.path.isabs(sh[k]):
                sh[k] = os.path.join(base, sh[k])
        if any(isinstance(v, list) and v and isinstance(v[0], dict) and k != "rotate"
               for k, v in sh.items()):
            raise SystemExit(f"specular_mask.py: shape keys {list(sh)} not supported")
        out.append("[[shape]]")
        out += [f"{k} = {tv(v)}" for k, v in sh.items()]
        out.append("")
    # a light keeps the scene valid; every surface is black, so it adds nothing
    for li in sc.get("light", []):
        out.append("[[light]]")
        out += [f"{k} = {tv(v)}" for k, v in li.items()]
        out.append("")
    if not sc.get("light"):
        out += ["[[light]]", 'type = "point"', "position = [0, 1000, 0]", "intensity = 1", ""]
    with open(dst, "w") as fh:
        fh.write("\n".join(out))
    print(f"{dst}: {specular} specular shape(s) emitting", file=sys.stderr)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = ap.add_subparsers(dest="cmd", required=True)
    a = sub.add_parser("toml")
    a.add_argument("scene")
    a.add_argument("out")
    b = sub.add_parser("mask")
    b.add_argument("cover")
    b.add_argument("out")
    b.add_argument("--threshold", type=float, default=1e-3)
    args = ap.parse_args()
    if args.cmd == "toml":
        cover_toml(args.scene, args.out)
    else:
        # numpy (and the PFM reader) only here: the toml subcommand runs under a bare python3.
        sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
        from equal_time_metrics import read_pfm, write_pfm

        cov = read_pfm(args.cover).max(axis=2)
        mask = (cov < args.threshold).astype(float)
        write_pfm(args.out, mask)
        print(f"{args.out}: {int(mask.sum())} of {mask.size} pixels see only diffuse surfaces",
              file=sys.stderr)


if __name__ == "__main__":
    main()
