#!/usr/bin/env bash
# lriplan_json.sh BUILD_DIR: the tools' JSON through the one writer (lib/io/json.h) with text
# that hand-printed JSON breaks on: a patient named 'O"Brien \ test', a line end and non-ASCII
# letters, in a folder whose name holds a quote, a backslash and a space. lri-plan --fast (one
# arc to 10 deg) writes plan.json that Python's json module reads with the name and the path as
# given; plan.html escapes the name; scene.yaml (the name in its header comment) reads back in
# mesh-prep; curvature --json on the chosen run (run.yaml names paths with those characters)
# is read by the json module too.
set -uo pipefail
B=$(cd "$1" && pwd)
cd "$(dirname "$0")/.."
tmp=$(mktemp -d /tmp/kt-lriplan-json.XXXXXX)
trap 'rm -rf "$tmp"' EXIT
d="$tmp/dir \"q\" \\ x"
mkdir -p "$d"
cat > "$d/p.yaml" <<'YAML'
name: "O\"Brien \\ test\nZoë Ålesund"
eye: OS
age: 66
cornea:
  keratometry: {k_steep: 44.5 D, k_flat: 43.0 D, steep_axis: 90 deg}
constraints: {incisions: single, max_arc: 10 deg}
YAML
if ! "$B/lri-plan" --fast -q "$d/p.yaml" -o "$d/plan" > "$tmp/summary" 2> "$tmp/err"; then
    echo "FAILED: lri-plan: $(cat "$tmp/err")"; exit 1
fi
"$B/curvature" -q --json --no-png --no-vtk --no-report "$d/plan/run" -o "$tmp/rc" > "$tmp/curv.json" 2> "$tmp/err" ||
    { echo "FAILED: curvature --json: $(cat "$tmp/err")"; exit 1; }
"$B/mesh-prep" -q --chosen-only "$d/plan/scene.yaml" -o "$tmp/prep.msh" > /dev/null 2> "$tmp/err" ||
    { echo "FAILED: mesh-prep on scene.yaml: $(cat "$tmp/err")"; exit 1; }
/usr/bin/python3 - "$d" "$tmp" <<'PY'
import json, sys
d, tmp = sys.argv[1:3]
fails = []
def check(cond, what):
    print(("ok   " if cond else "FAIL ") + what)
    if not cond: fails.append(what)
name = 'O"Brien \\ test\nZoë Ålesund'
try:
    j = json.load(open(f"{d}/plan/plan.json", encoding="utf-8"))
except ValueError as ex:
    j = None
    check(False, f"plan.json parses: {ex}")
if j:
    check(j["patient"]["name"] == name, f"plan.json's name is the patient's: {j['patient']['name']!r}")
    check(j["patient"]["file"] == f"{d}/p.yaml", f"and its file, a path with a quote and a backslash: {j['patient']['file']!r}")
    check(j["plan"]["arc_deg"] >= 0 and j["fallback"] == [], "the plan itself is whole")
html = open(f"{d}/plan/plan.html", encoding="utf-8").read()
check("O&quot;Brien \\ test" in html and 'O"Brien' not in html, "plan.html escapes the name")
check(open(f"{d}/plan/scene.yaml", encoding="utf-8").read().startswith("# the eye of patient O\"Brien \\ test\n# Zoë"),
      "scene.yaml's header comment keeps the name in comments (mesh-prep read it)")
try:
    c = json.load(open(f"{tmp}/curv.json", encoding="utf-8"))
    check(len(c["steps"]) >= 2 and "uncertainty" in c, f"curvature --json parses ({len(c['steps'])} steps, with its bands)")
except ValueError as ex:
    check(False, f"curvature --json parses: {ex}")
print(f"lriplan_json: {0 if fails else 1} passed, {len(fails)} failed")
sys.exit(1 if fails else 0)
PY
