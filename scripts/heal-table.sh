#!/usr/bin/env bash
# heal-table.sh BUILD OUT [K...]: the healed wound's table (docs/physics.md, "Healing"): the
# default eye (plans/eye.yaml) meshed once, then the paired and single 60-degree arcs
# (plans/lri-{paired,single}-60.yaml, one step each, scripts/lri-table.sh) solved with the wound
# immediate and healed at each bridge stiffness K (MPa/mm; default 0.026 0.05 0.15 0.26 0.5 1.5
# 2.6 5: the scene default 0.26 and a decade either side). Prints and writes OUT/heal.tsv:
#   state k_MPa_per_mm paired_sia_D single_sia_D paired_coupling single_coupling paired_over_single
# heal-table.sh BUILD OUT --age AGE... [--k K]: the age rule of both the moduli and the bridge:
# for each AGE the eye scene of lri-plan's patient rule (the cornea's moduli times
# 1 + 0.075 (AGE - 60) / 10, lib/model/patient_scene.c; uncertainty.age_slope.age AGE, which the
# wound's k follows: exp(-age_rate (AGE - 60))), paired 60 immediate and healed (K, default the
# scene default), into OUT/age.tsv:
#   age immediate_sia_D healed_sia_D k_MPa_per_mm
set -euo pipefail
B=$(realpath "$1") OUT=$2
shift 2
mkdir -p "$OUT"
OUT=$(realpath "$OUT")
here=$(cd "$(dirname "$0")/.." && pwd)
[ -f "$OUT/eye.msh" ] || "$B/mesh-prep" "$here/plans/eye.yaml" -o "$OUT/eye.msh" -q > "$OUT/mesh-prep.txt"
# scene NAME [WOUND_LINES...]: plans/eye.yaml with a wound: section (none: immediate)
scene() {
    local name=$1
    shift
    cp "$here/plans/eye.yaml" "$OUT/$name.yaml"
    if [ $# -gt 0 ]; then printf 'wound:\n' >> "$OUT/$name.yaml"; printf '  %s\n' "$@" >> "$OUT/$name.yaml"; fi
}
# row NAME PLAN...: lri-table.sh of the scene NAME into OUT/NAME/table.tsv (the mesh shared)
row() {
    local name=$1
    shift
    mkdir -p "$OUT/$name"
    ln -sf "$OUT/eye.msh" "$OUT/$name/eye.msh"
    # a variant already solved with this very scene is kept (rerun the table to add ks)
    if [ -f "$OUT/$name/table.tsv" ] && [ "$(wc -l < "$OUT/$name/table.tsv")" -eq $(($# + 1)) ] &&
        cmp -s "$OUT/$name.yaml" "$OUT/$name/scene.used"; then return; fi
    bash "$here/scripts/lri-table.sh" "$B" "$OUT/$name.yaml" "$OUT/$name" "$@" > /dev/null
    cp "$OUT/$name.yaml" "$OUT/$name/scene.used"
}
col() { awk -F'\t' -v p="$2" -v c="$3" 'NR == 1 { for (i = 1; i <= NF; i++) h[$i] = i; next } $1 == p { print $h[c] }' "$OUT/$1/table.tsv"; }
if [ "${1:-}" = --age ]; then
    shift
    ages=() k=
    while [ $# -gt 0 ]; do
        if [ "$1" = --k ]; then k=$2; shift 2; else ages+=("$1"); shift; fi
    done
    printf 'age\timmediate_sia_D\thealed_sia_D\tk_MPa_per_mm\n' | tee "$OUT/age.tsv"
    for a in "${ages[@]}"; do
        f=$(echo "1 + 0.075 * ($a - 60) / 10" | bc -l)
        for st in immediate healed; do
            lines=()
            [ $st = healed ] && lines=("state: healed") && [ -n "$k" ] && lines+=("bridge_stiffness: $k MPa/mm")
            scene "age$a-$st" "${lines[@]}"
            # the cornea's moduli times f (its E_inplane and G_transverse lines), the age for the rule
            awk -v f="$f" '
                /^  cornea:/ { c = 1 } /^  limbus:/ { c = 0 }
                c && /^    E_inplane: [0-9.]+ MPa/ { sub(/[0-9.]+ MPa/, sprintf("%.10g MPa", $2 * f)) }
                c && /^    G_transverse: [0-9.]+ kPa/ { sub(/[0-9.]+ kPa/, sprintf("%.10g kPa", $2 * f)) }
                { print }' "$OUT/age$a-$st.yaml" > "$OUT/age$a-$st.tmp"
            printf 'uncertainty:\n  age_slope: {sd: 0.05, age: %s}\n' "$a" >> "$OUT/age$a-$st.tmp"
            mv "$OUT/age$a-$st.tmp" "$OUT/age$a-$st.yaml"
            row "age$a-$st" "$here/plans/lri-paired-60.yaml"
        done
        kk=$(awk '/^  wound:/ { sub(/.*k_MPa_per_mm: /, ""); sub(/,.*/, ""); print; exit }' "$OUT/age$a-healed/lri-paired-60/run.yaml")
        printf '%s\t%s\t%s\t%s\n' "$a" "$(col "age$a-immediate" lri-paired-60 sia_D)" \
            "$(col "age$a-healed" lri-paired-60 sia_D)" "$kk" | tee -a "$OUT/age.tsv"
    done
    exit 0
fi
ks=("$@")
[ ${#ks[@]} -gt 0 ] || ks=(0.026 0.05 0.15 0.26 0.5 1.5 2.6 5)
printf 'state\tk_MPa_per_mm\tpaired_sia_D\tsingle_sia_D\tpaired_coupling\tsingle_coupling\tpaired_over_single\n' | tee "$OUT/heal.tsv"
for k in immediate "${ks[@]}"; do
    if [ "$k" = immediate ]; then scene imm; name=imm; st=immediate; kv=0
    else name="k$k"; scene "$name" "state: healed" "bridge_stiffness: $k MPa/mm"; st=healed; kv=$k; fi
    row "$name" "$here/plans/lri-paired-60.yaml" "$here/plans/lri-single-60.yaml"
    p=$(col "$name" lri-paired-60 sia_D) s=$(col "$name" lri-single-60 sia_D)
    printf '%s\t%s\t%s\t%s\t%s\t%s\t%.3f\n' "$st" "$kv" "$p" "$s" "$(col "$name" lri-paired-60 coupling_ratio)" \
        "$(col "$name" lri-single-60 coupling_ratio)" "$(echo "$p / $s" | bc -l)" | tee -a "$OUT/heal.tsv"
done
