#!/usr/bin/env bash
# gen.sh SPEC OUT: writes the study's inputs from its spec (study.spec, see there):
#   OUT/scenes/EYE.yaml    one scene per eye: the base scene with the eye's fields replaced
#   OUT/plans/RUN.yaml     one plan per run: its arcs cut from the centre out, one step per
#                          listed arc (steps of the arcs' greatest common divisor)
#   OUT/plans/RUN.meta     the run's columns for nomogram.tsv (tab-separated, with header)
#   OUT/study.mk           make variables: EYES_quick/EYES_full, RUNS_quick/RUNS_full, and
#                          each run's eye as a prerequisite
# A file is replaced only when its content changes (so make reruns only what a spec edit
# touches), and always atomically. A malformed spec line: "SPEC:LINE: expected ...", exit 2,
# nothing written.
set -euo pipefail
spec=$1 out=$2
here=$(cd "$(dirname "$0")" && pwd)
specdir=$(cd "$(dirname "$spec")" && pwd)
tmp=$(mktemp -d "${TMPDIR:-/tmp}/kt_gen_XXXXXX")
trap 'rm -rf "$tmp"' EXIT

# 1. Parse and check the spec into flat records (tmp/records), one per eye/run/band.
awk -v F="$spec" '
function die(msg) { printf "%s:%d: expected %s\n", F, NR, msg > "/dev/stderr"; bad = 1; exit 2 }
function num(s)   { return s ~ /^[0-9]+(\.[0-9]*)?$/ }
{ sub(/#.*/, "") }
NF == 0 { next }
$1 == "base"     { if (NF != 2) die("base SCENE"); print "base", $2; next }
$1 == "age_rule" { if (NF != 3 || !num($2) || !num($3)) die("age_rule AGE0 PER_DECADE")
                   print "age_rule", $2, $3; next }
$1 == "eye" {
    if (NF != 8) die("eye NAME K_STEEP K_FLAT AXIS CCT AGE STIFFNESS (8 fields)")
    if ($2 !~ /^[A-Za-z0-9_]+$/) die("an eye name of letters, digits and _")
    if (!num($3) || !num($4) || $3 < $4) die("K_STEEP >= K_FLAT, in D")
    if (!num($5) || $5 >= 180) die("AXIS in [0, 180) deg")
    if ($6 != "-" && !num($6)) die("CCT in um or -")
    if (!num($7)) die("AGE in years")
    if ($8 != "-" && (!num($8) || $8 <= 0)) die("STIFFNESS > 0 or -")
    if ($2 in eyes) die("a new eye name (" $2 " given twice)")
    eyes[$2] = 1; print; next }
$1 == "run" {
    if (NF < 7) die("run SET EYE INCISIONS DEPTH DIAMETER ARCS...")
    if ($2 != "quick" && $2 != "full") die("SET quick or full")
    if (!($3 in eyes)) die("an eye defined above (" $3 ")")
    if ($4 != 1 && $4 != 2) die("INCISIONS 1 or 2")
    if (!num($5) || $5 <= 0 || $5 > 0.9) die("DEPTH in (0, 0.9]")
    if (!num($6)) die("DIAMETER in mm")
    for (i = 7; i <= NF; i++) if (!num($i) || $i <= 0 || $i > 180 || int($i) != $i)
        die("ARCS: whole degrees in (0, 180]")
    print; next }
$1 == "band" { if (NF != 3 || !num($2) || !num($3) || $2 >= $3) die("band LOW HIGH (D)")
               print; next }
{ die("base, age_rule, eye, run or band") }
' "$spec" > "$tmp/records"
base=$(awk '$1 == "base" { print $2 }' "$tmp/records")
[ -n "$base" ] || { echo "$spec:1: expected a base SCENE line" >&2; exit 2; }
case $base in /*) ;; *) base=$specdir/$base ;; esac
[ -f "$base" ] || { echo "$spec: base scene $base not found" >&2; exit 2; }

# 2. Scenes. Each eye: name, K -> radii, axis, CCT, the incision rings its runs use (one per
# diameter, as deep as its deepest run), and its cornea's moduli times the stiffness factor.
mkdir -p "$tmp/scenes" "$tmp/plans"
awk -v T="$tmp" -v BASE="$base" '
$1 == "age_rule" { age0 = $2; slope = $3 }
$1 == "eye"  { ne++; en[ne] = $2; ks[$2] = $3; kf[$2] = $4; ax[$2] = $5; cct[$2] = $6
               age[$2] = $7; stf[$2] = ($8 == "-") ? 1 + slope * ($7 - age0) / 10 : $8 }
$1 == "run"  { k = $3 SUBSEP $6; if (!(k in dep) || $5 > dep[k]) dep[k] = $5
               if (!(k in seen)) { seen[k] = 1; nd[$3]++; dia[$3, nd[$3]] = $6 } }
END {
    for (i = 1; i <= ne; i++) scene(en[i])
}
function indent(s) { match(s, /^ */); return RLENGTH }
function scene(e,    f, line, blk, key, ind, skip, j, val, n, head, tail, c, out) {
    f = T "/scenes/" e ".yaml"
    printf "# scene of eye %s of the nomogram study (written by gen.sh from %s):\n", e, BASE > f
    printf "# K %s / %s D, steep axis %s deg, age %s y, cornea stiffness x %.4f\n",
           ks[e], kf[e], ax[e], age[e], stf[e] > f
    blk = ""; skip = -1; nmod = 0
    while ((getline line < BASE) > 0) {
        ind = indent(line)
        if (skip >= 0) { if (line ~ /^ *$/ || ind > skip || line ~ /^ *- /) continue; skip = -1 }
        if (ind == 0 && line ~ /^[a-z_]+:/) { blk = line; sub(/:.*/, "", blk) }
        if (ind == 0 && line ~ /^name:/) { print "name: " e > f; continue }
        key = line; sub(/^ */, "", key); sub(/:.*/, "", key)
        if (blk == "eye" && ind > 0) {
            val = ""
            if (key == "anterior_radius_steep") val = sprintf("%.4f mm", 337.5 / ks[e])
            if (key == "anterior_radius_flat")  val = sprintf("%.4f mm", 337.5 / kf[e])
            if (key == "steep_axis") val = ax[e] " deg"
            if (key == "central_thickness" && cct[e] != "-") val = cct[e] " um"
            if (val != "") { printf "%" ind "s%s: %s   # (study)\n", "", key, val > f; continue }
            if (key == "incision_rings") {
                printf "%" ind "s%s:   # (study) one ring per incision diameter\n", "", key > f
                for (j = 1; j <= nd[e]; j++)
                    printf "%" ind "s  - {name: incision-ring-%d, diameter: %s mm, depth_fraction: %s}\n",
                           "", j, dia[e, j], dep[e, dia[e, j]] > f
                skip = ind; continue
            }
        }
        if (blk == "materials" && ind > 0 && (key == "cornea" || (incornea && ind > cind))) {
            if (key == "cornea") { incornea = 1; cind = ind }
            head = line; tail = ""
            if ((c = index(line, "#")) > 0) { head = substr(line, 1, c - 1); tail = substr(line, c) }
            out = ""
            while (match(head, /[0-9]+(\.[0-9]+)?([eE][-+]?[0-9]+)? *(MPa|kPa|GPa|Pa)/)) {
                n = substr(head, RSTART, RLENGTH); val = n; sub(/ *[A-Za-z]+$/, "", val)
                sub(/^[0-9.eE+-]+/, "", n)
                out = out substr(head, 1, RSTART - 1) sprintf("%.6g", val * stf[e]) n
                head = substr(head, RSTART + RLENGTH); nmod++
            }
            print out head tail > f; continue
        } else if (blk != "materials" || ind <= cind) incornea = 0
        print line > f
    }
    close(BASE); close(f)
    if (nmod == 0 && stf[e] != 1) {
        printf "gen.sh: no modulus found in the cornea material of %s\n", BASE > "/dev/stderr"
        exit 1
    }
}' "$tmp/records"

