#!/usr/bin/env bash
# lriplan_pipeline.sh BUILD_DIR: lri-plan --fast on plans/patients/atr-os.yaml (a left eye,
# against the rule, measured posterior, the surgeon's SIA vector). A second reader checks the
# answer: the scene written carries the patient's values (axis, ordering centre, the age rule,
# the measured posterior's radii and steep axis, the blade depth); every candidate's predicted
# residual equals the double-angle sum, recomputed here, of the run's simulated total corneal
# astigmatism (run-*/curvature.tsv: both mesh surfaces, the posterior's toricity in the mesh)
# and the surgeon's SIA; the answer is
# the least of them; the arcs lower the astigmatism. Round trip: the chosen arc cut alone by
# hand (cutplan | augsolve | curvature) gives the predicted residual within 0.02 D. The band
# (lri-plan(1), BAND), read again from the chosen run's derivatives.tsv: the projection of the
# SIA vector's derivatives on the SIA itself gives curvature's own sia_D_sd of that step (the
# reader agrees with curvature), and on the predicted residual (here oblique to the SIA: the
# surgeon's vector and the posterior) it gives plan.json's residual sd and 90% interval.
set -uo pipefail
B=$(cd "$1" && pwd)
cd "$(dirname "$0")/.."
py=/usr/bin/python3
tmp=$(mktemp -d /tmp/kt-lriplan.XXXXXX)
trap 'rm -rf "$tmp"' EXIT
if ! "$B/lri-plan" --fast -q plans/patients/atr-os.yaml -o "$tmp/plan" > "$tmp/summary" 2> "$tmp/err"; then
    echo "FAILED: lri-plan: $(cat "$tmp/err")"; exit 1
fi
cat "$tmp/summary"
"$py" - "$tmp/plan" "$tmp/summary" <<'PY'
import json, math, sys
out = sys.argv[1]
summary = open(sys.argv[2]).read()
d = json.load(open(f"{out}/plan.json"))
fails = []
def check(cond, what):
    print(("ok   " if cond else "FAIL ") + what)
    if not cond: fails.append(what)
def vec(m, a): return (m * math.cos(2 * math.radians(a)), m * math.sin(2 * math.radians(a)))
# The patient (plans/patients/atr-os.yaml): posterior -6.25 / -5.90 D @ 92 (in the scene:
# radii 40/6.25, 40/5.90 mm; the mesh carries it); the surgeon's SIA 0.35 D @ 90 deg.
post, sia = (0.0, 0.0), vec(0.35, 90.0)
scene = open(f"{out}/scene.yaml").read()
def field(key):
    for line in scene.splitlines():
        s = line.strip()
        if s.startswith(key + ":"): return float(s.split()[1])
    return float("nan")
check(abs(field("steep_axis") - 178) < 1e-9, "scene steep_axis 178 deg")
check(abs(field("centre") - 178) < 1e-9, "ordering centred on the steep meridian")
check(abs(field("posterior_radius_steep") - 40 / 6.25) < 1e-9 and abs(field("posterior_radius_flat") - 40 / 5.90) < 1e-9,
      "posterior radii 40/6.25, 40/5.90 mm")
check(abs(field("posterior_steep_axis") - 92) < 1e-9, "posterior steep axis 92 deg")
rows = [l.rstrip("\n").split("\t") for l in open(f"{out}/run-{d['candidates'][0]['incisions']}/curvature.tsv")]
pc = float(rows[1][rows[0].index("post_cyl_D")])
check(abs(pc - 0.35) < 0.06, f"curvature reads the measured 0.35 D posterior cylinder from the mesh ({pc:.3f} D)")
check(abs(field("depth") - 0.58) < 1e-12, "blade depth 580 um")
check(abs(field("white_to_white") - 11.9) < 1e-12, "white-to-white")
e = [float(l.split("E_inplane: ")[1].split()[0]) for l in scene.splitlines() if l.strip().startswith("cornea:") and "E_inplane" in l]
check(len(e) == 1 and abs(e[0] - 2.0 * (1 + 0.075 * (74 - 60) / 10)) < 1e-9, f"age rule on the cornea: {e}")
check(d["main_incision"]["meridian_deg"] == 0.0, "temporal is 0 deg in a left eye")
head = {}
# The pair at 178/358 deg would run its 358 deg arc through the temporal incision at 0 deg
# (keratome-patient(5), CLEARANCE): it is left out, the single arc at 178 deg kept.
check([c["incisions"] for c in d["candidates"]] == ["single"], f"only the single arc: {[c['incisions'] for c in d['candidates']]}")
check("paired arcs left out: the arc at 358 deg would come within 15 deg of the main incision at 0 deg" in summary,
      "the summary says why the pair is left out")
