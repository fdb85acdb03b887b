#!/usr/bin/env bash
# lriplan_main.sh BUILD_DIR: the main cataract incision, simulated (keratome-plan(5) TUNNELS,
# keratome-patient(5) MAIN INCISION).
# 1. On a coarse eye (plans/eye.yaml with larger elements), a 2.4 mm tunnel alone at two
#    meridians (temporal OD 180 deg, superior 90 deg): cutplan | augsolve | curvature. Its
#    edits duplicate nodes on both the anterior and the posterior ('inner') surfaces (it goes
#    through the full thickness); its SIA is a flattening along its meridian: K along the
#    meridian falls, and the SIA's steep axis lies within 15 deg of the orthogonal meridian.
# 2. lri-plan --fast on a left eye with a simulated temporal incision (0 deg) and short single
#    arcs: the chosen run (PLAN_DIR/run, read by curvature: its plan.yaml gives the arcs) begins
#    with the tunnel's steps; plan.json's simulated SIA equals that run's curvature.tsv after the
#    tunnel's steps less step 0 (double-angle), its axis is orthogonal to the temporal meridian,
#    the candidate's curve starts after the tunnel (its readings = curvature's), the pre-op is
#    the intact eye, curvature.tsv's arc_deg is 0 through the tunnel and grows after it, and the
#    scene meshes the tunnel's site finer (eye.mesh_size.site). The report is the plan (issue 34):
#    report/curvature.tsv's last step is the run's step that holds the chosen arc (after the
#    tunnel's steps, not the arc's step count), its arc is plan.json's, its total corneal
#    astigmatism the predicted residual, and report.html draws the chosen arc and the main
#    incision.
# 3. Bad tunnels in a plan exit 2 at file:line:col before any cut, with nothing written.
# 4. The band on the predicted residual (lri-plan(1), BAND), lri-plan --fast on a right eye with
#    the rule, no main incision, single arcs to 15 deg (the residual far from zero, along the
#    SIA): the SIA's sd at the chosen step is curvature's own sia_D_sd of the chosen run (a
#    second reader: report/curvature.tsv), and so is the magnitude's sd there, its 90% interval
#    about residual +- 1.645 sd; with a base scene whose uncertainty section sets every sd to 0
#    the band is a point (sd 0, lo = hi = the residual).
set -uo pipefail
B=$(cd "$1" && pwd)
cd "$(dirname "$0")/.."
py=/usr/bin/python3
T=$(mktemp -d /tmp/kt-main.XXXXXX)
trap 'rm -rf "$T"' EXIT
fail() { echo "lriplan_main: FAILED: $*"; exit 1; }
sed -e 's/^    optical_zone: [0-9.]* mm/    optical_zone: 0.8 mm/' -e 's/^    incision: [0-9.]* mm/    incision: 0.4 mm/' \
    -e 's/^    cornea: [0-9.]* mm/    cornea: 1.0 mm/' -e 's/^    sclera: [0-9.]* mm/    sclera: 2.5 mm/' \
    -e '/^    incision_floor:/d' plans/eye.yaml > "$T/eye.yaml"
grep -q "cornea: 1.0 mm" "$T/eye.yaml" || fail "could not coarsen plans/eye.yaml"
"$B/mesh-prep" -q "$T/eye.yaml" -o "$T/eye.msh" > /dev/null 2> "$T/err" || fail "mesh-prep: $(cat "$T/err")"
for m in 180 90; do
    printf 'name: tunnel-%s\nscene: eye.yaml\ntunnels:\n  - {meridian: %s deg, width: 2.4 mm}\n' $m $m > "$T/t$m.yaml"
    "$B/cutplan" -q "$T/t$m.yaml" "$T/eye.msh" --mesh-out "$T/e$m.msh" -o "$T/t$m.edits" 2> "$T/err" &&
        "$B/augsolve" -q --binary "$T/e$m.msh" "$T/t$m.edits" -o "$T/r$m" 2>> "$T/err" &&
        "$B/curvature" -q --no-png --no-vtk --no-report "$T/r$m" > /dev/null 2>> "$T/err" ||
        fail "tunnel at $m deg: $(cat "$T/err")"
