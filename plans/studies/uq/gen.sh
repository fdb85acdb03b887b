#!/usr/bin/env bash
# gen.sh SPEC OUT SET [N]: the uncertainty study's inputs from its spec (study.spec, see there):
#   OUT/samples.tsv        the Latin hypercube of the set (lhs.sh; N rows, or the set's N): each
#                          quantity's deviation from the base scene (its unit) and its stratum u
#   OUT/scenes/NAME.yaml   one scene per eye: s000, s001, ... (the samples), nominal (the base
#                          scene as it is, on the set's mesh), and for the geometry target
#                          (make geometry) P_plus / P_minus for each quantity with a step H
#   OUT/plans/NAME-FAMILY.yaml  each family's plan on that eye (its depth moved for the depth
#                          quantity, its step and direction the spec's)
#   OUT/params.tsv         the quantities: name, dist, sd, h, unit, base value
#   OUT/study.mk           SAMPLES, GEOMETRY (the make targets' names), FAMILIES, STEP_DEG
# A file is replaced only when its content changes (make reruns only what changed), always
# atomically. A malformed spec line: "SPEC:LINE: expected ...", exit 2, nothing written.
set -euo pipefail
spec=$1 out=$2 set=$3 nover=${4:-}
here=$(cd "$(dirname "$0")" && pwd)
specdir=$(cd "$(dirname "$spec")" && pwd)
tmp=$(mktemp -d "${TMPDIR:-/tmp}/kt_uqgen_XXXXXX")
trap 'rm -rf "$tmp"' EXIT

