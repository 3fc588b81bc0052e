#!/usr/bin/env bash
# pbrt-v4 against Mitsuba XML load time for a 1 M-triangle plymesh scene (docs/performance.md,
# "pbrt-v4 import: parse time"). Writes a 709 x 709 vertex grid (1 002 528 triangles) as a
# binary little-endian PLY into target/pbrt-bench/ if missing, the same scene as ply.pbrt
# (Shape "plymesh") and ply.xml (<shape type="ply">), and the mesh written inline as a pbrt
# trianglemesh (inline.pbrt, ~40 MB of text); then times the loaders in one process
# (crates/loader/benches/pbrt_parse.rs: parse_scene_file, no BVH build), RUNS alternating
# rounds (default 7), and prints the medians and the ratios.
set -euo pipefail
cd "$(dirname "$0")/.."
out=target/pbrt-bench
mkdir -p "$out"
if [ ! -s "$out/grid.ply" ] || [ ! -s "$out/inline.pbrt" ]; then
python3 - "$out" <<'PY'
import struct, sys
out = sys.argv[1]
n = 709                      # vertices per side: 2 * 708^2 = 1 002 528 triangles
verts = [(x / (n - 1) * 2 - 1, 0.0, z / (n - 1) * 2 - 1) for z in range(n) for x in range(n)]
tris = []
for z in range(n - 1):
    for x in range(n - 1):
        a = z * n + x
        b, c, d = a + 1, a + n + 1, a + n
        tris.append((a, c, b))
        tris.append((a, d, c))
with open(f"{out}/grid.ply", "wb") as f:
    f.write(("ply\nformat binary_little_endian 1.0\n"
             f"element vertex {len(verts)}\nproperty float x\nproperty float y\nproperty float z\n"
             f"element face {len(tris)}\nproperty list uchar int vertex_indices\nend_header\n").encode())
    f.write(b"".join(struct.pack("<3f", *v) for v in verts))
    f.write(b"".join(struct.pack("<B3i", 3, *t) for t in tris))
with open(f"{out}/inline.pbrt", "w") as f:
    f.write('LookAt 0 3 3  0 0 0  0 1 0\nCamera "perspective" "float fov" 40\nWorldBegin\n')
    f.write('LightSource "distant" "point3 to" [ 0 -1 0 ]\nShape "trianglemesh"\n  "point3 P" [\n')
    for i in range(0, len(verts), 8):
        f.write(" ".join("%.6g %g %.6g" % v for v in verts[i:i + 8]) + "\n")
    f.write(']\n  "integer indices" [\n')
    for i in range(0, len(tris), 12):
        f.write(" ".join("%d %d %d" % t for t in tris[i:i + 12]) + "\n")
    f.write("]\n")
print(f"wrote {len(tris)} triangles")
PY
fi
cat > "$out/ply.pbrt" <<'PBRT'
LookAt 0 3 3  0 0 0  0 1 0
Camera "perspective" "float fov" 40
WorldBegin
LightSource "distant" "point3 to" [ 0 -1 0 ]
Shape "plymesh" "string filename" "grid.ply"
PBRT
cat > "$out/ply.xml" <<'XML'
<scene version="3.0.0">
  <sensor type="perspective">
    <float name="fov" value="40"/>
    <transform name="to_world"><lookat origin="0, 3, 3" target="0, 0, 0" up="0, 1, 0"/></transform>
  </sensor>
  <emitter type="directional"><vector name="direction" x="0" y="-1" z="0"/></emitter>
  <shape type="ply"><string name="filename" value="grid.ply"/></shape>
</scene>
XML
ls -l "$out"
CARGO_TARGET_DIR=${CARGO_TARGET_DIR:-target} cargo bench --profile fast -p caustica-loader --bench pbrt_parse -- "$PWD/$out"
