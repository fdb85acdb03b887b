#!/usr/bin/env bash
# lriplan.sh: the three-patient benchmark of lri-plan (issue 20; its figures: docs/planner.md): three
# patients of plans/patients (with the rule OD, against the rule OS, oblique OD), each planned
# with --fast and with the default setting. Prints one row per run (wall and CPU seconds, peak
# RSS, mesh nodes, the meshing and solving seconds lri-plan reports, the chosen arcs and the
# predicted residual) and per patient the difference between the settings (arc in deg,
# residual in D), then each family's best arc in both settings, with the machine's load. Not a
# test: it prints figures.
#
#   scripts/bench/lriplan.sh [-b BUILD_DIR] [-o OUT_DIR] [-p "wtr-od atr-os oblique-od"]
#                            [-s "fast default"] [-- lri-plan options...]
#
# Targets (issue 20): default under 120 s per patient, --fast under 20 s with the same arc
# within 5 deg. Wall seconds on a shared machine are ratios only: read them beside the CPU
# seconds and the load average printed with each row.
set -u
HERE=$(cd "$(dirname "$0")/../.." && pwd)
B=$HERE/build
OUT=${TMPDIR:-/tmp}/lriplan-bench
PATIENTS="wtr-od atr-os oblique-od"
SETTINGS="fast default"
while getopts b:o:p:s: opt; do
    case $opt in
    b) B=$OPTARG ;;
    o) OUT=$OPTARG ;;
    p) PATIENTS=$OPTARG ;;
    s) SETTINGS=$OPTARG ;;
    *) echo "usage: $0 [-b BUILD] [-o OUT] [-p PATIENTS] [-s SETTINGS] [-- lri-plan options]" >&2; exit 2 ;;
    esac
done
shift $((OPTIND - 1))
[ -x "$B/lri-plan" ] || { echo "lriplan.sh: $B/lri-plan: not built (bash scripts/build.sh build)" >&2; exit 2; }
mkdir -p "$OUT" || exit 1
PY=/usr/bin/python3
TSV=$OUT/lriplan-bench.tsv
printf 'patient\tsetting\trc\twall_s\tcpu_s\trss_MB\tload1\tprestress_s\tfactor_s\tfallback\tnodes\tmesh_s\tsolve_s\tincisions\tarc_deg\tarc_opp_deg\tresidual_D\n' >"$TSV"
for p in $PATIENTS; do
    for s in $SETTINGS; do
        dir=$OUT/$p-$s
        rm -rf "$dir"
        opt=()
        [ "$s" = fast ] && opt=(--fast)
        echo "lriplan.sh: $p $s ($(uptime | sed 's/.*load average: //'))" >&2
        load=$(cut -d' ' -f1 /proc/loadavg)
        t0=$(date +%s.%N)
        /usr/bin/time -f '%U %S %M' -o "$OUT/$p-$s.time" "$B/lri-plan" "$HERE/plans/patients/$p.yaml" \
            -o "$dir" "${opt[@]}" "$@" >"$OUT/$p-$s.out" 2>"$OUT/$p-$s.err"
        rc=$?
        wall=$(awk -v a="$t0" -v b="$(date +%s.%N)" 'BEGIN { printf "%.1f", b - a }')
        read -r us ss rss <"$OUT/$p-$s.time" 2>/dev/null || us=NaN ss=0 rss=0
        cpu=$(awk -v u="$us" -v s="$ss" 'BEGIN { printf "%.1f", u + s }')
        fields=$("$PY" - "$dir/plan.json" <<'PYEOF'
import json, sys
try:
    j = json.load(open(sys.argv[1]))
except Exception:
    print("NaN\tNaN\tNaN\t-\tNaN\tNaN\tNaN"); sys.exit(0)
pl, pr = j["plan"], j.get("provenance", j)
def g(d, k):
    for v in (d, j):
        if k in v: return v[k]
    for v in j.values():
        if isinstance(v, dict) and k in v: return v[k]
    return float("nan")
print("%s\t%s\t%s\t%s\t%s\t%s\t%s" % (g(j, "mesh_nodes"), g(j, "mesh_seconds"), g(j, "solve_seconds"),
      pl["incisions"], pl["arc_deg"], pl["arc_opposite_deg"], pl["predicted_residual_D"]))
PYEOF
)
        # where the solving goes (augsolve's progress lines, summed over the families): the
        # prestress of the measured geometry and the planned factorization, wall seconds
        pre=$(sed -n 's/.*prestress of the measured geometry under its loads (\([0-9.]*\) s).*/\1/p' "$OUT/$p-$s.err" |
            awk '{ t += $1 } END { printf "%.1f", t }')
        fac=$(sed -n 's/.*augsolve: planned: .* in \([0-9.]*\) s (assembly.*/\1/p' "$OUT/$p-$s.err" |
            awk '{ t += $1 } END { printf "%.1f", t }')
        fb=$(grep -c "falls back\|fallback\|refactor" "$OUT/$p-$s.err")
        printf '%s\t%s\t%d\t%s\t%s\t%d\t%s\t%s\t%s\t%s\t%s\n' "$p" "$s" "$rc" "$wall" "$cpu" $((rss / 1024)) "$load" \
            "$pre" "$fac" "$fb" "$fields" >>"$TSV"
        [ $rc -ne 0 ] && echo "lriplan.sh: $p $s: exit $rc: $(tail -n 1 "$OUT/$p-$s.err")" >&2
    done
