#!/usr/bin/env bash
# Merges the parts of a sharded caustica render: the container of merge-job.yaml runs it once the
# Indexed Job of render-job.yaml has completed. Environment:
#   PARTS_DIR      the parts (every *.cpart in it)
#   OUT            the merged image (.exr), byte-identical to an unsharded render
#   PNG            optional: also an sRGB PNG
#   MERGE_PARTIAL  1: merge whatever shards are present into a preview and name the missing ones
#   CAUSTICA       the caustica binary (default: `caustica` on PATH)
# Arguments: further caustica merge options.
set -euo pipefail

[[ -n ${PARTS_DIR:-} ]] || { echo "merge.sh: set PARTS_DIR to the directory of the parts" >&2; exit 2; }
[[ -n ${OUT:-} ]] || { echo "merge.sh: set OUT to the merged image (.exr)" >&2; exit 2; }
caustica=${CAUSTICA:-caustica}
opts=()
[[ -n ${PNG:-} ]] && opts+=(--png "$PNG")
[[ ${MERGE_PARTIAL:-0} == 1 ]] && opts+=(--partial)

mkdir -p "$(dirname "$OUT")"
start=$SECONDS
"$caustica" merge "$PARTS_DIR" -o "$OUT" "${opts[@]+"${opts[@]}"}" "$@"
echo "merged $PARTS_DIR into $OUT in $((SECONDS - start)) s" >&2
