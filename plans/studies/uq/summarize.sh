#!/usr/bin/env bash
# summarize.sh OUT: the uncertainty study's result from its runs (OUT/study.mk names them).
#   eyes.tsv    one row per sampled eye: its inputs' deviations (samples.tsv) and what curvature
#               read at the plan's last step
#   uq.tsv      per reading (sia_D, k_steep_D, k_flat_D, cyl_D, coupling_ratio, flattening_D,
#               steepening_D, dk_mean_D): the nominal eye's value; the sampled mean, sd (n - 1)
#               and 5% / 95% quantiles (linear interpolation between order statistics); the
#               nominal eye's first-order sd and 90% interval (curvature's band columns:
#               augsolve --uncertainty, with OUT/sens.tsv as --sens when the geometry target has
#               run), and the ratio sampled sd / first-order sd ("NaN" where no band exists)
#   report.md   the above in short, with what the first-order band left out
# Written under temporary names, renamed at the end (uq.tsv last: make's target).
set -euo pipefail
out=$1
B=${KT_BUILD:?KT_BUILD not set}
tmp=$(mktemp -d "$out/.summary.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
read -r -a samples < <(sed -n 's/^SAMPLES := //p' "$out/study.mk")
R="sia_D k_steep_D k_flat_D cyl_D coupling_ratio flattening_D steepening_D dk_mean_D"

last_row() { # CURVATURE.TSV -> header line and the last step's line
    awk -F'\t' 'NR == 1 { print; next } { last = $0 } END { print last }' "$1"
}
# 1. eyes.tsv
{
    head -n 1 "$out/samples.tsv" | tr '\n' '\t'; echo "$R" | tr ' ' '\t'
    i=0
    for s in "${samples[@]}"; do
        sed -n "$((i + 2))p" "$out/samples.tsv" | tr '\n' '\t'
        last_row "$out/runs/$s/run/curvature.tsv" | awk -F'\t' -v R="$R" '
            NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
            { n = split(R, r, " "); for (k = 1; k <= n; k++) printf "%s%s", $c[r[k]], k < n ? "\t" : "\n" }'
        i=$((i + 1))
    done
} > "$tmp/eyes.tsv"

# 2. The first-order band of the nominal eye.
nom=$out/runs/nominal/run
# The nominal run is solved with augsolve --uncertainty (task.sh); a nominal run without its
# uncertainty.tsv is stale (solved before issue 21) and is refused rather than summarized
# without a band. OUT/sens.tsv (make geometry) holds central differences for every quantity with
# a step h; curvature takes --sens rows only for the quantities augsolve marks fd (thickness,
# depth): the others have their derivatives from augsolve.
[ -f "$nom/uncertainty.tsv" ] || {
    echo "summarize.sh: $nom/uncertainty.tsv: missing: the nominal run was not solved with augsolve --uncertainty (rerun it: rm -r $out/runs/nominal; make)" >&2
    exit 1
}
sensopt=()
if [ -f "$out/sens.tsv" ]; then
    awk -F'\t' 'FNR == 1 { f++; if (f == 2) print; next } f == 1 { if ($5 == "fd") fd[$1] = 1; next } $1 in fd' \
        "$nom/uncertainty.tsv" "$out/sens.tsv" > "$tmp/sens.tsv"
    sensopt=(--sens "$tmp/sens.tsv")
fi
"$B/curvature" -q --no-png --no-vtk --no-report "${sensopt[@]}" -o "$tmp/band" "$nom" > "$tmp/band.txt"
band=$tmp/band/curvature.tsv
note="first-order band: $(grep -c -v -e '^param' "$nom/uncertainty.tsv") quantities in uncertainty.tsv; "
note+=$(grep '^left out' "$tmp/band.txt" || echo "none left out")
[ -f "$out/sens.tsv" ] || note+=" (make geometry writes the --sens file for the fd quantities)"

# 3. uq.tsv
{
    printf 'reading\tn\tnominal\tmean\tsd\tq05\tq95\tfo_sd\tfo_lo90\tfo_hi90\tsd_ratio\n'
    for r in $R; do
        col=$(head -n 1 "$tmp/eyes.tsv" | tr '\t' '\n' | grep -nx "$r" | cut -d: -f1)
        nominal=$(last_row "$nom/curvature.tsv" | awk -F'\t' -v r="$r" 'NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next } { print $c[r] }')
        fo="NaN NaN NaN"
        if [ -n "$band" ]; then
            fo=$(last_row "$band" | awk -F'\t' -v r="$r" 'NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
                { print $c[r "_sd"], $c[r "_lo90"], $c[r "_hi90"] }')
        fi
        tail -n +2 "$tmp/eyes.tsv" | cut -f"$col" | grep -x -E -- '-?[0-9.]+([eE][-+]?[0-9]+)?' | sort -g |
        awk -v r="$r" -v nom="$nominal" -v fo="$fo" '
            { x[++n] = $1; s += $1 }
            function q(p,   h, lo) { h = (n - 1) * p + 1; lo = int(h); return lo >= n ? x[n] : x[lo] + (h - lo) * (x[lo + 1] - x[lo]) }
            END {
                if (n == 0) { printf "%s\t0\t%s\tNaN\tNaN\tNaN\tNaN\tNaN\tNaN\tNaN\tNaN\n", r, nom; exit }
                m = s / n; for (i = 1; i <= n; i++) v += (x[i] - m) ^ 2
                sd = n > 1 ? sqrt(v / (n - 1)) : "NaN"
                split(fo, f, " ")
                ratio = (f[1] != "NaN" && f[1] + 0 > 0 && sd != "NaN") ? sprintf("%.3f", sd / f[1]) : "NaN"
                printf "%s\t%d\t%s\t%.4f\t%s\t%.4f\t%.4f\t%s\t%s\t%s\t%s\n", r, n, nom, m,
                       sd == "NaN" ? sd : sprintf("%.4f", sd), q(0.05), q(0.95), f[1], f[2], f[3], ratio
            }'
    done
} > "$tmp/uq.tsv"

# 4. report.md
{
    echo "# The uncertainty study: $(wc -l < "$out/samples.tsv" | awk '{ print $1 - 1 }') sampled eyes"
    echo
    echo "Inputs (deviations from the base scene, Latin hypercube; params.tsv):"
    echo
    echo '| quantity | distribution | sd | unit | base value |'
    echo '|---|---|---:|---|---:|'
    tail -n +2 "$out/params.tsv" | awk -F'\t' '{ printf "| %s | %s | %s | %s | %s |\n", $1, $2, $3, $5, $6 }'
    echo
    echo "At the plan's last step, sampled against the nominal eye's first-order band ($note):"
    echo
    echo '| reading | nominal | sampled mean | sampled sd | sampled 5-95% | first-order sd | first-order 90% | sd ratio |'
    echo '|---|---:|---:|---:|---|---:|---|---:|'
    tail -n +2 "$tmp/uq.tsv" | awk -F'\t' '{ printf "| %s | %s | %s | %s | %s-%s | %s | %s-%s | %s |\n",
        $1, $3, $4, $5, $6, $7, $8, $9, $10, $11 }'
    echo
    echo "Wall time of the eyes (mesh-prep, solve, curvature; s): $(cat "$out"/runs/*/run/time.tsv | awk -F'\t' '
        $1 != "eye" { m += $2; s += $3; c += $4; n++ } END { printf "%d eyes, %.0f + %.0f + %.0f", n, m, s, c }')"
} > "$tmp/report.md"
mv -f "$tmp/eyes.tsv" "$out/eyes.tsv"
mv -f "$tmp/report.md" "$out/report.md"
mv -f "$tmp/uq.tsv" "$out/uq.tsv"
cat "$out/report.md"