done
column -t -s$'\t' "$TSV"
# The speed-accuracy trade: --fast against the default, per patient.
awk -F'\t' 'NR > 1 { k = $1; if ($2 == "fast") { fa[k] = $15; fr[k] = $17; fw[k] = $4 } else if ($2 == "default") { da[k] = $15; dr[k] = $17; dw[k] = $4 } }
    END { print "\npatient\tarc_fast-default_deg\tresidual_fast-default_D\twall_default/fast";
          for (k in da) if (k in fa) printf "%s\t%+.1f\t%+.3f\t%.1f\n", k, fa[k] - da[k], fr[k] - dr[k], fw[k] > 0 ? dw[k] / fw[k] : 0 }' "$TSV" |
    column -t -s$'\t'
# Per family (the settings may choose different families when their residuals are close):
# each family's best arc and residual in both settings.
"$PY" - "$OUT" $PATIENTS <<'PYEOF'
import json, sys
out, pats = sys.argv[1], sys.argv[2:]
print("\npatient     family   fast                 default              arc fast-default")
for p in pats:
    best = {}
    for s in ("fast", "default"):
        try:
            j = json.load(open("%s/%s-%s/plan.json" % (out, p, s)))
        except Exception:
            continue
        for c in j["candidates"]:
            best.setdefault(c["incisions"], {})[s] = (c["best_arc_deg"], c["best_arc_opposite_deg"], c["best_residual_D"])
    for fam, v in best.items():
        cell = lambda s: "%g/%g (%.2f D)" % v[s] if s in v else "-"
        d = "%+g deg" % (v["fast"][0] - v["default"][0]) if len(v) == 2 else "-"
        print("%-11s %-8s %-20s %-20s %s" % (p, fam, cell("fast"), cell("default"), d))
PYEOF
# Where each family's time goes (lri-plan's progress lines; the planner solves in memory,
# lib/planner): wall seconds of the derivative quantities' matrices, the planned factorization
# (its assembly and ordering included) and the steps' derivatives (the solver's lines), then
# the CPU seconds of the family's cut, solve, readings and step files, of the shared prestress
# (solved once, before the first family) and of the mesh.
"$PY" - "$OUT" $PATIENTS -- $SETTINGS <<'PYEOF'
import re, sys
out = sys.argv[1]
i = sys.argv.index("--")
pats, sets = sys.argv[2:i], sys.argv[i + 1:]
num = r"([0-9.]+)"
print("\npatient     setting  family    dmat_s  factor_s  dsteps_s  | CPU: cut  solve  read  files  prestress  mesh")
for p in pats:
    for s in sets:
        try:
            lines = open("%s/%s-%s.err" % (out, p, s)).read().splitlines()
        except OSError:
            continue
        cmesh = cpre = float("nan")
        f = None
        for l in lines:
            m = re.search(r"lri-plan: meshed in %s s \(CPU %s s\)" % (num, num), l)
            if m: cmesh = float(m.group(2))
            m = re.search(r"lri-plan: the families' shared prestress \(CPU %s s\)" % num, l)
            if m: cpre = float(m.group(1))
            m = re.match(r"lri-plan: (\w+) arcs.*: cut, solve, read", l)
            if m: f = {"name": m.group(1), "dmat": float("nan"), "fac": float("nan"), "dst": float("nan")}
            if f is None: continue
            m = re.search(r"derivative quantities, their matrices in %s s" % num, l)
            if m: f["dmat"] = float(m.group(1))
            m = re.search(r"augsolve: planned: .* in %s s \(assembly" % num, l)
            if m: f["fac"] = float(m.group(1))
            m = re.search(r"%s s in the steps' derivatives" % num, l)
            if m: f["dst"] = float(m.group(1))
            m = re.search(r"lri-plan: \w+ arcs: CPU %s s cut, %s s solve, %s s read, %s s out" % ((num,) * 4), l)
            if m:
                g = [float(x) for x in m.groups()]
                print("%-11s %-8s %-8s %7.1f %9.1f %9.1f  |  %8.1f %6.1f %5.1f %6.1f %10.1f %5.1f" % (
                    p, s, f["name"], f["dmat"], f["fac"], f["dst"], g[0], g[1], g[2], g[3], cpre, cmesh))
                cmesh = cpre = float("nan")
                f = None
PYEOF
echo "table: $TSV; load now: $(uptime | sed 's/.*load average: //')"
