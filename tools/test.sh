#!/usr/bin/env bash
# The test suite (the README's test command): every Rust test of the workspace (and the
# scene crate's traversal-counter test, which needs its feature), then the
# Python package's tests (tools/python/test.sh, which installs maturin, NumPy and pytest from
# PyPI into target/py-venv the first time).
set -euo pipefail
cd "$(dirname "$0")/.."
cargo test --workspace --profile fast "$@"
# The traversal counters exist only with their feature (off in every other build).
cargo test -p caustica-scene --profile fast --features traversal-counts --test traversal_counts
bash tools/python/test.sh
