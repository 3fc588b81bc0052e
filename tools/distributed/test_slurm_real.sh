#!/usr/bin/env bash
# Runs the Slurm path for real: starts a single-node Slurm here (munged, slurmctld and slurmd
# from Debian's slurm-wlm, as root, with their own config, state, sockets and ports under a
# temporary directory), submits a 4-shard render with slurm/submit.sh (sbatch --array plus a merge
# with --dependency=afterok), and checks the merged bytes against the unsharded render. Then it
# resubmits two deleted shards (SHARDS=1,3: --array=1,3, whose task ids are the shard indices though
# SLURM_ARRAY_TASK_MIN is 1) and merges again, and checks that a failing array
# cancels its merge (--kill-on-invalid-dep). The daemons it started are stopped at the end.
#
# Environment: CAUSTICA (the binary; default caustica on PATH); CAUSTICA_SLURM_INSTALL=1 to
# apt-get install slurm-wlm and munge when missing (root only); REQUIRE_SLURM=1 to fail instead of
# skipping when Slurm cannot be installed or started; SLURM_TEST_PORT (default 16817: slurmctld,
# slurmd on the next port). Ends with "slurm: N passed, N failed".
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
CAUSTICA=$(command -v "${CAUSTICA:-caustica}") || { echo "test_slurm_real: caustica binary not found (set CAUSTICA)" >&2; exit 2; }
CAUSTICA=$(realpath "$CAUSTICA")
export CAUSTICA
SECONDS=0
pass=0 fail=0
ok() { echo "ok - $*"; pass=$((pass + 1)); }
not_ok() { echo "not ok - $*"; fail=$((fail + 1)); }
give_up() {
    if [[ ${REQUIRE_SLURM:-0} == 1 ]]; then
        echo "not ok - $*"
        echo "slurm: 0 passed, 1 failed"
        exit 1
    fi
    echo "skip - real Slurm: $*"
    echo "slurm: 0 passed, 0 failed, 1 skipped"
    exit 0
}

missing() { ! command -v slurmctld >/dev/null || ! command -v slurmd >/dev/null || ! command -v sbatch >/dev/null || ! command -v munged >/dev/null; }
if missing; then
    if [[ ${CAUSTICA_SLURM_INSTALL:-0} == 1 && $(id -u) == 0 ]] && command -v apt-get >/dev/null; then
        t0=$SECONDS
        if ! { apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends \
            slurm-wlm slurmctld slurmd slurm-client munge; } >/tmp/caustica-slurm-apt.log 2>&1; then
            tail -n 5 /tmp/caustica-slurm-apt.log
            give_up "apt-get install slurm-wlm munge failed (log above)"
        fi
        echo "# installed slurm-wlm and munge in $((SECONDS - t0)) s"
    else
        give_up "slurmctld, slurmd, sbatch or munged not installed (CAUSTICA_SLURM_INSTALL=1 installs them as root)"
    fi
fi
[[ $(id -u) == 0 ]] || give_up "slurmd must run as root"

dir=$(mktemp -d "${TMPDIR:-/tmp}/caustica-slurm.XXXXXX")
chmod 755 "$dir"
pids=()
stop() {
    local p
    for p in "${pids[@]+"${pids[@]}"}"; do
        kill "$p" 2>/dev/null || true
    done
    for p in "${pids[@]+"${pids[@]}"}"; do
        for _ in $(seq 50); do kill -0 "$p" 2>/dev/null || break; sleep 0.1; done
        kill -9 "$p" 2>/dev/null || true
    done
    rm -rf "$dir"
}
trap stop EXIT
# The pid a daemon wrote to its pid file.
started() {
    for _ in $(seq 100); do
        [[ -s $1 ]] && { pids+=("$(cat "$1")"); return 0; }
        sleep 0.1
    done
    return 1
}

t0=$SECONDS
host=$(hostname -s)
port=${SLURM_TEST_PORT:-16817}
mkdir -p "$dir"/{munge,state,spool,log,run,out}
chmod 755 "$dir/munge"
dd if=/dev/urandom of="$dir/munge/key" bs=128 count=1 status=none
chmod 600 "$dir/munge/key"
munged --force -S "$dir/munge/sock" --key-file="$dir/munge/key" --log-file="$dir/munge/log" \
    --pid-file="$dir/munge/pid" --seed-file="$dir/munge/seed" >"$dir/log/munged.out" 2>&1 ||
    { cat "$dir/log/munged.out"; give_up "munged did not start"; }
started "$dir/munge/pid" || give_up "munged wrote no pid file"
export SLURM_CONF=$dir/slurm.conf
cat >"$SLURM_CONF" <<EOF
ClusterName=caustica-test
SlurmctldHost=$host(127.0.0.1)
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$dir/munge/sock
SlurmctldPort=$port
SlurmdPort=$((port + 1))
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/run/slurmctld.pid
SlurmdPidFile=$dir/run/slurmd.pid
SlurmctldLogFile=$dir/log/slurmctld.log
SlurmdLogFile=$dir/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
ReturnToService=2
MpiDefault=none
MinJobAge=600
# Schedule every second (defaults 60 s and 30 s): array tasks and the dependent merge start at once.
SchedulerParameters=bf_interval=1,sched_interval=1
NodeName=$host NodeAddr=127.0.0.1 CPUs=$(nproc) RealMemory=1000 State=UNKNOWN
PartitionName=debug Nodes=ALL Default=YES MaxTime=INFINITE State=UP
EOF
slurmctld -c >"$dir/log/slurmctld.out" 2>&1 || { cat "$dir/log/slurmctld.out"; give_up "slurmctld did not start"; }
started "$dir/run/slurmctld.pid" || { tail -n 20 "$dir/log/slurmctld.log"; give_up "slurmctld wrote no pid file"; }
slurmd >"$dir/log/slurmd.out" 2>&1 || { cat "$dir/log/slurmd.out"; give_up "slurmd did not start"; }
started "$dir/run/slurmd.pid" || { tail -n 20 "$dir/log/slurmd.log"; give_up "slurmd wrote no pid file"; }
for _ in $(seq 150); do
    [[ $(sinfo -h -N -o %T 2>/dev/null) == idle ]] && break
    sleep 0.2