for line in open(f"{out}/single.edits"):
    w = line.split()
    if w and w[0] == "step": break
    if w: head[w[0]] = w[1:]
check(head.get("hash", [""])[0] == d["provenance"]["mesh_hash"], f"mesh hash {d['provenance']['mesh_hash']} as in the edits header")
best = None
for c in d["candidates"]:
    fam = c["incisions"]
    rows = [l.rstrip("\n").split("\t") for l in open(f"{out}/run-{fam}/curvature.tsv")]
    h = rows[0]
    ic, ia = h.index("total_cyl_D"), h.index("total_axis_deg")
    check(len(rows) - 1 == len(c["curve"]) == 19, f"{fam}: 18 steps of 5 deg and step 0")
    worst = 0
    for k, r in enumerate(rows[1:]):
        t = vec(float(r[ic]), float(r[ia]))
        x, y = t[0] + post[0] + sia[0], t[1] + post[1] + sia[1]
        worst = max(worst, abs(math.hypot(x, y) - c["curve"][k]["residual_D"]))
        check(abs(c["curve"][k]["arc_deg"] - 5 * k) < 1e-9, f"{fam} step {k}: arc {5 * k} deg") if k in (0, 18) else None
    check(worst < 2e-4, f"{fam}: every predicted residual recomputed (worst {worst:.2e} D)")
    m = min(p["residual_D"] for p in c["curve"])
    check(abs(c["best_residual_D"] - m) < 1e-3, f"{fam}: best arc is the least residual ({m:.3f} D)")
    check(m < d["pre_op"]["total_D"] - 0.2, f"{fam}: the arcs lower the total astigmatism ({d['pre_op']['total_D']:.2f} -> {m:.2f} D)")
    best = m if best is None else min(best, m)
p = d["plan"]
check(p["predicted_residual_D"] <= best + 0.01 + 1e-9, "the answer is the least residual of the families (within 0.01 D)")
check(p["reached"] == (p["predicted_residual_D"] <= 0.5), "reached says whether 0.5 D is reached")
check(abs(p["chord_mm"] - 10.5 * math.sin(math.radians(p["arc_deg"] / 2))) < 0.01, "chord at the zone")
check(abs((p["from_deg"] + p["arc_deg"] - p["to_deg"]) % 360) < 0.1, "arc end points")
# The round trip: the chosen arc alone, cut clockwise in one step (not as a prefix of the
# centre-out run), by hand with the tools.
with open(f"{out}/roundtrip.yaml", "w") as f:
    f.write(f"name: roundtrip\nscene: scene.yaml\nincisions:\n  - meridian: {p['centre_deg']} deg\n"
            f"    arc: {p['arc_deg']} deg\n    depth: 580 um\n    position: {{surface: incision-ring-1}}\n"
            f"    paired: {'true' if p['incisions'] == 'paired' else 'false'}\n    direction: cw\n"
            f"progression: {{degrees_per_step: {p['arc_deg']} deg}}\n")
with open(f"{out}/expect", "w") as f:
    f.write(f"{p['predicted_residual_D']}\n")
