/* surffit.c: corneal surfaces and the thickness profile from Pentacam maps (surffit.h). */
#include "surffit.h"

#include <math.h>
#include <stdlib.h>

/* The map's measured cells within radius a of (cx, cy) as points (x, y, -value); *np of them. */
static double *cells(const kt_pentacam_map *m, double cx, double cy, double a, int *np, kt_err *e)
{
    double *xyz = kt_calloc((size_t)3 * m->n * m->n, sizeof(double), e);
    if (!xyz) return NULL;
    int k = 0;
    for (int j = 0; j < m->n; j++)
        for (int i = 0; i < m->n; i++) {
            double v = m->v[j * m->n + i], x = kt_pentacam_coord(i), y = kt_pentacam_coord(j);
            if (isnan(v) || hypot(x - cx, y - cy) > a) continue;
            xyz[3 * k] = x, xyz[3 * k + 1] = y, xyz[3 * k + 2] = -v;
            k++;
        }
    *np = k;
    return xyz;
}

int kt_surffit_elevation(const kt_pentacam_map *m, double zone_d, kt_surffit *out, kt_err *e)
{
    int np;
    /* Every cell out to the zone plus 1 mm: kt_curv_fit keeps those within the zone around
     * the apex it finds. */
    double *xyz = cells(m, 0, 0, zone_d / 2 + 1, &np, e);
    if (!xyz) return e->code;
    kt_fit f;
    int rc = kt_curv_fit(xyz, np, KT_FIT_TORIC, 2, zone_d, 0, 0, &f, NULL, 0, e);
    if (rc == KT_OK) {
        /* Principal curvatures of M = [m11 m12; m12 m22]: the steep one along angle th. */
        double mean = 0.5 * (f.m11 + f.m22), dev = hypot(0.5 * (f.m11 - f.m22), f.m12);
        double th = 0.5 * atan2(2 * f.m12, f.m11 - f.m22) * 180 / KT_CURV_PI;
        if (th < 0) th += 180;
        if (th >= 180) th -= 180;
        out->r_steep = 1 / (mean + dev), out->r_flat = 1 / (mean - dev);
        out->axis = th, out->conic = f.conic;
        out->ax = f.ax, out->ay = f.ay;
        out->rms = f.rms, out->npts = f.npts, out->zone = zone_d;
        out->max_resid = 0;
        for (int k = 0; k < np; k++) {
            double *q = xyz + 3 * k, z, zx, zy;
            if (hypot(q[0] - f.xc, q[1] - f.yc) > f.a) continue;
            kt_fit_eval(&f, q[0], q[1], &z, &zx, &zy);
            out->max_resid = fmax(out->max_resid, fabs(q[2] - z));
        }
        if (!(out->r_steep > 0 && out->r_flat > 0 && isfinite(out->r_flat)))
            rc = kt_fail(e, KT_ERUN, "the elevation fit gave no convex surface (curvatures %g and %g 1/mm)", mean + dev,
                         mean - dev);
    }
    free(xyz);
    return rc;
}

/* Solve the 3x3 system A x = b (Gaussian elimination, partial pivoting); -1 when singular. */
static int solve3(double A[3][3], double b[3], double x[3])
{
    for (int c = 0; c < 3; c++) {
        int p = c;
        for (int r = c + 1; r < 3; r++)
            if (fabs(A[r][c]) > fabs(A[p][c])) p = r;
        if (fabs(A[p][c]) < 1e-300) return -1;
        for (int k = 0; k < 3; k++) {
            double t = A[c][k];
            A[c][k] = A[p][k], A[p][k] = t;
        }
        double t = b[c];
        b[c] = b[p], b[p] = t;
        for (int r = c + 1; r < 3; r++) {
            double f = A[r][c] / A[c][c];
            for (int k = c; k < 3; k++) A[r][k] -= f * A[c][k];
            b[r] -= f * b[c];
        }
    }
    for (int r = 2; r >= 0; r--) {
        double s = b[r];
        for (int k = r + 1; k < 3; k++) s -= A[r][k] * x[k];
        x[r] = s / A[r][r];
    }
    return 0;
}

double kt_pachyfit_at(const kt_pachyfit *p, double r) { return p->t0 + p->t2 * r * r + p->t4 * r * r * r * r; }

int kt_surffit_pachymetry(const kt_pentacam_map *m, double cx, double cy, double r_max, kt_pachyfit *out, kt_err *e)
{
    int np;
    double *xyz = cells(m, cx, cy, r_max, &np, e);
    if (!xyz) return e->code;
    double A[3][3] = {{0}}, b[3] = {0}, x[3];
    for (int k = 0; k < np; k++) {
        double r2 = pow(xyz[3 * k] - cx, 2) + pow(xyz[3 * k + 1] - cy, 2), t = -xyz[3 * k + 2];
        double phi[3] = {1, r2, r2 * r2};
        for (int i = 0; i < 3; i++) {
            b[i] += phi[i] * t;
            for (int j = 0; j < 3; j++) A[i][j] += phi[i] * phi[j];
        }
    }
    int rc = KT_OK;
    if (np < 12 || solve3(A, b, x) != 0) {
        rc = kt_fail(e, KT_ERUN, "only %d pachymetry cells within %.2f mm of the apex: too few for the thickness profile",
                     np, r_max);
    } else {
        out->t0 = x[0], out->t2 = x[1], out->t4 = x[2];
        out->npts = np, out->r_max = r_max;
        double ss = 0, mx = 0;
        for (int k = 0; k < np; k++) {
            double r = hypot(xyz[3 * k] - cx, xyz[3 * k + 1] - cy), d = -xyz[3 * k + 2] - kt_pachyfit_at(out, r);
            ss += d * d, mx = fmax(mx, fabs(d));
        }
        out->rms = sqrt(ss / np), out->max_resid = mx;
    }
    free(xyz);
    return rc;
}
