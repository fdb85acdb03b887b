#!/usr/bin/env bash
# lriplan_jobs.sh BUILD_DIR: the families side by side give the answer of the families one at a
# time, to the bit (lib/planner/lp_run.h). A with-the-rule right eye with its temporal main
# incision, single and paired arcs to 10 deg (lri-plan --fast) is planned with --jobs 1 and
# --jobs 2: plan.json is the same but for its timings and `jobs` (1 and 2, as asked), every
# file of run/ and report/ the same bytes but for the run's timings (steps.tsv's t_* columns,
# run.yaml's t_total_s, the report's times) and the plan folder's name (report.html names the
# folder the plan was renamed into, not the temporary one it was written in), the summary the
# same but for its seconds; with the refactor fallback in both families (METIS at every step,
# on both threads at once) the step files are the same bytes; report/steps.pvd names the run's VTKs relative to itself (they open
# after the rename); --jobs 0 and 4 are refused
# (exit 2, one line naming the option, nothing written).
set -uo pipefail
B=$(cd "$1" && pwd)
cd "$(dirname "$0")/.."
T=$(mktemp -d /tmp/kt-lriplan-jobs.XXXXXX)
trap 'rm -rf "$T"' EXIT
fail() { echo "lriplan_jobs: FAILED: $*" >&2; exit 1; }
cat > "$T/p.yaml" <<'YAML'
name: jobs
eye: OD
age: 70
cornea:
  keratometry: {k_steep: 44.5 D, k_flat: 43.25 D, steep_axis: 92 deg}
main_incision: {meridian: 180 deg, width: 2.4 mm}
constraints: {incisions: either, max_arc: 10 deg}
YAML
for j in 1 2; do
    "$B/lri-plan" --fast -j $j -q "$T/p.yaml" -o "$T/j$j" > "$T/sum$j" 2> "$T/err$j" ||
        fail "--jobs $j: $(cat "$T/err$j")"
done
/usr/bin/python3 - "$T" <<'PY' || exit 1
import json, sys
T = sys.argv[1]
a, b = (json.load(open(f"{T}/j{j}/plan.json")) for j in (1, 2))
def strip(d):
    if isinstance(d, dict):
        return {k: strip(v) for k, v in d.items() if not k.endswith("seconds") and k != "jobs"}
    if isinstance(d, list):
        return [strip(x) for x in d]
    return d
ok = True
def check(c, what):
    global ok
    print(("ok   " if c else "FAIL ") + what)
    ok = ok and c
check(a["provenance"]["jobs"] == 1 and b["provenance"]["jobs"] == 2, "jobs as asked: %s, %s" %
      (a["provenance"]["jobs"], b["provenance"]["jobs"]))
ran = [c["incisions"] for c in a["candidates"] if c["run"]]
check(len(ran) >= 2, "two families or more ran: %s" % ran)
check(strip(a) == strip(b), "plan.json the same but for timings and jobs")
import os, xml.etree.ElementTree as ET
rep = f"{T}/j2/report"
files = [d.get("file") for d in ET.parse(f"{rep}/steps.pvd").getroot().iter("DataSet")]
check(len(files) >= 2 and all(not f.startswith("/") and os.path.isfile(os.path.join(rep, f)) for f in files),
      "report/steps.pvd names the run's VTKs from its folder, after the rename: %s" % files)
html = open(f"{rep}/report.html", encoding="utf-8").read()
check(".tmp." not in html and f"{T}/j2/run" in html, "report.html names the plan folder, not the one it was written in")
sys.exit(0 if ok else 1)
PY
# run/ and report/: every file the same bytes, the timing columns and lines aside
timeless() {
    case "$1" in
    *steps.tsv) awk -F'\t' 'NR == 1 { for (i = 1; i <= NF; i++) if ($i !~ /^t_/) k[i] = 1 }
                   { s = ""; for (i = 1; i <= NF; i++) if (k[i]) s = s $i "\t"; print s }' "$1" ;;
    *.yaml | *.html | *.json | *.tsv | *.txt) grep -v -E 't_total_s|seconds|[0-9.]+ s\b' "$1" ;;
    *) cat "$1" ;;
    esac
}
n=0
while IFS= read -r f; do
    [ -f "$T/j2/$f" ] || fail "--jobs 2 has no $f"
    cmp -s <(timeless "$T/j1/$f" | sed "s#$T/j1#PLAN#g") <(timeless "$T/j2/$f" | sed "s#$T/j2#PLAN#g") ||
        fail "$f differs between --jobs 1 and 2"
    n=$((n + 1))
done < <(cd "$T/j1" && find run report -type f | sort)
[ "$n" -gt 10 ] || fail "only $n files in run/ and report/"
[ "$(cd "$T/j2" && find run report -type f | wc -l)" -eq "$n" ] || fail "--jobs 2 wrote another set of files"
cmp -s <(sed -E 's/[0-9]+ s\b/N s/g' "$T/sum1") <(sed -E 's/[0-9]+ s\b/N s/g; s#/j2/#/j1/#g; s#/j2,#/j1,#g' "$T/sum2") ||
    fail "the summaries differ: $(diff "$T/sum1" "$T/sum2" | head -5)"
echo "ok   run/ and report/: $n files the same, the summary the same"
# the refactor fallback (--plan-max-ratio 0.5: every family refused, METIS at every step, in
# both families at once with --jobs 2; no main incision, for time): the step files the same bytes
grep -v '^main_incision:' "$T/p.yaml" > "$T/p10.yaml"
for j in 1 2; do
    "$B/lri-plan" --fast -j $j -q --no-uncertainty --plan-max-ratio 0.5 "$T/p10.yaml" -o "$T/f$j" > /dev/null 2> "$T/ferr$j" ||
        fail "--jobs $j --plan-max-ratio 0.5: $(cat "$T/ferr$j")"
    grep -q "falling back to --method refactor" "$T/ferr$j" || fail "--plan-max-ratio 0.5 did not fall back: $(cat "$T/ferr$j")"
done
n=0
for f in "$T"/f1/run/step-*.vtk; do
    cmp -s "$f" "$T/f2/run/${f##*/}" || fail "refactor fallback: run/${f##*/} differs between --jobs 1 and 2"
    n=$((n + 1))
done
[ "$n" -ge 2 ] || fail "refactor fallback: only $n step files"
echo "ok   the refactor fallback (METIS every step, two families at once): $n step files the same"
for bad in 0 4 x; do
    rm -rf "$T/bad"
    "$B/lri-plan" --fast -j "$bad" -q "$T/p.yaml" -o "$T/bad" > /dev/null 2> "$T/err"
    rc=$?
    [ $rc -eq 2 ] || fail "--jobs $bad: exit $rc, expected 2"
    [ "$(wc -l < "$T/err")" -eq 1 ] && grep -q -- "--jobs $bad" "$T/err" || fail "--jobs $bad: $(cat "$T/err")"
    [ ! -e "$T/bad" ] || fail "--jobs $bad wrote $T/bad"
done
echo "ok   --jobs 0, 4, x refused"
echo "lriplan_jobs: passed"
