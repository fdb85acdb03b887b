/* test_predicates.c: the exact signs of orient3d, plane side and cylinder side on degenerate
 * and near-degenerate inputs, checked against an independent integer reference: every input
 * lies on a dyadic grid (multiples of 2^-S), so the determinant scaled by 2^(3S) is an integer,
 * summed here exactly in 256-bit two's complement. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "kt_test.h"
#include "predicates.h"

/* ---- 256-bit two's complement integers, 8 limbs of 32 bits, least significant first ---- */
typedef struct big {
    uint32_t w[8];
} big;

/* |x| of an int64 as a big magnitude, with its sign. */
static big big_from(int64_t x, int *neg)
{
    big r;
    memset(&r, 0, sizeof r);
    *neg = x < 0;
    uint64_t m = x < 0 ? (uint64_t)0 - (uint64_t)x : (uint64_t)x;
    r.w[0] = (uint32_t)m;
    r.w[1] = (uint32_t)(m >> 32);
    return r;
}

/* Magnitude times a 64-bit magnitude (no overflow for the sizes used here). */
static big big_mul(big a, uint64_t m)
{
    big r;
    memset(&r, 0, sizeof r);
    uint32_t mw[2] = {(uint32_t)m, (uint32_t)(m >> 32)};
    for (int j = 0; j < 2; j++) {
        uint64_t carry = 0;
        for (int i = 0; i + j < 8; i++) {
            uint64_t t = (uint64_t)a.w[i] * mw[j] + r.w[i + j] + carry;
            r.w[i + j] = (uint32_t)t;
            carry = t >> 32;
        }
    }
    return r;
}

static void big_add(big *acc, big a)
{
    uint64_t carry = 0;
    for (int i = 0; i < 8; i++) {
        uint64_t t = (uint64_t)acc->w[i] + a.w[i] + carry;
        acc->w[i] = (uint32_t)t;
        carry = t >> 32;
    }
}

static big big_neg(big a)
{
    big r;
    for (int i = 0; i < 8; i++) r.w[i] = ~a.w[i];
    big one;
    memset(&one, 0, sizeof one);
    one.w[0] = 1;
    big_add(&r, one);
    return r;
}

static int big_sign(big a)
{
    if (a.w[7] & 0x80000000u) return -1;
    for (int i = 0; i < 8; i++)
        if (a.w[i]) return 1;
    return 0;
}

/* acc += s * x * y * z (s = +1 or -1). */
static void big_add_prod3(big *acc, int s, int64_t x, int64_t y, int64_t z)
{
    int nx, ny, nz;
    big p = big_from(x, &nx);
    big py = big_from(y, &ny), pz = big_from(z, &nz);
    p = big_mul(p, (uint64_t)py.w[0] | (uint64_t)py.w[1] << 32);
    p = big_mul(p, (uint64_t)pz.w[0] | (uint64_t)pz.w[1] << 32);
    if ((s < 0) ^ nx ^ ny ^ nz) p = big_neg(p);
    big_add(acc, p);
}

/* x * 2^S as an int64; the test fails loudly if x is not on that grid. */
static int64_t grid(double x, int S)
{
    double y = ldexp(x, S);
    int64_t n = (int64_t)y;
    if ((double)n != y || fabs(y) >= 0x1p62) {
        fprintf(stderr, "%.17g is not on the grid 2^-%d\n", x, S);
        exit(1);
    }
    return n;
}

/* The exact sign of det[b-a, c-a, d-a] for points on the grid 2^-S. */
static int ref_orient3d(const double *a, const double *b, const double *c, const double *d, int S)
{
    int64_t u[3], v[3], w[3];
    for (int i = 0; i < 3; i++) {
        u[i] = grid(b[i], S) - grid(a[i], S);
        v[i] = grid(c[i], S) - grid(a[i], S);
        w[i] = grid(d[i], S) - grid(a[i], S);
    }
    big acc;
    memset(&acc, 0, sizeof acc);
    for (int i = 0; i < 3; i++) {
        int j = (i + 1) % 3, k = (i + 2) % 3;
        big_add_prod3(&acc, 1, u[i], v[j], w[k]);
        big_add_prod3(&acc, -1, u[i], v[k], w[j]);
    }
    return big_sign(acc);
}

