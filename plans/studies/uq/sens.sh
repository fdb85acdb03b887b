#!/usr/bin/env bash
# sens.sh OUT NAME...: the geometry target's finite differences -> OUT/sens/FAMILY.tsv for every
# family of OUT/study.mk, curvature's --sens file for that family's run (curvature(1),
# UNCERTAINTY), then OUT/sens/done (make's target). NAME are the runs P_plus / P_minus of gen.sh: the
# nominal eye with quantity P moved by +H and -H (study.spec's H, in P's unit), each meshed and
# cut on its own. For every step and every reading with a band:
#   dR/dP = (R(P + H) - R(P - H)) / (2 H)
# (an axis's difference taken on its 180-degree circle; sia_x_D / sia_y_D, the SIA's double-angle
# components, from sia_D and sia_axis_deg). A reading that is NaN in either run (the coupling
# ratio at step 0) gets no row. Columns: param reading dR_dp step. Written whole, then renamed.
set -euo pipefail
out=$1; shift
read -r -a families < <(sed -n 's/^FAMILIES := //p' "$out/study.mk")
mkdir -p "$out/sens"
rm -f "$out/sens/done"
for fam in "${families[@]}"; do
tmp=$out/sens/.$fam.tsv.$$
trap 'rm -f "$tmp"' EXIT
printf 'param\treading\tdR_dp\tstep\n' > "$tmp"
for name in "$@"; do
    case $name in *_plus) p=${name%_plus} ;; *) continue ;; esac
    h=$(awk -F'\t' -v p="$p" '$1 == p { print $4 }' "$out/params.tsv")
    [ -n "$h" ] && [ "$h" != - ] || { echo "sens.sh: $out/params.tsv: no step H for $p" >&2; exit 2; }
    awk -F'\t' -v OFS='\t' -v P="$p" -v H="$h" '
    function val(row, k,   a) {
        if (k == "sia_x_D") return row["sia_D"] * cos(2 * row["sia_axis_deg"] * atan2(0, -1) / 180)
        if (k == "sia_y_D") return row["sia_D"] * sin(2 * row["sia_axis_deg"] * atan2(0, -1) / 180)
        return row[k]
    }
    BEGIN { n = split("k_steep_D k_flat_D axis_steep_deg cyl_D k_mean_D dk_mean_D flattening_D steepening_D " \
                      "coupling_ratio sia_D sia_x_D sia_y_D sia_axis_deg dv_D", R, " ") }
    FNR == 1 { f++; for (i = 1; i <= NF; i++) c[f, i] = $i; next }
    {
        s = $1; steps[s] = 1
        for (i = 1; i <= NF; i++) v[f, s, c[f, i]] = $i
    }
    END {
        for (s = 0; (s in steps); s++)
            for (k = 1; k <= n; k++) {
                for (g = 1; g <= 2; g++) {
                    delete row
                    row["sia_D"] = v[g, s, "sia_D"]; row["sia_axis_deg"] = v[g, s, "sia_axis_deg"]
                    row[R[k]] = v[g, s, R[k]]
                    x[g] = val(row, R[k])
                    if (v[g, s, R[k]] == "NaN" && R[k] !~ /^sia_[xy]_D$/) x[g] = "NaN"
                    if (x[g] "" == "") x[g] = "NaN"
                }
                if (x[1] == "NaN" || x[2] == "NaN") continue
                d = x[1] - x[2]
                if (R[k] ~ /axis_deg$/) { while (d > 90) d -= 180; while (d <= -90) d += 180 }
                printf "%s\t%s\t%.8g\t%d\n", P, R[k], d / (2 * H), s
            }
    }' "$out/runs/${p}_plus/run-$fam/curvature.tsv" "$out/runs/${p}_minus/run-$fam/curvature.tsv" >> "$tmp"
done
mv -f "$tmp" "$out/sens/$fam.tsv"
trap - EXIT
done
touch "$out/sens/done"
