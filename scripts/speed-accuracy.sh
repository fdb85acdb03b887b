#!/usr/bin/env bash
# speed-accuracy.sh BUILD OUT [PATIENT]: lri-plan's speed-accuracy trade on one patient (default
# plans/patients/wtr-od.yaml; docs/planner.md): `--fast`, the default and a converged reference
# (the default with the wound refined further: eye.mesh_size.incision 0.14 mm and incision_floor
# 29 um, 0.7x the default's 0.2 mm and 42 um, through --base). Each setting runs once into
# OUT/<setting> under /usr/bin/time (OUT/<setting>.time: user, system s, peak KB, wall s); a
# setting whose plan.json and .time are there is not run again. Writes OUT/speed-accuracy.tsv
#   setting nodes cpu_s peak_mib chosen residual_D sia_D sia_2x55_D sia_2x60_D sia_2x65_D
# (the SIA, keratometric from arc 0, of the chosen arcs and of the paired family at 55, 60 and
# 65 deg: plan.json's curve) and OUT/speed-accuracy.svg (the SIA of the paired family against
# the arc, one line per setting, CPU seconds in the legend), and prints the table. About 8 CPU
# minutes in all on the 2-core machine; one run at a time (OPENBLAS_NUM_THREADS=1).
set -euo pipefail
[ $# -ge 2 ] || { echo "usage: speed-accuracy.sh BUILD OUT [PATIENT]" >&2; exit 2; }
B=$(realpath "$1")
mkdir -p "$2"
OUT=$(realpath "$2")
P=${3:-plans/patients/wtr-od.yaml}
cd "$(dirname "$0")/.."
[ -x "$B/lri-plan" ] || { echo "speed-accuracy.sh: $B/lri-plan: not built" >&2; exit 2; }
[ -f "$P" ] || { echo "speed-accuracy.sh: $P: no such patient file" >&2; exit 2; }
sed -e 's/^    incision: 0.2 mm /    incision: 0.14 mm /' -e 's/^    incision_floor: 42 um /    incision_floor: 29 um /' \
    plans/eye.yaml > "$OUT/reference-base.yaml"
grep -q '^    incision: 0.14 mm ' "$OUT/reference-base.yaml" && grep -q '^    incision_floor: 29 um ' "$OUT/reference-base.yaml" ||
    { echo "speed-accuracy.sh: plans/eye.yaml's mesh_size.incision or incision_floor line changed" >&2; exit 1; }
export OPENBLAS_NUM_THREADS=1
run() { # SETTING LRI-PLAN-OPTIONS...
    local s=$1
    shift
    [ -f "$OUT/$s/plan.json" ] && [ -f "$OUT/$s.time" ] && return 0
    echo "speed-accuracy.sh: lri-plan $* ($s)" >&2
    /usr/bin/time -f '%U %S %M %e' -o "$OUT/$s.time.part" "$B/lri-plan" -q "$@" "$P" -o "$OUT/$s" > "$OUT/$s.log" 2>&1 ||
        { tail -n 5 "$OUT/$s.log" >&2; echo "speed-accuracy.sh: lri-plan ($s) failed (log: $OUT/$s.log)" >&2; exit 1; }
    mv "$OUT/$s.time.part" "$OUT/$s.time"
}
run fast --fast
run default
run reference --base "$OUT/reference-base.yaml"
/usr/bin/python3 - "$OUT" <<'EOF'
import json, math, sys
out = sys.argv[1]
rows, curves = [], {}
for s in ("fast", "default", "reference"):
    d = json.load(open(f"{out}/{s}/plan.json"))
    u, sy, kb, wall = (float(x) for x in open(f"{out}/{s}.time").read().split())
    pl = d["plan"]
    pair = next(c for c in d["candidates"] if c["incisions"] == "paired")
    at = {round(p["arc_deg"]): p["sia_D"] for p in pair["curve"]}
    chosen = next(c for c in d["candidates"] if c["incisions"] == pl["incisions"])
    sia = next(p["sia_D"] for p in chosen["curve"] if abs(p["arc_deg"] - pl["arc_deg"]) < 1e-6)
    name = f'2 x {pl["arc_deg"]:.0f}' if pl["incisions"] == "paired" else f'{pl["arc_deg"]:.0f}'
    rows.append((s, d["provenance"]["mesh_nodes"], u + sy, kb / 1024, name, pl["predicted_residual_D"], sia,
                 at.get(55, math.nan), at.get(60, math.nan), at.get(65, math.nan)))
    curves[s] = sorted((p["arc_deg"], p["sia_D"]) for p in pair["curve"])
head = "setting nodes cpu_s peak_mib chosen residual_D sia_D sia_2x55_D sia_2x60_D sia_2x65_D".split()
with open(f"{out}/speed-accuracy.tsv", "w") as f:
    f.write("\t".join(head) + "\n")
    for r in rows:
        f.write("\t".join([r[0], str(r[1]), f"{r[2]:.1f}", f"{r[3]:.0f}", r[4]] + [f"{x:.4f}" for x in r[5:]]) + "\n")
print(open(f"{out}/speed-accuracy.tsv").read(), end="")
# The figure: the paired family's SIA against the arc, one polyline per setting.
W, H, L, R, T, B = 640, 400, 70, 20, 30, 50
xs = [a for c in curves.values() for a, _ in c]
ys = [v for c in curves.values() for _, v in c]
x0, x1, y0, y1 = min(xs), max(xs), 0.0, math.ceil(max(ys) * 2) / 2
X = lambda a: L + (a - x0) / (x1 - x0) * (W - L - R)
Y = lambda v: H - B - (v - y0) / (y1 - y0) * (H - T - B)
col = {"fast": "#d95f02", "default": "#1b9e77", "reference": "#333333"}
o = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{W}" height="{H}" viewBox="0 0 {W} {H}" font-family="sans-serif" font-size="12">',
     f'<rect width="{W}" height="{H}" fill="white"/>',
     f'<line x1="{L}" y1="{H-B}" x2="{W-R}" y2="{H-B}" stroke="black"/><line x1="{L}" y1="{T}" x2="{L}" y2="{H-B}" stroke="black"/>']