done
if [[ $(sinfo -h -N -o %T 2>/dev/null) != idle ]]; then
    sinfo -N 2>&1 | tail -n 3
    tail -n 20 "$dir/log/slurmctld.log" "$dir/log/slurmd.log"
    give_up "the node did not become idle"
fi
echo "# single-node Slurm $(sinfo -V | awk '{print $2}') up in $((SECONDS - t0)) s ($(nproc) CPUs on $host, port $port)"

# Waits until the jobs have left the queue; prints their states, one per job or array task.
wait_jobs() {
    local end=$((SECONDS + 300))
    while squeue -h -j "$(IFS=,; echo "$*")" 2>/dev/null | grep -q .; do
        ((SECONDS < end)) || { echo TIMEOUT; return; }
        sleep 0.2
    done
    local id
    for id in "$@"; do
        scontrol show job -o "$id" 2>/dev/null | grep -o 'JobState=[A-Z_]*' | sed 's/JobState=//'
    done
}
all_completed() { [[ -n $1 ]] && ! grep -qv '^COMPLETED$' <<<"$1"; }

SCENE=cornell-box
OPTS=(--integrator path --spp 4 --width 64 --seed 11)
"$CAUSTICA" render "$SCENE" "${OPTS[@]}" -q -o "$dir/out/ref.exr" >/dev/null 2>&1

t0=$SECONDS
read -r array_id merge_id < <(bash "$here/slurm/submit.sh" "$SCENE" 4 "$dir/out/a.exr" "${OPTS[@]}" 2>"$dir/log/submit.err")
states=$(wait_jobs "$array_id" "$merge_id")
if all_completed "$states" && cmp -s "$dir/out/ref.exr" "$dir/out/a.exr"; then
    ok "real Slurm: array job $array_id (4 shards) + merge $merge_id (afterok): identical to the unsharded render ($((SECONDS - t0)) s from submission to merged image)"
else
    not_ok "real Slurm: 4-shard array job: states $(tr "\n" " " <<<"$states"), image $(cmp "$dir/out/ref.exr" "$dir/out/a.exr" 2>&1)"
    cat "$dir/log/submit.err" "$dir"/out/a.parts/logs/* 2>/dev/null | tail -n 30 | sed 's/^/    /'
fi

# Shards 1 and 3 lost: resubmit them (sbatch --array=1,3: Slurm sets SLURM_ARRAY_TASK_MIN=1, and
# task 3 renders shard 3, the task id being the shard index) and merge again.
mkdir -p "$dir/out/saved"
cp "$dir"/out/a.parts/shard-000[13]-of-0004.cpart "$dir/out/saved/" 2>/dev/null || true
rm -f "$dir"/out/a.parts/shard-000[13]-of-0004.cpart "$dir/out/a.exr"
t0=$SECONDS
read -r array_id merge_id < <(SHARDS=1,3 bash "$here/slurm/submit.sh" "$SCENE" 4 "$dir/out/a.exr" "${OPTS[@]}" 2>"$dir/log/submit.err")
states=$(wait_jobs "$array_id" "$merge_id")
if all_completed "$states" && cmp -s "$dir/out/ref.exr" "$dir/out/a.exr" &&
    cmp -s "$dir/out/saved/shard-0001-of-0004.cpart" "$dir/out/a.parts/shard-0001-of-0004.cpart" &&
    cmp -s "$dir/out/saved/shard-0003-of-0004.cpart" "$dir/out/a.parts/shard-0003-of-0004.cpart"; then
    ok "real Slurm: shards 1 and 3 resubmitted (SHARDS=1,3: --array=1,3) wrote the same parts (task 3: $(grep -h -o 'shard 3/4 ([^)]*)' "$dir/out/a.parts/logs/shard-${array_id}_3.out" 2>/dev/null)); merged again identical ($((SECONDS - t0)) s)"
else
    not_ok "real Slurm: resubmission of shards 1 and 3: states $(tr "\n" " " <<<"$states")"
    find "$dir/out/a.parts" -maxdepth 1 -name '*.cpart' | sed 's/^/    /'
    tail -n 20 "$dir"/out/a.parts/logs/* 2>/dev/null | sed 's/^/    /'
fi

# A shard that fails for good: the merge is cancelled, not left pending, and writes nothing.
t0=$SECONDS
read -r array_id merge_id < <(bash "$here/slurm/submit.sh" "$SCENE" 2 "$dir/out/bad.exr" "${OPTS[@]}" --no-such-option 2>"$dir/log/submit.err")
states=$(wait_jobs "$array_id" "$merge_id")
merge_state=$(tail -n1 <<<"$states")
if grep -q FAILED <<<"$states" && [[ $merge_state == CANCELLED ]] && [[ ! -e $dir/out/bad.exr ]]; then
    ok "real Slurm: a failing array (an unknown option) cancels its merge job ($((SECONDS - t0)) s): $(grep -h -m1 -i error "$dir"/out/bad.parts/logs/shard-* 2>/dev/null | head -n1)"
else
    not_ok "real Slurm: failing array: states $(tr "\n" " " <<<"$states")"
fi

echo "# test_slurm_real.sh: $SECONDS s"
echo "slurm: $pass passed, $fail failed"
((fail == 0))
