/* curv_fit.c: surface fits for keratometry: Zernike sag expansion, biconic (toric) quadric,
 * best-fit sphere; their height, slope and axial power. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "curv.h"

#define NP KT_ZERN_NP

/* ---------------------------------------------------------------- dense least squares */

/* Solve min |A x - b| by Householder QR. A is m x n column-major (overwritten), b has m
 * entries (overwritten); x gets n. A column that is numerically dependent is KT_ERUN. */
static int lsq_solve(double *A, int m, int n, double *b, double *x, kt_err *e)
{
    if (m < n) return kt_fail(e, KT_ERUN, "least squares: %d equations for %d unknowns", m, n);
    double rmax = 0;
    for (int k = 0; k < n; k++) {
        double *ak = A + (size_t)k * m;
        double nrm = 0;
        for (int i = k; i < m; i++) nrm += ak[i] * ak[i];
        nrm = sqrt(nrm);
        if (nrm == 0) return kt_fail(e, KT_ERUN, "least squares: column %d is zero", k);
        double alpha = ak[k] > 0 ? -nrm : nrm;
        ak[k] -= alpha;     /* v = x - alpha e1, stored in place */
        double vv = 0;
        for (int i = k; i < m; i++) vv += ak[i] * ak[i];
        for (int j = k + 1; j < n; j++) {
            double *aj = A + (size_t)j * m, s = 0;
            for (int i = k; i < m; i++) s += ak[i] * aj[i];
            s *= 2 / vv;
            for (int i = k; i < m; i++) aj[i] -= s * ak[i];
        }
        double s = 0;
        for (int i = k; i < m; i++) s += ak[i] * b[i];
        s *= 2 / vv;
        for (int i = k; i < m; i++) b[i] -= s * ak[i];
        ak[k] = alpha;      /* R(k,k); the rest of v is not needed again */
        if (fabs(alpha) > rmax) rmax = fabs(alpha);
    }
    for (int k = n - 1; k >= 0; k--) {
        double rkk = A[(size_t)k * m + k];
        if (!(fabs(rkk) > 1e-13 * rmax)) /* NaN too */
            return kt_fail(e, KT_ERUN, "least squares: rank deficient (column %d)", k);
        double s = b[k];
        for (int j = k + 1; j < n; j++) s -= A[(size_t)j * m + k] * x[j];
        x[k] = s / rkk;
    }
    return KT_OK;
}

/* ---------------------------------------------------------------- Zernike polynomials */

/* The polynomials themselves (monomials, evaluation) are lib/core/zernike.h's. */

/* Indices of the points within radius a of (cx, cy). */
static int zone_points(const double *xyz, int n, double cx, double cy, double a, int *idx)
{
    int k = 0;
    for (int i = 0; i < n; i++) {
        double dx = xyz[3 * i] - cx, dy = xyz[3 * i + 1] - cy;
        if (dx * dx + dy * dy <= a * a) idx[k++] = i;
    }
    return k;
}

/* One Zernike least-squares fit on the zone centred at (f->xc, f->yc). */
static int zernike_once(const double *xyz, const int *idx, int np, kt_fit *f, const double *zmono,
                        kt_err *e)
{
    int nt = f->nterms;
    double *A = kt_calloc((size_t)np * nt, sizeof(double), e);
    double *b = kt_calloc(np, sizeof(double), e);
    if (!A || !b) {
        free(A), free(b);
        return e->code;
    }
    for (int p = 0; p < np; p++) {
        const double *q = xyz + 3 * idx[p];
        double u = (q[0] - f->xc) / f->a, v = (q[1] - f->yc) / f->a;
        for (int t = 0; t < nt; t++) A[(size_t)t * np + p] = kt_zern_poly_value(zmono + (size_t)t * NP * NP, f->order, u, v);
        b[p] = q[2];
    }
    int rc = lsq_solve(A, np, nt, b, f->zern, e);
    if (rc == KT_OK) {
        memset(f->poly, 0, sizeof f->poly);
        for (int t = 0; t < nt; t++)
            for (int i = 0; i < NP * NP; i++) f->poly[i] += f->zern[t] * zmono[(size_t)t * NP * NP + i];
    }
    free(A), free(b);
    return rc;
}

/* The apex of a Zernike fit: Newton on grad P = 0 from the centre, in unit-disk coordinates;
 * 0 when found inside the disk at a maximum (the cornea is convex towards +z). */
static int zernike_apex(const kt_fit *f, double *u, double *v)
{
    double x = 0, y = 0, d[6];
    for (int it = 0; it < 30; it++) {
        kt_zern_poly_eval(f->poly, f->order, x, y, d);
        double det = d[3] * d[5] - d[4] * d[4];
        if (!(d[3] < 0 && det > 0)) return -1;
        double sx = (d[5] * d[1] - d[4] * d[2]) / det, sy = (d[3] * d[2] - d[4] * d[1]) / det;
        x -= sx, y -= sy;
        if (x * x + y * y > 0.81) return -1;
        if (fabs(sx) + fabs(sy) < 1e-13) break;
    }
    *u = x, *v = y;
    return 0;
}

