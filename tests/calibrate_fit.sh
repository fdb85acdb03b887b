#!/usr/bin/env bash
# calibrate_fit.sh: the calibration study's fit and report (plans/studies/calibrate/fit.py,
# report.py) on a synthetic training set whose answer is known. Each model eye's SIA is
# A exp(-0.5 ln k) (a bridge that closes the wound as k grows), the runs table gives it and its
# derivative at the study's grid, and each arm's measured mean is that curve at
# ln k(age) = theta0 - theta1 (age - 60) / 10 with theta = (ln 0.2, 0.3), exactly (100 eyes, sd
# 5% of the mean: 0.5% on the log mean). Both studies span two ages, so each alone identifies
# both parameters. Checks:
#   1. the fit finds theta (to 2e-3 and 5e-3: the cubic Hermite between grid points a factor 3
#      apart) with tau = 0, under a weak prior on the age fall (0.06 +- 1 per decade; with the
#      study's 0.06 +- 0.06, a truth 4 prior sds away, the marginal likelihood rightly prefers a
#      tau that lets the prior win: not a test of the fit);
#   2. leaving either study out, the other predicts its arms within 1%, and every band covers;
#   3. a mixed-orientation arm is the mean of its WTR and ATR eyes;
#   4. the non-tissue cv is the spread rows' pooled cv less the tissue cv (0.1), in quadrature;
#   5. report.py writes validation.md and .svg, with the identified k60 and the with-the-rule and
#      against-the-rule arms' left-out ratios read from the table.
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
tmp=$(mktemp -d /tmp/kt-calfit.XXXXXX)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "calibrate_fit: FAILED: $*"; exit 1; }
PY=/usr/bin/python3

"$PY" - "$tmp" <<'EOF'
import math, sys
tmp = sys.argv[1]
t0, t1 = math.log(0.2), 0.3
grid = [0.005, 0.015, 0.05, 0.15, 0.45, 1.35]
# study, arm, age, orientation, amplitude(s) A (WTR, ATR)
arms = [("Study A", "WTR paired 60", 50, "WTR", (1.0,)),
        ("Study A", "ATR paired 60", 70, "ATR", (1.6,)),
        ("Study B", "WTR single 60", 60, "WTR", (0.5,)),
        ("Study B", "paired 80 mixed", 80, "mixed", (1.2, 2.0))]
head = ("role\tstudy\tarm\teyes\tage_mean_y\tage_sd_y\torientation\tincisions\tarc_deg\tzone_mm\tdepth\t"
        "main_incision\tmeasure\ttime_months\tmean_D\tsd_D\tderived\tsource\n")
with open(f"{tmp}/outcomes.tsv", "w") as f, open(f"{tmp}/runs.tsv", "w") as g:
    f.write(head)
    g.write("arm\tsub\tage_y\tlog_k\tpred_D\tdpred_dlogk_D\ttissue_sd_D\n")
    for study, arm, age, orient, amps in arms:
        lk = t0 - t1 * (age - 60) / 10
        m = sum(a * math.exp(-0.5 * lk) for a in amps) / len(amps)
        f.write(f"train\t{study}\t{arm}\t100\t{age}\t5\t{orient}\tpaired\t60\t10.5\t90 %\tnone\tSIA\t4\t"
                f"{m!r}\t{0.05 * m!r}\tsynthetic\tsynthetic\n")
        subs = ["WTR", "ATR"] if orient == "mixed" else [orient]
        for s, a in zip(subs, amps):
            for k in grid:
                p = a * math.exp(-0.5 * math.log(k))
                g.write(f"{study} | {arm}\t{s}\t{age}\t{math.log(k)!r}\t{p!r}\t{-0.5 * p!r}\t{0.1 * p!r}\n")
    # spread rows: cvs 0.3 and 0.4, pooled sqrt((0.09 + 0.16) / 2)
    f.write("spread\tSpread C\tWTR\t20\t\t\tWTR\tnomogram\t\t\t\t\tSIA\t6\t1.0\t0.3\t\tsynthetic\n")
    f.write("spread\tSpread C\tATR\t20\t\t\tATR\tnomogram\t\t\t\t\tSIA\t6\t1.0\t0.4\t\tsynthetic\n")
