#!/usr/bin/env bash
# bounds_memlimit.sh BUILD_DIR: under a memory limit (ulimit -v) every tool ends, with exit 0
# or with exit 1 and a message, whatever the BLAS thread count (issue 26, item 7). With two
# OpenBLAS threads, a worker thread whose buffer allocation fails retries it for ever: mesh-prep
# then printed "CHOLMOD symbolic analysis failed" and hung in OpenBLAS's destructor at exit,
# or hung in the BLAS call. `timeout` turns such a hang into a failure of this test.
# Since issue 36: every tool takes OpenBLAS's 128 MB buffer at its start (kt_blas_warm, blas.h),
# refusing to start ("cannot hold the BLAS's ... buffer") when the limit leaves no room for it,
# and checks a factor's size from CHOLMOD's analysis against the room left before factoring
# ("needs N MB, ... leaves M MB"); lri-plan on a shipped patient under 700 MB ends with exit 1.
set -u
B=$(cd "$1" && pwd)
cd "$(dirname "$0")/.."
tmp=$(mktemp -d /tmp/kt_bounds_mem_XXXXXX)
trap 'rm -rf "$tmp"' EXIT
fails=0

# ends NAME LIMIT_KB CODES CMD...: CMD under ulimit -v LIMIT_KB and OPENBLAS_NUM_THREADS=2 ends
# within the timeout with one of CODES ("0 1"); exit 1 must come with a message.
ends() {
    local name=$1 limit=$2 codes=$3 rc
    shift 3
    (ulimit -v "$limit"; OPENBLAS_NUM_THREADS=2 exec timeout 120 "$@") >/dev/null 2>"$tmp/stderr"
    rc=$?
    if [[ " $codes " != *" $rc "* ]]; then
        echo "FAIL $name: exit $rc (124: hung), expected one of $codes"; tail -3 "$tmp/stderr"
        fails=$((fails + 1))
    elif [ $rc -eq 1 ] && ! grep -q . "$tmp/stderr"; then
        echo "FAIL $name: exit 1 without a message"; fails=$((fails + 1))
    else
        echo "ok   $name: exit $rc $(tail -1 "$tmp/stderr")"
    fi
}

# a 21 x 21 x 41 brick (18081 nodes) about fits in 250 MB: it must end (it hung with two threads)
ends "mesh-prep brick-20 in 250 MB" 250000 "0 1" "$B/mesh-prep" -q plans/bench/brick-20.yaml -o "$tmp/brick.msh"
# a 41 x 41 x 61 brick does not: CHOLMOD's analysis fails, and the tool must say so and end
sed 's/nodes: \[21, 21, 41\]/nodes: [41, 41, 61]/' plans/bench/brick-20.yaml >"$tmp/big.yaml"
ends "mesh-prep of a larger brick in 250 MB" 250000 "1" "$B/mesh-prep" -q "$tmp/big.yaml" -o "$tmp/big.msh"
grep -q "CHOLMOD\|out of memory" "$tmp/stderr" || { echo "FAIL: no CHOLMOD or memory message"; fails=$((fails + 1)); }
[ ! -e "$tmp/big.msh" ] || { echo "FAIL: a failed run left its output"; fails=$((fails + 1)); }

# augsolve on the brick's cut: finishes, or fails with a message, in limits around its need
"$B/cutplan" -q plans/bench/cut-brick-20.yaml "$tmp/brick.msh" -o "$tmp/brick.edits" 2>/dev/null ||
    OPENBLAS_NUM_THREADS=1 "$B/mesh-prep" -q plans/bench/brick-20.yaml -o "$tmp/brick.msh" >/dev/null
"$B/cutplan" -q plans/bench/cut-brick-20.yaml "$tmp/brick.msh" -o "$tmp/brick.edits" || { echo "FAIL cutplan"; exit 1; }
for limit in 400000 900000; do
    ends "augsolve in $((limit / 1000)) MB" $limit "0 1" \
        "$B/augsolve" -q --no-vtk "$tmp/brick.msh" "$tmp/brick.edits" -o "$tmp/run-$limit"
done
# too small for the BLAS's buffer beside two OpenBLAS threads: refused at the start, exit 1
ends "augsolve in 250 MB: refused at its start" 250000 "1" \
    "$B/augsolve" -q --no-vtk "$tmp/brick.msh" "$tmp/brick.edits" -o "$tmp/run-start"
grep -q "cannot hold the BLAS's 128 MB work buffer" "$tmp/stderr" || { echo "FAIL: no BLAS buffer message"; fails=$((fails + 1)); }
# room for the buffer, not for the planned factor (350 MB): refused before factoring, saying so
ends "augsolve in 700 MB: the factor's budget" 700000 "1" \
    "$B/augsolve" -q --no-vtk "$tmp/brick.msh" "$tmp/brick.edits" -o "$tmp/run-budget"
grep -q "Cholesky factor: out of memory: needs [0-9]* MB, the address-space limit (ulimit -v) leaves [0-9]* MB" "$tmp/stderr" ||
    { echo "FAIL: no factor budget message"; fails=$((fails + 1)); }
[ ! -e "$tmp/run-budget/run.yaml" ] || { echo "FAIL: a refused run wrote run.yaml"; fails=$((fails + 1)); }
# lri-plan on a shipped patient (--fast: the suite's time) under 700 MB: exit 1, a message
ends "lri-plan --fast wtr-od in 700 MB" 700000 "1" \
    "$B/lri-plan" -q --fast plans/patients/wtr-od.yaml -o "$tmp/plan"
grep -q "out of memory" "$tmp/stderr" || { echo "FAIL: lri-plan: no out-of-memory message"; fails=$((fails + 1)); }

if [ $fails -ne 0 ]; then echo "$fails failure(s)"; exit 1; fi
echo "every run ended under the memory limit"
