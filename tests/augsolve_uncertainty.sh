#!/bin/bash
# augsolve_uncertainty.sh BUILD_DIR: augsolve --uncertainty (keratome-scene(5), UNCERTAINTY) on
# the prestressed eye (plans/eye.yaml physics) on the smallest P2 eye that cuts, a paired
# 60-degree LRI in 2 steps. Checks that can fail:
#   1. each derivative field dudp_<q> (E_inplane, G_transverse, iop, limbal_density, and
#      age_slope for a scene that states its age) agrees with the central finite difference of
#      two more runs at q +- h (h 1e-3 relative; the scene edited, the same mesh and edits) to
#      1e-4 relative, max norm over the nodes, at every step: the prestress's dependence on
#      the moduli and the IOP included;
#   2. the planned method's derivatives equal those of a stream method (refactor: derived from
#      scratch on the cut mesh) to 1e-6, and with --output anterior they equal the full run's
#      on the anterior surface and are NaN elsewhere;
#   3. uncertainty.tsv holds the header and one row per quantity (sd 0: method none and no
#      field; thickness and depth fd), run.yaml says `uncertainty: on`;
#   4. without --uncertainty: no uncertainty.tsv, no dudp field, and the displacement and
#      steps.tsv's non-timing columns equal the --uncertainty run's;
#   5. --method newton --uncertainty is refused with exit 2 before anything is solved.
#   7. the planned method's derivative matrices, made on a thread beside the factorization, give
#      the same step files as when made after it (under ulimit -v, where no thread starts).
#   6. curvature on these runs (issue 21 end to end): dSIA/dp in derivatives.tsv (through the
#      dudp fields) against the central difference of curvature.tsv's sia_D over two more runs
#      at E_inplane and iop +-5%, to 1%; sia_D_sd = sqrt(sum (dSIA/dp sd_p)^2) from
#      uncertainty.tsv and derivatives.tsv; the summary prints the SIA with its 90% interval;
#      report.html has the band and the tornado chart.
set -u
build="$1"
tmp=$(mktemp -d /tmp/kt-uncertainty.XXXXXX)
trap 'rm -rf "$tmp"' EXIT
printf 'leak:libgmsh.so\n' > "$tmp/lsan.supp"
export LSAN_OPTIONS="suppressions=$tmp/lsan.supp:print_suppressions=0"
fail() { echo "augsolve_uncertainty: FAILED: $*"; exit 1; }
# the smallest eye that still cuts (the bench suite's smoke eye: plans/eye.yaml's mesh sizes x4,
# cut off at 60 deg; about 14k P2 nodes)
awk -v f=4 -f scripts/bench/awk/tradeoff-scale-eye.awk plans/eye.yaml |
    sed -e '/^    incision_floor:/d' -e 's/^  extent: [0-9]* deg/  extent: 60 deg/' > "$tmp/eye.yaml"
grep -q "^  extent: 60 deg" "$tmp/eye.yaml" && grep -q "reference: prestressed" "$tmp/eye.yaml" ||
    fail "could not make the small eye"
# the scene states an age (as lri-plan's do) and leaves limbal_density at sd 0 in one variant
printf 'uncertainty:\n  age_slope: {sd: 0.05, age: 72}\n' >> "$tmp/eye.yaml"
sed -e "s|^scene:.*|scene: $tmp/eye.yaml|" -e 's|degrees_per_step:.*|degrees_per_step: 30 deg|' \
    plans/lri-paired-60.yaml > "$tmp/plan.yaml"
"$build/mesh-prep" -q "$tmp/eye.yaml" -o "$tmp/eye.msh" > /dev/null || fail "mesh-prep"
"$build/cutplan" -q "$tmp/plan.yaml" "$tmp/eye.msh" -o "$tmp/lri.edits" || fail "cutplan"
aug() { # RUN SCENE [options]
    local run=$1 scene=$2
    shift 2
    "$build/augsolve" -q "$tmp/eye.msh" "$tmp/lri.edits" --scene "$scene" -o "$tmp/$run" "$@" \
        2> "$tmp/$run.err" || fail "augsolve $*: $(cat "$tmp/$run.err")"
}
aug base "$tmp/eye.yaml" --uncertainty
aug plain "$tmp/eye.yaml"
aug refactor "$tmp/eye.yaml" --uncertainty --method refactor
aug anterior "$tmp/eye.yaml" --uncertainty --output anterior
# 7. the derivative matrices on a thread beside the factorization (base) and after it (under an
# address-space limit, where augsolve starts no thread): the same step files, byte for byte
(ulimit -v 16000000 && aug limited "$tmp/eye.yaml" --uncertainty) || fail "augsolve --uncertainty under ulimit -v"
n=0
for f in "$tmp"/base/step-*.vtk; do
    cmp -s "$f" "$tmp/limited/${f##*/}" || fail "${f##*/}: the derivative matrices beside the factor and after it differ"
    n=$((n + 1))