done
"$py" - "$T" <<'PY' || exit 1
import math, sys
import meshio
T = sys.argv[1]
fails = []
def check(cond, what):
    print(("ok   " if cond else "FAIL ") + what)
    if not cond: fails.append(what)
for mer in (180, 90):
    m = meshio.read(f"{T}/e{mer}.msh")
    tags = {k: v[0] for k, v in m.field_data.items()}
    on = {"anterior": set(), "inner": set()}
    for cb, phys in zip(m.cells, m.cell_data["gmsh:physical"]):
        if cb.type.startswith("triangle"):
            for name in on:
                on[name].update((cb.data[phys == tags[name]].ravel() + 1).tolist())  # 1-based as the edits
    dups = [int(l.split()[1]) for l in open(f"{T}/t{mer}.edits") if l.startswith("dup ")]
    na, ni = sum(d in on["anterior"] for d in dups), sum(d in on["inner"] for d in dups)
    check(na > 0 and ni > 0, f"{mer} deg: the tunnel opens both surfaces ({na} anterior, {ni} posterior nodes split)")
    rows = [l.rstrip("\n").split("\t") for l in open(f"{T}/r{mer}/curvature.tsv")]
    h = rows[0]
    col = lambda r, k: float(r[h.index(k)])
    def k_along(r, th):
        ks, kf, ax = col(r, "k_steep_D"), col(r, "k_flat_D"), col(r, "axis_steep_deg")
        return kf + (ks - kf) * math.cos(math.radians(th - ax)) ** 2
    pre, post = rows[1], rows[-1]
    dk = k_along(post, mer) - k_along(pre, mer)
    check(dk < -0.02, f"{mer} deg: K along the incised meridian falls by {-dk:.3f} D")
    sia, ax = col(post, "sia_D"), col(post, "sia_axis_deg")
    off = abs((ax - (mer + 90)) % 180)
    off = min(off, 180 - off)
    check(sia > 0.05 and off < 15, f"{mer} deg: SIA {sia:.3f} D @ {ax:.1f} (steep axis {off:.1f} deg from {(mer + 90) % 180})")
print(f"lriplan_main (tunnel alone): {6 - len(fails)} passed, {len(fails)} failed")
sys.exit(1 if fails else 0)
PY

# 2. lri-plan with the main incision simulated.
cat > "$T/os.yaml" <<'EOF'
name: main-os
eye: OS
age: 70
cornea:
  keratometry: {k_steep: 44.50 D, k_flat: 43.50 D, steep_axis: 90 deg}
main_incision: {meridian: temporal, width: 2.4 mm, kind: clear_corneal}
constraints: {incisions: single, max_arc: 15 deg}
EOF
"$B/lri-plan" -q --fast "$T/os.yaml" -o "$T/plan" > "$T/summary" 2> "$T/err" || fail "lri-plan: $(cat "$T/err")"
cat "$T/summary"
"$B/curvature" -q --no-png --no-vtk --no-report "$T/plan/run" -o "$T/plan/rc" > /dev/null 2> "$T/err" ||
    fail "curvature on the chosen run: $(cat "$T/err")"
"$py" - "$T/plan" <<'PY' || exit 1
import json, math, sys
d = sys.argv[1]
j = json.load(open(f"{d}/plan.json"))
fails = []
def check(cond, what):
    print(("ok   " if cond else "FAIL ") + what)
    if not cond: fails.append(what)
def vec(m, a): return (m * math.cos(2 * math.radians(a)), m * math.sin(2 * math.radians(a)))
mi = j["main_incision"]
check(mi["meridian_deg"] == 0.0 and mi["sia"].startswith("simulated"), "temporal is 0 deg in a left eye, simulated")
site = [l for l in open(f"{d}/scene.yaml") if l.strip().startswith("site:")]
check(len(site) == 1 and "meridian: 0 deg" in site[0], f"the scene refines the main incision's site: {site[0].strip() if site else None}")
ntun = mi["simulated_steps"]
plan = open(f"{d}/run/plan.yaml").read()
check(ntun >= 1 and "tunnels:" in plan and plan.index("tunnels:") < plan.index("incisions:"),
      f"the chosen run's plan cuts the tunnel first ({ntun} steps)")