/* The naive double-precision sign, to show a case really defeats plain floating point. */
static int naive_orient3d(const double *a, const double *b, const double *c, const double *d)
{
    double u[3], v[3], w[3];
    for (int i = 0; i < 3; i++) u[i] = b[i] - a[i], v[i] = c[i] - a[i], w[i] = d[i] - a[i];
    double det = u[0] * (v[1] * w[2] - v[2] * w[1]) + u[1] * (v[2] * w[0] - v[0] * w[2]) +
                 u[2] * (v[0] * w[1] - v[1] * w[0]);
    return (det > 0) - (det < 0);
}

static uint64_t rng = 88172645463325252ull;
static uint64_t next_u64(void)
{
    rng ^= rng << 13;
    rng ^= rng >> 7;
    rng ^= rng << 17;
    return rng;
}
/* A uniform integer in [-2^(bits-1), 2^(bits-1)). */
static int64_t next_int(int bits) { return (int64_t)(next_u64() >> (64 - bits)) - ((int64_t)1 << (bits - 1)); }

/* The classic near-degenerate family (after Kettner et al.'s orient2d examples): a point
 * a = (0.5 + i u, 0.5 + j u, 0.5 + k u), u = 2^-53, against the plane through (12,12,12),
 * (24,24,24) and (1,3,2) far away. */
static void test_classic(void)
{
    const double u = 0x1p-53;
    double b[3] = {12, 12, 12}, c[3] = {24, 24, 24}, d[3] = {1, 3, 2};
    int agree = 0, total = 0, naive_wrong = 0, zeros = 0;
    kt_pred_stats st = {0, 0};
    for (int i = 0; i < 16; i++)
        for (int j = 0; j < 16; j++)
            for (int k = 0; k < 4; k++) {
                double a[3] = {0.5 + i * u, 0.5 + j * u, 0.5 + k * u};
                int want = ref_orient3d(a, b, c, d, 53);
                int got = kt_pred_orient3d_counted(a, b, c, d, &st);
                agree += got == want;
                naive_wrong += naive_orient3d(a, b, c, d) != want;
                zeros += want == 0;
                total++;
            }
    CHECK(agree == total, "classic family: %d of %d signs agree with the exact reference", agree, total);
    /* the family is only worth testing if plain doubles get it wrong and it has exact zeros */
    CHECK(naive_wrong > 0, "plain double precision got every sign right: the family is too easy");
    CHECK(zeros > 0, "no exactly coplanar point in the family");
    CHECK(st.calls == total && st.exact > 0, "calls %ld, exact fallbacks %ld", st.calls, st.exact);
}

/* Exactly coplanar points whose rounded determinant is not zero, and one grid step off. */
static void test_coplanar_grid(void)
{
    const int S = 40;
    int agree = 0, total = 0, zero_ok = 0, nzero = 0, off_ok = 0;
    kt_pred_stats st = {0, 0};
    for (int t = 0; t < 2000; t++) {
        int64_t A[3], U[3], V[3], D[3];
        for (int i = 0; i < 3; i++) {
            A[i] = next_int(36);
            U[i] = 8 * next_int(33);
            V[i] = 8 * next_int(33);
        }
        /* d = a + (3/8) u - (5/8) v: exactly in the plane a, b, c */
        for (int i = 0; i < 3; i++) D[i] = A[i] + U[i] / 8 * 3 - V[i] / 8 * 5;
        double a[3], b[3], c[3], d[3];
        for (int i = 0; i < 3; i++) {
            a[i] = ldexp((double)A[i], -S);
            b[i] = ldexp((double)(A[i] + U[i]), -S);
            c[i] = ldexp((double)(A[i] + V[i]), -S);
            d[i] = ldexp((double)D[i], -S);
        }
        int s0 = kt_pred_orient3d_counted(a, b, c, d, &st);
        zero_ok += s0 == 0 && ref_orient3d(a, b, c, d, S) == 0;
        nzero++;
        /* one grid step off the plane along a random axis */
        int ax = (int)(next_u64() % 3);
        double step = next_u64() & 1 ? 0x1p-40 : -0x1p-40;
        d[ax] += step;
        int want = ref_orient3d(a, b, c, d, S);
        int got = kt_pred_orient3d(a, b, c, d);
        agree += got == want;
        off_ok += want != 0;
        total++;
    }
    CHECK(zero_ok == nzero, "exactly coplanar: %d of %d gave 0", zero_ok, nzero);
    CHECK(agree == total, "one step off the plane: %d of %d agree", agree, total);
    CHECK(off_ok > total / 2, "the step left the plane in only %d of %d cases", off_ok, total);
    CHECK(st.exact == st.calls, "coplanar inputs must all take the exact path: %ld of %ld", st.exact, st.calls);
}

