#!/usr/bin/env bash
# Instructions per ray of caustica's BVH queries (single rays, and eight-ray streams of the camera
# rays and the shadow segments), counted by callgrind (issue 26):
# deterministic, so a traversal change can be judged on a shared, noisy machine. Runs
# crates/scene/examples/traversal_instructions.rs on the benchmark's displaced sphere at two
# tessellations (3,968 and 65,024 triangles by default), 16,384 rays per set, and prints one
# Markdown row per mesh; its checksums show whether every hit stayed the same.
#
# Usage: bench/traversal_instructions.sh [NPHI,NTHETA ...]    (default: 64,32 256,128)
# Needs valgrind (apt-get install valgrind). CARGO_TARGET_DIR as usual.
set -euo pipefail
cd "$(dirname "$0")/.."
# Valgrind cannot run AVX-512 code: build for any x86-64, as the earlier records were (a set
# RUSTFLAGS, even empty, replaces .cargo/config.toml's target-cpu=native).
export RUSTFLAGS="${RUSTFLAGS-}"
command -v valgrind >/dev/null || { echo "valgrind is needed (apt-get install valgrind)" >&2; exit 1; }
cargo build --release --quiet -p caustica-scene --example traversal_instructions
bin="${CARGO_TARGET_DIR:-target}/release/examples/traversal_instructions"
meshes=("$@")
[ ${#meshes[@]} -gt 0 ] || meshes=(64,32 256,128)
out="$(mktemp)"
trap 'rm -f "$out"' EXIT
echo "caustica $(git rev-parse --short HEAD 2>/dev/null || echo unknown)$(git diff --quiet -- crates 2>/dev/null || echo ', with uncommitted changes')"
echo
echo "| mesh | camera (closest) | random (closest) | random (\`intersect\`) | shadow (any) | camera (\`intersect_stream\`) | shadow (\`occluded_stream\`) | checksums |"
echo "|---|---:|---:|---:|---:|---:|---:|---|"
for m in "${meshes[@]}"; do
    sums="$(valgrind --tool=callgrind --callgrind-out-file="$out" "$bin" "${m%,*}" "${m#*,}" 2>/dev/null)"
    row="$(callgrind_annotate --inclusive=yes --threshold=100 "$out" 2>/dev/null \
        | awk '$0 !~ /=>/ && /traversal_instructions::trace_(camera|random|intersect|shadow|camera_stream|shadow_stream) / {
              gsub(",", "", $1); n = split($(NF-1), a, "::"); v[a[n]] = sprintf("%.0f", $1 / 16384) }
              END { printf "%s | %s | %s | %s | %s | %s", v["trace_camera"], v["trace_random"], v["trace_intersect"], v["trace_shadow"], v["trace_camera_stream"], v["trace_shadow_stream"] }')"
    echo "| displaced_sphere(${m%,*}, ${m#*,}) | $row | ${sums#checksums: } |"
done