# 3. Plans, run metadata and the make include.
awk -v T="$tmp" '
function gcd(a, b) { while (b) { t = a % b; a = b; b = t }; return a }
$1 == "eye" { ks[$2] = $3; kf[$2] = $4; ax[$2] = $5; age[$2] = $7; stf[$2] = $8 }
$1 == "age_rule" { age0 = $2; slope = $3 }
$1 == "run" {
    e = $3; n = $4; depth = $5; diam = $6
    run = sprintf("%s-n%d-d%s-D%s", e, n, depth, diam)
    if (run in runset) { printf "gen.sh: run %s given twice\n", run > "/dev/stderr"; exit 2 }
    runset[run] = 1
    mx = 0; g = 0; arcs = ""
    for (i = 7; i <= NF; i++) { if ($i > mx) mx = $i; g = gcd(g, $i); arcs = arcs (i > 7 ? "," : "") $i }
    if (n == 2 && mx > 180) { printf "gen.sh: paired arcs of at most 180 deg\n" > "/dev/stderr"; exit 2 }
    f = T "/plans/" run ".yaml"
    printf "# plan of run %s of the nomogram study (written by gen.sh): arcs %s deg,\n", run, arcs > f
    printf "# opened from the centre out %d deg a step, so every listed arc is a step of it\n", g > f
    printf "name: %s\nscene: ../scenes/%s.yaml\nincisions:\n", run, e > f
    printf "  - meridian: %s deg\n    arc: %d deg\n    depth_fraction: %s\n", ax[e], mx, depth > f
    printf "    position: {diameter: %s mm}\n    paired: %s\n    direction: centre-out\n",
           diam, n == 2 ? "true" : "false" > f
    printf "progression: {degrees_per_step: %d deg}\n", g > f
    printf "target: {magnitude: %.2f D, axis: %s deg}\n", ks[e] - kf[e], ax[e] > f
    close(f)
    s = (stf[e] == "-") ? 1 + slope * (age[e] - age0) / 10 : stf[e]
    f = T "/plans/" run ".meta"
    print "run\teye\tk_steep_D\tk_flat_D\taxis_deg\tage_y\tstiffness\tincisions\tdepth\tdiameter_mm\tstep_deg\tarcs" > f
    printf "%s\t%s\t%s\t%s\t%s\t%s\t%.4f\t%d\t%s\t%s\t%d\t%s\n", run, e, ks[e], kf[e], ax[e],
           age[e], s, n, depth, diam, g, arcs > f
    close(f)
    runs[$2] = runs[$2] " " run; eyes[$2] = eyes[$2] " " e; alle[e] = 1
    deps = deps sprintf("$(OUT)/runs/%s/curvature.tsv: $(OUT)/eyes/%s.msh $(OUT)/plans/%s.yaml\n", run, e, run)
}
END {
    f = T "/study.mk"
    print "# written by gen.sh from the study spec; do not edit" > f
    # full = quick + full lines
    printf "RUNS_quick :=%s\nRUNS_full :=%s%s\n", runs["quick"], runs["quick"], runs["full"] > f
    printf "EYES_quick := $(sort%s)\nEYES_full := $(sort%s%s)\n", eyes["quick"], eyes["quick"], eyes["full"] > f
    printf "%s", deps > f
    for (e in alle) printf "$(OUT)/eyes/%s.msh: $(OUT)/scenes/%s.yaml\n", e, e > f
}' "$tmp/records"
awk '$1 == "band" { print $2 "\t" $3 }' "$tmp/records" > "$tmp/bands.tsv"

# 4. Install what changed, atomically.
install_if_changed() { # SRC DST
    if ! cmp -s "$1" "$2"; then
        mkdir -p "$(dirname "$2")"
        cp "$1" "$2.tmp.$$" && mv -f "$2.tmp.$$" "$2"
    fi
}
for f in "$tmp"/scenes/*.yaml; do install_if_changed "$f" "$out/scenes/${f##*/}"; done
for f in "$tmp"/plans/*; do install_if_changed "$f" "$out/plans/${f##*/}"; done
install_if_changed "$tmp/bands.tsv" "$out/bands.tsv"
install_if_changed "$tmp/study.mk" "$out/study.mk"
touch "$out/study.mk"
