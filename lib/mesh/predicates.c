/* predicates.c: filtered exact geometric predicates.
 *
 * An expansion is an array of doubles, smallest magnitude first, whose components do not
 * overlap (each one's lowest set bit lies above the highest bit of the one below it), so its
 * exact value is the sum of the components and its sign is the sign of the last one. Sums and
 * products are made error-free with Knuth's two-sum and an fma-based two-product; results
 * are grown one scalar at a time with zero components dropped. Assumes no overflow and no
 * underflow in products (coordinates in mm make both impossible in practice). */
#include "predicates.h"

#include <math.h>

#define EPS (0.5 * 2.220446049250313e-16) /* unit round-off 2^-53 */

/* x + y = *s + *t exactly, |*t| <= ulp(*s)/2. */
static void two_sum(double x, double y, double *s, double *t)
{
    double a = x + y;
    double yv = a - x;
    double xv = a - yv;
    *t = (x - xv) + (y - yv);
    *s = a;
}

/* x * y = *p + *t exactly (fma rounds once, so the residual is exact). */
static void two_prod(double x, double y, double *p, double *t)
{
    *p = x * y;
    *t = fma(x, y, -*p);
}

/* h = e + b; h may not alias e; returns the length of h (at least 1). */
static int grow(const double *e, int n, double b, double *h)
{
    double q = b;
    int k = 0;
    for (int i = 0; i < n; i++) {
        double s, t;
        two_sum(q, e[i], &s, &t);
        if (t != 0.0) h[k++] = t;
        q = s;
    }
    if (q != 0.0 || k == 0) h[k++] = q;
    return k;
}

/* An accumulator: the running sum kept in one of two buffers, swapped on each growth. */
typedef struct acc {
    double buf[2][512];
    int cur, n;
} acc;

static void acc_init(acc *a)
{
    a->cur = 0;
    a->n = 1;
    a->buf[0][0] = 0.0;
}

static void acc_add(acc *a, double b)
{
    if (b == 0.0) return;
    a->n = grow(a->buf[a->cur], a->n, b, a->buf[1 - a->cur]);
    a->cur = 1 - a->cur;
}

/* Add the exact product x*y. */
static void acc_add_prod(acc *a, double x, double y)
{
    double p, t;
    two_prod(x, y, &p, &t);
    acc_add(a, t);
    acc_add(a, p);
}

static int acc_sign(const acc *a)
{
    double top = a->buf[a->cur][a->n - 1];
    return (top > 0.0) - (top < 0.0);
}

/* The exact product of two short expansions (at most 16 components each) added to a. */
static void acc_add_exp_prod(acc *a, const double *e, int n, const double *f, int m)
{
    for (int i = 0; i < n; i++)
        for (int j = 0; j < m; j++) acc_add_prod(a, e[i], f[j]);
}

/* The exact difference x - y as an expansion of one or two components. */
static int diff2(double x, double y, double *h)
{
    double s, t;
    two_sum(x, -y, &s, &t);
    int k = 0;
    if (t != 0.0) h[k++] = t;
    h[k++] = s;
    return k;
}

/* Exact product of two expansions of at most 2 components: at most 8 components. */
static int prod22(const double *e, int n, const double *f, int m, double *h)
{
    acc a;
    acc_init(&a);
    acc_add_exp_prod(&a, e, n, f, m);
    for (int i = 0; i < a.n; i++) h[i] = a.buf[a.cur][i];
    return a.n;
}

/* Exact sign of det[u, v, w] with u = b-a, v = c-a, w = d-a formed without rounding. */
static int orient3d_exact(const double *a, const double *b, const double *c, const double *d)
{
    double u[3][2], v[3][2], w[3][2];
    int nu[3], nv[3], nw[3];
    for (int i = 0; i < 3; i++) {
        nu[i] = diff2(b[i], a[i], u[i]);
        nv[i] = diff2(c[i], a[i], v[i]);
        nw[i] = diff2(d[i], a[i], w[i]);
    }
    acc total;
    acc *t = &total;
    acc_init(t);
    /* det = sum over cyclic (i,j,k) of u_i (v_j w_k - v_k w_j) */
    for (int i = 0; i < 3; i++) {
        int j = (i + 1) % 3, k = (i + 2) % 3;
        double p[9], q[9];
        int np = prod22(v[j], nv[j], w[k], nw[k], p);
        int nq = prod22(v[k], nv[k], w[j], nw[j], q);
        for (int r = 0; r < nq; r++) q[r] = -q[r];
        acc_add_exp_prod(t, u[i], nu[i], p, np);
        acc_add_exp_prod(t, u[i], nu[i], q, nq);
    }
    return acc_sign(t);
}

