#!/usr/bin/env bash
# sia-table.sh BUILD OUT [LRI-PLAN OPTIONS...]: where the arcs sit (docs/physics.md, "Where the
# arcs sit"): the SIA of paired 80 deg arcs at a 9, 10, 10.5 and 11 mm zone (age 60) and of paired
# 60 deg arcs at 45, 60, 75 and 85 y (zone 10.5 mm), each immediate and healed (lri-plan
# --state), on a with-the-rule model eye (K 44.02 / 42.52 D @ 90, white-to-white 11.7 mm; 12 mm
# for the 11 mm zone, which needs zone <= white-to-white - 1 mm; no main incision, so the SIA is
# the arcs' alone). One lri-plan run per row and state (options passed on, e.g. --fast); the SIA
# is the curve point's sia_intact_D at the arc (lri-plan(1), FILES). Writes OUT/sia.tsv:
#   what zone_mm age_y arc_deg immediate_sia_D healed_sia_D healed_over_immediate
# and prints it. Each run is one lri-plan's CPU (--fast about 15-30 s, the default 2-4 min).
set -euo pipefail
[ $# -ge 2 ] || { echo "usage: sia-table.sh BUILD OUT [LRI-PLAN OPTIONS...]" >&2; exit 2; }
B=$(realpath "$1") OUT=$2
shift 2
mkdir -p "$OUT"
OUT=$(realpath "$OUT")
[ -x "$B/lri-plan" ] || { echo "sia-table.sh: $B/lri-plan: not built" >&2; exit 2; }
# patient NAME ZONE AGE ARC WTW: the model eye's patient file
patient() {
    cat > "$OUT/$1.yaml" <<EOF
# $1: a model eye of scripts/sia-table.sh
name: $1
eye: OD
age: $3
cornea:
  keratometry: {k_steep: 44.02 D, k_flat: 42.52 D, steep_axis: 90 deg}
  white_to_white: $5 mm
target: {astigmatism: keratometric, residual: 0.5 D}
constraints: {incisions: paired, max_arc: $4 deg, zone: $2 mm}
EOF
}
# sia NAME STATE ARC: the SIA from the intact eye at ARC on the paired curve
sia() {
    local dir="$OUT/$1-$2"
    [ -f "$dir/plan.json" ] || nice -n 5 "$B/lri-plan" -q --state "$2" "${opts[@]}" "$OUT/$1.yaml" -o "$dir" > "$dir.log" 2>&1 ||
        { tail -n 5 "$dir.log" >&2; echo "sia-table.sh: lri-plan $1 --state $2 failed (log: $dir.log)" >&2; exit 1; }
    /usr/bin/python3 - "$dir/plan.json" "$3" <<'EOF'
import json, sys
plan = json.load(open(sys.argv[1]))
for c in plan["candidates"]:
    if c["incisions"] == "paired":
        for p in c["curve"]:
            if abs(p["arc_deg"] - float(sys.argv[2])) < 1e-6:
                print(f'{p["sia_intact_D"]:.3f}')
                sys.exit(0)
sys.exit(f"{sys.argv[1]}: no paired curve point at {sys.argv[2]} deg")
EOF
}
opts=("$@")
printf 'what\tzone_mm\tage_y\tarc_deg\timmediate_sia_D\thealed_sia_D\thealed_over_immediate\n' > "$OUT/sia.tsv.part"
row() { # what zone age arc wtw
    local name="$1-z$2-a$3"
    patient "$name" "$2" "$3" "$4" "$5"
    local im he
    im=$(sia "$name" immediate "$4") he=$(sia "$name" healed "$4")
    printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$1" "$2" "$3" "$4" "$im" "$he" \
        "$(awk -v a="$im" -v b="$he" 'BEGIN { printf "%.3f", b / a }')" >> "$OUT/sia.tsv.part"
    echo "sia-table.sh: $1 row: zone $2 mm, $3 y, $4 deg: immediate $im D, healed $he D" >&2
}
for z in 9 10 10.5 11; do row zone "$z" 60 80 "$([ "$z" = 11 ] && echo 12 || echo 11.7)"; done
for a in 45 60 75 85; do row age 10.5 "$a" 60 11.7; done
mv -f "$OUT/sia.tsv.part" "$OUT/sia.tsv"
column -t -s $'\t' "$OUT/sia.tsv"
