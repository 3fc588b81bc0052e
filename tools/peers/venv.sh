#!/usr/bin/env bash
# Prints the path of a Python venv with the peer renderers (Mitsuba 3), creating it if missing.
# Override the location with CAUSTICA_PEERS_VENV.
set -euo pipefail
venv="${CAUSTICA_PEERS_VENV:-$HOME/.cache/caustica/peers-venv}"
if [ ! -x "$venv/bin/python" ] || ! "$venv/bin/python" -c "import mitsuba" >/dev/null 2>&1; then
  python3 -m venv "$venv" >&2
  "$venv/bin/pip" install -q mitsuba numpy >&2
fi
echo "$venv"
