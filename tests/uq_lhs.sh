#!/usr/bin/env bash
# uq_lhs.sh BUILD_DIR: the uncertainty study's Latin hypercube sampler (plans/studies/uq/lhs.sh),
# read back by this script's own reader: every one of the N strata of every dimension holds
# exactly one sample (floor(N u) is a permutation of 0..N-1); each value is MEAN + SD z(u) for
# normal (z checked against an independent inverse of the normal CDF: erf by bisection) and
# MEAN + SD sqrt(3)(2u - 1) for uniform; the same seed gives the same bytes, another seed other
# samples; the sample mean and sd of a large normal hypercube are near MEAN and SD; bad
# arguments: one line, exit 2. Also gen.sh on the study's spec: the set's N eyes, the nominal
# eye and the geometry pairs, each scene the base one with only the sampled fields moved.
set -euo pipefail
cd "$(dirname "$0")/.."
L=plans/studies/uq/lhs.sh
tmp=$(mktemp -d /tmp/kt_lhs_XXXXXX)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "uq_lhs: FAILED: $*" >&2; exit 1; }

bash $L 64 7 a:normal:2:0.6 b:uniform:-1:3 c:normal:0:10 > "$tmp/a.tsv"
bash $L 64 7 a:normal:2:0.6 b:uniform:-1:3 c:normal:0:10 > "$tmp/b.tsv"
bash $L 64 8 a:normal:2:0.6 b:uniform:-1:3 c:normal:0:10 > "$tmp/c.tsv"
cmp "$tmp/a.tsv" "$tmp/b.tsv" || fail "the same seed gave two samples"
! cmp -s "$tmp/a.tsv" "$tmp/c.tsv" || fail "two seeds gave one sample"
bash $L 2000 1 z:normal:0:1 > "$tmp/big.tsv"
awk -F'\t' '
function erf_inv_check(u, z,   lo, hi, m, i) { # z against the normal CDF inverted by bisection
    lo = -10; hi = 10
    for (i = 0; i < 200; i++) { m = (lo + hi) / 2; if (cdf(m) < u) lo = m; else hi = m }
    return (lo + hi) / 2
}
function cdf(x,   t, s, k, term) { # Phi(x) by its Taylor series of erf (|x| <= 10 with enough terms)
    if (x < -8) return 0; if (x > 8) return 1
    s = 0; term = x / sqrt(2); k = 0
    # erf(y) = 2/sqrt(pi) sum (-1)^k y^(2k+1) / (k! (2k+1))
    y = x / sqrt(2); s = 0; p = y
    for (k = 0; k < 400; k++) { s += p / (2 * k + 1); p *= -y * y / (k + 1); if (p + 0 == 0) break }
    return 0.5 * (1 + 2 / sqrt(atan2(0, -1)) * s)
}
FNR == 1 { f++; next }
f <= 1 {
    n++
    ka = int(64 * $3); kb = int(64 * $5); kc = int(64 * $7)
    if (ha[ka]++ || hb[kb]++ || hc[kc]++ || ka > 63 || kb > 63 || kc > 63) { print "stratum hit twice or out of range at row " n; bad = 1 }
    if ($3 <= 0 || $3 >= 1) { print "u out of (0, 1)"; bad = 1 }
    zz = erf_inv_check($3)
    if (abs($2 - (2 + 0.6 * zz)) > 1e-6) { printf "normal value %s against %.9f (u %s)\n", $2, 2 + 0.6 * zz, $3; bad = 1 }
    if (abs($4 - (-1 + 3 * sqrt(3) * (2 * $5 - 1))) > 1e-6) { print "uniform value " $4; bad = 1 }
    zz = erf_inv_check($7)
    if (abs($6 - 10 * zz) > 1e-5 * (1 + abs(10 * zz))) { print "normal c " $6; bad = 1 }
    next
}
{ m++; s += $2; ss += $2 * $2 }
function abs(x) { return x < 0 ? -x : x }
END {
    if (n != 64) { print "rows " n; bad = 1 }
    mean = s / m; sd = sqrt((ss - m * mean * mean) / (m - 1))
    if (abs(mean) > 0.01 || abs(sd - 1) > 0.02) { printf "2000-point normal hypercube: mean %g, sd %g\n", mean, sd; bad = 1 }
    printf "uq_lhs: 64 strata x 3 once each; 2000 points: mean %.5f, sd %.5f\n", mean, sd
    exit bad
}' "$tmp/a.tsv" "$tmp/big.tsv" || fail "hypercube properties"

