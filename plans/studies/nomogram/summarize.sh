#!/usr/bin/env bash
# summarize.sh OUT SET: the study's results from its runs (OUT/set.txt names them).
#   nomogram.tsv         one row per case (one arc of one run): the eye (age, stiffness, K,
#                        cylinder), incisions, arc_deg, depth, diameter, and what curvature(1)
#                        read at that step: sia_D, flattening_D, steepening_D, coupling_ratio,
#                        dk_mean_D, the post-operative cylinder
#   nomogram-table.tsv   the simulated nomogram in the shape of the clinical ones: cylinder band
#   nomogram-table.md    x age -> arc per incision and number of incisions, with the SIA
#   sia-vs-arc.png/.svg  SIA against arc per incision count, per depth and per age, beside the
#                        clinical anchors (anchors.tsv)
#   timing.tsv           wall time of every job, and the naive cost (one full pipeline per case)
#   report.md            the above in short
# Every file is written under a temporary name and renamed; nomogram.tsv last (make's target).
set -euo pipefail
out=$1 set=$2
here=$(cd "$(dirname "$0")" && pwd)
read -r -a words < "$out/set.txt"
runs=("${words[@]:1}")
tmp=$(mktemp -d "$out/.summary.XXXXXX")
trap 'rm -rf "$tmp"' EXIT

# 1. nomogram.tsv: the steps of each run that end at a listed arc (a centre-out step k of a
# run opened k * step_deg of each arc, the last step the whole arc).
{
    printf 'eye\tage_y\tstiffness\tk_steep_D\tk_flat_D\tcyl_pre_D\taxis_deg\tincisions\tarc_deg'
    printf '\tdepth\tdiameter_mm\tsia_D\tsia_axis_deg\tflattening_D\tsteepening_D\tcoupling_ratio'
    printf '\tdk_mean_D\tcyl_post_D\tcyl_post_axis_deg\tstep\trun\n'
    for r in "${runs[@]}"; do
        awk -F'\t' -v OFS='\t' '
        FNR == 1 { for (i = 1; i <= NF; i++) col[FILENAME, $i] = i; next }
        FILENAME ~ /\.meta$/ { run = $1; eye = $2; ks = $3; kf = $4; ax = $5; age = $6; stf = $7
                   n = $8; dep = $9; dia = $10; st = $11; na = split($12, arcs, ",")
                   mx = 0; for (i = 1; i <= na; i++) { want[arcs[i]] = 1; if (arcs[i] + 0 > mx) mx = arcs[i] + 0 }
                   next }
        { k = $col[FILENAME, "step"]; if (k == 0) next
          a = k * st; if (a > mx) a = mx
          if (!(a in want)) next
          c = FILENAME
          print eye, age, stf, ks, kf, sprintf("%.2f", ks - kf), ax, n, a, dep, dia,
                $col[c, "sia_D"], $col[c, "sia_axis_deg"], $col[c, "flattening_D"],
                $col[c, "steepening_D"], $col[c, "coupling_ratio"], $col[c, "dk_mean_D"],
                $col[c, "cyl_D"], $col[c, "axis_steep_deg"], k, run }
        ' "$out/plans/$r.meta" "$out/runs/$r/curvature.tsv"
    done | sort -t$'\t' -k1,1 -k8,8n -k10,10gr -k11,11g -k9,9n
} > "$tmp/nomogram.tsv"

# 2. The table. For each band (bands.tsv) and age: the eye of that age whose cylinder is nearest
# the band's midpoint; its cases at the deepest depth and the most used diameter; the case whose
# SIA is nearest the midpoint, preferring one incision when its SIA lies within the band (as the
# clinical nomograms use a single arc where one suffices). Cells: "ARC (N)", or "> ARC (2)" when
# no simulated case reaches the band's lower edge, "< ARC (1)" when every case overshoots it.
awk -F'\t' -v OFS='\t' -v T="$tmp" '
FNR == 1 { file++ }
file == 1 { lo[++nb] = $1; hi[nb] = $2; next }
FNR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
{ e = $c["eye"]; age[e] = $c["age_y"]; cyl[e] = $c["cyl_pre_D"]; ages[$c["age_y"]] = 1
  dcount[e, $c["diameter_mm"]]++; if ($c["depth"] + 0 > maxdep[e] + 0) maxdep[e] = $c["depth"]
  nr++; re[nr] = e; rn[nr] = $c["incisions"]; ra[nr] = $c["arc_deg"]; rs[nr] = $c["sia_D"]
  rdep[nr] = $c["depth"]; rdia[nr] = $c["diameter_mm"] }