rows = [l.rstrip("\n").split("\t") for l in open(f"{d}/rc/curvature.tsv")]
h = rows[0]
def astig(r, kind):
    return vec(float(r[h.index("cyl_D" if kind == "k" else "total_cyl_D")]),
               float(r[h.index("axis_steep_deg" if kind == "k" else "total_axis_deg")]))
a0, a1 = astig(rows[1], "k"), astig(rows[1 + ntun], "k")
sia = math.hypot(a1[0] - a0[0], a1[1] - a0[1])
check(abs(sia - mi["simulated_sia_keratometric_D"]) < 1e-3, f"simulated SIA {mi['simulated_sia_keratometric_D']:.4f} D = the run's {sia:.4f} D")
ax = mi["simulated_sia_keratometric_axis_deg"]
check(min(abs(ax - 90), 180 - abs(ax - 90)) < 15 and sia > 0.05, f"its steep axis {ax:.1f} deg is orthogonal to the temporal meridian")
check(abs(j["pre_op"]["keratometric_D"] - float(rows[1][h.index("cyl_D")])) < 1e-3, "pre-op is the intact eye (step 0)")
p = j["plan"]
c = j["candidates"][0]["curve"]
check(len(rows) - 1 == p["run_step"] + 1 == ntun + round(p["arc_deg"] / 5) + 1,
      f"run/ holds step 0, the tunnel's {ntun} steps and the arcs up to the chosen {p['arc_deg']} deg")
arc = [float(r[h.index("arc_deg")]) for r in rows[1:]]
check(all(x == 0 for x in arc[:1 + ntun]) and all(b > a for a, b in zip(arc[ntun:], arc[ntun + 1:])),
      f"curvature.tsv's arc_deg: 0 through the tunnel's steps, growing after them: {arc}")
worst = max(abs(c[k]["keratometric_D"] - float(rows[1 + ntun + k][h.index("cyl_D")])) for k in range(len(rows) - 1 - ntun))
check(worst < 2e-4, f"the curve starts after the tunnel: arc 0 is the eye after the main incision (readings within {worst:.1e} D)")
rr = [l.rstrip("\n").split("\t") for l in open(f"{d}/report/curvature.tsv")]
rh, last = rr[0], rr[-1]
check(int(last[0]) == p["run_step"] and abs(float(last[rh.index("arc_deg")]) - p["arc_deg"]) < 1e-9,
      f"the report's step is the run's step {p['run_step']} holding the chosen {p['arc_deg']} deg arc (got step {last[0]}, "
      f"{last[rh.index('arc_deg')]} deg)")
res = float(last[rh.index("total_cyl_D" if j["target"]["astigmatism"] == "total_corneal" else "cyl_D")])
check(abs(res - p["predicted_residual_D"]) < 1e-3, f"the report's residual {res:.4f} D = plan.json's {p['predicted_residual_D']} D")
rep = open(f"{d}/report/report.html").read()
check(f"{p['arc_deg']:.0f}&deg; (arc length" in rep and "main 2.4 mm" in rep and "simulated: its tunnel is cut" in rep,
      "report.html draws the chosen arc and the main incision")
print(f"lriplan_main (lri-plan): {13 - len(fails)} passed, {len(fails)} failed")
sys.exit(1 if fails else 0)
PY

# 3. Bad tunnels.
n=0
for c in "length: 0.3 mm|4:48: tunnels[0].length: expected a tunnel that reaches the anterior chamber" \
         "entry_diameter: 6 mm|4:56: tunnels[0].entry_diameter: expected the entry on the peripheral cornea" \
         "width: 12 mm|4:32: tunnels[0].width: expected" "steps: 0|4:47: tunnels[0].steps: expected"; do
    IFS='|' read -r field want <<< "$c"
    case $field in width*) line="{meridian: 180 deg, $field}" ;; *) line="{meridian: 180 deg, width: 2.4 mm, $field}" ;; esac
    printf 'name: bad\nscene: eye.yaml\ntunnels:\n  - %s\n' "$line" > "$T/bad.yaml"
    rc=0
    "$B/cutplan" -q "$T/bad.yaml" "$T/eye.msh" -o "$T/bad.edits" 2> "$T/err" || rc=$?
    if [ $rc -eq 2 ] && [ ! -e "$T/bad.edits" ] && [ "$(wc -l < "$T/err")" -eq 1 ] && grep -qF -- "bad.yaml:$want" "$T/err"; then
        echo "ok   bad tunnel '$field': $(cat "$T/err")"; n=$((n + 1))
    else
        fail "bad tunnel '$field': exit $rc, '$(cat "$T/err")', want 'bad.yaml:$want'"
    fi
