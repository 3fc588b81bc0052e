#!/usr/bin/env bash
# The Python package against the command line on small renders, both release builds:
# `pip install ./python` (maturin, [profile.release]) into target/py-release-venv, and
# target/release/caustica. Alternating runs; medians and ratios (bench/python_overhead.py).
#   bash bench/python_overhead.sh            (ROUNDS=7 by default)
set -euo pipefail
cd "$(dirname "$0")/.."
venv=target/py-release-venv
cargo build -q --release -p caustica-cli
if [ ! -x "$venv/bin/python" ]; then
    python3 -m venv "$venv"
fi
"$venv/bin/pip" install -q "numpy==2.4.6"
CARGO_TARGET_DIR=$PWD/target "$venv/bin/pip" install -q --force-reinstall --no-deps ./python
root=$PWD
cd target
CAUSTICA=$root/target/release/caustica "$root/$venv/bin/python" "$root/bench/python_overhead.py"
