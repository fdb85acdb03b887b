#!/usr/bin/env bash
# lri-sensitivity.sh [--scene BASE] BUILD OUT [VARIANT...]: the paired 60-degree LRI
# (plans/lri-paired-60.yaml) on variants of the eye scene BASE (default plans/eye.yaml), one
# uncertain parameter moved to an end of its literature range at a time (docs/physics.md, One
# parameter at a time). Each variant is a sed edit of the scene (V below) and, for the blade-depth
# variants, of the plan (P below); the table (scripts/lri-table.sh rows) goes to
# OUT/sensitivity.tsv with the variant's name first.
# The variants incision_0.14mm, incision_0.10mm, incision_0.07mm (named explicitly) refine the
# mesh at the incision ring: the convergence series. The variants depth_500um, depth_550um,
# depth_600um (named explicitly) set the blade depth in micrometres, ring and cut alike, instead
# of the default 90% of the local thickness (587 um at the default eye's 10.5 mm zone, whose
# pachymetry is 652 um): the depth series (docs/physics.md). --scene runs the same variants on
# another base, e.g. a scene with a healed wound (every sed must still change it).
set -euo pipefail
BASE=plans/eye.yaml
if [ "${1:-}" = --scene ]; then BASE=$2; shift 2; fi
B=$1 OUT=$2
shift 2
declare -A V=(
  [defaults]=''
  # the moduli (keratome-scene(5), "Rate: which moduli a slowly opening wound sees"): E_inplane
  # extrapolated to a day (1.3) and at 10 kHz (4.0); G_transverse by the ex vivo torsion route
  # (2.7), at 30 days (6.9) and 1 hour (12.8), the former default (47) and 10 kHz (94)
  [E_inplane_1.3MPa]='s/E_inplane: 2.0 MPa/E_inplane: 1.3 MPa/g'
  [E_inplane_4.0MPa]='s/E_inplane: 2.0 MPa/E_inplane: 4.0 MPa/g'
  [G_transverse_2.7kPa]='s/G_transverse: 9.5 kPa/G_transverse: 2.7 kPa/g'
  [G_transverse_6.9kPa]='s/G_transverse: 9.5 kPa/G_transverse: 6.9 kPa/g'
  [G_transverse_12.8kPa]='s/G_transverse: 9.5 kPa/G_transverse: 12.8 kPa/g'
  [G_transverse_47kPa]='s/G_transverse: 9.5 kPa/G_transverse: 47 kPa/g'
  [G_transverse_94kPa]='s/G_transverse: 9.5 kPa/G_transverse: 94 kPa/g'
  # the cornea's transverse shear by depth third (Petsche 2012: 7.71 / 1.99 / 1.31 kPa, scaled
  # so that the layers in series keep 9.5 kPa: 34.1 / 8.8 / 5.8 kPa; keratome-scene(5))
  [G_transverse_profile_on]='s/^    G_transverse: 9.5 kPa /    G_transverse_profile: on\n&/'
  [limbal_density_1.46]='s/limbal_density: 1.91 /limbal_density: 1.46 /'
  [limbal_density_2.36]='s/limbal_density: 1.91 /limbal_density: 2.36 /'
  [limbal_band_1.0mm]='s/limbal_band: 1.5 mm/limbal_band: 1.0 mm/'
  [limbal_band_2.0mm]='s/limbal_band: 1.5 mm/limbal_band: 2.0 mm/'
  [nu_0.45]='s/nu: 0.49/nu: 0.45/g'
  [nu_0.499]='s/nu: 0.49/nu: 0.499/g'
  [IOP_10mmHg]='s/value: 15 mmHg/value: 10 mmHg/'
  [IOP_21mmHg]='s/value: 15 mmHg/value: 21 mmHg/'
  [sclera_E_1MPa]='s/sclera: {E: 3.0 MPa/sclera: {E: 1.0 MPa/'
  [sclera_E_10MPa]='s/sclera: {E: 3.0 MPa/sclera: {E: 10.0 MPa/'
  [extent_120deg]='s/extent: 150 deg/extent: 120 deg/'
  [extent_170deg]='s/extent: 150 deg/extent: 170 deg/'
  [no_prestress]='s/reference: prestressed/reference: unloaded/'
  # the convergence series (not in the default list): incision size field at the rings
  [incision_0.14mm]='s/^    incision: 0.2 mm /    incision: 0.14 mm /'
  [incision_0.10mm]='s/^    incision: 0.2 mm /    incision: 0.10 mm /'
  [incision_0.07mm]='s/^    incision: 0.2 mm /    incision: 0.07 mm /'
  # the depth series (not in the default list): the ring at a blade depth in micrometres
  [depth_500um]='s/^      depth_fraction: 0.9 /      depth: 500 um /'
  [depth_550um]='s/^      depth_fraction: 0.9 /      depth: 550 um /'
  [depth_600um]='s/^      depth_fraction: 0.9 /      depth: 600 um /'
)
# plan edits of the depth series: the cut as deep as its ring
declare -A P=(
  [depth_500um]='s/^    depth_fraction: 0.9 /    depth: 500 um /'
  [depth_550um]='s/^    depth_fraction: 0.9 /    depth: 550 um /'
  [depth_600um]='s/^    depth_fraction: 0.9 /    depth: 600 um /'
)
names=("$@")
[ ${#names[@]} -gt 0 ] || names=(defaults E_inplane_1.3MPa E_inplane_4.0MPa G_transverse_2.7kPa
    G_transverse_6.9kPa G_transverse_12.8kPa G_transverse_47kPa G_transverse_94kPa G_transverse_profile_on limbal_density_1.46 limbal_density_2.36 limbal_band_1.0mm limbal_band_2.0mm
    nu_0.45 nu_0.499 IOP_10mmHg IOP_21mmHg sclera_E_1MPa sclera_E_10MPa extent_120deg
    extent_170deg no_prestress)
mkdir -p "$OUT"
[ -f "$OUT/sensitivity.tsv" ] || printf 'variant\tplan\tarc\tpaired\tflattening_D\tsteepening_D\tcoupling_ratio\tdk_mean_D\tsia_D\tnodes\tseconds\n' > "$OUT/sensitivity.tsv"
for n in "${names[@]}"; do
    [ -n "${V[$n]+set}" ] || { echo "lri-sensitivity: no variant $n" >&2; exit 1; }
    mkdir -p "$OUT/$n"
    sed -e "${V[$n]:-}" "$BASE" > "$OUT/$n/eye.yaml"
    if [ -n "${V[$n]}" ] && cmp -s "$BASE" "$OUT/$n/eye.yaml"; then
        echo "lri-sensitivity: variant $n changed nothing in $BASE" >&2; exit 1
    fi
    plan=plans/lri-paired-60.yaml
    if [ -n "${P[$n]:-}" ]; then
        mkdir -p "$OUT/$n/plan"
        plan=$OUT/$n/plan/lri-paired-60.yaml  # not in $OUT/$n, where lri-table writes its copy
        sed -e "${P[$n]}" plans/lri-paired-60.yaml > "$plan"
        if cmp -s plans/lri-paired-60.yaml "$plan"; then
            echo "lri-sensitivity: variant $n changed nothing in plans/lri-paired-60.yaml" >&2; exit 1
        fi
    fi
    bash scripts/lri-table.sh "$B" "$OUT/$n/eye.yaml" "$OUT/$n" "$plan" |
        sed "s/^/$n\t/" | tee -a "$OUT/sensitivity.tsv"
done
