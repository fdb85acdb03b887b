#!/usr/bin/env bash
# lri-asym.sh [-b BUILD] [-B OTHER_LRI_PLAN] [-s "fast default"] [-F "101 102 103 104"] [-o OUT] [-t]: the unequal pair
# against the equal one on plans/patients/asym-od.yaml, with the meshing noise beside them
# (docs/planner.md). For each setting, lri-plan runs on the nominal mesh and on meshes the
# mesher alone perturbs: --fast with the incision floor refined at 101 ... 104 um instead of
# 100 um (-F: the floors in um; the base's incision_floor, which --fast keeps when above its
# 0.1 mm: --fast sets every other size itself, so scaling the base's sizes does not change its
# mesh, and a floor below 100 um is 100 um); the default
# with every mesh size of plans/eye.yaml times 0.98 and 1.02. -B also runs another lri-plan
# binary (e.g. one built before the measured cornea: the toric mesh) on the same meshes' bases.
# Runs are sequential, under nice -n 5, the step files deleted after each; -t only prints the
# table from OUT's plan.json files. The table: each run's best equal and unequal pair (arcs,
# predicted residual), their difference, the choice, the SIA of each family at the
# same arcs (the equal pair 2 x 50 deg, the unequal pair's longer arc 60 deg); then the noise:
# the mean and spread (largest less smallest) of each figure over one setting's meshes.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=$root/build other= settings="fast default" out=/tmp/kt-lri-asym table_only=0
floors="101 102 103 104"
while getopts "b:B:s:F:o:t" o; do
    case $o in
    b) build=$(cd "$OPTARG" && pwd) ;;
    B) other=$OPTARG ;;
    s) settings=$OPTARG ;;
    F) floors=$OPTARG ;;
    o) out=$OPTARG ;;
    t) table_only=1 ;;
    *) echo "usage: lri-asym.sh [-b BUILD] [-B OTHER_LRI_PLAN] [-s \"fast default\"] [-F \"101 102 103 104\"] [-o OUT] [-t]" >&2; exit 2 ;;
    esac
done
mkdir -p "$out/bases"
base=$root/plans/eye.yaml
for f in $floors; do
    sed "s/^    incision_floor: 42 um/    incision_floor: $f um/" "$base" > "$out/bases/floor$f.yaml"
done
for s in 0.98 1.02; do
    awk -v s="$s" '/^  mesh_size:/ { inb = 1; print; next }
        inb && match($0, /^    (optical_zone|incision|incision_floor|cornea|sclera): [0-9.]+ (mm|um)/) {
            split(substr($0, 1, RLENGTH), a, ": "); split(a[2], v, " ")
            printf "%s: %.6g %s%s\n", a[1], v[1] * s, v[2], substr($0, RLENGTH + 1); next }
        inb && !/^    / && !/^                / { inb = 0 } { print }' "$base" > "$out/bases/scale$s.yaml"
done
run() { # NAME BINARY SETTING BASE
    local name=$1 bin=$2 setting=$3 b=$4 args=()
    [ "$setting" = fast ] && args+=(--fast)
    [ -n "$b" ] && args+=(--base "$b")
    rm -rf "${out:?}/$name"
    echo "lri-asym: $name" >&2
    (cd "$root" && nice -n 5 /usr/bin/time -f '%U %S %M %e' -o "$out/$name.time" "$bin" "${args[@]}" \
        plans/patients/asym-od.yaml -o "$out/$name" > "$out/$name.summary" 2> "$out/$name.err")
    find "$out/$name" -name 'step-*.vtk' -delete
}
if [ $table_only = 0 ]; then
    for setting in $settings; do
        for bin in "$build/lri-plan" $other; do
            tag=$([ "$bin" = "$build/lri-plan" ] && echo measured || echo other)
            if [ "$setting" = fast ]; then
                run "fast-$tag" "$bin" fast ""
                for f in $floors; do run "fast-$tag-f$f" "$bin" fast "$out/bases/floor$f.yaml"; done
            else
                run "default-$tag" "$bin" default ""
                for s in 0.98 1.02; do run "default-$tag-s$s" "$bin" default "$out/bases/scale$s.yaml"; done
            fi
        done
    done
fi
/usr/bin/python3 - "$out" <<'PY'
import glob, json, math, os, statistics, sys
out = sys.argv[1]
runs = {}
for p in sorted(glob.glob(f"{out}/*/plan.json")):
    name = os.path.basename(os.path.dirname(p))
    d = json.load(open(p))
    fam = {c["incisions"]: c for c in d["candidates"]}
    t = open(f"{out}/{name}.time").read().split() if os.path.exists(f"{out}/{name}.time") else ["nan"] * 4
    runs[name] = (d, fam, float(t[0]) + float(t[1]))
def arcs(c):
    return f"2 x {c['best_arc_deg']:g}" if c["incisions"] == "paired" else f"{c['best_arc_deg']:g} + {c['best_arc_opposite_deg']:g}"
def sia_at(c, arc):
    for s in c["curve"]:
        if abs(s["arc_deg"] - arc) < 1e-6: return s["sia_D"]
    return math.nan
print("| run | nodes | equal pair: arcs, residual D | unequal pair: arcs, residual D | unequal - equal D | chosen | "
      "SIA D: 2 x 50 / 60 + ratio x 60 | CPU s |")
print("|---|---:|---|---|---:|---|---|---:|")
groups = {}
for name, (d, fam, cpu) in runs.items():
    group = name.split("-f1")[0].split("-s0")[0].split("-s1")[0]
    groups.setdefault(group, []).append(name)
rows = {}
for group, names in groups.items():
    nominal = runs.get(group)
    for name in sorted(names, key=lambda n: (n != group, n)):
        d, fam, cpu = runs[name]
        p, u = fam.get("paired"), fam.get("unequal")
        if not (p and u): continue
        sp, su = sia_at(p, 50), sia_at(u, 60)
        diff = u["best_residual_D"] - p["best_residual_D"]
        rows[name] = (p["best_residual_D"], u["best_residual_D"], diff, sp, su)
        print(f"| {name} | {d['provenance']['mesh_nodes']:,} | {arcs(p)}, {p['best_residual_D']:.3f} | {arcs(u)}, "
              f"{u['best_residual_D']:.3f} | {diff:+.3f} | {d['plan']['incisions']} | {sp:.3f} / {su:.3f} | {cpu:.1f} |")
print()
print("| meshes | n | equal pair's residual: mean, spread D | unequal's | unequal - equal | SIA 2 x 50 | SIA 60 + ratio x 60 |")
print("|---|---:|---|---|---|---|---|")
for group, names in groups.items():
    v = [rows[n] for n in names if n in rows]
    if len(v) < 2: continue
    cols = []
    for k in range(5):
        x = [r[k] for r in v]
        cols.append(f"{statistics.mean(x):+.3f}, {max(x) - min(x):.3f}")
    print(f"| {group} | {len(v)} | " + " | ".join(cols) + " |")
PY