/* Random points on the grid 2^-53 in (-1, 1): every sign equals the reference. */
static void test_random(void)
{
    int agree = 0;
    kt_pred_stats st = {0, 0};
    for (int t = 0; t < 5000; t++) {
        double p[4][3];
        for (int v = 0; v < 4; v++)
            for (int i = 0; i < 3; i++) p[v][i] = ldexp((double)next_int(53), -53);
        agree += kt_pred_orient3d_counted(p[0], p[1], p[2], p[3], &st) ==
                 ref_orient3d(p[0], p[1], p[2], p[3], 53);
    }
    CHECK(agree == 5000, "random: %d of 5000 agree", agree);
    /* well-separated random points are decided by the filter almost always */
    CHECK(st.exact < 50, "random inputs took the exact path %ld times of %ld", st.exact, st.calls);
    /* a unit tet: positive, filter only */
    double o[3] = {0, 0, 0}, x[3] = {1, 0, 0}, y[3] = {0, 1, 0}, z[3] = {0, 0, 1};
    kt_pred_stats s1 = {0, 0};
    CHECK(kt_pred_orient3d_counted(o, x, y, z, &s1) == 1 && s1.exact == 0, "unit tet");
    CHECK(kt_pred_orient3d(o, y, x, z) == -1, "mirrored unit tet");
    CHECK(kt_pred_orient3d(o, x, x, z) == 0 && kt_pred_orient3d(o, o, o, o) == 0, "repeated points");
}

/* Parity of a permutation of 0..3. */
static int parity(const int *p)
{
    int inv = 0;
    for (int i = 0; i < 4; i++)
        for (int j = i + 1; j < 4; j++) inv += p[i] > p[j];
    return inv & 1;
}

/* All 24 orderings of near-degenerate tets: an odd permutation flips the sign, an even one
 * keeps it, and a zero stays zero. */
static void test_permutations(void)
{
    const double u = 0x1p-53;
    int bad = 0, tried = 0;
    for (int t = 0; t < 64; t++) {
        double P[4][3] = {{0.5 + (t % 8) * u, 0.5 + (t / 8) * u, 0.5}, {12, 12, 12}, {24, 24, 24}, {1, 3, 2}};
        int s0 = kt_pred_orient3d(P[0], P[1], P[2], P[3]);
        int perm[24][4], np = 0;
        for (int a = 0; a < 4; a++)
            for (int b = 0; b < 4; b++)
                for (int c = 0; c < 4; c++)
                    for (int d = 0; d < 4; d++)
                        if (a != b && a != c && a != d && b != c && b != d && c != d) {
                            int q[4] = {a, b, c, d};
                            memcpy(perm[np++], q, sizeof q);
                        }
        for (int k = 0; k < np; k++) {
            const int *q = perm[k];
            int s = kt_pred_orient3d(P[q[0]], P[q[1]], P[q[2]], P[q[3]]);
            int want = parity(q) ? -s0 : s0;
            bad += s != want;
            tried++;
        }
    }
    CHECK(bad == 0 && tried == 64 * 24, "%d of %d permutations broke the sign rule", bad, tried);
}

/* Plane side: sign of n . (sum x_j - k p), n = (na, nb, 1) small integers, points and p on
 * the grid 2^-52 about an offset of 1 (which cancels exactly). */