for args in "0 1 a:normal:0:1" "4 x a:normal:0:1" "4 1 a:lognormal:0:1" "4 1 a:normal:0:-1" "4 1"; do
    set +e
    # shellcheck disable=SC2086
    bash $L $args > "$tmp/o" 2> "$tmp/e"
    st=$?
    set -e
    [ $st -eq 2 ] && [ "$(wc -l < "$tmp/e")" -eq 1 ] && [ ! -s "$tmp/o" ] || fail "lhs.sh $args: exit $st, $(cat "$tmp/e")"
done

# gen.sh on the study's own spec, the ci set with N = 3
bash plans/studies/uq/gen.sh plans/studies/uq/study.spec "$tmp/g" ci 3
grep -qx "SAMPLES := s000 s001 s002" "$tmp/g/study.mk" || fail "study.mk: $(cat "$tmp/g/study.mk")"
# the fd pairs only: the material quantities come from augsolve --uncertainty (h "-" in the spec)
grep -qx "GEOMETRY := thickness_plus thickness_minus depth_plus depth_minus" "$tmp/g/study.mk" || fail "GEOMETRY: $(grep GEOMETRY "$tmp/g/study.mk")"
grep -qx "FAMILIES := single paired" "$tmp/g/study.mk" || fail "FAMILIES"
[ "$(wc -l < "$tmp/g/samples.tsv")" -eq 4 ] || fail "samples.tsv rows"
# the nominal eye: the base scene on the quick mesh, nothing else moved, plus the study's
# uncertainty section at its end (the first-order band's sds are the sampled ones)
awk '/^uncertainty:/ { u = 1 } u' "$tmp/g/scenes/nominal.yaml" > "$tmp/unc"
grep -qx '  E_inplane: {sd: 0.6, distribution: normal}' "$tmp/unc" &&
    grep -qx '  depth: {sd: 15, distribution: normal}' "$tmp/unc" &&
    grep -qx '  age_slope: {sd: 0}' "$tmp/unc" || fail "the nominal scene's uncertainty section: $(cat "$tmp/unc")"
diff <(awk '/^uncertainty:/ { exit } 1' "$tmp/g/scenes/nominal.yaml" | grep -v '^#' | grep -v -E '^    (optical_zone|incision|cornea|sclera):') \
     <(grep -v '^#' plans/eye.yaml | grep -v -E '^    (optical_zone|incision|incision_floor|cornea|sclera):') ||
    fail "the nominal scene differs from plans/eye.yaml beyond the mesh sizes"
# a sample: its E_inplane moved by the sampled deviation, in the cornea and the limbus
dE=$(awk -F'\t' 'NR == 2 { print $2 }' "$tmp/g/samples.tsv")
want=$(awk -v d="$dE" 'BEGIN { printf "%.6g", 2.0 + d }')
[ "$(grep -c "E_inplane: $want MPa" "$tmp/g/scenes/s000.yaml")" -eq 2 ] || fail "s000: E_inplane $want MPa not in cornea and limbus"
# the depth pair: +-H um over the 653 um local thickness, in the plan and the scene's ring
grep -q "depth_fraction: 0.915314" "$tmp/g/plans/depth_plus-paired.yaml" && grep -q "depth_fraction: 0.915314" "$tmp/g/plans/depth_plus-single.yaml" &&
    grep -q "depth_fraction: 0.884686" "$tmp/g/scenes/depth_minus.yaml" ||
    fail "depth_plus / depth_minus depth fractions"
echo "uq_lhs: ok"
