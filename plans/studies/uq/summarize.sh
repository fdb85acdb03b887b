#!/usr/bin/env bash
# summarize.sh OUT: the uncertainty study's result from its runs (OUT/study.mk names them).
#   eyes.tsv     one row per sampled eye, family and step: its inputs' deviations (samples.tsv),
#                the family, the step and its arc (deg, each arc of a pair), and what curvature read
#   uq.tsv       per family, arc (every step after 0) and reading (sia_D, k_steep_D, k_flat_D,
#                cyl_D, coupling_ratio, flattening_D, steepening_D, dk_mean_D): the nominal eye's
#                value; the sampled mean, sd (n - 1) and 5% / 95% quantiles (linear interpolation
#                between order statistics); the nominal eye's first-order sd and 90% interval
#                (curvature's band columns: augsolve --uncertainty, with OUT/sens/FAMILY.tsv as
#                --sens when the geometry target has run), and the ratio sampled sd / first-order
#                sd ("NaN" where no band exists)
#   tornado.tsv  per family and arc, each quantity's share of the SIA's first-order sd,
#                |dSIA/dp| sd_p in D, ranked (1: the largest); the quantities left out have none
#   report.md    the per-arc SIA table of every family, the tornado ranking, every reading at the
#                longest arc of the last family, and what the first-order band left out
# Written under temporary names, renamed at the end (uq.tsv last: make's target). PARTIAL=1
# (`make summary PARTIAL=1` does not wait for the eyes: run summarize.sh by hand) summarizes the
# eyes done so far and says so in report.md: a part of a Latin hypercube, each eye drawn from
# the right marginals, the strata no longer balanced.
set -euo pipefail
out=$1
B=${KT_BUILD:?KT_BUILD not set}
tmp=$(mktemp -d "$out/.summary.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
read -r -a samples < <(sed -n 's/^SAMPLES := //p' "$out/study.mk")
read -r -a families < <(sed -n 's/^FAMILIES := //p' "$out/study.mk")
step_deg=$(sed -n 's/^STEP_DEG := //p' "$out/study.mk")
[ ${#families[@]} -gt 0 ] && [ -n "$step_deg" ] ||
    { echo "summarize.sh: $out/study.mk: no FAMILIES / STEP_DEG (rerun gen.sh: make)" >&2; exit 1; }
R="sia_D k_steep_D k_flat_D cyl_D coupling_ratio flattening_D steepening_D dk_mean_D"

# 1. eyes.tsv
{
    head -n 1 "$out/samples.tsv" | tr '\n' '\t'; printf 'family\tstep\tarc_deg\t'; echo "$R" | tr ' ' '\t'
    i=0
    for s in "${samples[@]}"; do
        dev=$(sed -n "$((i + 2))p" "$out/samples.tsv")
        if [ "${PARTIAL:-0}" = 1 ] && [ ! -f "$out/runs/$s/time.tsv" ]; then i=$((i + 1)); continue; fi
        for fam in "${families[@]}"; do
            awk -F'\t' -v R="$R" -v D="$dev" -v F="$fam" -v S="$step_deg" '
                NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
                { printf "%s\t%s\t%s\t%g", D, F, $1, $1 * S
                  n = split(R, r, " "); for (k = 1; k <= n; k++) printf "\t%s", $c[r[k]]; printf "\n" }' \
                "$out/runs/$s/run-$fam/curvature.tsv"
        done
        i=$((i + 1))
    done
} > "$tmp/eyes.tsv"

# 2. The first-order band of the nominal eye, per family.
# The nominal run is solved with augsolve --uncertainty (task.sh); a nominal run without its
# uncertainty.tsv is stale (solved before issue 21) and is refused rather than summarized
# without a band. OUT/sens/FAMILY.tsv (make geometry) holds central differences for every
# quantity with a step h; curvature takes --sens rows only for the quantities augsolve marks fd
# (thickness, depth): the others have their derivatives from augsolve.
note=
for fam in "${families[@]}"; do
    nom=$out/runs/nominal/run-$fam
    [ -f "$nom/uncertainty.tsv" ] || {
        echo "summarize.sh: $nom/uncertainty.tsv: missing: the nominal run was not solved with augsolve --uncertainty (rerun it: rm -r $out/runs/nominal; make)" >&2
        exit 1
    }
    sensopt=()
    if [ -f "$out/sens/$fam.tsv" ]; then
        awk -F'\t' 'FNR == 1 { f++; if (f == 2) print; next } f == 1 { if ($5 == "fd") fd[$1] = 1; next } $1 in fd' \
            "$nom/uncertainty.tsv" "$out/sens/$fam.tsv" > "$tmp/sens-$fam.tsv"
        sensopt=(--sens "$tmp/sens-$fam.tsv")
    fi
    "$B/curvature" -q --no-png --no-vtk --no-report "${sensopt[@]}" -o "$tmp/band-$fam" "$nom" > "$tmp/band-$fam.txt"
    note+="${note:+; }$fam: first-order band: $(grep -c -v -e '^param' "$nom/uncertainty.tsv") quantities in uncertainty.tsv, "
    note+=$(grep '^left out' "$tmp/band-$fam.txt" || echo "none left out")
done
[ -d "$out/sens" ] || note+=" (make geometry writes the --sens files for the fd quantities)"

# 3. uq.tsv and tornado.tsv
printf 'family\tarc_deg\treading\tn\tnominal\tmean\tsd\tq05\tq95\tfo_sd\tfo_lo90\tfo_hi90\tsd_ratio\n' > "$tmp/uq.tsv"
printf 'family\tarc_deg\tparam\tsia_sd_D\trank\n' > "$tmp/tornado.tsv"
for fam in "${families[@]}"; do
    awk -F'\t' -v R="$R" -v F="$fam" -v S="$step_deg" '
    function isnum(x) { return x ~ /^-?[0-9.]+([eE][-+]?[0-9]+)?$/ }
    function q(a, n, p,   h, lo) { h = (n - 1) * p + 1; lo = int(h); return lo >= n ? a[n] : a[lo] + (h - lo) * (a[lo + 1] - a[lo]) }
    BEGIN { nr = split(R, r, " ") }
    FNR == 1 { f++; delete c; for (i = 1; i <= NF; i++) c[$i] = i; next }
    f == 1 { if ($c["family"] != F || $c["step"] == 0) next   # eyes.tsv
             s = $c["step"]; steps[s] = 1
             for (k = 1; k <= nr; k++) if (isnum($c[r[k]])) { m = ++cnt[s, k]; x[s, k, m] = $c[r[k]] }
             next }
    f == 2 { for (k = 1; k <= nr; k++) nom[$1, k] = $c[r[k]]; next }             # nominal curvature.tsv
    f == 3 { for (k = 1; k <= nr; k++) { sd[$1, k] = $c[r[k] "_sd"]; lo[$1, k] = $c[r[k] "_lo90"]; hi[$1, k] = $c[r[k] "_hi90"] } }
    END {
        for (s = 1; (s in steps); s++)
            for (k = 1; k <= nr; k++) {
                n = cnt[s, k] + 0; delete a; sum = 0
                for (i = 1; i <= n; i++) { a[i] = x[s, k, i]; sum += a[i] }
                for (i = 2; i <= n; i++) { v = a[i]; for (j = i - 1; j >= 1 && a[j] > v; j--) a[j + 1] = a[j]; a[j + 1] = v }
                fs = (s, k) in sd && sd[s, k] != "" ? sd[s, k] : "NaN"
                if (n == 0) { printf "%s\t%g\t%s\t0\t%s\tNaN\tNaN\tNaN\tNaN\t%s\t%s\t%s\tNaN\n", F, s * S, r[k], nom[s, k], fs, lo[s, k], hi[s, k]; continue }
                mean = sum / n; var = 0; for (i = 1; i <= n; i++) var += (a[i] - mean) ^ 2
                ssd = n > 1 ? sprintf("%.4f", sqrt(var / (n - 1))) : "NaN"
                ratio = (fs != "NaN" && fs + 0 > 0 && ssd != "NaN") ? sprintf("%.3f", ssd / fs) : "NaN"
                printf "%s\t%g\t%s\t%d\t%s\t%.4f\t%s\t%.4f\t%.4f\t%s\t%s\t%s\t%s\n", F, s * S, r[k], n, nom[s, k], mean, ssd,
                       q(a, n, 0.05), q(a, n, 0.95), fs, (s, k) in lo ? lo[s, k] : "NaN", (s, k) in hi ? hi[s, k] : "NaN", ratio
            }
    }' "$tmp/eyes.tsv" "$out/runs/nominal/run-$fam/curvature.tsv" "$tmp/band-$fam/curvature.tsv" >> "$tmp/uq.tsv"
    awk -F'\t' -v F="$fam" -v S="$step_deg" '
        NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
        $c["step"] > 0 && $c["used"] == 1 { printf "%s\t%g\t%s\t%.4f\n", F, $c["step"] * S, $c["param"], sqrt(($c["sia_D"] * $c["sd"]) ^ 2) }' \
        "$tmp/band-$fam/derivatives.tsv" | sort -t$'\t' -k2,2g -k4,4gr |
        awk -F'\t' -v OFS='\t' '{ rank = $2 == prev ? rank + 1 : 1; prev = $2; print $0, rank }' >> "$tmp/tornado.tsv"
done

# 4. report.md
last=${families[-1]}
lastarc=$(awk -F'\t' -v F="$last" '$1 == F { a = $2 } END { print a }' "$tmp/uq.tsv")
{
    ndone=$(tail -n +2 "$tmp/eyes.tsv" | cut -f1 | sort -u | wc -l)
    echo "# The uncertainty study: $ndone of $(wc -l < "$out/samples.tsv" | awk '{ print $1 - 1 }') sampled eyes, families ${families[*]}"
    echo
    echo "Inputs (deviations from the base scene, Latin hypercube; params.tsv):"
    echo
    echo '| quantity | distribution | sd | unit | base value |'
    echo '|---|---|---:|---|---:|'
    tail -n +2 "$out/params.tsv" | awk -F'\t' '{ printf "| %s | %s | %s | %s | %s |\n", $1, $2, $3, $5, $6 }'
    echo
    echo "The SIA (D) per arc, the nominal eye's first-order band against the sampled eyes ($note):"
    echo
    echo '| family | arc (deg) | nominal | first-order sd | first-order 90% | sampled mean | sampled sd | sampled 5-95% | sd ratio |'
    echo '|---|---:|---:|---:|---|---:|---:|---|---:|'
    awk -F'\t' '$3 == "sia_D" { printf "| %s | %s | %.3f | %.3f | %.2f-%.2f | %.3f | %.3f | %.2f-%.2f | %s |\n",
        $1, $2, $5, $10, $11, $12, $6, $7, $8, $9, $13 }' "$tmp/uq.tsv"
    echo
    echo "Tornado: each quantity's share of the SIA's first-order sd, |dSIA/dp| sd_p (D), largest first:"
    echo
    echo '| family | arc (deg) | ranking |'
    echo '|---|---:|---|'
    tail -n +2 "$tmp/tornado.tsv" | awk -F'\t' '{ k = $1 " " $2; if (!(k in row)) ord[++n] = k; row[k] = row[k] (row[k] == "" ? "" : ", ") sprintf("%s %.3f", $3, $4) }
        END { for (i = 1; i <= n; i++) { split(ord[i], p, " "); printf "| %s | %s | %s |\n", p[1], p[2], row[ord[i]] } }'
    echo
    echo "Every reading, $last $lastarc deg:"
    echo
    echo '| reading | nominal | sampled mean | sampled sd | sampled 5-95% | first-order sd | first-order 90% | sd ratio |'
    echo '|---|---:|---:|---:|---|---:|---|---:|'
    awk -F'\t' -v F="$last" -v A="$lastarc" '$1 == F && $2 == A { printf "| %s | %s | %s | %s | %s-%s | %s | %s-%s | %s |\n",
        $3, $5, $6, $7, $8, $9, $10, $11, $12, $13 }' "$tmp/uq.tsv"
    echo
    echo "Wall time of the eyes (mesh-prep, solves, curvature; s): $(cat "$out"/runs/*/time.tsv | awk -F'\t' '
        $1 != "eye" { m += $3; s += $4; c += $5; e[$1] = 1 } END { printf "%d eyes, %.0f + %.0f + %.0f", length(e), m, s, c }')"
} > "$tmp/report.md"
mv -f "$tmp/eyes.tsv" "$out/eyes.tsv"
mv -f "$tmp/tornado.tsv" "$out/tornado.tsv"
mv -f "$tmp/report.md" "$out/report.md"
mv -f "$tmp/uq.tsv" "$out/uq.tsv"
cat "$out/report.md"