static void test_plane_side(void)
{
    const double u = 0x1p-52;
    /* hand cases: rounding of the sum hides 2^-53 */
    double n[3] = {1, 0, 0}, p0[3] = {0, 0, 0};
    double x1[3] = {1, 0, 0}, x2[3] = {0x1p-53, 0, 0}, x3[3] = {-1, 0, 0}, x4[3] = {-0x1p-53, 0, 0};
    const double *xs[4] = {x1, x2, x3, x4};
    CHECK(kt_pred_plane_side(p0, n, xs, 3) == 1, "1 + 2^-53 - 1 is positive");
    CHECK(kt_pred_plane_side(p0, n, xs, 4) == 0, "1 + 2^-53 - 1 - 2^-53 is zero");
    const double *ys[3] = {x1, x4, x3};
    CHECK(kt_pred_plane_side(p0, n, ys, 3) == -1, "1 - 2^-53 - 1 is negative");
    int zero_ok = 0, off_ok = 0, total = 0;
    for (int t = 0; t < 2000; t++) {
        int k = 1 + (int)(next_u64() % 10);
        int64_t na = next_int(4), nb = next_int(4);
        int64_t X[10][3], P[3];
        for (int i = 0; i < 3; i++) P[i] = next_int(44);
        for (int j = 0; j < k; j++)
            for (int i = 0; i < 3; i++) X[j][i] = next_int(44);
        /* the last point's z puts the centroid on the plane: n . (sum X - k P) = 0 */
        int64_t rest = na * (-k * P[0]) + nb * (-k * P[1]) - k * P[2];
        for (int j = 0; j < k; j++) {
            rest += na * X[j][0] + nb * X[j][1];
            if (j < k - 1) rest += X[j][2];
        }
        X[k - 1][2] = -rest;
        double xd[10][3], pd[3], nd[3] = {(double)na, (double)nb, 1.0};
        const double *xp[10];
        for (int i = 0; i < 3; i++) pd[i] = 1.0 + (double)P[i] * u;
        for (int j = 0; j < k; j++) {
            for (int i = 0; i < 3; i++) xd[j][i] = 1.0 + (double)X[j][i] * u;
            xp[j] = xd[j];
        }
        int s0 = kt_pred_plane_side(pd, nd, xp, k);
        double step = next_u64() & 1 ? u : -u;
        xd[k - 1][2] += step; /* n_z = 1: the value moves by exactly step */
        int s1 = kt_pred_plane_side(pd, nd, xp, k);
        zero_ok += s0 == 0;
        off_ok += s1 == (step > 0 ? 1 : -1);
        total++;
    }
    CHECK(zero_ok == total, "centroid on the plane: %d of %d gave 0", zero_ok, total);
    CHECK(off_ok == total, "centroid one grid step off: %d of %d right", off_ok, total);
}

static void test_cylinder_side(void)
{
    double on[3] = {3, 4, 7}, out[3] = {3, 4 + 0x1p-50, 0}, in[3] = {3, 4 - 0x1p-50, 0};
    const double *x[3] = {on, out, in};
    CHECK(kt_pred_cylinder_side(5, &x[0], 1) == 0, "(3,4) on r = 5");
    CHECK(kt_pred_cylinder_side(5, &x[1], 1) == 1, "(3, 4 + 2^-50) outside r = 5");
    CHECK(kt_pred_cylinder_side(5, &x[2], 1) == -1, "(3, 4 - 2^-50) inside r = 5");
    /* r = 0.1 (not a dyadic number): r*r rounds, yet (0.1, 0) is exactly on */
    double r = 0.1, p[3] = {0.1, 0, 0}, pu[3] = {nextafter(0.1, 1), 0, 0}, pd[3] = {nextafter(0.1, 0), 0, 0};
    const double *y[3] = {p, pu, pd};
    CHECK(kt_pred_cylinder_side(r, &y[0], 1) == 0, "(0.1, 0) on r = 0.1");
    CHECK(kt_pred_cylinder_side(r, &y[1], 1) == 1, "one ulp beyond 0.1");
    CHECK(kt_pred_cylinder_side(r, &y[2], 1) == -1, "one ulp inside 0.1");
    /* a centroid of far points: (2^30, 0) and (-2^30 + 1, 0) average to 0.5 exactly */
    double f1[3] = {0x1p30, 0, 0}, f2[3] = {-0x1p30 + 1, 0, 0}, f3[3] = {0x1p30 + 0x1p-22, 0, 0};
    const double *z1[2] = {f1, f2}, *z2[2] = {f3, f2};
    CHECK(kt_pred_cylinder_side(0.5, z1, 2) == 0, "centroid 0.5 on r = 0.5");
    CHECK(kt_pred_cylinder_side(0.5, z2, 2) == 1, "centroid 0.5 + 2^-23 outside r = 0.5");
    CHECK(kt_pred_cylinder_side(0.5 + 0x1p-22, z2, 2) == -1, "centroid 0.5 + 2^-23 inside r = 0.5 + 2^-22");
    /* centroid of three points (1.5, 2, *): on r = 2.5 */
    double a[3] = {4.5, 0, 0}, b[3] = {0, 6, 0}, c[3] = {0, 0, 0};
    const double *w[3] = {a, b, c};
    CHECK(kt_pred_cylinder_side(2.5, w, 3) == 0, "centroid (1.5, 2) on r = 2.5");
    CHECK(kt_pred_cylinder_side(nextafter(2.5, 3), w, 3) == -1, "inside a radius one ulp larger");
    CHECK(kt_pred_cylinder_side(nextafter(2.5, 2), w, 3) == 1, "outside a radius one ulp smaller");
}

int main(void)
{
    test_classic();
    test_coplanar_grid();
    test_random();
    test_permutations();
    test_plane_side();
    test_cylinder_side();
    return kt_test_done("test_predicates");
}
