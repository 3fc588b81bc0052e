#!/usr/bin/env bash
# Tests the Slurm, Kubernetes and Ray paths of tools/distributed against the caustica binary:
# every sharded run must merge to the bytes of the unsharded render.
#   (a) the unsharded references (cornell-box: path tracer, light tracer)
#   (b) Slurm: render_array.sbatch run for every array index with the environment Slurm gives a
#       task (shuffled; resubmitted subsets, --array=1 and --array=3,5, whose task ids are the
#       shard indices), merge.sbatch, a missing shard, a shard's temporary *.partial.cpart left in
#       the directory, --partial, and submit.sh (also SHARDS=1,3) against a stand-in sbatch
#   (c) Kubernetes: the manifests checked (against the API models if the kubernetes client is
#       installed), their containers' commands run with the environment of an Indexed Job's pods
#       (JOB_COMPLETION_INDEX), the merge job's command; shard.sh directly
#   (d) Ray: ray_render.py on a local Ray cluster of 2 CPUs, 4 shards, a worker killed in the
#       middle of a shard and retried by Ray, with --watch; a failing task resubmitted by the driver
# Environment: CAUSTICA (the binary; default caustica on PATH), PYTHON (a Python with ray, pyyaml
# and optionally kubernetes; default python3), REQUIRE_RAY=1 to fail instead of skipping (d) and
# the manifest checks when Ray or PyYAML is missing. Ends with "engines: N passed, N failed".
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
CAUSTICA=$(command -v "${CAUSTICA:-caustica}") || { echo "test_engines: caustica binary not found (set CAUSTICA)" >&2; exit 2; }
CAUSTICA=$(realpath "$CAUSTICA")
export CAUSTICA
PYTHON=${PYTHON:-python3}
REQUIRE_RAY=${REQUIRE_RAY:-0}
export RAY_USAGE_STATS_ENABLED=0

work=$(mktemp -d "${TMPDIR:-/tmp}/caustica-engines.XXXXXX")
trap 'rm -rf "$work"' EXIT
log=$work/log
pass=0 fail=0 skip=0
ok() { echo "ok - $*"; pass=$((pass + 1)); }
not_ok() { echo "not ok - $*"; fail=$((fail + 1)); }
skipped() { echo "skip - $*"; skip=$((skip + 1)); }
# same NAME REFERENCE FILE: the bytes must be equal.
same() {
    if [[ ! -f $3 ]]; then
        not_ok "$1: $3 was not written"
    elif cmp "$2" "$3" >"$work/cmp" 2>&1; then
        ok "$1: identical to the unsharded render ($(stat -c %s "$3") bytes)"
    else
        not_ok "$1: differs from the unsharded render: $(cat "$work/cmp")"
    fi
}
# Runs a command quietly; on failure shows its output and counts a failure.
run() {
    local name=$1
    shift
    local status=0
    "$@" >"$log" 2>&1 || status=$?
    ((status == 0)) && return 0
    not_ok "$name: command failed (status $status): $*"
    sed 's/^/    /' "$log" | tail -n 30
    return 1
}

SCENE=cornell-box
PATH_OPTS=(--integrator path --spp 4 --width 64 --seed 7)
LT_OPTS=(--integrator lighttrace --spp 2 --width 64 --seed 3)
# Shards long enough for the injected kill (0.3 s in) to land mid-render: about 1 s each on one
# thread here (at 256 spp a shard took 0.26 s once builds targeted the building CPU, and the
# kill came after it had finished).
RAY_OPTS=(--integrator path --spp 1024 --width 64 --seed 5)
SECONDS=0

echo "# (a) unsharded references ($CAUSTICA)"
run "reference (path)" "$CAUSTICA" render "$SCENE" "${PATH_OPTS[@]}" -q -o "$work/ref-path.exr" &&
    ok "reference (path): $(stat -c %s "$work/ref-path.exr") bytes"
run "reference (lighttrace)" "$CAUSTICA" render "$SCENE" "${LT_OPTS[@]}" -q -o "$work/ref-lt.exr" &&
    ok "reference (lighttrace): $(stat -c %s "$work/ref-lt.exr") bytes"
