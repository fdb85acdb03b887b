#!/usr/bin/env bash
# readme_plan.sh BUILD_DIR: README.md's picture of plan.html (docs/plan.png) shows what the tool
# gives today. lri-plan --fast on plans/patients/asym-od.yaml (the picture's run); its answer as
# one line (scripts/plan_answer.py: the family, the arcs, the predicted residual) must be the
# PNG's tEXt "Description" (scripts/plan-png.sh writes it with the screenshot) and must stand in
# the README's alt text for the picture. When the physics or the planner changes the answer,
# this fails until docs/plan.png is made again (bash scripts/plan-png.sh) and the alt text
# follows.
set -uo pipefail
B=$(cd "$1" && pwd)
cd "$(dirname "$0")/.."
tmp=$(mktemp -d /tmp/kt-readme-plan.XXXXXX)
trap 'rm -rf "$tmp"' EXIT
if ! "$B/lri-plan" --fast -q plans/patients/asym-od.yaml -o "$tmp/plan" > /dev/null 2> "$tmp/err"; then
    echo "FAILED: lri-plan: $(cat "$tmp/err")"; exit 1
fi
/usr/bin/python3 - "$tmp/plan/plan.json" <<'PY'
import json, re, sys
sys.path.insert(0, "scripts")
from plan_answer import answer, png_description
want = answer(json.load(open(sys.argv[1])))
fails = 0
def check(cond, what):
    global fails
    print(("ok   " if cond else "FAIL ") + what)
    fails += not cond
png = png_description("docs/plan.png")
check(png == want, f"docs/plan.png was made from today's answer: '{png}' against '{want}'")
alts = re.findall(r"!\[([^\]]*)\]\(docs/plan\.png\)", open("README.md").read())
check(len(alts) == 1 and want in alts[0], f"README.md's alt text carries it: {alts}")
print(f"readme_plan: {0 if fails else 1} passed, {fails} failed")
sys.exit(1 if fails else 0)
PY