awk -v F="$spec" '
function die(msg) { printf "%s:%d: expected %s\n", F, NR, msg > "/dev/stderr"; exit 2 }
function num(s)   { return s ~ /^[0-9]+(\.[0-9]*)?$/ }
{ sub(/#.*/, "") }
NF == 0 { next }
$1 == "base" { if (NF != 2) die("base FILE"); print; next }
$1 == "plan" { if (NF != 3 || $2 !~ /^[a-z0-9_]+$/) die("plan FAMILY FILE (FAMILY: a-z, 0-9, _)")
               if ($2 in fam) die("each family once (" $2 " again)"); fam[$2] = 1; print; next }
$1 == "direction" { if (NF != 2 || $2 !~ /^(cw|ccw|centre-out|center-out)$/) die("direction cw|ccw|centre-out"); print; next }
$1 == "step_deg" { if (NF != 2 || !num($2) || $2 <= 0 || int($2) != $2) die("step_deg DEG (whole degrees > 0)"); print; next }
$1 == "seed" { if (NF != 2 || $2 !~ /^[0-9]+$/ || length($2) > 9) die("seed S (a whole number, at most 9 digits)"); print; next }
$1 == "set" { if (NF != 4 || $2 !~ /^[a-z0-9_]+$/ || $3 !~ /^[1-9][0-9]*$/ || ($4 != "quick" && $4 != "default"))
                  die("set NAME N quick|default"); print; next }
$1 == "param" {
    if (NF != 6) die("param NAME DIST SD H UNIT")
    if ($2 !~ /^(E_inplane|G_transverse|iop|limbal_density|thickness|depth)$/)
        die("a quantity the study can move: E_inplane G_transverse iop limbal_density thickness depth (found " $2 ")")
    if ($3 != "normal" && $3 != "uniform") die("DIST normal or uniform")
    if (!num($4)) die("SD >= 0")
    if ($5 != "-" && (!num($5) || $5 <= 0)) die("H > 0 or -")
    if (($2 == "thickness" || $2 == "depth") && $5 == "-") die("a step H for " $2 " (it moves the mesh)")
    if ($2 in seen) die("each quantity once (" $2 " again)")
    seen[$2] = 1; print; next }
{ die("base, plan, step_deg, direction, set, seed or param") }
' "$spec" > "$tmp/records"
get() { awk -v k="$1" '$1 == k { print $2 }' "$tmp/records"; }
abspath() { case $1 in /*) echo "$1" ;; *) echo "$specdir/$1" ;; esac; }
base=$(abspath "$(get base)") step=$(get step_deg) seed=$(get seed) dir=$(get direction)
[ -f "$base" ] || { echo "$spec: base scene $base not found" >&2; exit 2; }
families=() plans=()
while read -r _ fam file; do
    families+=("$fam") plans+=("$(abspath "$file")")
    [ -f "${plans[-1]}" ] || { echo "$spec: plan $fam: ${plans[-1]} not found" >&2; exit 2; }
done < <(awk '$1 == "plan"' "$tmp/records")
[ ${#families[@]} -gt 0 ] || { echo "$spec: expected at least one plan FAMILY FILE line" >&2; exit 2; }
[ -n "$step" ] && [ -n "$seed" ] || { echo "$spec: expected step_deg and seed lines" >&2; exit 2; }
read -r n mesh < <(awk -v s="$set" '$1 == "set" && $2 == s { print $3, $4 }' "$tmp/records") ||
    { echo "$spec: no set $set (set NAME N MESH lines)" >&2; exit 2; }
[ -z "$nover" ] || n=$nover

# The base values (the scene's own), each found once at least.
base_of() { # PATTERN: the number after it, first match
    grep -m1 -oE "$1 *[0-9.]+" "$base" | grep -oE '[0-9.]+$' || { echo "gen.sh: $base: no '$1' line" >&2; exit 1; }
}
declare -A BASEV=(
  [E_inplane]=$(base_of 'E_inplane:') [G_transverse]=$(base_of 'G_transverse:')
  [iop]=$(base_of 'pressure: \{surface: [a-z]+, value:') [limbal_density]=$(base_of 'limbal_density:')
  [thickness]=$(base_of 'central_thickness:') [depth]=0
)
args=()
: > "$tmp/params.tsv"
printf 'param\tdist\tsd\th\tunit\tbase\n' > "$tmp/params.tsv"
while read -r _ name dist sd h unit; do
    args+=("$name:$dist:0:$sd")
    printf '%s\t%s\t%s\t%s\t%s\t%s\n' "$name" "$dist" "$sd" "$h" "$unit" "${BASEV[$name]}" >> "$tmp/params.tsv"
done < <(awk '$1 == "param"' "$tmp/records")
bash "$here/lhs.sh" "$n" "$seed" "${args[@]}" > "$tmp/samples.tsv"

# One eye: NAME then NAME=DELTA pairs -> scene and plan.
mkdir -p "$tmp/scenes" "$tmp/plans"
write_eye() { # NAME [PARAM DELTA]...
    local name=$1; shift
    awk -v LD0="${BASEV[limbal_density]}" -v T="$tmp" -v NAME="$name" -v BASE="$base" -v PLANS="${plans[*]}" \
        -v FAMS="${families[*]}" -v MESH="$mesh" -v STEP="$step" -v DIR="$dir" -v D="$*" '
    function bump(line, key, unit, delta,    pre, v, rest) {
        if (!match(line, key ": *[0-9.]+" (unit == "" ? "" : " *" unit))) return line
        pre = substr(line, 1, RSTART - 1); v = substr(line, RSTART, RLENGTH); rest = substr(line, RSTART + RLENGTH)
        match(v, /[0-9.]+/); hit[key]++
        if (delta + 0 == 0) return line  # unmoved: the base scene text as it is
        return pre substr(v, 1, RSTART - 1) sprintf("%.6g", substr(v, RSTART, RLENGTH) + delta) substr(v, RSTART + RLENGTH) rest
    }
    BEGIN {
        nd = split(D, d, " ")
        for (i = 1; i < nd; i += 2) dv[d[i]] = d[i + 1]
        if (LD0 + dv["limbal_density"] < 1 || LD0 + dv["limbal_density"] > 5) {
            printf "gen.sh: eye %s: limbal_density %+g leaves the scene range [1, 5] (keratome-scene(5)): use a bounded distribution\n",
                   NAME, dv["limbal_density"] > "/dev/stderr"; exit 2 }
        frac = 0.9 + dv["depth"] / 653
        if (frac > 0.97 || frac < 0.3) {
            printf "gen.sh: eye %s: depth %+g um gives depth_fraction %.3f, outside [0.3, 0.97]: lower the depth sd\n",
                   NAME, dv["depth"], frac > "/dev/stderr"; exit 2 }
        f = T "/scenes/" NAME ".yaml"
        printf "# scene of eye %s of the uncertainty study (written by gen.sh from %s): %s\n", NAME, BASE, D > f
        while ((getline line < BASE) > 0) {
            if (MESH == "quick") {
                sub(/^    optical_zone: [0-9.]* mm/, "    optical_zone: 0.8 mm", line)
                sub(/^    incision: [0-9.]* mm/, "    incision: 0.4 mm", line)
                sub(/^    cornea: [0-9.]* mm/, "    cornea: 1.0 mm", line)
                sub(/^    sclera: [0-9.]* mm/, "    sclera: 2.5 mm", line)
                if (line ~ /^    incision_floor:/) continue
            }
            line = bump(line, "E_inplane", "MPa", dv["E_inplane"])
            line = bump(line, "G_transverse", "kPa", dv["G_transverse"])
            if (line ~ /pressure: \{surface: [a-z]+, value:/) line = bump(line, "value", "mmHg", dv["iop"])
            line = bump(line, "limbal_density", "", dv["limbal_density"])
            line = bump(line, "central_thickness", "um", dv["thickness"])
            if (line ~ /^      depth_fraction:/) line = bump(line, "depth_fraction", "", frac - 0.9)
            print line > f
        }
        close(f)
        if (hit["E_inplane"] < 1 || hit["G_transverse"] < 1 || hit["value"] != 1 || hit["limbal_density"] != 1 ||
            hit["central_thickness"] != 1 || hit["depth_fraction"] < 1) {
            printf "gen.sh: %s: a field the study moves was not found (E_inplane %d, G_transverse %d, pressure %d, limbal_density %d, central_thickness %d, ring depth_fraction %d)\n",
                   BASE, hit["E_inplane"], hit["G_transverse"], hit["value"], hit["limbal_density"], hit["central_thickness"], hit["depth_fraction"] > "/dev/stderr"
            exit 1 }
        np = split(PLANS, pl, " "); split(FAMS, fm, " ")
        for (j = 1; j <= np; j++) {
            PLAN = pl[j]; f = T "/plans/" NAME "-" fm[j] ".yaml"; hit["depth_fraction"] = 0; hit["dir"] = 0
            printf "# plan %s of eye %s of the uncertainty study (written by gen.sh from %s)\n", fm[j], NAME, PLAN > f
            while ((getline line < PLAN) > 0) {
                if (line ~ /^scene:/) line = "scene: ../scenes/" NAME ".yaml"
                sub(/degrees_per_step: [0-9.]+ deg/, "degrees_per_step: " STEP " deg", line)
                if (DIR != "" && sub(/direction: [a-z-]+/, "direction: " DIR, line)) hit["dir"]++
                line = bump(line, "depth_fraction", "", frac - 0.9)
                print line > f
            }
            close(f)
            if (hit["depth_fraction"] != 1) { printf "gen.sh: %s: no depth_fraction line\n", PLAN > "/dev/stderr"; exit 1 }
            if (DIR != "" && hit["dir"] != 1) { printf "gen.sh: %s: no direction line to set to %s\n", PLAN, DIR > "/dev/stderr"; exit 1 }
        }
    }' || exit $?
}
names=()
while IFS=$'\t' read -r -a row; do
    [ "${row[0]}" = sample ] && { hdr=("${row[@]}"); continue; }
    name=$(printf 's%03d' "${row[0]}") pairs=()
    for ((i = 1; i < ${#row[@]}; i += 2)); do pairs+=("${hdr[$i]}" "${row[$i]}"); done
    write_eye "$name" "${pairs[@]}"
    names+=("$name")
done < "$tmp/samples.tsv"
write_eye nominal
# The nominal scene states the study's standard deviations (keratome-scene(5), UNCERTAINTY), so
# that augsolve --uncertainty and curvature's band use the sd the samples are drawn with; what
# the study does not sample (age_slope) is left out (sd 0).
{
    echo "uncertainty:"
    awk -F'\t' 'NR > 1 { printf "  %s: {sd: %s, distribution: %s}\n", $1, $3, $2 }' "$tmp/params.tsv"
    echo "  age_slope: {sd: 0}"
} >> "$tmp/scenes/nominal.yaml"
geo=()
while IFS=$'\t' read -r p _ _ h _ _; do
    [ "$p" = param ] || [ "$h" = - ] && continue
    write_eye "${p}_plus" "$p" "$h"; write_eye "${p}_minus" "$p" "-$h"
    geo+=("${p}_plus" "${p}_minus")
done < "$tmp/params.tsv"
{
    echo "# written by gen.sh from the study spec (set $set, $n samples); do not edit"
    echo "SAMPLES := ${names[*]}"
    echo "GEOMETRY := ${geo[*]}"
    echo "FAMILIES := ${families[*]}"
    echo "STEP_DEG := $step"
} > "$tmp/study.mk"

install_if_changed() { # SRC DST
    if ! cmp -s "$1" "$2"; then
        mkdir -p "$(dirname "$2")"
        cp "$1" "$2.tmp.$$" && mv -f "$2.tmp.$$" "$2"
    fi
}
for f in "$tmp"/scenes/*.yaml; do install_if_changed "$f" "$out/scenes/${f##*/}"; done
for f in "$tmp"/plans/*.yaml; do install_if_changed "$f" "$out/plans/${f##*/}"; done
for f in samples.tsv params.tsv study.mk; do install_if_changed "$tmp/$f" "$out/$f"; done
touch "$out/study.mk"
