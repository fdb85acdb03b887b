#!/usr/bin/env bash
# study_slurm.sh BUILD_DIR: the nomogram study (plans/studies/nomogram) through a real Slurm
# cluster, checked against a local run. It starts a single-node Slurm on this machine (as root):
# munged with a key it creates, slurmctld and slurmd on 127.0.0.1 on free ports, from a
# slurm.conf it writes to a temporary folder; runs the study there with ENGINE=slurm (job arrays
# for the eyes and the runs, the summary after them), then locally with make from the Slurm
# run's eye mesh (so that only the solve, cut and read are compared, see below), and once more with ENGINE=parallel;
# checks that the three nomogram.tsv are identical, that the Slurm arrays ran (their task logs),
# and that a second ENGINE=slurm run resumes with nothing to redo; and stops everything it
# started (trap), cancelling any job left. Bounded: every study under timeout
# (STUDY_SLURM_TIMEOUT seconds, default 2400), the daemons' start-up under a minute.
# Case set: STUDY_SLURM_SET=quick runs the study's quick set (make quick: >= 4 arcs, minutes);
# the default (for CI) is a reduced spec written here: the same default eye and incision surface,
# paired arcs of 15 and 30 deg (two steps of one run). Not root: skipped (exit 77).
set -euo pipefail
B=$(cd "$1" && pwd)
cd "$(dirname "$0")/.."
ROOT=$PWD
STUDY=$ROOT/plans/studies/nomogram
if [ "$(id -u)" -ne 0 ]; then echo "study_slurm: needs root to start slurmd; skipped"; exit 77; fi
for p in munged slurmctld slurmd sbatch sinfo squeue scancel; do
    command -v "$p" > /dev/null || { echo "study_slurm: $p missing (bash scripts/setup.sh)" >&2; exit 1; }