done
[ "$n" -ge 2 ] || fail "only $n step files"
echo "ok   7. $n step files the same with the derivative matrices beside the factor and after it"
# 1. the finite differences: each quantity at q +- h
variant() { # NAME SED
    sed -e "$2" "$tmp/eye.yaml" > "$tmp/$1.yaml"
    cmp -s "$tmp/eye.yaml" "$tmp/$1.yaml" && fail "variant $1 did not change the scene"
    aug "$1" "$tmp/$1.yaml"
}
variant Ep 's/E_inplane: 2.0 MPa/E_inplane: 2.002 MPa/g'
variant Em 's/E_inplane: 2.0 MPa/E_inplane: 1.998 MPa/g'
variant Gp 's/G_transverse: 9.5 kPa/G_transverse: 9.5095 kPa/g'
variant Gm 's/G_transverse: 9.5 kPa/G_transverse: 9.4905 kPa/g'
variant Ip 's/value: 15 mmHg/value: 15.015 mmHg/'
variant Im 's/value: 15 mmHg/value: 14.985 mmHg/'
variant Lp 's/limbal_density: 1.91 /limbal_density: 1.912 /'
variant Lm 's/limbal_density: 1.91 /limbal_density: 1.908 /'
# age_slope 0.075 +- 0.001 at age 72: the cornea's moduli (not the limbus's) times
# (1 + (0.075 +- 0.001) 1.2) / (1 + 0.075 x 1.2)
ap=$(awk 'BEGIN { printf "%.12g", (1 + 0.076 * 1.2) / (1 + 0.075 * 1.2) }')
am=$(awk 'BEGIN { printf "%.12g", (1 + 0.074 * 1.2) / (1 + 0.075 * 1.2) }')
cor() { awk -v f="$1" 'BEGIN { printf "s/^    E_inplane: 2.0 MPa/    E_inplane: %.15g MPa/;", 2.0 * f
                               printf "s/^    G_transverse: 9.5 kPa/    G_transverse: %.15g kPa/", 9.5 * f }'; }
variant Ap "$(cor "$ap")"
variant Am "$(cor "$am")"
# 5. newton is refused before anything is solved
"$build/augsolve" -q "$tmp/eye.msh" "$tmp/lri.edits" -o "$tmp/newton" --method newton --uncertainty \
    2> "$tmp/newton.err"
rc=$?
[ "$rc" -eq 2 ] || fail "--method newton --uncertainty: exit $rc, expected 2"
grep -q "uncertainty" "$tmp/newton.err" || fail "--method newton --uncertainty: no clear message"
[ -e "$tmp/newton/run.yaml" ] && fail "--method newton --uncertainty left a run.yaml"
python3 - "$tmp" <<'PY' || exit 1
import math, sys
tmp = sys.argv[1]

sys.path.insert(0, "tests/lib")
from vtkvec import point_vectors as read_vtk

def fail(msg):
    print("augsolve_uncertainty: FAILED:", msg)
    sys.exit(1)

steps = [0, 1, 2]
pairs = {"E_inplane": ("Ep", "Em", 0.004), "G_transverse": ("Gp", "Gm", 0.019),
         "iop": ("Ip", "Im", 0.03), "limbal_density": ("Lp", "Lm", 0.004),
         "age_slope": ("Ap", "Am", 0.002)}
