#!/usr/bin/env bash
# caustica's BVH against Embree 3 (issue 26): build times and single-thread Mrays/s of
# caustica's `Geometry` queries and Embree's rtcIntersect1/8/1M and rtcOccluded1/8/1M on the
# workload of crates/scene/benches/bvh.rs (the shared crates/scene/benches/workload/mod.rs:
# displaced sphere of 1,046,528 triangles; 512x512 camera rays, their diffuse bounces, 200,000
# random rays, 200,000 shadow segments), with a hit-agreement check. The bench crate
# (bench/embree) is its own workspace, outside the root build.
#
# Usage: bench/embree_vs_caustica.sh [REPS] [--reps N] [--build-reps N] [--out FILE | --no-write]
#        [--robust] [--mesh NPHI,NTHETA]
# Arguments pass through to the benchmark (default: 9 traversal and 3 build repetitions, the
# report written to docs/results/embree/latest.md). CARGO_TARGET_DIR defaults to
# target/embree-bench. Installs Debian's libembree-dev if its header is missing.
set -euo pipefail
cd "$(dirname "$0")/.."
if [ ! -f /usr/include/embree3/rtcore.h ]; then
    sudo=""
    if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
    echo "installing libembree-dev (Embree 3) with apt-get" >&2
    $sudo apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq libembree-dev >&2
fi
export CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-$PWD/target/embree-bench}"
commit="$(git rev-parse --short HEAD 2>/dev/null || echo unknown)"
if [ "$commit" != unknown ] && [ -n "$(git status --porcelain -- crates/core crates/scene 2>/dev/null)" ]; then
    commit="$commit, with uncommitted changes under crates/core or crates/scene"
fi
echo "caustica $commit; nproc $(nproc); $(grep -m1 'model name' /proc/cpuinfo | sed 's/.*: //'); $(rustc --version)" >&2
echo "rustflags: ${RUSTFLAGS-$(grep -m1 '^rustflags' .cargo/config.toml 2>/dev/null || echo none) (.cargo/config.toml)}" >&2
cd bench/embree
cargo build --release --quiet
exec cargo run --release --quiet -- "$@"
