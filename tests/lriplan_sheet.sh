#!/usr/bin/env bash
# lriplan_sheet.sh BUILD_DIR: the plan sheet and unequal paired arcs. lri-plan --fast on
# plans/patients/asym-od.yaml (a Pentacam export whose inferior half-meridian is the steeper).
# A second reader parses plan.json back and checks every number plan.html shows (each is in an
# element data-key="<json path>") against it, within the page's printed precision; checks the
# unequal family (the half-meridians found asymmetric, the inferior half steeper, the plan cut
# with arc_opposite = ratio x arc, every step's opposite arc in that ratio, the SIA curve
# recomputed from the run's curvature.tsv, the answer the least residual of the families) and
# the link to the chosen run's report.html; then headless Chromium renders plan.html: no console
# message, no network request, a screenshot. Without Chromium that last part is skipped.
set -uo pipefail
B=$(cd "$1" && pwd)
cd "$(dirname "$0")/.."
PY=/usr/bin/python3
tmp=$(mktemp -d /tmp/kt-lriplan-sheet.XXXXXX)
trap 'rm -rf "$tmp"' EXIT
out=$tmp/plan
if ! "$B/lri-plan" --fast -q plans/patients/asym-od.yaml -o "$out" > "$tmp/summary" 2> "$tmp/err"; then
    echo "FAILED: lri-plan: $(cat "$tmp/err")"; exit 1
fi
cat "$tmp/summary"
CHROME=$(command -v chromium || true)
if [ -n "$CHROME" ]; then
    timeout 120 "$CHROME" --headless --no-sandbox --disable-gpu --disable-quic --hide-scrollbars --no-first-run \
        --disable-background-networking --disable-component-update --disable-sync \
        --host-resolver-rules="MAP * ~NOTFOUND" --user-data-dir="$(mktemp -d "$tmp/profile.XXXXXX")" \
        --enable-logging=stderr --v=0 --log-net-log="$tmp/netlog.json" \
        --window-size=1280,2600 --screenshot="$tmp/page.png" "file://$out/plan.html" 2> "$tmp/chrome.stderr" > /dev/null || true
fi
$PY - "$out" "$tmp" "$CHROME" <<'PY'
import json, math, os, re, sys
out, tmp, chrome = sys.argv[1:4]
fails = []
def check(cond, what):
    print(("ok   " if cond else "FAIL ") + what)
    if not cond: fails.append(what)
d = json.load(open(f"{out}/plan.json"))
html = open(f"{out}/plan.html").read()
def lookup(path):
    v = d
    for part in path.split("."):
        v = v[int(part)] if isinstance(v, list) else v[part]
    return v
# Every number of the page against plan.json.
spans = re.findall(r'<span data-key="([^"]+)">([^<]*)</span>', html)
bad = []
for key, text in spans:
    try:
        want = lookup(key)
    except (KeyError, IndexError, ValueError):
        bad.append(f"{key}: not in plan.json"); continue
    if isinstance(want, str):
        if text != want: bad.append(f"{key}: page '{text}', json '{want}'")
        continue
    dec = len(text.split(".")[1]) if "." in text else 0
    tol = 0.5 * 10 ** -dec + 1e-9
    # the page rounds the value plan.json rounds to its own precision: allow both roundings
    jdec = len(repr(float(want)).split(".")[1]) if "." in repr(float(want)) else 0
    tol += 0.5 * 10 ** -jdec
    if not abs(float(text) - float(want)) <= tol: bad.append(f"{key}: page {text}, json {want}")
check(len(spans) >= 40, f"plan.html holds {len(spans)} numbers tied to plan.json")
check(not bad, f"every one of them agrees with plan.json ({bad[:3]})")
keys = {k for k, _ in spans}
for k in ("plan.arcs.0.from_deg", "plan.arcs.0.to_clock", "plan.arcs.1.chord_mm", "plan.blade_um", "plan.post_op_keratometric_D",
          "plan.post_op_total_D", "pre_op.total_D", "provenance.mesh_hash", "fit.anterior.rms_um", "halves.ratio"):
    check(k in keys, f"the page shows {k}")
