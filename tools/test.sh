#!/usr/bin/env bash
# The test suite (the README's test command): every Rust test of the workspace, then the
# Python package's tests (tools/python/test.sh, which installs maturin, NumPy and pytest from
# PyPI into target/py-venv the first time).
set -euo pipefail
cd "$(dirname "$0")/.."
cargo test --workspace --profile fast "$@"
bash tools/python/test.sh
