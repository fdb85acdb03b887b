#!/usr/bin/env bash
# lriplan_fallback.sh BUILD_DIR: a fallback of the planned method is loud (lri-plan(1),
# DESCRIPTION 5). lri-plan --fast --plan-max-ratio 0.5 (no planned factor is that small: every
# family falls back to refactor) with -q on a short single arc: exit 0, one line per family on
# stderr saying so whatever -q says, plan.json's fallback lists it and the family's method is
# refactor; the same patient planned with the planned method (no fallback: stderr empty, fallback
# []) gives the same answer (the two methods agree to round-off: augsolve --verify).
set -uo pipefail
B=$(cd "$1" && pwd)
cd "$(dirname "$0")/.."
tmp=$(mktemp -d /tmp/kt-lriplan-fb.XXXXXX)
trap 'rm -rf "$tmp"' EXIT
cat > "$tmp/p.yaml" <<'YAML'
name: fallback
eye: OD
age: 66
cornea:
  keratometry: {k_steep: 44.5 D, k_flat: 43.0 D, steep_axis: 90 deg}
constraints: {incisions: single, max_arc: 10 deg}
YAML
"$B/lri-plan" --fast -q --no-uncertainty --plan-max-ratio 0.5 "$tmp/p.yaml" -o "$tmp/fb" > /dev/null 2> "$tmp/fb.err" ||
    { echo "FAILED: lri-plan --plan-max-ratio 0.5: $(cat "$tmp/fb.err")"; exit 1; }
"$B/lri-plan" --fast -q --no-uncertainty "$tmp/p.yaml" -o "$tmp/pl" > /dev/null 2> "$tmp/pl.err" ||
    { echo "FAILED: lri-plan: $(cat "$tmp/pl.err")"; exit 1; }
/usr/bin/python3 - "$tmp" <<'PY'
import json, sys
t = sys.argv[1]
fails = []
def check(cond, what):
    print(("ok   " if cond else "FAIL ") + what)
    if not cond: fails.append(what)
fb, pl = json.load(open(f"{t}/fb/plan.json")), json.load(open(f"{t}/pl/plan.json"))
err = open(f"{t}/fb.err").read().splitlines()
check(len(err) == 1 and "single arcs: the planned method does not apply" in err[0] and "falling back to --method refactor" in err[0],
      f"with -q, one line on stderr says so: {err}")
check(len(fb["fallback"]) == 1 and fb["candidates"][0]["method"] == "refactor" and fb["candidates"][0]["fallback"] == fb["fallback"][0],
      f"plan.json records it: {fb['fallback']}")
check("fallback:" in open(f"{t}/fb/run/run.yaml").read(), "and the chosen run's run.yaml")
check(open(f"{t}/pl.err").read() == "" and pl["fallback"] == [] and pl["candidates"][0]["method"] == "planned",
      "the planned method: nothing on stderr, no fallback")
a, b = fb["plan"], pl["plan"]
check(a["arc_deg"] == b["arc_deg"] and abs(a["predicted_residual_D"] - b["predicted_residual_D"]) <= 1e-3,
      f"the same answer: {a['arc_deg']} deg, {a['predicted_residual_D']} against {b['predicted_residual_D']} D")
w = max(abs(x["residual_D"] - y["residual_D"]) for x, y in zip(fb["candidates"][0]["curve"], pl["candidates"][0]["curve"]))
check(w <= 2e-4, f"every step's residual the same within {w:.1e} D")
print(f"lriplan_fallback: {0 if fails else 1} passed, {len(fails)} failed")
sys.exit(1 if fails else 0)
PY
