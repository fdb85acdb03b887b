#!/usr/bin/env bash
# atr-wtr.sh BUILD OUT [--coarse] [--healed]: the against-the-rule / with-the-rule ratio of paired 60 deg
# arcs on the default eye (docs/physics.md, "The oval cornea"), with and without the main
# cataract incision, on the oval cornea and, for comparison, the round one.
#   WTR: plans/eye.yaml as it is (1.5 D, steep meridian 90 deg), arcs centred on 90 and 270 deg;
#   ATR: the same eye with steep_axis 180 deg, arcs centred on 0 and 180 deg;
#   oval: white_to_white 11.7 x 10.6 mm (plans/eye.yaml); round: 11.7 x 11.7 mm;
#   main: a 2.4 mm temporal clear-corneal tunnel of a right eye (180 deg), keratome-plan(5)
#   TUNNELS, cut first (its 4 steps), then the arcs as plans/lri-paired-60.yaml cuts them.
# Each of the four scenes is meshed once with the main incision's site refined (as lri-plan
# meshes a patient with a simulated main incision: eye.mesh_size.site; here the site lri-plan
# derives for the default eye's temporal 2.4 mm tunnel, 4.92 mm from the axis, its radius 1.52
# mm rounded up to 1.6 mm), so a scene's runs with and without the tunnel share one mesh.
# Writes OUT/table.tsv, one row per run:
#   cornea orientation main sia_D arcs_sia_D main_sia_D flattening_D steepening_D nodes cpu_s
# sia_D: the whole cut's SIA against step 0 (curvature.tsv sia_D at the last step); arcs_sia_D:
# the arcs' own, the vector difference (double angle) of the keratometric astigmatism after the
# last step and after the tunnel; main_sia_D: the tunnel's alone (0 without it). cpu_s: user +
# system CPU seconds of cutplan, augsolve and curvature. Then one ratio row per cornea and main:
#   ratio cornea main sia_ATR/sia_WTR arcs_ATR/arcs_WTR
# --healed: the wound healed with the scene's identified defaults (default: immediate).
# A run cutplan refuses is a row "refused: <its message>" and no ratio. Runs already solved in OUT
# (RUN/curvature.tsv) are not solved again.
# --coarse: the coarse eye of the pipeline tests (tests/lib/coarse-eye.sh 0.8 0.4 1.0 2.5) for a
# quick look. Heavy runs one at a time; each default-eye run about 60 s of CPU and 2.3 GB.
set -euo pipefail
B=$(cd "$1" && pwd) OUT=$2
coarse=0 healed=0
for a in "${@:3}"; do
    case $a in --coarse) coarse=1 ;; --healed) healed=1 ;; *) echo "atr-wtr.sh: $a: expected --coarse or --healed" >&2; exit 2 ;; esac
done
cd "$(dirname "$0")/.."
ROOT=$PWD
mkdir -p "$OUT"
OUT=$(cd "$OUT" && pwd)
if [ $coarse = 1 ]; then bash tests/lib/coarse-eye.sh 0.8 0.4 1.0 2.5 "$OUT/base.yaml"
else cp plans/eye.yaml "$OUT/base.yaml"; fi
# --healed: the identified healed wound (keratome-scene(5), WOUND: its defaults, at the pivot age 60 y)
[ $healed = 1 ] && printf 'wound: {state: healed}\n' >> "$OUT/base.yaml"
grep -q '^    horizontal: 11.7 mm' "$OUT/base.yaml" && grep -q '^    vertical: 10.6 mm' "$OUT/base.yaml" &&
    grep -q '^  steep_axis: 90 deg' "$OUT/base.yaml" && grep -q '^    sclera: ' "$OUT/base.yaml" ||
    { echo "atr-wtr: plans/eye.yaml's white_to_white, steep_axis or mesh_size.sclera lines changed" >&2; exit 1; }

scene() { # CORNEA ORIENT -> OUT/CORNEA-ORIENT.yaml
    local v=10.6 ax=90
    [ "$1" = round ] && v=11.7
    [ "$2" = atr ] && ax=180
    sed -e "s|^    vertical: 10.6 mm|    vertical: $v mm|" -e "s|^  steep_axis: 90 deg|  steep_axis: $ax deg|" \
        -e "s|^\(    sclera: [0-9.]* mm\)|\1\n    site: {meridian: 180 deg, distance: 4.92 mm, radius: 1.6 mm}|" \
        "$OUT/base.yaml" > "$OUT/$1-$2.yaml"
}