static int fit_zernike(const double *xyz, int n, int *idx, kt_fit *f, char *note, size_t nl,
                       kt_err *e)
{
    int order = f->order;
    double *zmono = NULL;
    int rc = KT_OK;
    for (int it = 0; it < 10; it++) {
        int np = zone_points(xyz, n, f->xc, f->yc, f->a, idx);
        if (np < 12)
            return kt_fail(e, KT_ERUN, "only %d surface points within the %.2f mm zone (at least 12 needed)",
                           np, 2 * f->a);
        while (order > 2 && np < 3 * (order + 1) * (order + 2) / 2) order--;
        if (order != f->order && note)
            snprintf(note, nl, "Zernike order lowered from %d to %d: %d points in the %.2f mm zone",
                     f->order, order, np, 2 * f->a);
        if (!zmono || order != f->order) {
            f->order = order;
            f->nterms = (order + 1) * (order + 2) / 2;
            free(zmono);
            zmono = kt_calloc((size_t)f->nterms * NP * NP, sizeof(double), e);
            if (!zmono) return e->code;
            for (int t = 0; t < f->nterms; t++) {
                int zn, zm;
                kt_zern_nm(t, &zn, &zm);
                kt_zern_mono(zn, zm, zmono + (size_t)t * NP * NP);
            }
        }
        f->npts = np;
        if ((rc = zernike_once(xyz, idx, np, f, zmono, e)) != KT_OK || f->kind == KT_FIT_ZERNIKE_AT) break;
        double u, v;
        if (zernike_apex(f, &u, &v) != 0) {
            f->ax = f->xc, f->ay = f->yc; /* no interior maximum: keep the axis at the centre */
            break;
        }
        f->ax = f->xc + f->a * u, f->ay = f->yc + f->a * v;
        if (hypot(f->ax - f->xc, f->ay - f->yc) < 1e-6) break;
        f->xc = f->ax, f->yc = f->ay;
    }
    free(zmono);
    return rc;
}

/* ---------------------------------------------------------------- biconic (toric) */

enum { TP_XC, TP_YC, TP_Z0, TP_M11, TP_M12, TP_M22, TP_CONIC, TP_N };

/* Sag s of the biconic at d = (dx, dy) and ds/ddx, ds/ddy; -1 outside its domain. */
static int toric_sag(const double *p, double dx, double dy, double *s, double *sx, double *sy)
{
    double g1 = p[TP_M11] * dx + p[TP_M12] * dy, g2 = p[TP_M12] * dx + p[TP_M22] * dy;
    double q1 = dx * g1 + dy * g2, q2 = g1 * g1 + g2 * g2, beta = 1 + p[TP_CONIC];
    double w2 = 1 - beta * q2;
    if (w2 <= 0) return -1;
    double w = sqrt(w2);
    *s = q1 / (1 + w);
    if (sx) {
        double ds_q1 = 1 / (1 + w), ds_q2 = q1 / ((1 + w) * (1 + w)) * beta / (2 * w);
        *sx = ds_q1 * 2 * g1 + ds_q2 * 2 * (g1 * p[TP_M11] + g2 * p[TP_M12]);
        *sy = ds_q1 * 2 * g2 + ds_q2 * 2 * (g1 * p[TP_M12] + g2 * p[TP_M22]);
    }
    return 0;
}

/* Residuals z_i - f(x_i, y_i); a point outside the biconic's domain is a huge residual. */
static double toric_resid(const double *p, const double *xyz, const int *idx, int np, double *r)
{
    double ss = 0;
    for (int i = 0; i < np; i++) {
        const double *q = xyz + 3 * idx[i];
        double s;
        if (toric_sag(p, q[0] - p[TP_XC], q[1] - p[TP_YC], &s, NULL, NULL) != 0) s = -1e3;
        r[i] = q[2] - (p[TP_Z0] - s);
        ss += r[i] * r[i];
    }
    return ss;
}

/* Levenberg-Marquardt on the biconic's 7 parameters: each step a QR solve of
 * [J; sqrt(lambda) D] dp = [-r; 0] with D the column norms of J (Marquardt scaling). */