done
echo "lriplan_main (bad tunnels): $n passed, 0 failed"

# 4. The band.
cat > "$T/od.yaml" <<'EOF'
name: band-od
eye: OD
age: 70
cornea:
  keratometry: {k_steep: 44.50 D, k_flat: 43.50 D, steep_axis: 90 deg}
constraints: {incisions: single, max_arc: 15 deg}
EOF
{ cat plans/eye.yaml; printf 'uncertainty:\n'
  for q in E_inplane G_transverse iop limbal_density thickness depth age_slope heal; do printf '  %s: {sd: 0}\n' "$q"; done
  printf '  nontissue_cv: 0\n'
} > "$T/eye0.yaml"
"$B/lri-plan" -q --fast "$T/od.yaml" -o "$T/band" > "$T/band.txt" 2> "$T/err" || fail "lri-plan (band): $(cat "$T/err")"
"$B/lri-plan" -q --fast --base "$T/eye0.yaml" "$T/od.yaml" -o "$T/band0" > "$T/band0.txt" 2> "$T/err" ||
    fail "lri-plan (zero sd): $(cat "$T/err")"
grep "band" "$T/band.txt"
"$py" - "$T" <<'PY' || exit 1
import json, math, sys
T = sys.argv[1]
fails = []
def check(cond, what):
    print(("ok   " if cond else "FAIL ") + what)
    if not cond: fails.append(what)
j = json.load(open(f"{T}/band/plan.json"))
b, p = j["band"], j["plan"]
rr = [l.rstrip("\n").split("\t") for l in open(f"{T}/band/report/curvature.tsv")]
h, r = rr[0], rr[-1]
sd_c = float(r[h.index("sia_D_sd")])
res = b["predicted_residual"]
check(int(r[0]) == p["run_step"] and sd_c > 0, f"the chosen step {p['run_step']} ({p['arc_deg']} deg) has curvature's SIA sd {sd_c:.4f} D")
check(abs(b["sia_sd_tissue_D"] - sd_c) <= 2e-4 + 1e-3 * sd_c,
      f"the band's tissue SIA sd {b['sia_sd_tissue_D']:.4f} D = curvature's sia_D_sd {sd_c:.4f} D")
sd_a = b["sia_sd_D"] # with the non-tissue term along the SIA (nontissue_cv)
check(b["nontissue_cv"] > 0 and sd_a > sd_c, f"the non-tissue term widens it: cv {b['nontissue_cv']}, {sd_a:.4f} D")
m = p["predicted_residual_D"]
check(m > 3 * sd_a and abs(res["sd_D"] - sd_a) <= 0.02 * sd_a + 2e-4,
      f"far from zero along the SIA, the magnitude's sd {res['sd_D']:.4f} D is the SIA's {sd_a:.4f} D (residual {m:.3f} D)")
check(abs(res["lo90_D"] - (m - 1.6448536 * sd_a)) < 0.02 * sd_a + 2e-3 and abs(res["hi90_D"] - (m + 1.6448536 * sd_a)) < 0.02 * sd_a + 2e-3,
      f"90%: {res['lo90_D']:.3f}-{res['hi90_D']:.3f} D about {m:.3f} D")
check("thickness" in b["left_out"] and "depth" in b["left_out"], f"left out: {b['left_out']}")
z = json.load(open(f"{T}/band0/plan.json"))["band"]
zr = z["predicted_residual"]
check(zr["sd_D"] == 0 and abs(zr["lo90_D"] - zr["hi90_D"]) < 1e-9 and z["post_op_total"]["sd_D"] == 0 and z["left_out"] == "",
      f"every sd 0: zero band ({zr})")
print(f"lriplan_main (band): {7 - len(fails)} passed, {len(fails)} failed")
sys.exit(1 if fails else 0)
PY