run "reference (path, 256 spp)" "$CAUSTICA" render "$SCENE" "${RAY_OPTS[@]}" -q -o "$work/ref-ray.exr" &&
    ok "reference (path, 256 spp): $(stat -c %s "$work/ref-ray.exr") bytes"

echo "# (b) Slurm array: render_array.sbatch and merge.sbatch with the environment of array tasks"
slurm=$here/slurm
# slurm_task TASK_ID MIN MAX JOB_ID SCRIPT ARGS...: one array task, as slurmd starts it
# (TASK_COUNT: the array's task count, if not MAX - MIN + 1).
slurm_task() {
    local id=$1 min=$2 max=$3 job=$4
    shift 4
    env SLURM_ARRAY_JOB_ID="$job" SLURM_ARRAY_TASK_ID="$id" SLURM_ARRAY_TASK_MIN="$min" \
        SLURM_ARRAY_TASK_MAX="$max" SLURM_ARRAY_TASK_COUNT="${TASK_COUNT:-$((max - min + 1))}" SLURM_ARRAY_TASK_STEP=1 \
        SLURM_JOB_ID=$((job + id + 1)) SLURM_JOBID=$((job + id + 1)) SLURM_JOB_NAME=caustica-shard \
        SLURM_CPUS_PER_TASK=1 SLURM_CPUS_ON_NODE=1 SLURM_NNODES=1 SLURM_JOB_NUM_NODES=1 \
        SLURM_NODELIST="$(hostname -s)" SLURM_SUBMIT_DIR="$work" SLURM_CLUSTER_NAME=test \
        bash "$@"
}
parts=$work/slurm/parts
ran=1
for i in 2 0 1; do
    slurm_task "$i" 0 2 500 "$slurm/render_array.sbatch" "$SCENE" 3 "$parts" "${PATH_OPTS[@]}" >"$log" 2>&1 ||
        { ran=0; not_ok "slurm: task $i of --array=0-2 failed"; sed 's/^/    /' "$log" | tail -n 20; }
done
if ((ran)); then
    if [[ $(find "$parts" -name '*.cpart' | wc -l) == 3 && -f $parts/shard-0002-of-0003.cpart ]]; then
        ok "slurm: 3 tasks (run as 2, 0, 1) wrote shard-000{0,1,2}-of-0003.cpart"
    else
        not_ok "slurm: expected 3 parts named shard-IIII-of-0003.cpart, found: $(ls "$parts")"
    fi
    run "slurm merge" env SLURM_JOB_ID=504 bash "$slurm/merge.sbatch" "$parts" "$work/slurm/out.exr" &&
        same "slurm: 3 shards merged" "$work/ref-path.exr" "$work/slurm/out.exr"
    # A shard rendered again and killed while writing leaves its temporary file (the part's name
    # with .partial.cpart) next to the complete parts: the merge skips it.
    head -c 1000 "$parts/shard-0001-of-0003.cpart" >"$parts/shard-0001-of-0003.partial.cpart"
    run "slurm merge beside a .partial.cpart" bash "$slurm/merge.sbatch" "$parts" "$work/slurm/out-tmp.exr" &&
        same "slurm: merged with a half-written shard-0001-of-0003.partial.cpart in the directory" \
            "$work/ref-path.exr" "$work/slurm/out-tmp.exr"
fi

# A shard is idempotent by index: rendered again, its part has the same bytes.
cp "$parts/shard-0001-of-0003.cpart" "$work/slurm/saved-1.cpart"
rm "$parts/shard-0001-of-0003.cpart"
# Without shard 1 (still writing: only its .partial.cpart is there) the merge fails, names shard 1
# missing and writes nothing; --partial previews the rest.
if env SLURM_JOB_ID=505 bash "$slurm/merge.sbatch" "$parts" "$work/slurm/missing.exr" >"$log" 2>&1; then
    not_ok "slurm: merge with shard 1 of 3 missing succeeded"
elif [[ -e $work/slurm/missing.exr ]]; then
    not_ok "slurm: merge with a missing shard failed but wrote $work/slurm/missing.exr"
