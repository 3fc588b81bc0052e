#!/usr/bin/env bash
# Submits a sharded caustica render to Slurm: an array job of N shards and a merge job that
# runs when every shard has succeeded (--dependency=afterok).
#
#   submit.sh SCENE N OUT.exr [caustica render options...]
#   e.g. submit.sh scenes/pool.toml 64 renders/pool.exr --integrator pppm --iterations 10000
#
# SCENE: a scene file (made absolute) or a built-in name; `-` for the default scene.
# Environment (all optional):
#   CAUSTICA            the caustica binary (default: `caustica` on PATH), the same path on every node
#   PARTS_DIR           where the shards write their parts (default: OUT without extension + .parts),
#                       on a file system every node sees
#   PNG                 also write this sRGB PNG at the merge
#   CPUS_PER_TASK       cores per shard (default 1; caustica's --threads follows it)
#   MAX_PARALLEL        at most this many shards at once (--array=...%K)
#   SHARDS              only these shard indices, as a Slurm array spec (e.g. 3,5 or 10-19): it
#                       becomes --array=$SHARDS (the task id is the shard index), to run failed or
#                       missing shards again; the merge then waits for them only
#   GROUP               merge in two levels, for many shards: an array job (merge_group.sbatch)
#                       merges each GROUP consecutive parts into PARTS_DIR/groups/group-KKKK.cpart,
#                       then the final merge reads the groups (each merge reads GROUP or N/GROUP
#                       films instead of N; the same bytes; about sqrt(N) is a good GROUP)
#   SBATCH_ARGS         extra sbatch options for every job (e.g. "--partition=long --time=4:00:00")
#   SHARD_SBATCH_ARGS   extra sbatch options for the array only; MERGE_SBATCH_ARGS for the merge only
# Prints the job ids (array, [group merges,] merge). Logs go to PARTS_DIR/logs/. If a shard fails for good the merge is
# cancelled (--kill-on-invalid-dep=yes); `SHARDS=... submit.sh` with the same arguments runs the
# missing shards and a new merge, and `MERGE_PARTIAL=1 sbatch merge.sbatch PARTS_DIR PREVIEW.exr`
# previews what is there.
set -euo pipefail

if [[ $# -lt 3 ]]; then
    awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "$0" >&2
    exit 2
fi
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
scene=$1 shards=$2 out=$3
shift 3
if ! [[ $shards =~ ^[1-9][0-9]*$ ]]; then
    echo "submit.sh: N must be a positive integer, not '$shards'" >&2
    exit 2
fi
[[ -e $scene ]] && scene=$(realpath "$scene")
out=$(realpath -m "$out")
parts=$(realpath -m "${PARTS_DIR:-${out%.*}.parts}")
logs="$parts/logs"
mkdir -p "$logs" "$(dirname "$out")"

# The jobs inherit this environment (sbatch's default --export=ALL): pin the binary's full path.
caustica=${CAUSTICA:-caustica}
if resolved=$(command -v "$caustica"); then
    caustica=$(realpath "$resolved")
else
    echo "submit.sh: warning: '$caustica' is not on this host's PATH; the jobs look for it on theirs" >&2
fi
export CAUSTICA=$caustica

# The array task id is the shard index (caustica render --shard /N): 0-based, or a subset of 0..N-1.
array=${SHARDS:-0-$((shards - 1))}
if [[ -n ${SHARDS:-} ]]; then
    # Each index (range ends; a range's :step left out) must be a shard of 0..N-1.
    IFS=, read -r -a pieces <<<"${SHARDS%%\%*}"
    for piece in "${pieces[@]}"; do
        piece=${piece%%:*}
        for k in ${piece/-/ }; do
            if ! [[ $k =~ ^[0-9]+$ ]] || ((10#$k >= shards)); then
                echo "submit.sh: SHARDS=$SHARDS: '$k' is not a shard index of 0..$((shards - 1))" >&2
                exit 2
            fi
        done
    done
fi
[[ -n ${MAX_PARALLEL:-} ]] && array+="%$MAX_PARALLEL"

read -r -a common <<<"${SBATCH_ARGS:-}"
read -r -a shard_extra <<<"${SHARD_SBATCH_ARGS:-}"
read -r -a merge_extra <<<"${MERGE_SBATCH_ARGS:-}"
merge_opts=()
[[ -n ${PNG:-} ]] && merge_opts=(--png "$(realpath -m "$PNG")")

array_id=$(sbatch --parsable --array="$array" \
    --cpus-per-task="${CPUS_PER_TASK:-1}" \
    --output="$logs/shard-%A_%a.out" \
    "${common[@]+"${common[@]}"}" "${shard_extra[@]+"${shard_extra[@]}"}" \
    "$here/render_array.sbatch" "$scene" "$shards" "$parts" "$@")
array_id=${array_id%%;*}
# With GROUP, a level of group merges between the shards and the final merge.
after=$array_id merge_from=$parts group_id=""
if [[ -n ${GROUP:-} ]]; then
    if ! [[ $GROUP =~ ^[1-9][0-9]*$ ]]; then
        echo "submit.sh: GROUP must be a positive integer, not '$GROUP'" >&2
        exit 2
    fi
    groups=$(((shards + GROUP - 1) / GROUP))
    rm -rf "$parts/groups"
    group_id=$(sbatch --parsable --array="0-$((groups - 1))" \
        --dependency="afterok:$array_id" --kill-on-invalid-dep=yes \
        --output="$logs/group-%A_%a.out" \
        "${common[@]+"${common[@]}"}" "${merge_extra[@]+"${merge_extra[@]}"}" \
        "$here/merge_group.sbatch" "$parts" "$shards" "$GROUP")
    group_id=${group_id%%;*}
    after=$group_id merge_from=$parts/groups
fi
merge_id=$(sbatch --parsable --dependency="afterok:$after" --kill-on-invalid-dep=yes \
    --output="$logs/merge-%j.out" \
    "${common[@]+"${common[@]}"}" "${merge_extra[@]+"${merge_extra[@]}"}" \
    "$here/merge.sbatch" "$merge_from" "$out" "${merge_opts[@]+"${merge_opts[@]}"}")
merge_id=${merge_id%%;*}
echo "caustica: array job $array_id (shards $array of $shards) -> $parts;${group_id:+ group merges $group_id (groups of $GROUP) -> $parts/groups;} merge job $merge_id -> $out" >&2
echo "$array_id${group_id:+ $group_id} $merge_id"