for s in steps:
    base = read_vtk(f"{tmp}/base/step-{s:04d}.vtk")
    for q, (p, m, dh) in pairs.items():
        d = base.get("dudp_" + q)
        if d is None:
            fail(f"step {s}: no dudp_{q} field")
        up = read_vtk(f"{tmp}/{p}/step-{s:04d}.vtk")["displacement"]
        um = read_vtk(f"{tmp}/{m}/step-{s:04d}.vtk")["displacement"]
        fd = [[(a - b) / dh for a, b in zip(x, y)] for x, y in zip(up, um)]
        big = max(abs(c) for v in fd for c in v)
        diff = max(abs(a - b) for v, w in zip(d, fd) for a, b in zip(v, w))
        if s == 0:  # the intact eye stays put whatever q: both zero to rounding
            if not (max(abs(c) for v in d for c in v) < 1e-9):
                fail(f"step 0: dudp_{q} is not zero")
            continue
        rel = diff / big if big > 0 else float("nan")
        print(f"augsolve_uncertainty: step {s} dudp_{q}: max |fd| {big:.4g} mm per unit, "
              f"relative difference {rel:.2e}")
        if not (big > 0 and rel <= 1e-4):
            fail(f"step {s}: dudp_{q} and the central difference differ by {rel:.3g} (> 1e-4)")
    # 2. the stream method's derivatives from scratch; the restricted output
    ref = read_vtk(f"{tmp}/refactor/step-{s:04d}.vtk")
    ant = read_vtk(f"{tmp}/anterior/step-{s:04d}.vtk")
    for q in pairs:
        a, b, c = base["dudp_" + q], ref["dudp_" + q], ant["dudp_" + q]
        big = max(abs(x) for v in a for x in v)
        diff = max(abs(x - y) for v, w in zip(a, b) for x, y in zip(v, w))
        if s and not (diff <= 1e-6 * big):
            fail(f"step {s}: dudp_{q}: planned and refactor differ by {diff:.3g} of {big:.3g}")
        on = [not math.isnan(v[0]) for v in ant["displacement"]]
        if not any(on) or all(on):
            fail(f"step {s}: --output anterior has no or every node")
        for k, v in enumerate(c):
            if on[k] != (not math.isnan(v[0])):
                fail(f"step {s}: dudp_{q} is NaN where the displacement is not, or the reverse")
            if on[k] and s and any(abs(x - y) > 1e-6 * big for x, y in zip(v, a[k])):
                fail(f"step {s}: dudp_{q} with --output anterior differs at node {k + 1}")
    # 4. without --uncertainty: the same displacement, no derivative field
    plain = read_vtk(f"{tmp}/plain/step-{s:04d}.vtk")
    if any(k.startswith("dudp_") for k in plain):
        fail(f"step {s}: a dudp field without --uncertainty")
    if plain["displacement"] != base["displacement"]:
        fail(f"step {s}: --uncertainty changed the displacement")

# 3. uncertainty.tsv
rows = [l.rstrip("\n").split("\t") for l in open(f"{tmp}/base/uncertainty.tsv")]
if rows[0] != ["param", "unit", "value", "sd", "method", "source"]:
    fail(f"uncertainty.tsv header {rows[0]}")
got = {r[0]: r for r in rows[1:]}
want = {"E_inplane": "derivative", "G_transverse": "derivative", "iop": "derivative",
        "limbal_density": "derivative", "thickness": "fd", "depth": "fd", "age_slope": "derivative"}
for q, m in want.items():
    if q not in got or got[q][4] != m or len(got[q]) != 6:
        fail(f"uncertainty.tsv: row {q}: {got.get(q)}, expected method {m}")
if float(got["iop"][2]) != 15 or float(got["E_inplane"][2]) != 2:
    fail("uncertainty.tsv: the values of iop and E_inplane are not the scene's")
if "uncertainty: on" not in open(f"{tmp}/base/run.yaml").read():
    fail("run.yaml does not say uncertainty: on")
import os
if os.path.exists(f"{tmp}/plain/uncertainty.tsv") or "\nuncertainty:" in open(f"{tmp}/plain/run.yaml").read():
    fail("a run without --uncertainty has an uncertainty.tsv or says uncertainty in run.yaml")
t = lambda r: [l.split("\t")[:6] for l in open(f"{tmp}/{r}/steps.tsv")]
if t("plain") != t("base"):
    fail("steps.tsv's non-timing columns differ with --uncertainty")
print("augsolve_uncertainty: ok")
PY
# 6. the pipeline with curvature (issue 21): curvature's bands on these derivatives against two
# full runs per quantity. dSIA/dp (curvature's derivatives.tsv, through dudp_<p>) is checked
# against the central difference of curvature.tsv's sia_D (printed to 1e-4 D) over E_inplane
# and iop at +-5%: h so large that the printed rounding (<= 1e-4 D over the difference: 0.43% at
# step 1, 0.12% at step 2 for E_inplane) and the O(h^2) truncation stay under 1% together
# (measured: 0.41% and 0.17% for E_inplane, 0.30% and 0.02% for iop, at steps 1 and 2); 1%.
variant E5p 's/E_inplane: 2.0 MPa/E_inplane: 2.1 MPa/g'
variant E5m 's/E_inplane: 2.0 MPa/E_inplane: 1.9 MPa/g'
variant I5p 's/value: 15 mmHg/value: 15.75 mmHg/'
variant I5m 's/value: 15 mmHg/value: 14.25 mmHg/'
for r in E5p E5m I5p I5m; do
    "$build/curvature" -q --no-png --no-report --no-vtk "$tmp/$r" > /dev/null 2> "$tmp/$r.cerr" ||
        fail "curvature $r: $(cat "$tmp/$r.cerr")"
