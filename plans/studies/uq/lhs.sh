#!/usr/bin/env bash
# lhs.sh N SEED NAME:DIST:MEAN:SD... : a seeded Latin hypercube sample of N points, one column per
# quantity, on stdout (tab-separated, header `sample` then for each quantity NAME and u_NAME).
#   Each dimension's unit interval is cut into N equal strata; each stratum is used by exactly
#   one sample (a random permutation per dimension), at a uniform random position inside it:
#   u = (stratum + U) / N. The value is MEAN + SD z(u) for DIST normal (z: the standard normal
#   quantile), MEAN + SD sqrt(3) (2u - 1) for uniform (a uniform law of that sd).
#   The generator is the 32-bit linear congruential one of Numerical Recipes (x <- 1664525 x +
#   1013904223 mod 2^32, exact in awk's doubles), seeded with SEED, so the same N and SEED give
#   the same sample with any awk (mawk or gawk) on any machine. The normal quantile is P. J.
#   Acklam's rational approximation (2003; relative error below 1.2e-9), written here.
# Bad arguments: one line, exit 2.
set -euo pipefail
[ $# -ge 3 ] || { echo "usage: lhs.sh N SEED NAME:DIST:MEAN:SD..." >&2; exit 2; }
n=$1 seed=$2; shift 2
[[ $n =~ ^[1-9][0-9]{0,5}$ ]] || { echo "lhs.sh: N $n: expected a whole number 1 to 999999" >&2; exit 2; }
[[ $seed =~ ^[0-9]{1,9}$ ]] || { echo "lhs.sh: SEED $seed: expected a whole number 0 to 999999999" >&2; exit 2; }
for q in "$@"; do
    [[ $q =~ ^[A-Za-z_][A-Za-z0-9_]*:(normal|uniform):-?[0-9.]+([eE][-+]?[0-9]+)?:[0-9.]+([eE][-+]?[0-9]+)?$ ]] ||
        { echo "lhs.sh: $q: expected NAME:normal|uniform:MEAN:SD (SD >= 0)" >&2; exit 2; }
done
awk -v N="$n" -v SEED="$seed" -v Q="$*" '
function rnd() { X = (1664525 * X + 1013904223) % 4294967296; return X / 4294967296 }
# uniform in (0, 1), never 0
function unif(  u) { do u = rnd(); while (u == 0); return u }
# the standard normal quantile: Acklam (2003) rational approximation
function qnorm(p,   q, r, x) {
    if (p < 0.02425) {
        q = sqrt(-2 * log(p))
        x = (((((c1 * q + c2) * q + c3) * q + c4) * q + c5) * q + c6) / ((((d1 * q + d2) * q + d3) * q + d4) * q + 1)
    } else if (p <= 1 - 0.02425) {
        q = p - 0.5; r = q * q
        x = (((((a1 * r + a2) * r + a3) * r + a4) * r + a5) * r + a6) * q / (((((b1 * r + b2) * r + b3) * r + b4) * r + b5) * r + 1)
    } else {
        q = sqrt(-2 * log(1 - p))
        x = -(((((c1 * q + c2) * q + c3) * q + c4) * q + c5) * q + c6) / ((((d1 * q + d2) * q + d3) * q + d4) * q + 1)
    }
    return x
}
BEGIN {
    a1 = -3.969683028665376e+01; a2 = 2.209460984245205e+02; a3 = -2.759285104469687e+02
    a4 = 1.383577518672690e+02; a5 = -3.066479806614716e+01; a6 = 2.506628277459239e+00
    b1 = -5.447609879822406e+01; b2 = 1.615858368580409e+02; b3 = -1.556989798598866e+02
    b4 = 6.680131188771972e+01; b5 = -1.328068155288572e+01
    c1 = -7.784894002430293e-03; c2 = -3.223964580411365e-01; c3 = -2.400758277161838e+00
    c4 = -2.549732539343734e+00; c5 = 4.374664141464968e+00; c6 = 2.938163982698783e+00
    d1 = 7.784695709041462e-03; d2 = 3.224671290700398e-01; d3 = 2.445134137142996e+00
    d4 = 3.754408661907416e+00
    X = SEED % 4294967296
    for (k = 0; k < 8; k++) rnd()  # let the seed mix in
    nq = split(Q, q, " ")
    for (d = 1; d <= nq; d++) {
        split(q[d], f, ":"); name[d] = f[1]; dist[d] = f[2]; mean[d] = f[3]; sd[d] = f[4]
        for (i = 0; i < N; i++) perm[i] = i
        for (i = N - 1; i > 0; i--) { j = int(rnd() * (i + 1)); t = perm[i]; perm[i] = perm[j]; perm[j] = t }
        for (i = 0; i < N; i++) {
            u = (perm[i] + unif()) / N
            uu[i, d] = u
            val[i, d] = dist[d] == "normal" ? mean[d] + sd[d] * qnorm(u) : mean[d] + sd[d] * sqrt(3) * (2 * u - 1)
        }
    }
    printf "sample"
    for (d = 1; d <= nq; d++) printf "\t%s\tu_%s", name[d], name[d]
    printf "\n"
    for (i = 0; i < N; i++) {
        printf "%d", i
        for (d = 1; d <= nq; d++) printf "\t%.9g\t%.9f", val[i, d], uu[i, d]
        printf "\n"
    }
}'