# The band, a second reader.
b = d["band"]
fam = p["incisions"]
ks = [i for i, q in enumerate(next(c for c in d["candidates"] if c["incisions"] == fam)["curve"]) if abs(q["arc_deg"] - p["arc_deg"]) < 1e-9]
k = ks[0] if ks else -1
der = [l.rstrip("\n").split("\t") for l in open(f"{out}/run-{fam}/derivatives.tsv")]
dh = der[0]
dq = [(float(r[dh.index("sia_x_D")]), float(r[dh.index("sia_y_D")]), float(r[dh.index("sd")]))
      for r in der[1:] if int(r[dh.index("step")]) == k and r[dh.index("used")] == "1"]
def proj(v):
    n = math.hypot(*v)
    return math.sqrt(sum(((v[0] * x + v[1] * y) / n * s) ** 2 for x, y, s in dq))
rows = [l.rstrip("\n").split("\t") for l in open(f"{out}/run-{fam}/curvature.tsv")]
h, r = rows[0], rows[1 + k]
sia_sd = float(r[h.index("sia_D_sd")])
mine = proj(vec(float(r[h.index("sia_D")]), float(r[h.index("sia_axis_deg")])))
check(k > 0 and len(dq) >= 4 and abs(mine - sia_sd) <= 2e-4 + 1e-3 * sia_sd,
      f"band reader: the SIA's own projection {mine:.4f} D = curvature's sia_D_sd {sia_sd:.4f} D ({len(dq)} quantities, step {k})")
res = vec(p["predicted_residual_D"], p["predicted_residual_axis_deg"])
want = proj(res)
got = b["predicted_residual"]["sd_D"]
check(abs(got - want) <= 5e-4 + 2e-3 * want, f"residual sd {got:.4f} D = the projection on the residual {want:.4f} D (SIA sd {sia_sd:.4f} D)")
rm = p["predicted_residual_D"]
check(abs(b["predicted_residual"]["lo90_D"] - max(0, rm - 1.6448536 * got)) < 2e-3 and
      abs(b["predicted_residual"]["hi90_D"] - (rm + 1.6448536 * got)) < 2e-3, "residual's 90% interval")
print(f"lriplan_pipeline: {0 if fails else 1} passed, {len(fails)} failed")
sys.exit(1 if fails else 0)
PY
[ $? -eq 0 ] || exit 1
d="$tmp/plan"
if [ "$(/usr/bin/python3 -c "import json; print(json.load(open('$d/plan.json'))['plan']['arc_deg'] > 0)")" != True ]; then
    echo "FAILED: the answer has no arc to check"; exit 1
fi
"$B/cutplan" -q "$d/roundtrip.yaml" "$d/eye.msh" -o "$d/rt.edits" 2> "$tmp/err" &&
    "$B/augsolve" -q --binary "$d/eye.msh" "$d/rt.edits" -o "$d/rt" 2>> "$tmp/err" &&
    "$B/curvature" -q --no-png --no-vtk --no-report "$d/rt" > /dev/null 2>> "$tmp/err" ||
    { echo "FAILED: the round trip's tools: $(cat "$tmp/err")"; exit 1; }
"$py" - "$d" <<'PY'
import math, sys
d = sys.argv[1]
rows = [l.rstrip("\n").split("\t") for l in open(f"{d}/rt/curvature.tsv")]
h, last = rows[0], rows[-1]
def vec(m, a): return (m * math.cos(2 * math.radians(a)), m * math.sin(2 * math.radians(a)))
t, post, sia = vec(float(last[h.index("total_cyl_D")]), float(last[h.index("total_axis_deg")])), (0.0, 0.0), vec(0.35, 90.0)
got = math.hypot(t[0] + post[0] + sia[0], t[1] + post[1] + sia[1])
want = float(open(f"{d}/expect").read())
ok = abs(got - want) <= 0.02
print(f"{'ok  ' if ok else 'FAIL'} round trip: the chosen arc cut alone gives {got:.4f} D, lri-plan predicted {want:.4f} D")
print(f"lriplan_roundtrip: {1 if ok else 0} passed, {0 if ok else 1} failed")
sys.exit(0 if ok else 1)
PY