static int orient3d_filtered(const double *a, const double *b, const double *c, const double *d,
                             int *exact)
{
    double u[3], v[3], w[3];
    for (int i = 0; i < 3; i++) {
        u[i] = b[i] - a[i];
        v[i] = c[i] - a[i];
        w[i] = d[i] - a[i];
    }
    double m0 = v[1] * w[2] - v[2] * w[1];
    double m1 = v[2] * w[0] - v[0] * w[2];
    double m2 = v[0] * w[1] - v[1] * w[0];
    double det = u[0] * m0 + u[1] * m1 + u[2] * m2;
    double perm = fabs(u[0]) * (fabs(v[1] * w[2]) + fabs(v[2] * w[1])) +
                  fabs(u[1]) * (fabs(v[2] * w[0]) + fabs(v[0] * w[2])) +
                  fabs(u[2]) * (fabs(v[0] * w[1]) + fabs(v[1] * w[0]));
    /* three rounded differences, a product, a difference, a product and two sums: 8 eps */
    double bound = 10.0 * EPS * perm;
    *exact = 0;
    if (det > bound) return 1;
    if (-det > bound) return -1;
    if (perm == 0.0) return 0; /* every product is exactly zero */
    *exact = 1;
    return orient3d_exact(a, b, c, d);
}

int kt_pred_orient3d(const double *a, const double *b, const double *c, const double *d)
{
    int exact;
    return orient3d_filtered(a, b, c, d, &exact);
}

int kt_pred_orient3d_counted(const double *a, const double *b, const double *c, const double *d,
                             kt_pred_stats *st)
{
    int exact;
    int s = orient3d_filtered(a, b, c, d, &exact);
    st->calls++;
    st->exact += exact;
    return s;
}

int kt_pred_plane_side(const double *p, const double *n, const double *const *x, int k)
{
    double val = 0.0, mag = 0.0;
    for (int i = 0; i < 3; i++) {
        double s = 0.0, sa = 0.0;
        for (int j = 0; j < k; j++) {
            s += x[j][i];
            sa += fabs(x[j][i]);
        }
        val += n[i] * (s - k * p[i]);
        mag += fabs(n[i]) * (sa + k * fabs(p[i]));
    }
    double bound = 4.0 * (k + 4) * EPS * mag;
    if (val > bound) return 1;
    if (-val > bound) return -1;
    acc total;
    acc *t = &total;
    acc_init(t);
    for (int i = 0; i < 3; i++) {
        for (int j = 0; j < k; j++) acc_add_prod(t, n[i], x[j][i]);
        /* -k n_i p_i: the product as two components, each scaled exactly by -k */
        double pr, pt;
        two_prod(n[i], p[i], &pr, &pt);
        acc_add_prod(t, pt, (double)-k);
        acc_add_prod(t, pr, (double)-k);
    }
    return acc_sign(t);
}

/* Exact square of a sum of k doubles, added to t. */
static void add_square_of_sum(acc *t, const double *const *x, int k, int comp)
{
    acc s;
    acc_init(&s);
    for (int j = 0; j < k; j++) acc_add(&s, x[j][comp]);
    double e[64];
    int n = s.n;
    for (int i = 0; i < n; i++) e[i] = s.buf[s.cur][i];
    acc_add_exp_prod(t, e, n, e, n);
}

int kt_pred_cylinder_side(double r, const double *const *x, int k)
{
    double sx = 0.0, sy = 0.0, ax = 0.0, ay = 0.0;
    for (int j = 0; j < k; j++) {
        sx += x[j][0];
        sy += x[j][1];
        ax += fabs(x[j][0]);
        ay += fabs(x[j][1]);
    }
    double kr = k * r;
    double val = sx * sx + sy * sy - kr * kr;
    double bound = 4.0 * (k + 4) * EPS * (ax * ax + ay * ay + kr * kr);
    if (val > bound) return 1;
    if (-val > bound) return -1;
    acc total;
    acc *t = &total;
    acc_init(t);
    add_square_of_sum(t, x, k, 0);
    add_square_of_sum(t, x, k, 1);
    /* (k r)^2 = r^2 k^2: r*r as two components, each times k*k (an exact small integer) */
    double rr, rt;
    two_prod(r, r, &rr, &rt);
    acc_add_prod(t, rt, -(double)(k * k));
    acc_add_prod(t, rr, -(double)(k * k));
    return acc_sign(t);
}