static int toric_lm(double *p, const double *xyz, const int *idx, int np, kt_err *e)
{
    static const double hstep[TP_N] = {1e-6, 1e-6, 1e-6, 1e-7, 1e-7, 1e-7, 1e-5};
    int m = np + TP_N, rc = KT_OK;
    double *r = kt_calloc(np, sizeof(double), e), *rt = kt_calloc(np, sizeof(double), e);
    double *J = kt_calloc((size_t)np * TP_N, sizeof(double), e);
    double *A = kt_calloc((size_t)m * TP_N, sizeof(double), e), *b = kt_calloc(m, sizeof(double), e);
    if (!r || !rt || !J || !A || !b) {
        rc = e->code;
        goto done;
    }
    double cost = toric_resid(p, xyz, idx, np, r), lambda = 1e-3;
    for (int it = 0; it < 200; it++) {
        for (int k = 0; k < TP_N; k++) {
            double pk = p[k];
            p[k] = pk + hstep[k];
            toric_resid(p, xyz, idx, np, rt);
            for (int i = 0; i < np; i++) J[(size_t)k * np + i] = rt[i];
            p[k] = pk - hstep[k];
            toric_resid(p, xyz, idx, np, rt);
            for (int i = 0; i < np; i++) J[(size_t)k * np + i] = (J[(size_t)k * np + i] - rt[i]) / (2 * hstep[k]);
            p[k] = pk;
        }
        int accepted = 0;
        while (!accepted && lambda < 1e12) {
            memset(A, 0, sizeof(double) * (size_t)m * TP_N);
            for (int k = 0; k < TP_N; k++) {
                double d = 0;
                for (int i = 0; i < np; i++) {
                    A[(size_t)k * m + i] = J[(size_t)k * np + i];
                    d += J[(size_t)k * np + i] * J[(size_t)k * np + i];
                }
                A[(size_t)k * m + np + k] = sqrt(lambda * d) + 1e-300;
            }
            for (int i = 0; i < np; i++) b[i] = -r[i];
            for (int i = np; i < m; i++) b[i] = 0;
            double dp[TP_N], pn[TP_N];
            kt_err e2 = {0};
            if (lsq_solve(A, m, TP_N, b, dp, &e2) != KT_OK) {
                lambda *= 10;
                continue;
            }
            for (int k = 0; k < TP_N; k++) pn[k] = p[k] + dp[k];
            double cn = toric_resid(pn, xyz, idx, np, rt);
            if (cn < cost) {
                double dec = cost - cn;
                memcpy(p, pn, sizeof pn);
                memcpy(r, rt, sizeof(double) * np);
                cost = cn;
                lambda = fmax(lambda / 10, 1e-12);
                accepted = 1;
                if (dec <= 1e-14 * cost + 1e-30) goto done;
            } else {
                lambda *= 10;
            }
        }
        if (!accepted) break; /* no descent left: converged to round-off */
    }
done:
    free(r), free(rt), free(J), free(A), free(b);
    return rc;
}

static int fit_toric(const double *xyz, int n, int *idx, kt_fit *f, kt_err *e)
{
    /* Start from a second-order Zernike fit: its apex, height and curvature tensor. */
    kt_fit z = *f;
    z.kind = KT_FIT_ZERNIKE;
    z.order = 2;
    int rc = fit_zernike(xyz, n, idx, &z, NULL, 0, e);
    if (rc != KT_OK) return rc;
    double d[6];
    kt_zern_poly_eval(z.poly, z.order, (z.ax - z.xc) / z.a, (z.ay - z.yc) / z.a, d);
    double p[TP_N] = {z.ax, z.ay, d[0], -d[3] / (z.a * z.a), -d[4] / (z.a * z.a), -d[5] / (z.a * z.a), 0};
    for (int it = 0; it < 6; it++) {
        int np = zone_points(xyz, n, p[TP_XC], p[TP_YC], f->a, idx);
        if (np < 12)
            return kt_fail(e, KT_ERUN, "only %d surface points within the %.2f mm zone (at least 12 needed)",
                           np, 2 * f->a);
        double c0[2] = {p[TP_XC], p[TP_YC]};
        if ((rc = toric_lm(p, xyz, idx, np, e)) != KT_OK) return rc;
        f->npts = np;
        if (hypot(p[TP_XC] - c0[0], p[TP_YC] - c0[1]) < 1e-6) break;
    }
    f->xc = f->ax = p[TP_XC];
    f->yc = f->ay = p[TP_YC];
    f->z0 = p[TP_Z0];
    f->m11 = p[TP_M11], f->m12 = p[TP_M12], f->m22 = p[TP_M22], f->conic = p[TP_CONIC];
    return KT_OK;
}

/* ---------------------------------------------------------------- public */

void kt_fit_eval(const kt_fit *f, double x, double y, double *z, double *zx, double *zy)
{
    if (f->kind == KT_FIT_TORIC) {
        double p[TP_N] = {f->xc, f->yc, f->z0, f->m11, f->m12, f->m22, f->conic}, s, sx, sy;
        if (toric_sag(p, x - f->xc, y - f->yc, &s, &sx, &sy) != 0) {
            *z = *zx = *zy = NAN;
            return;
        }
        *z = f->z0 - s, *zx = -sx, *zy = -sy;
        return;
    }
    double d[6];
    kt_zern_poly_eval(f->poly, f->order, (x - f->xc) / f->a, (y - f->yc) / f->a, d);
    *z = d[0], *zx = d[1] / f->a, *zy = d[2] / f->a;
}