a = x0
while a <= x1 + 1e-9:
    o.append(f'<line x1="{X(a):.1f}" y1="{H-B}" x2="{X(a):.1f}" y2="{H-B+5}" stroke="black"/>'
             f'<text x="{X(a):.1f}" y="{H-B+18}" text-anchor="middle">{a:.0f}</text>')
    a += 15
v = y0
while v <= y1 + 1e-9:
    o.append(f'<line x1="{L-5}" y1="{Y(v):.1f}" x2="{W-R}" y2="{Y(v):.1f}" stroke="#ddd"/>'
             f'<text x="{L-8}" y="{Y(v)+4:.1f}" text-anchor="end">{v:.1f}</text>')
    v += 0.5
o.append(f'<text x="{(L+W-R)/2}" y="{H-12}" text-anchor="middle">each arc of the pair, deg</text>')
o.append(f'<text x="16" y="{(T+H-B)/2}" text-anchor="middle" transform="rotate(-90 16 {(T+H-B)/2})">SIA of the pair, D (keratometric)</text>')
for i, r in enumerate(rows):
    s = r[0]
    pts = " ".join(f"{X(a):.1f},{Y(v):.1f}" for a, v in curves[s])
    o.append(f'<polyline points="{pts}" fill="none" stroke="{col[s]}" stroke-width="2"/>')
    o.append(f'<text x="{L+12}" y="{T+16*i+4}" fill="{col[s]}">{s}: {r[1]:,} nodes, {r[2]:.0f} CPU s; chooses {r[4]}, residual {r[5]:.3f} D</text>')
o.append("</svg>\n")
open(f"{out}/speed-accuracy.svg", "w").write("\n".join(o))
EOF