plan() { # SCENE ORIENT MAIN -> stdout
    local m=90
    [ "$2" = atr ] && m=0
    printf 'name: paired-60-%s-%s\nscene: %s\n' "$2" "$3" "$1"
    [ "$3" = main ] && printf 'tunnels:\n  - {meridian: 180 deg, width: 2.4 mm}\n'
    printf 'incisions:\n  - {meridian: %s deg, arc: 60 deg, depth_fraction: 0.9, position: {surface: incision-ring-1}, paired: true, direction: cw}\n' "$m"
    printf 'progression: {degrees_per_step: 5 deg}\n'
}

printf 'cornea\torientation\tmain\tsia_D\tarcs_sia_D\tmain_sia_D\tflattening_D\tsteepening_D\tnodes\tcpu_s\n' > "$OUT/table.tsv"
for cornea in oval round; do
    for orient in wtr atr; do
        name=$cornea-$orient
        scene $cornea $orient
        [ -f "$OUT/$name.msh" ] || "$B/mesh-prep" -q "$OUT/$name.yaml" -o "$OUT/$name.msh" > "$OUT/$name-prep.txt"
        nodes=$(awk '/^\$Nodes/ { getline; print $2; exit }' "$OUT/$name.msh")
        for main in none main; do
            run=$OUT/$name-$main
            plan "$OUT/$name.yaml" $orient $main > "$run.yaml"
            if [ ! -f "$run/curvature.tsv" ] && ! /usr/bin/time -f '%U %S' -o "$run.time" bash -c '
                "$1/cutplan" -q "$2.yaml" "$3" --mesh-out "$2.msh" -o "$2.edits" &&
                "$1/augsolve" -q "$2.msh" "$2.edits" -o "$2" && "$1/curvature" -q --no-png --no-report "$2" > /dev/null' \
                _ "$B" "$run" "$OUT/$name.msh" 2> "$run.err"; then
                # a refused cut (the ATR eye's temporal arc crosses the temporal tunnel): a row
                # that says so, and the next run
                printf '%s\t%s\t%s\trefused: %s\n' $cornea $orient $main "$(head -c 300 "$run.err")" | tee -a "$OUT/table.tsv"
                continue
            fi
            tun=0
            [ $main = main ] && tun=$(grep -c '^step .*(tunnel ' "$run.edits" || true)
            awk -F'\t' -v c=$cornea -v o=$orient -v m=$main -v tun="$tun" -v nn="$nodes" -v cpu="$(awk '{ print $1 + $2 }' "$run.time")" '
                function vx(r) { split(r, f, "\t"); return f[k["cyl_D"]] * cos(2 * f[k["axis_steep_deg"]] * 3.141592653589793 / 180) }
                function vy(r) { split(r, f, "\t"); return f[k["cyl_D"]] * sin(2 * f[k["axis_steep_deg"]] * 3.141592653589793 / 180) }
                NR == 1 { for (i = 1; i <= NF; i++) k[$i] = i; next }
                { row[$k["step"]] = $0; last = $k["step"] }
                END { split(row[last], f, "\t");
                      sia = f[k["sia_D"]]; fl = f[k["flattening_D"]]; st = f[k["steepening_D"]]
                      arcs = sqrt((vx(row[last]) - vx(row[tun]))^2 + (vy(row[last]) - vy(row[tun]))^2)
                      mn = sqrt((vx(row[tun]) - vx(row[0]))^2 + (vy(row[tun]) - vy(row[0]))^2)
                      printf "%s\t%s\t%s\t%.3f\t%.3f\t%.3f\t%.3f\t%.3f\t%s\t%.0f\n", c, o, m, sia, arcs, mn, fl, st, nn, cpu }' \
                "$run/curvature.tsv" | tee -a "$OUT/table.tsv"
        done
    done
done
awk -F'\t' 'NR > 1 && $4 !~ /^refused/ { s[$1 "\t" $3 "\t" $2] = $4; a[$1 "\t" $3 "\t" $2] = $5; key[$1 "\t" $3] = 1 }
    END { for (q in key) if ((q "\tatr") in s && (q "\twtr") in s)
              printf "ratio\t%s\t%.2f\t%.2f\n", q, s[q "\tatr"] / s[q "\twtr"], a[q "\tatr"] / a[q "\twtr"] }' \
    "$OUT/table.tsv" | sort | tee "$OUT/ratios.tsv"
