"""Shared fixtures: the `caustica` binary the Python package is checked against."""

import os
import pathlib
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]


def _binary() -> pathlib.Path:
    given = os.environ.get("CAUSTICA_BIN")
    if given:
        return pathlib.Path(given)
    for profile in ("fast", "release"):
        p = ROOT / "target" / profile / "caustica"
        if p.exists():
            return p
    pytest.fail("no caustica binary: build it (cargo build --profile fast) or set CAUSTICA_BIN")


@pytest.fixture(scope="session")
def cli():
    """Runs `caustica ARGS` from the repository root; returns the CompletedProcess."""
    exe = _binary()

    def run(*args, check=True):
        r = subprocess.run([str(exe), *map(str, args)], cwd=ROOT, capture_output=True, text=True)
        if check and r.returncode != 0:
            raise AssertionError(f"caustica {' '.join(map(str, args))} failed:\n{r.stderr}")
        return r

    return run


@pytest.fixture(scope="session")
def root():
    return ROOT