/* Mean normal curvature at the apex (1/mm): -(z_xx + z_yy) / 2 there. */
static double apex_mean_curvature(const kt_fit *f)
{
    if (f->kind == KT_FIT_TORIC) return 0.5 * (f->m11 + f->m22);
    double d[6];
    kt_zern_poly_eval(f->poly, f->order, (f->ax - f->xc) / f->a, (f->ay - f->yc) / f->a, d);
    return -0.5 * (d[3] + d[5]) / (f->a * f->a);
}

double kt_fit_axial_power(const kt_fit *f, double x, double y)
{
    double r = hypot(x - f->ax, y - f->ay);
    if (r < 1e-9) return KT_CURV_N_KERATO * apex_mean_curvature(f);
    double z, zx, zy;
    kt_fit_eval(f, x, y, &z, &zx, &zy);
    double g = hypot(zx, zy);
    /* sin of the normal's angle to the axis: |grad| / sqrt(1 + |grad|^2); R_axial = r / sin */
    return KT_CURV_N_KERATO * (g / sqrt(1 + g * g)) / r;
}

int kt_curv_fit(const double *xyz, int n, int kind, int order, double zone_d, double cx,
                double cy, kt_fit *f, char *note, size_t note_len, kt_err *e)
{
    memset(f, 0, sizeof *f);
    if (note && note_len) note[0] = '\0';
    if (!(zone_d > 0)) return kt_fail(e, KT_EINPUT, "zone diameter %g mm: expected > 0", zone_d);
    if (order < 2 || order > KT_ZERN_ORDER_MAX)
        return kt_fail(e, KT_EINPUT, "Zernike order %d: expected 2..%d", order, KT_ZERN_ORDER_MAX);
    f->kind = kind;
    f->a = zone_d / 2;
    f->xc = f->ax = cx, f->yc = f->ay = cy;
    f->order = order;
    int *idx = kt_calloc(n, sizeof(int), e);
    if (!idx) return e->code;
    int rc = kind == KT_FIT_TORIC ? fit_toric(xyz, n, idx, f, e) : fit_zernike(xyz, n, idx, f, note, note_len, e);
    if (rc == KT_OK) {
        double zx, zy, ss = 0;
        kt_fit_eval(f, f->ax, f->ay, &f->az, &zx, &zy);
        int np = zone_points(xyz, n, f->xc, f->yc, f->a, idx);
        for (int i = 0; i < np; i++) {
            const double *q = xyz + 3 * idx[i];
            double z;
            kt_fit_eval(f, q[0], q[1], &z, &zx, &zy);
            ss += (q[2] - z) * (q[2] - z);
        }
        f->npts = np;
        f->rms = np ? sqrt(ss / np) : NAN;
        if (!isfinite(f->rms) || !isfinite(f->az)) /* the iterations' stops pass NaN by */
            rc = kt_fail(e, KT_ERUN, "the %s fit over the %.2f mm zone is not finite (rms %g): "
                         "NaN or overflowed surface coordinates?", kind == KT_FIT_TORIC ? "toric" :
                         "Zernike", zone_d, f->rms);
    }
    free(idx);
    return rc;
}

int kt_curv_sphere_fit(const double *xyz, int n, double c[3], double *radius, kt_err *e)
{
    if (n < 4) return kt_fail(e, KT_ERUN, "best-fit sphere: %d points (at least 4 needed)", n);
    double g[3] = {0, 0, 0};
    for (int i = 0; i < n; i++)
        for (int k = 0; k < 3; k++) g[k] += xyz[3 * i + k] / n;
    double *A = kt_calloc((size_t)n * 4, sizeof(double), e), *b = kt_calloc(n, sizeof(double), e);
    int rc = e->code;
    if (A && b) {
        /* |p - g|^2 = 2 (p - g).c' + d, c' the centre relative to the centroid (conditioning) */
        for (int i = 0; i < n; i++) {
            double q[3], qq = 0;
            for (int k = 0; k < 3; k++) q[k] = xyz[3 * i + k] - g[k], qq += q[k] * q[k];
            for (int k = 0; k < 3; k++) A[(size_t)k * n + i] = 2 * q[k];
            A[(size_t)3 * n + i] = 1;
            b[i] = qq;
        }
        double x[4];
        rc = lsq_solve(A, n, 4, b, x, e);
        if (rc == KT_OK) {
            for (int k = 0; k < 3; k++) c[k] = g[k] + x[k];
            *radius = sqrt(x[3] + x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
        }
    }
    free(A), free(b);
    return rc;
}
