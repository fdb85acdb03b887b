#!/usr/bin/env bash
# summarize.sh OUT SET: the study's results from its runs (OUT/set.txt names them).
#   nomogram.tsv         one row per case (one arc of one run): the eye (age, stiffness, K,
#                        cylinder), incisions, arc_deg, depth, diameter, and what curvature(1)
#                        read at that step: sia_D, flattening_D, steepening_D, coupling_ratio,
#                        dk_mean_D, the post-operative cylinder; then the first-order band of
#                        the SIA and the cylinder (curvature's sia_D_sd, sia_D_lo90, sia_D_hi90,
#                        cyl_D_sd: sia_sd_D, sia_lo90_D, sia_hi90_D, cyl_post_sd_D; NaN for a
#                        run solved without augsolve --uncertainty)
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
    printf '\tdk_mean_D\tcyl_post_D\tcyl_post_axis_deg\tstep\trun\tsia_sd_D\tsia_lo90_D\tsia_hi90_D\tcyl_post_sd_D\n'
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
                $col[c, "cyl_D"], $col[c, "axis_steep_deg"], k, run,
                opt(c, "sia_D_sd"), opt(c, "sia_D_lo90"), opt(c, "sia_D_hi90"), opt(c, "cyl_D_sd") }
        function opt(c, name) { return (c, name) in col ? $col[c, name] : "NaN" }
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
  age[e] = $c["age_y"]; cyl[e] = $c["cyl_pre_D"]; if (d + 0 > maxd[e] + 0) maxd[e] = d }
END {
    # the reference eye: the one with the most runs
    for (k = 1; k <= nk; k++) { split(keys[k], p, SUBSEP); cnt[p[1]]++ }
    for (e in cnt) if (ref == "" || cnt[e] > cnt[ref]) ref = e
    for (k = 1; k <= nk; k++) {
        split(keys[k], p, SUBSEP)
        t = sprintf("%s, %s y, %.2f D: %s, depth %s, %s mm", p[1], age[p[1]], cyl[p[1]], p[2] == 2 ? "paired" : "single", p[3], p[4])
        if (p[1] == ref && p[3] == maxd[ref]) { print "\"" t "\"\n" rows[keys[k]] "\n" >> (T "/by-count.dat"); nc++ }
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

# 4. Timing: the study's jobs (wall and CPU seconds), and the naive cost: every case run alone
# (its eye meshed, its own plan cut and solved from the intact eye up to its arc, its curvature).
# A run's steps.tsv gives every step's time, so a case alone costs its eye's mesh-prep plus the
# share of its run up to its step: (start-up and factorization + steps 1..k) / the whole run.
{
    printf 'job\tkind\twall_s\tcpu_s\n'
    for r in "${runs[@]}"; do
        awk -F'\t' -v OFS='\t' 'NR == 2 { print $1, "run", $2 + $3, (NF > 3 ? $4 : $2 + $3) }' "$out/runs/$r/time.tsv"
    done
    for e in $(awk -F'\t' 'NR > 1 { print $1 }' "$tmp/nomogram.tsv" | sort -u); do
        awk -F'\t' -v OFS='\t' 'NR == 2 { print $1, "eye", $2, (NF > 2 ? $3 : $2) }' "$out/eyes/$e.time.tsv"
    done
} > "$tmp/timing.tsv"
naive_wall=0 naive_cpu=0
for r in "${runs[@]}"; do
    eye=$(awk -F'\t' 'NR == 2 { print $2 }' "$out/plans/$r.meta")
    read -r w c < <(awk -F'\t' -v r="$r" -v steps="$out/runs/$r/steps.tsv" -v tt="$out/runs/$r/time.tsv" \
                          -v et="$out/eyes/$eye.time.tsv" '
        BEGIN {
            getline h < et; getline l < et; split(l, t, "\t"); mpw = t[2]; mpc = (t[3] != "") ? t[3] : t[2]
            getline h < tt; getline l < tt; n = split(l, t, "\t"); rw = t[2] + t[3]; rc = (n > 3) ? t[4] : rw
            getline h < steps; nf = split(h, hc, "\t"); for (i = 1; i <= nf; i++) c[hc[i]] = i
            while ((getline l < steps) > 0) { split(l, v, "\t"); ms[v[c["step"]]] = v[c["t_total_ms"]] / 1000; last = v[c["step"]] }
            tot = 0; for (k = 1; k <= last; k++) tot += ms[k]
            base = t[2] - tot; if (base < 0) base = 0
        }
        NR > 1 && $21 == r { k = $20; s = base; for (j = 1; j <= k; j++) s += ms[j]
                             f = s / (base + tot); cw += mpw + rw * f; cc += mpc + rc * f }
        END { printf "%.2f %.2f\n", cw, cc }' "$tmp/nomogram.tsv")
    naive_wall=$(awk -v a="$naive_wall" -v b="$w" 'BEGIN { printf "%.2f", a + b }')
    naive_cpu=$(awk -v a="$naive_cpu" -v b="$c" 'BEGIN { printf "%.2f", a + b }')
done
read -r study_wall study_cpu < <(awk -F'\t' 'NR > 1 { w += $3; c += $4 } END { printf "%.2f %.2f\n", w, c }' "$tmp/timing.tsv")
printf 'total\tstudy\t%s\t%s\ntotal\tnaive\t%s\t%s\n' "$study_wall" "$study_cpu" "$naive_wall" "$naive_cpu" >> "$tmp/timing.tsv"

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
    echo "Clinical (Wallace, with the rule; docs/references.md): 1.00-1.50 D: 60 (1) at 40-50 y,"
    echo "50 (1) at 60-70 y, 30 (1) at 80+ y; 2.00-2.50 D: 60 (2) at 40-70 y; 3.00-4.00 D: 80 (2) at 40-70 y."
    echo "Wang 2003: a single 60-degree incision 0.55 D, a pair 1.18 D."
    echo
    echo "## Cases"
    echo
    echo "| eye | age | incisions | depth | arc | SIA (D) | SIA sd (D) | SIA 90% (D) | flattening | steepening | coupling | dK mean |"
    echo "|---|---|---|---|---|---|---|---|---|---|---|---|"
    awk -F'\t' 'NR > 1 { printf "| %s | %s | %s | %s | %s | %.2f | %.2f | %.2f-%.2f | %.2f | %.2f | %.2f | %.2f |\n",
        $1, $2, $8, $10, $9, $12, $22, $23, $24, $14, $15, $16, $17 }' "$tmp/nomogram.tsv"
    echo
    echo "The SIA's sd is first order (augsolve --uncertainty, curvature(1) UNCERTAINTY): the scene's"
    echo "derivative quantities only; the thickness and the depth (fd) are left out."
    echo
    echo "## Cost"
    echo
    echo "Jobs of the study: $study_wall s wall, $study_cpu s CPU in all. The naive cost (each case meshed,"
    echo "cut and solved on its own, from the same runs' per-step times): $naive_wall s wall, $naive_cpu s CPU:"
    echo "$(awk -v a="$naive_cpu" -v b="$study_cpu" 'BEGIN { printf "%.1f", a / b }')x the study's CPU time (timing.tsv). Wall times carry the machine's other load."
    echo
    echo "![SIA against arc](sia-vs-arc.svg)"
} > "$tmp/report.md"

for f in nomogram-table.tsv nomogram-table.md sia-vs-arc.png sia-vs-arc.svg timing.tsv report.md nomogram.tsv; do
    mv -f "$tmp/$f" "$out/$f"
done
echo "summary: $ncase cases in $out/nomogram.tsv; table $out/nomogram-table.md; report $out/report.md"