END {
    na = 0; for (a in ages) al[++na] = a + 0
    for (i = 1; i <= na; i++) for (j = i + 1; j <= na; j++) if (al[j] < al[i]) { t = al[i]; al[i] = al[j]; al[j] = t }
    for (e in age) { best = ""; for (k in dcount) { split(k, p, SUBSEP); if (p[1] == e && (best == "" || dcount[k] > dcount[e, best])) best = p[2] }; dia[e] = best }
    f = T "/nomogram-table.tsv"; m = T "/nomogram-table.md"
    printf "cylinder_D" > f; printf "| cylinder (D) |" > m
    for (i = 1; i <= na; i++) { printf "\t%s y", al[i] > f; printf " %s y |", al[i] > m }
    printf "\n" > f; printf "\n|---|" > m
    for (i = 1; i <= na; i++) printf "---|" > m
    printf "\n" > m
    for (b = 1; b <= nb; b++) {
        mid = (lo[b] + hi[b]) / 2
        printf "%.2f-%.2f", lo[b], hi[b] > f; printf "| %.2f-%.2f |", lo[b], hi[b] > m
        for (i = 1; i <= na; i++) {
            be = ""
            for (e in age) if (age[e] + 0 == al[i] && (be == "" || abs(cyl[e] - mid) < abs(cyl[be] - mid))) be = e
            pick = 0; inband = 0; smax = -1; smin = 1e9
            for (r = 1; r <= nr; r++) {
                if (re[r] != be || rdep[r] != maxdep[be] || rdia[r] != dia[be]) continue
                if (rs[r] > smax) { smax = rs[r]; rmax = r }
                if (rs[r] < smin) { smin = rs[r]; rmin = r }
                ib = (rs[r] >= lo[b] && rs[r] <= hi[b])
                if (!pick || (ib && !inband) || (ib == inband && (ib ? (rn[r] < rn[pick] || (rn[r] == rn[pick] && abs(rs[r] - mid) < abs(rs[pick] - mid))) : abs(rs[r] - mid) < abs(rs[pick] - mid)))) { pick = r; inband = ib }
            }
            if (!pick) cell = "-"
            else if (smax < lo[b]) cell = sprintf("> %d (%d) %.2f D", ra[rmax], rn[rmax], rs[rmax])
            else if (smin > hi[b]) cell = sprintf("< %d (%d) %.2f D", ra[rmin], rn[rmin], rs[rmin])
            else cell = sprintf("%d (%d) %.2f D", ra[pick], rn[pick], rs[pick])
            printf "\t%s", cell > f; printf " %s |", cell > m
        }
        printf "\n" > f; printf "\n" > m
    }
}
function abs(x) { return x < 0 ? -x : x }
' "$out/bands.tsv" "$tmp/nomogram.tsv"

# 3. Plots: three panels, SIA against arc. Series files for gnuplot (blank-line separated
# blocks, one per series, each headed by its title).
awk -F'\t' -v T="$tmp" '
NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
{ e = $c["eye"]; n = $c["incisions"]; d = $c["depth"]
  key = e SUBSEP n SUBSEP d SUBSEP $c["diameter_mm"]
  if (!(key in rows)) { nk++; keys[nk] = key }
  rows[key] = rows[key] $c["arc_deg"] "\t" $c["sia_D"] "\n"
  age[e] = $c["age_y"]; cyl[e] = $c["cyl_pre_D"] }
END {
    # the reference eye: the one with the most runs
    for (k = 1; k <= nk; k++) { split(keys[k], p, SUBSEP); cnt[p[1]]++ }
    for (e in cnt) if (ref == "" || cnt[e] > cnt[ref]) ref = e
    for (k = 1; k <= nk; k++) {
        split(keys[k], p, SUBSEP)
        t = sprintf("%s, %s y, %.2f D: %s, depth %s, %s mm", p[1], age[p[1]], cyl[p[1]], p[2] == 2 ? "paired" : "single", p[3], p[4])
        if (p[1] == ref) { print "\"" t "\"\n" rows[keys[k]] "\n" >> (T "/by-count.dat"); nc++ }
        if (p[1] == ref && p[2] == 2) { print "\"" t "\"\n" rows[keys[k]] "\n" >> (T "/by-depth.dat"); nd++ }
        if (p[3] == 0.9 || p[3] == "0.9") { print "\"" t "\"\n" rows[keys[k]] "\n" >> (T "/by-age.dat"); na++ }
    }
    printf "%d %d %d\n", nc, nd, na > (T "/counts")
}' "$tmp/nomogram.tsv"
for f in by-count by-depth by-age; do [ -f "$tmp/$f.dat" ] || : > "$tmp/$f.dat"; done
read -r nc nd na < "$tmp/counts"
for term in png svg; do
    gnuplot -e "term='$term'; out='$tmp/sia-vs-arc.$term'; dir='$tmp'; anchors='$here/anchors.tsv'; nc=$nc; nd=$nd; na=$na" \
        "$here/plot.gp"
done

