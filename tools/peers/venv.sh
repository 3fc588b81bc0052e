#!/usr/bin/env bash
# Prints the path of a Python venv with the peer renderers (Mitsuba 3, LuxCore 2.11 as
# pyluxcore), creating or completing it if missing. Override the location with
# CAUSTICA_PEERS_VENV.
# Each import is checked in its own Python process: mitsuba must never be imported into a
# process that loaded pyluxcore (both bundle their own native libraries, TBB among them), so no peer script
# imports both.
set -euo pipefail
venv="${CAUSTICA_PEERS_VENV:-$HOME/.cache/caustica/peers-venv}"
has() { "$venv/bin/python" -c "import $1" >/dev/null 2>&1; }
if [ ! -x "$venv/bin/python" ]; then
  python3 -m venv "$venv" >&2
fi
if ! has mitsuba || ! has numpy; then
  "$venv/bin/pip" install -q mitsuba numpy >&2
fi
if ! has pyluxcore; then
  "$venv/bin/pip" install -q "pyluxcore>=2.11,<2.12" >&2
fi
echo "$venv"
