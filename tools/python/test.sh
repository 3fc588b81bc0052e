#!/usr/bin/env bash
# Tests of the Python package (python/): builds its wheel with maturin into a venv kept in
# target/py-venv (maturin, NumPy and pytest from PyPI), installs it, and runs python/tests
# against the `caustica` binary of the same build (CAUSTICA_BIN, default
# ${CARGO_TARGET_DIR:-target}/fast/caustica).
#
# The wheel is built with the `fast` profile into the workspace's target directory, so after
# `cargo test --workspace --profile fast` (which builds the extension crate with the same
# features) maturin only links it.
set -euo pipefail
cd "$(dirname "$0")/../.."

venv=${PY_VENV:-target/py-venv}
if ! "$venv/bin/python" -c "import maturin, numpy, pytest" >/dev/null 2>&1; then
    python3 -m venv "$venv"
    "$venv/bin/pip" install -q "maturin==1.16.0" "numpy==2.4.6" "pytest==9.2.0"
fi
# The binary with the features `cargo test --workspace` unifies (built by it already; a
# `-p caustica-cli` build would unify fewer and compile the renderer again).
cargo build -q --profile fast --workspace --bin caustica
rm -rf target/wheels
"$venv/bin/maturin" build -q --profile fast -m python/Cargo.toml -o target/wheels
"$venv/bin/pip" install -q --force-reinstall --no-deps target/wheels/caustica-*.whl
# From outside the source tree, so `import caustica` is the installed package.
root=$PWD
cd target
target_dir=${CARGO_TARGET_DIR:-$root/target}
CAUSTICA_BIN=${CAUSTICA_BIN:-$target_dir/fast/caustica} "$root/$venv/bin/python" -m pytest -q -p no:cacheprovider "$root/python/tests" "$@"
