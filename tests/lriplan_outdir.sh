#!/usr/bin/env bash
# lriplan_outdir.sh BUILD_DIR: lri-plan's plan folder is a unit (issue 36, item 9; kt_outdir,
# lib/core/outdir.h). A folder holding an earlier plan (its marker .keratome-outdir, an old
# plan.html and plan.json) is re-run:
# - interrupted by SIGINT while meshing: no plan.html or plan.json is left (neither the earlier
#   run's nor a partial one), no temporary folder, no lock;
# - a second run while one holds the folder: exit 2, "locked by another run";
# - a folder that is no earlier output (no marker, e.g. a FIFO named eye.msh in it): exit 2,
#   untouched;
# - on a full disk (a tiny tmpfs, when mounted as root): exit 1 naming the file and "disk full",
#   and no plan.html or plan.json left.
set -u
set -m # job control: a background job keeps SIGINT (without it bash starts it with SIGINT ignored)
B=$(cd "${1:?build dir}" && pwd)
cd "$(dirname "$0")/.."
T=$(mktemp -d /tmp/kt_outdir.XXXXXX)
trap 'umount "$T/tiny" 2>/dev/null; rm -rf "$T"' EXIT
fails=0
fail() { echo "FAIL $*"; fails=$((fails + 1)); }
P=plans/patients/wtr-od.yaml

old_plan() { # an earlier run's plan folder
    rm -rf "$1"; mkdir -p "$1"
    echo "a folder written whole by a keratome tool" >"$1/.keratome-outdir"
    echo "<p>OLD PLAN</p>" >"$1/plan.html"; echo '{"old": true}' >"$1/plan.json"
}
leftovers() { ls -A "$(dirname "$1")" | grep -E "^$(basename "$1")\.(tmp\.|lock)" | tr '\n' ' '; }

# ---- SIGINT while meshing -----------------------------------------------------------------
old_plan "$T/plan"
"$B/lri-plan" --fast "$P" -o "$T/plan" >/dev/null 2>"$T/err" &
pid=$!
for _ in $(seq 1 600); do grep -q "meshing" "$T/err" && break; sleep 0.1; done
kill -INT $pid; wait $pid; rc=$?
if [ -e "$T/plan/plan.html" ] || [ -e "$T/plan/plan.json" ]; then fail "SIGINT: a plan.html or plan.json is left: $(ls "$T/plan")"
elif [ -n "$(leftovers "$T/plan")" ]; then fail "SIGINT: left $(leftovers "$T/plan")"
else echo "ok   a re-run interrupted by SIGINT (exit $rc): no plan.html, no plan.json, no temporary, no lock"; fi

# ---- two runs into one folder --------------------------------------------------------------
old_plan "$T/plan"
"$B/lri-plan" --fast "$P" -o "$T/plan" >/dev/null 2>"$T/err1" &
pid=$!
for _ in $(seq 1 600); do grep -q "meshing" "$T/err1" && break; sleep 0.1; done
rc=0; "$B/lri-plan" --fast "$P" -o "$T/plan" >/dev/null 2>"$T/err2" || rc=$?
kill -TERM $pid; wait $pid
if [ $rc -eq 2 ] && grep -q "locked by another run" "$T/err2"; then echo "ok   the second run: $(cat "$T/err2")"
else fail "the second run into a locked folder: exit $rc: $(cat "$T/err2")"; fi
[ -z "$(leftovers "$T/plan")" ] || fail "SIGTERM: left $(leftovers "$T/plan")"

# ---- a folder that is no earlier output ------------------------------------------------------
rm -rf "$T/mine"; mkdir -p "$T/mine"; mkfifo "$T/mine/eye.msh"; echo keep >"$T/mine/notes.txt"
rc=0; timeout 60 "$B/lri-plan" --fast "$P" -o "$T/mine" >/dev/null 2>"$T/err" || rc=$?
if [ $rc -eq 2 ] && grep -q "no earlier output" "$T/err" && [ -p "$T/mine/eye.msh" ] && [ -f "$T/mine/notes.txt" ]; then
    echo "ok   a folder with a FIFO named eye.msh, no marker: $(cat "$T/err")"
else fail "a folder that is no earlier output: exit $rc: $(cat "$T/err")"; fi

# ---- a full disk -------------------------------------------------------------------------------
mkdir -p "$T/tiny"
if mount -t tmpfs -o size=3m kt-plan-full "$T/tiny" 2>/dev/null; then
    old_plan "$T/tiny/plan"
    rc=0; timeout 300 "$B/lri-plan" --fast "$P" -o "$T/tiny/plan" >/dev/null 2>"$T/err" || rc=$?
    if [ $rc -eq 1 ] && grep -q "write failed: disk full" "$T/err" && [ ! -e "$T/tiny/plan/plan.html" ] &&
        [ ! -e "$T/tiny/plan/plan.json" ] && [ -z "$(leftovers "$T/tiny/plan")" ]; then
        echo "ok   a re-run on a full disk: no plan.html, no plan.json: $(tail -1 "$T/err")"
    else fail "a full disk: exit $rc, left $(ls -A "$T/tiny"): $(tail -1 "$T/err")"; fi
    umount "$T/tiny"
else
    echo "skip the full disk: mount needs root"
fi

if [ $fails -ne 0 ]; then echo "$fails failure(s)"; exit 1; fi
echo "the plan folder is a unit"