elif grep -q 'partial\.cpart' "$log" || ! grep -q 'missing' "$log"; then
    not_ok "slurm: merge with shard 1 missing (a .partial.cpart present) failed for another reason: $(tail -n1 "$log")"
else
    ok "slurm: merge refuses a missing shard: $(grep -m1 -i 'shard' "$log" || tail -n1 "$log")"
fi
if env MERGE_PARTIAL=1 SLURM_JOB_ID=506 bash "$slurm/merge.sbatch" "$parts" "$work/slurm/preview.exr" >"$log" 2>&1 &&
    [[ -s $work/slurm/preview.exr ]]; then
    ok "slurm: MERGE_PARTIAL=1 previews 2 of 3 shards: $(grep -m1 -i 'missing' "$log" || tail -n1 "$log")"
else
    not_ok "slurm: MERGE_PARTIAL=1 merge.sbatch failed"
    sed 's/^/    /' "$log" | tail -n 20
fi
# Resubmitting the missing shard (sbatch --array=1, as submit.sh SHARDS=1 does: SLURM_ARRAY_TASK_MIN
# is 1 too, and the task id is the index). It replaces the temporary file.
resubmitted=0
slurm_task 1 1 1 600 "$slurm/render_array.sbatch" "$SCENE" 3 "$parts" "${PATH_OPTS[@]}" >"$log" 2>&1 && resubmitted=1
if ((resubmitted)); then
    if cmp -s "$work/slurm/saved-1.cpart" "$parts/shard-0001-of-0003.cpart" &&
        [[ ! -e $parts/shard-0001-of-0003.partial.cpart && $(find "$parts" -name '*.cpart' | wc -l) == 3 ]]; then
        ok "slurm: shard 1 resubmitted alone (--array=1) wrote the same bytes again"
    else
        not_ok "slurm: shard 1 resubmitted alone wrote different bytes (or another file: $(ls "$parts"))"
    fi
    run "slurm merge after resubmission" bash "$slurm/merge.sbatch" "$parts" "$work/slurm/out2.exr" &&
        same "slurm: merged after the resubmission" "$work/ref-path.exr" "$work/slurm/out2.exr"
else
    not_ok "slurm: resubmitted task 1 failed"
    sed 's/^/    /' "$log" | tail -n 20
fi

# A resubmitted subset, --array=3,5 of 6 shards: SLURM_ARRAY_TASK_MIN is 3, and task 5 renders
# shard 5 (the task id as is, not minus the minimum). Into an empty directory: only shards 3 and 5
# appear, with the bytes of the full array's; with the other four the merge is the unsharded image.
full6=$work/slurm6/full subset6=$work/slurm6/subset
ran=1
for i in 5 0 3 1 4 2; do
    slurm_task "$i" 0 5 700 "$slurm/render_array.sbatch" "$SCENE" 6 "$full6" "${PATH_OPTS[@]}" >"$log" 2>&1 ||
        { ran=0; not_ok "slurm: task $i of --array=0-5 failed"; sed 's/^/    /' "$log" | tail -n 20; }
done
for i in 5 3; do
    TASK_COUNT=2 slurm_task "$i" 3 5 800 "$slurm/render_array.sbatch" "$SCENE" 6 "$subset6" "${PATH_OPTS[@]}" >"$log" 2>&1 ||
        { ran=0; not_ok "slurm: task $i of --array=3,5 failed"; sed 's/^/    /' "$log" | tail -n 20; }
    # The shard's one-line summary names the shard it rendered: `..., shard 5/6 (<work>, X MB) in T s`.
    if [[ $i == 5 ]] && ((ran)); then
        if grep -q 'shard 5/6 (.* MB) in [0-9.]* s' "$log"; then
            ok "slurm: task 5 of --array=3,5 (SLURM_ARRAY_TASK_MIN=3) rendered $(grep -o 'shard 5/6 ([^)]*)' "$log")"
        else
            not_ok "slurm: task 5 of --array=3,5: no 'shard 5/6 (…) in T s' in its log: $(grep -m1 'shard' "$log")"
        fi
    fi