check(html.count("<svg") >= 3, "the eye and the two curves are drawn (inline SVG)")
check("<script" not in html and "http://" not in html.replace("http://www.w3.org/2000/svg", ""), "no script, no external reference")
# Unequal pairs.
h = d["halves"]
check(h["astig_opposite_D"] > h["astig_at_axis_D"] and abs(h["steeper_half_deg"] - (d["patient"]["anterior"]["steep_axis_deg"] + 180)) < 0.1,
      f"the inferior half is the steeper ({h['astig_opposite_D']:.2f} against {h['astig_at_axis_D']:.2f} D)")
check(0.2 <= h["ratio"] < 0.9, f"asymmetric: ratio {h['ratio']:.3f}")
fams = {c["incisions"]: c for c in d["candidates"]}
check(set(fams) == {"paired", "unequal"}, f"families run: {sorted(fams)}")
u = fams.get("unequal")
if u:
    check(abs(u["ratio"] - h["ratio"]) < 1e-4 and abs(u["meridian_deg"] - h["steeper_half_deg"]) < 0.1, "the unequal family's ratio and centre")
    plan = open(f"{out}/plan-unequal.yaml").read()
    arc = float(re.search(r"\n    arc: ([0-9.eE+-]+) deg", plan).group(1))
    opp = float(re.search(r"arc_opposite: ([0-9.eE+-]+) deg", plan).group(1))
    check(abs(opp - u["ratio"] * arc) < 0.01, f"plan-unequal.yaml: arc_opposite {opp:.3f} = ratio x arc {arc:g}")
    check(all(abs(p["arc_opposite_deg"] - u["ratio"] * p["arc_deg"]) < 0.01 for p in u["curve"]), "every step's opposite arc in the ratio")
    rows = [l.rstrip("\n").split("\t") for l in open(f"{out}/run-unequal/curvature.tsv")]
    hd = rows[0]
    ic, ia = hd.index("cyl_D"), hd.index("axis_steep_deg")
    def vec(m, a): return (m * math.cos(2 * math.radians(a)), m * math.sin(2 * math.radians(a)))
    v0 = vec(float(rows[1][ic]), float(rows[1][ia]))
    worst = 0
    for k, r in enumerate(rows[1:]):
        v = vec(float(r[ic]), float(r[ia]))
        worst = max(worst, abs(math.hypot(v[0] - v0[0], v[1] - v0[1]) - u["curve"][k]["sia_D"]))
    check(worst < 2e-4, f"the SIA curve recomputed from run-unequal/curvature.tsv (worst {worst:.1e} D)")
    check(u["curve"][-1]["sia_D"] > u["curve"][1]["sia_D"] > 0, "the SIA grows with the arc")
best = min(c["best_residual_D"] for c in d["candidates"])
p = d["plan"]
check(p["predicted_residual_D"] <= best + 0.01 + 1e-9, f"the answer ({p['incisions']}) is the least residual of the families")
if p["incisions"] == "unequal":
    check(len(p["arcs"]) == 2 and abs(p["arcs"][1]["arc_deg"] - u["ratio"] * p["arcs"][0]["arc_deg"]) < 0.11, "the chosen pair's two arcs")
rep = d["provenance"]["report"]
check(rep != "" and os.path.getsize(f"{out}/{rep}") > 10000 and f'href="{rep}"' in html, f"plan.html links the chosen run's report ({rep})")
# Chromium.
if not chrome:
    print("SKIP the Chromium render: chromium missing (bash scripts/setup.sh --test)")
else:
    err = open(f"{tmp}/chrome.stderr", errors="replace").read()
    console = [l for l in err.splitlines() if ":CONSOLE" in l]
    check(os.path.exists(f"{tmp}/page.png") and os.path.getsize(f"{tmp}/page.png") > 10000, "Chromium rendered plan.html")
    check(not console, f"no console message ({console[:1]})")
    try:
        nl = json.load(open(f"{tmp}/netlog.json"))
        et = {v: k for k, v in nl["constants"]["logEventTypes"].items()}
        reqs = sorted({e["params"].get("url", "") for e in nl["events"] if et.get(e["type"]) == "URL_REQUEST_START_JOB"
                       and not e["params"].get("url", "").startswith(("file:", "data:"))
                       and "file://" in e["params"].get("network_isolation_key", "")})
        check(not reqs, f"no request leaves the page ({reqs[:2]})")
    except (OSError, ValueError) as ex:
        check(False, f"the net log: {ex}")
print(f"lriplan_sheet: {0 if fails else 1} passed, {len(fails)} failed")
sys.exit(1 if fails else 0)
PY