done
"$build/curvature" -q --no-png --no-vtk "$tmp/base" > "$tmp/base.txt" 2> "$tmp/base.cerr" ||
    fail "curvature on the --uncertainty run: $(cat "$tmp/base.cerr")"
grep -q "^uncertainty, step 2 (first order, [0-9]* independent quantities, 90% = +-1.645 sd): SIA [0-9.]* D (90%: [0-9.]*-[0-9.]*)" \
    "$tmp/base.txt" || fail "the summary has no SIA with its 90% interval: $(grep ^uncertainty "$tmp/base.txt")"
grep -q 'class="band"' "$tmp/base/report.html" && grep -q 'id="tornado"' "$tmp/base/report.html" ||
    fail "report.html has no band or no tornado chart"
python3 - "$tmp" <<'PY' || exit 1
import csv, math, sys
tmp = sys.argv[1]
def table(p):
    with open(p) as f:
        return list(csv.DictReader(f, delimiter="\t"))
def fail(msg):
    print("augsolve_uncertainty: FAILED:", msg)
    sys.exit(1)
cur = {r: {int(x["step"]): x for x in table(f"{tmp}/{r}/curvature.tsv")} for r in ("base", "E5p", "E5m", "I5p", "I5m")}
der = {(int(x["step"]), x["param"]): x for x in table(f"{tmp}/base/derivatives.tsv")}
unc = {x["param"]: x for x in table(f"{tmp}/base/uncertainty.tsv")}
for q, p, m, dh in (("E_inplane", "E5p", "E5m", 0.2), ("iop", "I5p", "I5m", 1.5)):
    for s in (1, 2):
        fd = (float(cur[p][s]["sia_D"]) - float(cur[m][s]["sia_D"])) / dh
        d = float(der[s, q]["sia_D"])
        rel = abs(d - fd) / abs(fd) if fd else float("nan")
        print(f"augsolve_uncertainty: step {s} dSIA/d{q}: curvature {d:.5g} D per unit, two runs "
              f"{fd:.5g}, relative difference {rel:.2e}")
        if not (rel <= 0.01):
            fail(f"step {s}: dSIA/d{q} {d:.5g} against the two runs' {fd:.5g} ({rel:.3g} > 1%)")
# sia_D_sd = sqrt(sum (dSIA/dp sd_p)^2) over the quantities used
for s, row in cur["base"].items():
    want = math.sqrt(sum((float(der[s, q]["sia_D"]) * float(unc[q]["sd"])) ** 2
                         for q in unc if der.get((s, q), {}).get("used") == "1"))
    got = float(row["sia_D_sd"])
    if not (abs(got - want) <= 1e-4 * want + 6e-5):
        fail(f"step {s}: sia_D_sd {got} but sqrt(sum (dSIA/dp sd)^2) = {want:.6g}")
print("augsolve_uncertainty: curvature's bands ok, SIA sd at step 2: %s D" % cur["base"][2]["sia_D_sd"])
PY
# sd 0 removes a quantity: no field, method none
sed -e 's/^uncertainty:$/uncertainty:\n  limbal_density: {sd: 0}\n  iop: {sd: 0, distribution: uniform}/' \
    "$tmp/eye.yaml" > "$tmp/sd0.yaml"
aug sd0 "$tmp/sd0.yaml" --uncertainty --steps 2
awk -F'\t' '$1 == "limbal_density" || $1 == "iop" { n++; if ($5 != "none") bad = 1 }
    END { exit !(n == 2 && !bad) }' "$tmp/sd0/uncertainty.tsv" || fail "sd 0 is not method none"
grep -q "dudp_limbal_density\|dudp_iop" "$tmp/sd0/step-0002.vtk" && fail "sd 0 still writes its field"
grep -q "dudp_E_inplane" "$tmp/sd0/step-0002.vtk" || fail "sd 0 on two quantities removed the others"
# a bad entry: file:line:col, exit 2
printf 'uncertainty:\n  iop: {sd: -1}\n' > "$tmp/bad.yaml"
sed '/^uncertainty:/,$d' "$tmp/eye.yaml" > "$tmp/bad2.yaml"
printf 'uncertainty:\n  iop: {sd: -1}\n' >> "$tmp/bad2.yaml"
"$build/augsolve" -q "$tmp/eye.msh" "$tmp/lri.edits" --scene "$tmp/bad2.yaml" -o "$tmp/bad" --uncertainty 2> "$tmp/bad.err"
rc=$?
[ "$rc" -eq 2 ] && grep -q "bad2.yaml:[0-9]*:[0-9]*: .*uncertainty.iop" "$tmp/bad.err" ||
    fail "a negative sd: exit $rc, $(cat "$tmp/bad.err")"
echo "augsolve_uncertainty: passed"