done
if ((ran)); then
    subset_files=$(cd "$subset6" && ls)
    if [[ $subset_files == $'shard-0003-of-0006.cpart\nshard-0005-of-0006.cpart' ]] &&
        cmp -s "$full6/shard-0003-of-0006.cpart" "$subset6/shard-0003-of-0006.cpart" &&
        cmp -s "$full6/shard-0005-of-0006.cpart" "$subset6/shard-0005-of-0006.cpart"; then
        ok "slurm: --array=3,5 wrote shard-0003 and shard-0005-of-0006.cpart, the bytes of the full array's"
    else
        not_ok "slurm: --array=3,5 wrote $(tr '\n' ' ' <<<"$subset_files")(expected shards 3 and 5, as in the full array)"
    fi
    for i in 0 1 2 4; do cp "$full6/shard-000$i-of-0006.cpart" "$subset6/"; done
    run "slurm merge (--array=0-5 and 3,5)" bash "$slurm/merge.sbatch" "$subset6" "$work/slurm6/out.exr" &&
        same "slurm: 6 shards, 3 and 5 from the resubmitted --array=3,5" "$work/ref-path.exr" "$work/slurm6/out.exr"
fi
# Outside an array job the script says so.
if bash "$slurm/render_array.sbatch" "$SCENE" 3 "$work/slurm-x" "${PATH_OPTS[@]}" >"$log" 2>&1; then
    not_ok "slurm: render_array.sbatch ran without SLURM_ARRAY_TASK_ID"
else
    ok "slurm: outside an array job: $(tail -n1 "$log")"
fi

# submit.sh against a stand-in sbatch that runs each job here at once, with Slurm's environment,
# and honours --dependency=afterok.
mkdir -p "$work/bin" "$work/sbatch"
cat >"$work/bin/sbatch" <<'STUB'
#!/usr/bin/env bash
# Stand-in for sbatch (test_engines.sh): runs the job now, here, with Slurm's environment.
set -uo pipefail
state=$STUB_SBATCH_STATE
id=$(($(cat "$state/next" 2>/dev/null || echo 9000) + 1))
echo "$id" >"$state/next"
echo "sbatch $*" >>"$state/calls"
array="" dep="" parsable=0 output="" cpus=1
while [[ $# -gt 0 && $1 == -* ]]; do
    case $1 in
        --array=*) array=${1#*=} ;;
        --dependency=*) dep=${1#*=} ;;
        --parsable) parsable=1 ;;
        --output=*) output=${1#*=} ;;
        --cpus-per-task=*) cpus=${1#*=} ;;
        *) ;;
    esac
    shift