# 4. Timing: the study's jobs, and the naive cost: every case run alone (its eye meshed, its own
# plan cut and solved from the intact eye up to its arc, its curvature). A run's steps.tsv gives
# the factorization and every step's time, so a case's solve is the run's time up to its step.
{
    printf 'job\tkind\twall_s\n'
    for r in "${runs[@]}"; do awk -F'\t' -v OFS='\t' 'NR == 2 { print $1, "run", $2 + $3 }' "$out/runs/$r/time.tsv"; done
    for e in $(awk -F'\t' 'NR > 1 { print $1 }' "$tmp/nomogram.tsv" | sort -u); do
        awk -F'\t' -v OFS='\t' 'NR == 2 { print $1, "eye", $2 }' "$out/eyes/$e.time.tsv"
    done
} > "$tmp/timing.tsv"
naive=0
for r in "${runs[@]}"; do
    eye=$(awk -F'\t' 'NR == 2 { print $2 }' "$out/plans/$r.meta")
    mp=$(awk -F'\t' 'NR == 2 { print $2 }' "$out/eyes/$eye.time.tsv")
    # run wall time = start-up and factorization + the steps; curvature per step ~ its share
    n=$(awk -F'\t' -v r="$r" 'NR > 1 && $21 == r' "$tmp/nomogram.tsv" | wc -l)
    add=$(awk -F'\t' -v mp="$mp" -v r="$r" -v steps="$out/runs/$r/steps.tsv" -v tt="$out/runs/$r/time.tsv" '
        BEGIN {
            getline h < tt; getline l < tt; split(l, t, "\t"); solve = t[2]; curv = t[3]
            getline h < steps; nf = split(h, hc, "\t"); for (i = 1; i <= nf; i++) c[hc[i]] = i
            while ((getline l < steps) > 0) { split(l, v, "\t"); k = v[c["step"]]; ms[k] = v[c["t_total_ms"]] / 1000; last = k }
            tot = 0; for (k = 1; k <= last; k++) tot += ms[k]
            base = solve - tot; if (base < 0) base = 0
        }
        NR > 1 && $21 == r { k = $20; s = base; for (j = 1; j <= k; j++) s += ms[j]
                             cost += mp + s + curv * (k + 1) / (last + 1) }
        END { printf "%.2f", cost }' "$tmp/nomogram.tsv")
    naive=$(awk -v a="$naive" -v b="$add" 'BEGIN { printf "%.2f", a + b }')
done
study=$(awk -F'\t' 'NR > 1 { s += $3 } END { printf "%.2f", s }' "$tmp/timing.tsv")
printf 'total\tstudy\t%s\ntotal\tnaive\t%s\n' "$study" "$naive" >> "$tmp/timing.tsv"

# 5. report.md
ncase=$(($(wc -l < "$tmp/nomogram.tsv") - 1))
rev=$(git -C "$here" rev-parse --short HEAD 2>/dev/null || echo unknown)
{
    echo "# Nomogram study ($set set)"
    echo
    echo "keratome $rev, tools from $KT_BUILD; $ncase cases from ${#runs[@]} runs; written $(date -u +%Y-%m-%dT%H:%MZ)."
    echo
    echo "## Simulated nomogram (arc per incision in degrees, (1) one incision, (2) a pair, and its SIA)"
    echo
    cat "$tmp/nomogram-table.md"
    echo
    echo "Clinical (Wallace, with the rule; shared/CLINICAL-ANCHORS.md): 1.00-1.50 D: 60 (1) at 40-50 y,"
    echo "50 (1) at 60-70 y, 30 (1) at 80+ y; 2.00-2.50 D: 60 (2) at 40-70 y; 3.00-4.00 D: 80 (2) at 40-70 y."
    echo "Wang 2003: a single 60-degree incision 0.55 D, a pair 1.18 D."
    echo
    echo "## Cases"
    echo
    echo "| eye | age | incisions | depth | arc | SIA (D) | flattening | steepening | coupling | dK mean |"
    echo "|---|---|---|---|---|---|---|---|---|---|"
    awk -F'\t' 'NR > 1 { printf "| %s | %s | %s | %s | %s | %.2f | %.2f | %.2f | %.2f | %.2f |\n",
        $1, $2, $8, $10, $9, $12, $14, $15, $16, $17 }' "$tmp/nomogram.tsv"
    echo
    echo "## Cost"
    echo
    echo "Sum of job wall times $study s; the naive cost (each case meshed, cut and solved on its own,"
    echo "estimated from the same runs' per-step times) $naive s: $(awk -v a="$naive" -v b="$study" 'BEGIN { printf "%.1f", a / b }')x."
    echo
    echo "![SIA against arc](sia-vs-arc.svg)"
} > "$tmp/report.md"

for f in nomogram-table.tsv nomogram-table.md sia-vs-arc.png sia-vs-arc.svg timing.tsv report.md nomogram.tsv; do
    mv -f "$tmp/$f" "$out/$f"
done
echo "summary: $ncase cases in $out/nomogram.tsv; table $out/nomogram-table.md; report $out/report.md"