done
T=$(mktemp -d /tmp/kt_study_slurm_XXXXXX)
chmod 700 "$T"
pids=()
cleanup() {
    local rc=$?
    if [ -n "${SLURM_CONF:-}" ]; then
        jobs=$(timeout 10 squeue -h -o %i 2> /dev/null || true)
        [ -n "$jobs" ] && timeout 10 scancel $jobs 2> /dev/null || true
    fi
    for ((i = ${#pids[@]} - 1; i >= 0; i--)); do kill "${pids[i]}" 2> /dev/null || true; done
    for pid in "${pids[@]}"; do
        for _ in $(seq 50); do kill -0 "$pid" 2> /dev/null || break; sleep 0.2; done
        kill -9 "$pid" 2> /dev/null || true
    done
    if [ $rc -ne 0 ]; then
        echo "study_slurm: FAILED; logs:" >&2
        tail -n 15 "$T"/log/*.log "$T"/slurm/slurm/*.out >&2 2> /dev/null || true
    fi
    rm -rf "$T"
    exit $rc
}
trap cleanup EXIT
trap 'exit 1' INT TERM

# Two free TCP ports (nothing answers on them).
free_port() {
    local p
    for _ in $(seq 100); do
        p=$((20000 + RANDOM % 20000))
        (exec 3<> "/dev/tcp/127.0.0.1/$p") 2> /dev/null || { echo "$p"; return; }
    done
    echo "study_slurm: no free port" >&2; return 1
}
ctld_port=$(free_port)
slurmd_port=$(free_port)
[ "$ctld_port" != "$slurmd_port" ] || slurmd_port=$((ctld_port + 1))

mkdir -p "$T/state" "$T/spool" "$T/log"
dd if=/dev/urandom of="$T/munge.key" bs=1024 count=1 status=none
chmod 400 "$T/munge.key"
cat > "$T/slurm.conf" << EOF
ClusterName=ktstudy
SlurmctldHost=localhost(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
AuthType=auth/munge
AuthInfo=socket=$T/munge.sock
CredType=cred/munge
SlurmUser=root
SlurmdUser=root
StateSaveLocation=$T/state
SlurmdSpoolDir=$T/spool
SlurmctldPidFile=$T/slurmctld.pid
SlurmdPidFile=$T/slurmd.pid
SlurmctldLogFile=$T/log/slurmctld.log
SlurmdLogFile=$T/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SwitchType=switch/none
MpiDefault=none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
ReturnToService=2
NodeName=ktnode NodeAddr=127.0.0.1 NodeHostname=$(hostname) CPUs=$(nproc) State=UNKNOWN
PartitionName=study Nodes=ktnode Default=YES MaxTime=INFINITE State=UP
EOF
export SLURM_CONF=$T/slurm.conf

munged -F --force --key-file="$T/munge.key" --socket="$T/munge.sock" --pid-file="$T/munged.pid" \
    --log-file="$T/log/munged.log" --seed-file="$T/munged.seed" > "$T/log/munged.out" 2>&1 &
pids+=($!)
for _ in $(seq 50); do [ -S "$T/munge.sock" ] && break; sleep 0.2; done
slurmctld -D -f "$SLURM_CONF" > "$T/log/slurmctld.out" 2>&1 &
pids+=($!)
slurmd -D -f "$SLURM_CONF" -N ktnode > "$T/log/slurmd.out" 2>&1 &
pids+=($!)
up=0
for _ in $(seq 60); do
    if timeout 5 sinfo -h -N -o '%T' 2> /dev/null | grep -q -x idle; then up=1; break; fi
    sleep 1
done
[ $up = 1 ] || { echo "study_slurm: the node did not come up" >&2; exit 1; }
echo "study_slurm: slurm up (ports $ctld_port/$slurmd_port)"

# The case set.
mk=(make --no-print-directory -C "$STUDY" KT_BUILD="$B" KEEP_VTK=0)
if [ "${STUDY_SLURM_SET:-}" = quick ]; then
    target=quick
else
    target=all
    spec=$T/study.spec
    printf 'base %s/plans/eye.yaml\nage_rule 60 0.075\n' "$ROOT" > "$spec"
    printf 'eye default 44.02 42.52 90 540 60 -\nrun full default 2 0.9 10.5 15 30\n' >> "$spec"
    printf 'band 1.00 1.50\n' >> "$spec"
    mk+=(SPEC="$spec")
fi
limit=${STUDY_SLURM_TIMEOUT:-2400}
# The Slurm run first, all of it (the eye meshed by the eye array). The local run then starts
# from the Slurm run's eye (scenes, plans and mesh copied with their times, so make takes them
# as done) and does the runs and the summary itself, so the comparison is of the same mesh
# solved, cut and read under Slurm and locally (mesh-prep's own reproducibility is
# tests/reproducible.sh's). It must be exact.
t0=$(date +%s)
timeout "$limit" "${mk[@]}" OUT="$T/slurm" ENGINE=slurm "$target" > "$T/log/slurm-make.log" 2>&1
t1=$(date +%s)
mkdir -p "$T/local"
cp -a "$T/slurm/scenes" "$T/slurm/plans" "$T/slurm/eyes" "$T/slurm/study.mk" "$T/slurm/bands.tsv" "$T/local/"
timeout "$limit" "${mk[@]}" OUT="$T/local" "$target" > "$T/log/local.log" 2>&1
t2=$(date +%s)
echo "study_slurm: slurm $((t1 - t0)) s, local (runs only) $((t2 - t1)) s"
if grep -q 'task.sh eye' "$T/log/local.log"; then echo "study_slurm: the local run remeshed" >&2; exit 1; fi

# The same cases, the same numbers, to the last digit written.
L=$T/local/nomogram.tsv S=$T/slurm/nomogram.tsv
[ -s "$L" ] && [ -s "$S" ]
nl=$(wc -l < "$L")
[ "$nl" -ge 3 ] || { echo "study_slurm: only $nl lines in $L" >&2; exit 1; }
if ! cmp "$L" "$S"; then
    diff "$L" "$S" >&2 || true
    echo "study_slurm: the local and the Slurm nomogram.tsv differ" >&2; exit 1
fi
# The work ran as array tasks (one log per eye and per run) and the summary as a job.
ls "$T/slurm/slurm"/eye-0.out "$T/slurm/slurm"/run-0.out "$T/slurm/slurm/summary.out" > /dev/null
grep -q 'summary:' "$T/slurm/slurm/summary.out"
# Every case's SIA is a number, and one of the first arcs' is positive (the cut did something).
awk -F'\t' 'NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
    { if ($c["sia_D"] !~ /^[0-9.]+$/) exit 1; if ($c["sia_D"] > 0) pos = 1 } END { exit !pos }' "$S"
# A rerun resumes: nothing is redone (no new mesh, no new run folder).
before=$(find "$T/slurm/eyes" "$T/slurm/runs" -newer "$S" | wc -l)
timeout 600 "${mk[@]}" OUT="$T/slurm" ENGINE=slurm "$target" > "$T/log/slurm-rerun.log" 2>&1
after=$(find "$T/slurm/eyes" "$T/slurm/runs" -newer "$S" | wc -l)
[ "$before" -eq 0 ] && [ "$after" -eq 0 ] || { echo "study_slurm: the rerun redid work" >&2; exit 1; }
echo "study_slurm: $((nl - 1)) cases equal between the local and the Slurm run"

# ENGINE=parallel on a copy of the local results without their runs: the eye is kept (not
# remeshed), the runs are redone through GNU parallel and give the same table.
if [ -z "${STUDY_SLURM_NO_PARALLEL:-}" ]; then
    cp -a "$T/local" "$T/par"
    rm -rf "$T/par/runs" "$T/par/nomogram.tsv"
    timeout "$limit" "${mk[@]}" OUT="$T/par" ENGINE=parallel "$target" > "$T/log/parallel.log" 2>&1
    [ -z "$(find "$T/par/eyes" -newer "$T/par/set.txt")" ] || { echo "study_slurm: parallel remeshed" >&2; exit 1; }
    cmp "$T/local/nomogram.tsv" "$T/par/nomogram.tsv"
    echo "study_slurm: ENGINE=parallel gives the same table"
fi
