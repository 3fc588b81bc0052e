#!/usr/bin/env bash
# One shard of a caustica render, run by each pod of the Indexed Job in render-job.yaml.
# Kubernetes sets JOB_COMPLETION_INDEX (0..completions-1), which `caustica render --shard /N`
# takes as the shard index. Environment (the Job's container sets these):
#   SHARDS          N, the number of shards: the Job's `completions`
#   SCENE           a scene file (on the shared volume or in the image) or a built-in name;
#                   empty for the default scene
#   PARTS_DIR       where the part is written (PARTS_DIR/shard-IIII-of-NNNN.cpart), on the shared volume
#   CAUSTICA_ARGS   caustica render options, split at spaces (no quoting; for options with spaces
#                   give them as this script's arguments, the container's `args`)
#   CAUSTICA_THREADS  --threads (the Job passes the container's CPU limit), unless the options give it
#   CAUSTICA        the caustica binary (default: `caustica` on PATH)
# Arguments: further caustica render options, word for word.
# A retried index overwrites its own part, so retries (backoffLimitPerIndex) are safe.
set -euo pipefail

fail() {
    echo "shard.sh: $*" >&2
    exit 2
}
[[ -n ${JOB_COMPLETION_INDEX:-} ]] || fail "JOB_COMPLETION_INDEX is not set: run it in an Indexed Job (completionMode: Indexed)"
[[ -n ${SHARDS:-} ]] || fail "set SHARDS to the number of shards (the Job's completions)"
[[ -n ${PARTS_DIR:-} ]] || fail "set PARTS_DIR to a directory on the shared volume"
caustica=${CAUSTICA:-caustica}

read -r -a opts <<<"${CAUSTICA_ARGS:-}"
opts+=("$@")
has_option() {
    local arg flag
    for arg in "${opts[@]+"${opts[@]}"}"; do
        for flag in "$@"; do
            [[ $arg == "$flag" || $arg == "$flag="* ]] && return 0
        done
    done
    return 1
}
if [[ -n ${CAUSTICA_THREADS:-} ]] && ! has_option --threads; then
    opts+=(--threads "$CAUSTICA_THREADS")
fi
has_option -q --quiet || opts+=(--quiet)
scene_arg=()
[[ -z ${SCENE:-} || ${SCENE:-} == - ]] || scene_arg=("$SCENE")

mkdir -p "$PARTS_DIR"
echo "caustica shard $JOB_COMPLETION_INDEX of $SHARDS on ${HOSTNAME:-$(hostname)}" >&2
start=$SECONDS
"$caustica" render "${scene_arg[@]+"${scene_arg[@]}"}" "${opts[@]}" --shard "/$SHARDS" -o "$PARTS_DIR/"
echo "shard $JOB_COMPLETION_INDEX done in $((SECONDS - start)) s" >&2