EOF

mkdir -p "$tmp/fit" "$tmp/docs"
if ! "$PY" "$here/plans/studies/calibrate/fit.py" "$tmp/outcomes.tsv" "$tmp/runs.tsv" "-1.347 2.0 0.06 1.0" \
        "$tmp/fit" 2> "$tmp/fit.log"; then
    cat "$tmp/fit.log"; fail "fit.py failed"
fi

"$PY" - "$tmp" <<'EOF' || fail "the fit's answer (above)"
import csv, math, sys
tmp = sys.argv[1]
rd = lambda p: list(csv.DictReader(open(p), delimiter="\t"))
ident = {r["quantity"]: r for r in rd(f"{tmp}/fit/identified.tsv")}
bad = []
def check(ok, what):
    if not ok: bad.append(what)
t0, t1 = math.log(0.2), 0.3
lk, fall, tau = (float(ident[q]["mean"]) for q in ("log_k60", "age_fall", "tau"))
check(abs(lk - t0) < 2e-3, f"log_k60 {lk} against {t0}")
check(abs(fall - t1) < 5e-3, f"age_fall {fall} against {t1} (the prior's 0.06 must not hold it)")
check(tau == 0, f"tau {tau} against 0 (exact data)")
cvnt = float(ident["cv_nontissue"]["mean"])
want = math.sqrt((0.09 + 0.16) / 2 - 0.01)
check(abs(cvnt - want) < 2e-3, f"non-tissue cv {cvnt} against {want}")
for a in rd(f"{tmp}/fit/arms.tsv"):
    m, fit, loso = float(a["measured_D"]), float(a["fit_D"]), float(a["loso_D"])
    check(abs(fit / m - 1) < 2e-3, f"{a['arm']}: fitted {fit} against measured {m}")
    check(abs(loso / m - 1) < 1e-2, f"{a['arm']}: left out {loso} against measured {m}")
    check(a["loso_covers"] == "1" and a["loso_eye_covers"] == "1", f"{a['arm']}: a band misses")
    check(float(a["loso_lo90_D"]) < loso < float(a["loso_hi90_D"]), f"{a['arm']}: the band is not about the prediction")
for q in bad: print("  " + q)
sys.exit(1 if bad else 0)
EOF

if ! "$PY" "$here/plans/studies/calibrate/report.py" "$tmp/outcomes.tsv" "$tmp" "$tmp/docs" "0.005 1.35" \
        "-1.347 2.0 0.06 1.0" "" 2> "$tmp/report.log"; then
    cat "$tmp/report.log"; fail "report.py failed"
fi
v=$tmp/docs/validation.md
[ -s "$tmp/docs/validation.svg" ] || fail "no validation.svg"
grep -E -q '^\| k60 \| 0\.(1999|2|2001) \|' "$v" || fail "validation.md: k60 is not 0.2 MPa/mm: $(grep '| k60' "$v")"
grep -q "lri-plan options \`(default mesh)\`" "$v" || fail "validation.md: the mesh is not named"
grep -q "with-the-rule arms are predicted at 1.00-1.00 of the measured" "$v" \
    || fail "validation.md: the with-the-rule ratios: $(grep -A1 'with-the-rule arms' "$v")"
grep -q "against-the-rule arms at 1.00-1.00" "$v" || fail "validation.md: the against-the-rule ratios"
[ "$(grep -c '^| Study [AB] |' "$v")" = 4 ] || fail "validation.md: not one row per training arm"
echo "calibrate_fit: ok (fit, leave-one-study-out, report)"