done
script=$1
shift
if [[ -n $dep ]]; then
    [[ $dep == afterok:* ]] || { echo "stub sbatch: unsupported dependency $dep" >&2; exit 1; }
    [[ -e $state/ok-${dep#afterok:} ]] || { echo "stub sbatch: dependency $dep never satisfied" >&2; echo "$id" >"$state/cancelled"; echo "$id"; exit 0; }
fi
status=0
if [[ -n $array ]]; then
    spec=${array%%\%*}
    idx=()
    IFS=, read -r -a pieces <<<"$spec"
    for p in "${pieces[@]}"; do
        if [[ $p == *-* ]]; then for ((k = ${p%-*}; k <= ${p#*-}; k++)); do idx+=("$k"); done; else idx+=("$p"); fi
    done
    min=$(printf '%s\n' "${idx[@]}" | sort -n | head -n1)
    max=$(printf '%s\n' "${idx[@]}" | sort -n | tail -n1)
    for k in "${idx[@]}"; do
        o=${output:-slurm-%A_%a.out}; o=${o//%A/$id}; o=${o//%a/$k}
        SLURM_ARRAY_JOB_ID=$id SLURM_ARRAY_TASK_ID=$k SLURM_ARRAY_TASK_MIN=$min SLURM_ARRAY_TASK_MAX=$max \
            SLURM_ARRAY_TASK_COUNT=${#idx[@]} SLURM_JOB_ID=$((id * 100 + k)) SLURM_CPUS_PER_TASK=$cpus \
            bash "$script" "$@" >"$o" 2>&1 || status=1
    done
else
    o=${output:-slurm-%j.out}; o=${o//%j/$id}
    SLURM_JOB_ID=$id bash "$script" "$@" >"$o" 2>&1 || status=1
fi
((status == 0)) && touch "$state/ok-$id"
echo "$id"
STUB
chmod +x "$work/bin/sbatch"
export STUB_SBATCH_STATE=$work/sbatch
if PATH="$work/bin:$PATH" bash "$slurm/submit.sh" "$SCENE" 4 "$work/submit/out.exr" "${PATH_OPTS[@]}" >"$log" 2>&1; then
    ids=$(tail -n1 "$log")
    if grep -q -- "--dependency=afterok:${ids%% *} .*merge.sbatch" "$work/sbatch/calls" &&
        grep -q -- "--array=0-3 .*render_array.sbatch" "$work/sbatch/calls"; then
        ok "slurm: submit.sh submitted --array=0-3 and a merge with --dependency=afterok:${ids%% *}"
    else
        not_ok "slurm: submit.sh's sbatch calls: $(cat "$work/sbatch/calls")"
    fi
    same "slurm: submit.sh (4 shards, stand-in sbatch)" "$work/ref-path.exr" "$work/submit/out.exr"
    # Shards 1 and 3 lost: SHARDS=1,3 submits --array=1,3 (task ids = shard indices) and a new merge.
    sparts=$work/submit/out.parts
    mkdir -p "$work/submit/saved"
    mv "$sparts/shard-0001-of-0004.cpart" "$sparts/shard-0003-of-0004.cpart" "$work/submit/saved/"
    mv "$work/submit/out.exr" "$work/submit/first.exr"
    if SHARDS=1,3 PATH="$work/bin:$PATH" bash "$slurm/submit.sh" "$SCENE" 4 "$work/submit/out.exr" "${PATH_OPTS[@]}" >"$log" 2>&1; then
        if grep -q -- "--array=1,3 .*render_array.sbatch" "$work/sbatch/calls" &&
            cmp -s "$work/submit/saved/shard-0001-of-0004.cpart" "$sparts/shard-0001-of-0004.cpart" &&
            cmp -s "$work/submit/saved/shard-0003-of-0004.cpart" "$sparts/shard-0003-of-0004.cpart" &&
            [[ $(find "$sparts" -maxdepth 1 -name '*.cpart' | wc -l) == 4 ]]; then
            ok "slurm: SHARDS=1,3 submit.sh submitted --array=1,3, which rewrote shards 1 and 3 with the same bytes"
        else
            not_ok "slurm: SHARDS=1,3 submit.sh: calls $(grep -o -- '--array=[^ ]*' "$work/sbatch/calls" | tr '\n' ' '), parts $(ls "$sparts" | tr '\n' ' ')"
        fi
        same "slurm: merged again after SHARDS=1,3 submit.sh" "$work/ref-path.exr" "$work/submit/out.exr"
    else
        not_ok "slurm: SHARDS=1,3 submit.sh failed"
        sed 's/^/    /' "$log" | tail -n 20
        tail -n 5 "$sparts"/logs/* 2>/dev/null | sed 's/^/    /'
    fi
else
    not_ok "slurm: submit.sh failed"
    sed 's/^/    /' "$log" | tail -n 20
    cat "$work"/submit/out.parts/logs/* 2>/dev/null | tail -n 20 | sed 's/^/    /'
fi

# A tree of merges: GROUP=2 with 5 shards submits group merges (3 groups) between the array and
# the final merge, which reads only the groups.
if GROUP=2 PATH="$work/bin:$PATH" bash "$slurm/submit.sh" "$SCENE" 5 "$work/group/out.exr" "${PATH_OPTS[@]}" >"$log" 2>&1; then
    ids=$(tail -n1 "$log")
    gparts=$work/group/out.parts
    if [[ $(wc -w <<<"$ids") == 3 ]] &&
        grep -q -- "--array=0-2 --dependency=afterok:${ids%% *} .*merge_group.sbatch" "$work/sbatch/calls" &&
        [[ $(find "$gparts/groups" -maxdepth 1 -name 'group-*.cpart' | wc -l) == 3 ]]; then
        ok "slurm: GROUP=2 submit.sh: 5 shards, 3 group merges after the array, the final merge after them"
    else
        not_ok "slurm: GROUP=2 submit.sh: ids '$ids', calls $(grep -o -- '--array=[^ ]* [^ ]*' "$work/sbatch/calls" | tr '\n' ' '), groups $(ls "$gparts/groups" 2>/dev/null | tr '\n' ' ')"
    fi
    same "slurm: GROUP=2 submit.sh (a two-level merge of 5 shards)" "$work/ref-path.exr" "$work/group/out.exr"
else
    not_ok "slurm: GROUP=2 submit.sh failed"
    sed 's/^/    /' "$log" | tail -n 20
    cat "$work"/group/out.parts/logs/* 2>/dev/null | tail -n 20 | sed 's/^/    /'
fi

echo "# (c) Kubernetes Indexed Job: the manifests' commands with the environment of their pods"
k8s=$here/k8s
# shard.sh and merge.sh directly, as the containers run them (light tracer, 2 shards).
kparts=$work/k8s-direct/parts
ran=1
for i in 1 0; do
    env JOB_COMPLETION_INDEX=$i SHARDS=2 SCENE=$SCENE PARTS_DIR="$kparts" CAUSTICA_ARGS="${LT_OPTS[*]}" \
        CAUSTICA_THREADS=1 HOSTNAME=caustica-render-t-$i bash "$k8s/shard.sh" >"$log" 2>&1 ||
        { ran=0; not_ok "k8s: shard.sh index $i failed"; sed 's/^/    /' "$log" | tail -n 20; }
done
if ((ran)); then
    run "k8s merge.sh" env PARTS_DIR="$kparts" OUT="$work/k8s-direct/out.exr" PNG="$work/k8s-direct/out.png" bash "$k8s/merge.sh" &&
        same "k8s: shard.sh with JOB_COMPLETION_INDEX 1, 0 and merge.sh (lighttrace)" "$work/ref-lt.exr" "$work/k8s-direct/out.exr"
fi
if env SHARDS=2 PARTS_DIR="$kparts" bash "$k8s/shard.sh" >"$log" 2>&1; then
    not_ok "k8s: shard.sh ran without JOB_COMPLETION_INDEX"
else
    ok "k8s: without JOB_COMPLETION_INDEX: $(tail -n1 "$log")"
fi

if "$PYTHON" -c "import yaml" 2>/dev/null; then
    sets=(--set RUN=t1 --set IMAGE=caustica:test --set SHARDS=4 --set PARALLELISM=2 --set CPUS=1
        --set "SCENE=$SCENE" --set "CAUSTICA_ARGS=${PATH_OPTS[*]}")
    for m in pvc.yaml render-job.yaml merge-job.yaml; do
        if "$PYTHON" "$k8s/local_pod.py" check "$k8s/$m" "${sets[@]}" >"$log" 2>&1; then
            ok "k8s: $(tail -n1 "$log")"
        else
            not_ok "k8s: $m: $(cat "$log")"
        fi
    done
    pod=("$PYTHON" "$k8s/local_pod.py" run --map "/data=$work/k8s" --map "/opt/caustica-distributed=$k8s"
        --env "CAUSTICA=$CAUSTICA" "${sets[@]}")
    ran=1
    for i in 3 0 2 1; do
        "${pod[@]}" "$k8s/render-job.yaml" --index "$i" >"$log" 2>&1 ||
            { ran=0; not_ok "k8s: render-job pod of index $i failed"; sed 's/^/    /' "$log" | tail -n 20; }
    done
    if ((ran)); then
        run "k8s merge-job pod" "${pod[@]}" "$k8s/merge-job.yaml" &&
            same "k8s: render-job.yaml's 4 pods (indices 3, 0, 2, 1) and merge-job.yaml's" "$work/ref-path.exr" "$work/k8s/t1/out.exr"
    fi
elif [[ $REQUIRE_RAY == 1 ]]; then
    not_ok "k8s: $PYTHON has no PyYAML: the manifests were not checked"
else
    skipped "k8s: manifests (no PyYAML in $PYTHON)"
fi

echo "# (d) Ray: ray_render.py on a local cluster of 2 CPUs"
if "$PYTHON" -c "import ray" 2>/dev/null; then
    ray_version=$("$PYTHON" -c "import ray; print(ray.__version__)")
    t0=$SECONDS
    if "$PYTHON" "$here/ray_render.py" --num-cpus 2 --shards 4 --inject-failure 1 --no-bar \
        --watch "$work/ray/preview.exr" -o "$work/ray/out.exr" -- "$SCENE" "${RAY_OPTS[@]}" >"$log" 2>&1; then
        same "ray $ray_version: 4 shards on 2 CPUs, worker of shard 1 killed mid-shard ($((SECONDS - t0)) s)" \
            "$work/ref-ray.exr" "$work/ray/out.exr"
        if grep -q "shard 1 done.*recovered from the injected failure.*caustica was running" "$log"; then
            ok "ray: Ray retried shard 1 after its worker died: $(grep -o 'shard 1 done.*' "$log" | head -n1)"
        else
            not_ok "ray: no sign of the retried shard 1 in the driver's log"
            sed 's/^/    /' "$log" | tail -n 20
        fi
        if [[ $(grep -c '^\[[ 0-9]*/4\] shard' "$log") == 4 ]] && grep -q "ETA" "$log"; then
            ok "ray: a progress line with ETA per shard"
        else
            not_ok "ray: progress lines missing"
        fi
        if [[ $(grep -c '^preview -> ' "$log") == 4 && -s $work/ray/preview.exr ]]; then
            ok "ray: --watch wrote a preview after each of the 4 shards"
            same "ray: the last --watch preview (merge --partial of all 4 shards)" "$work/ref-ray.exr" "$work/ray/preview.exr"
        else
            not_ok "ray: --watch previews: $(grep -c 'preview' "$log") lines"
        fi
    else
        not_ok "ray: ray_render.py failed"
        sed 's/^/    /' "$log" | tail -n 30
    fi
    # Ray gives up at once (--max-retries 0); the driver submits the shard again.
    t0=$SECONDS
    if "$PYTHON" "$here/ray_render.py" --num-cpus 2 --shards 4 --inject-failure 2 --inject-mode raise \
        --max-retries 0 --no-bar -o "$work/ray2/out.exr" -- "$SCENE" "${PATH_OPTS[@]}" >"$log" 2>&1; then
        same "ray: shard 2's task raised, resubmitted by the driver ($((SECONDS - t0)) s)" "$work/ref-path.exr" "$work/ray2/out.exr"
        if grep -q "shard 2: failed after Ray's retries.*submitting it again" "$log"; then
            ok "ray: the driver's retry loop: $(grep -o "shard 2: failed after.*" "$log" | cut -c1-120)"
        else
            not_ok "ray: no resubmission of shard 2 in the driver's log"
        fi
    else
        not_ok "ray: ray_render.py with a failing task failed"
        sed 's/^/    /' "$log" | tail -n 30
    fi
    # A usage error is not retried: the driver stops with caustica's message.
    if "$PYTHON" "$here/ray_render.py" --num-cpus 2 --shards 2 --no-bar -o "$work/ray3/out.exr" -- \
        "$SCENE" --no-such-option >"$log" 2>&1; then
        not_ok "ray: an unknown caustica option did not fail"
    elif grep -q "usage error, not retried" "$log"; then
        ok "ray: a usage error fails at once, not retried"
    else
        not_ok "ray: an unknown caustica option failed without the usage-error message"
        sed 's/^/    /' "$log" | tail -n 10
    fi
elif [[ $REQUIRE_RAY == 1 ]]; then
    not_ok "ray: $PYTHON cannot import ray"
else
    skipped "ray: $PYTHON cannot import ray (pip install ray)"
fi

echo "# test_engines.sh: $SECONDS s"
echo "engines: $pass passed, $fail failed, $skip skipped"
((fail == 0))
