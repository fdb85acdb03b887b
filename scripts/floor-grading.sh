#!/usr/bin/env bash
# floor-grading.sh [--fast] BUILD OUT [PATIENT] [GRADING...]: how lri-plan's answer and its cost
# move with eye.mesh_size.floor_grading, the slope at which the element size grows away from an
# incision's floor (keratome-scene(5); default patient plans/patients/wtr-od.yaml, gradings
# 0.35 0.5 0.75 1; docs/planner.md, "Fewer increments"). Each grading runs once, the default
# setting (--fast: lri-plan --fast, which keeps the base's grading) with the base scene
# plans/eye.yaml given that grading (--base), into OUT/g<grading> under /usr/bin/time
# (OUT/g<grading>.time: user, system s, peak KB, wall s; the log with augsolve's factor lines
# in OUT/g<grading>.log); a grading whose plan.json and .time are there is not run again.
# Writes OUT/floor-grading.tsv
#   grading nodes increments_single increments_paired factor_s_paired cpu_s peak_mib chosen
#   residual_D sia_2x55_D sia_2x60_D sia_2x65_D sia_single_60_D
# and prints it. About 2-4 CPU minutes a grading on the 2-core machine, one at a time
# (OPENBLAS_NUM_THREADS=1, --jobs 1: the CPU figures are comparable).
set -euo pipefail
FAST=()
[ "${1:-}" = --fast ] && FAST=(--fast) && shift
[ $# -ge 2 ] || { echo "usage: floor-grading.sh [--fast] BUILD OUT [PATIENT] [GRADING...]" >&2; exit 2; }
B=$(realpath "$1")
mkdir -p "$2"
OUT=$(realpath "$2")
P=${3:-plans/patients/wtr-od.yaml}
shift $(($# >= 3 ? 3 : 2))
G=("$@")
[ ${#G[@]} -gt 0 ] || G=(0.35 0.5 0.75 1)
cd "$(dirname "$0")/.."
[ -x "$B/lri-plan" ] || { echo "floor-grading.sh: $B/lri-plan: not built" >&2; exit 2; }
[ -f "$P" ] || { echo "floor-grading.sh: $P: no such patient file" >&2; exit 2; }
grep -q '^    floor_grading: ' plans/eye.yaml ||
    { echo "floor-grading.sh: plans/eye.yaml has no mesh_size.floor_grading line" >&2; exit 1; }
export OPENBLAS_NUM_THREADS=1
for g in "${G[@]}"; do
    s=g$g
    [ -f "$OUT/$s/plan.json" ] && [ -f "$OUT/$s.time" ] && continue
    sed -e "s/^    floor_grading: [0-9.]*/    floor_grading: $g/" plans/eye.yaml > "$OUT/$s.yaml"
    echo "floor-grading.sh: lri-plan with floor_grading $g" >&2
    /usr/bin/time -f '%U %S %M %e' -o "$OUT/$s.time.part" "$B/lri-plan" ${FAST[@]+"${FAST[@]}"} --jobs 1 --base "$OUT/$s.yaml" "$P" -o "$OUT/$s" \
        > "$OUT/$s.log" 2>&1 || { tail -n 5 "$OUT/$s.log" >&2; echo "floor-grading.sh: lri-plan ($s) failed (log: $OUT/$s.log)" >&2; exit 1; }
    mv "$OUT/$s.time.part" "$OUT/$s.time"
done
/usr/bin/python3 - "$OUT" "${G[@]}" <<'EOF'
import json, math, re, sys
out, grads = sys.argv[1], sys.argv[2:]
head = ("grading nodes increments_single increments_paired factor_s_paired cpu_s peak_mib chosen residual_D "
        "sia_2x55_D sia_2x60_D sia_2x65_D sia_single_60_D").split()
rows = []
for g in grads:
    s = f"g{g}"
    d = json.load(open(f"{out}/{s}/plan.json"))
    u, sy, kb, wall = (float(x) for x in open(f"{out}/{s}.time").read().split())
    # augsolve's factor line of each family, in family order (single, paired)
    fac = re.findall(r"free DOFs \+ (\d+) increments, factor \d+ nonzeros .*? in ([0-9.]+) s", open(f"{out}/{s}.log").read())
    if len(fac) != 2:
        sys.exit(f"floor-grading.sh: {out}/{s}.log: expected two factor lines, found {len(fac)}")
    pl = d["plan"]
    fam = {c["incisions"]: {round(p["arc_deg"]): p["sia_D"] for p in c["curve"]} for c in d["candidates"]}
    name = f'2 x {pl["arc_deg"]:.0f}' if pl["incisions"] == "paired" else f'{pl["arc_deg"]:.0f}'
    pair, single = fam.get("paired", {}), fam.get("single", {})
    rows.append([g, str(d["provenance"]["mesh_nodes"]), fac[0][0], fac[1][0], fac[1][1], f"{u + sy:.1f}", f"{kb / 1024:.0f}",
                 name, f'{pl["predicted_residual_D"]:.4f}'] +
                [f"{x:.4f}" for x in (pair.get(55, math.nan), pair.get(60, math.nan), pair.get(65, math.nan), single.get(60, math.nan))])
with open(f"{out}/floor-grading.tsv", "w") as f:
    f.write("\t".join(head) + "\n")
    for r in rows:
        f.write("\t".join(r) + "\n")
print(open(f"{out}/floor-grading.tsv").read(), end="")
EOF
