/* surffit.c: corneal surfaces and the thickness profile from Pentacam maps (surffit.h). */
#include "surffit.h"
#include "units.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "eye_geom.h"

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

/* Solve the n x n system A x = b in place (Gaussian elimination, partial pivoting, n <= 8);
 * -1 when singular. */
static int solve_n(int n, double A[8][8], double b[8], double x[8])
{
    for (int c = 0; c < n; c++) {
        int p = c;
        for (int r = c + 1; r < n; r++)
            if (fabs(A[r][c]) > fabs(A[p][c])) p = r;
        if (fabs(A[p][c]) < 1e-300) return -1;
        for (int k = 0; k < n; k++) {
            double t = A[c][k];
            A[c][k] = A[p][k], A[p][k] = t;
        }
        double t = b[c];
        b[c] = b[p], b[p] = t;
        for (int r = c + 1; r < n; r++) {
            double f = A[r][c] / A[c][c];
            for (int k = c; k < n; k++) A[r][k] -= f * A[c][k];
            b[r] -= f * b[c];
        }
    }
    for (int r = n - 1; r >= 0; r--) {
        double s = b[r];
        for (int k = r + 1; k < n; k++) s -= A[r][k] * x[k];
        x[r] = s / A[r][r];
    }
    return 0;
}

/* The fitted biconic's sag at (x, y) (mm, >= 0 towards the eye); NAN outside its domain. */
static double biconic_sag(const kt_surffit *f, double x, double y)
{
    double t = f->axis * KT_CURV_PI / 180, c = cos(t), sn = sin(t);
    double dx = x - f->ax, dy = y - f->ay, u = c * dx + sn * dy, v = -sn * dx + c * dy;
    double cs = 1 / f->r_steep, cf = 1 / f->r_flat;
    double q1 = cs * u * u + cf * v * v, q2 = cs * cs * u * u + cf * cf * v * v, w = 1 - (1 + f->conic) * q2;
    return w > 0 ? q1 / (1 + sqrt(w)) : NAN;
}

/* What one half-meridian adds to the fitted biconic's power: the fit's residual (cells minus
 * biconic) within the wedge around direction phi (deg), 0.3 ... 1.7 mm from the fitted apex,
 * least squares z = z0 + t r + c r^2 + b r^3 + d r^4; its axial power 337.5 (2c + 3b r + 4d r^2)
 * (small slopes; the tilt t is the residual's slope at the apex, where the biconic's is zero,
 * not power), averaged over r = 0.5 ... 1.5 mm (the 3 mm zone of a keratometer). */
static int half_power(const kt_pentacam_map *m, const kt_surffit *fit, double phi, double *k, int *np, kt_err *e)
{
    double A[8][8] = {{0}}, b[8] = {0}, x[8];
    int n = 0;
    for (int j = 0; j < m->n; j++)
        for (int i = 0; i < m->n; i++) {
            double v = m->v[j * m->n + i], gx = kt_pentacam_coord(i), gy = kt_pentacam_coord(j);
            double dx = gx - fit->ax, dy = gy - fit->ay, r = hypot(dx, dy);
            if (isnan(v) || r < 0.3 || r > 1.7) continue;
            double d = remainder(atan2(dy, dx) * 180 / KT_CURV_PI - phi, 360.0);
            if (fabs(d) > KT_SURFFIT_HALF_WEDGE) continue;
            double z = v - biconic_sag(fit, gx, gy);
            if (isnan(z)) continue;
            double p[5] = {1, r, r * r, r * r * r, r * r * r * r};
            for (int a = 0; a < 5; a++) {
                b[a] += p[a] * z;
                for (int c = 0; c < 5; c++) A[a][c] += p[a] * p[c];
            }
            n++;
        }
    if (n < 20 || solve_n(5, A, b, x) != 0)
        return kt_fail(e, KT_ERUN, "only %d elevation cells on the half-meridian at %.0f deg (0.3 ... 1.7 mm from the apex): "
                       "too few for its power", n, phi);
    double sum = 0;
    int ns = 0;
    for (double r = 0.5; r <= 1.5 + 1e-9; r += 0.05, ns++) sum += 2 * x[2] + 3 * x[3] * r + 4 * x[4] * r * r;
    *k = 337.5 * sum / ns;
    *np += n;
    return KT_OK;
}

int kt_surffit_halves(const kt_pentacam_map *m, const kt_surffit *fit, kt_halfmer *out, kt_err *e)
{
    double kf1, kf2;
    out->npts = 0;
    out->axis = fit->axis;
    if (half_power(m, fit, fit->axis, &out->k_a, &out->npts, e) || half_power(m, fit, fit->axis + 180, &out->k_b, &out->npts, e) ||
        half_power(m, fit, fit->axis + 90, &kf1, &out->npts, e) || half_power(m, fit, fit->axis + 270, &kf2, &out->npts, e))
        return e->code;
    double ks = KT_N_KERATO / fit->r_steep, kf = KT_N_KERATO / fit->r_flat;
    out->k_a += ks, out->k_b += ks;
    out->k_flat = kf + 0.5 * (kf1 + kf2);
    if (!(isfinite(out->k_a) && isfinite(out->k_b) && isfinite(out->k_flat)))
        return kt_fail(e, KT_ERUN, "the half-meridian powers are not finite");
    return KT_OK;
}

int kt_surffit_departure(const kt_pentacam_map *m, const kt_eye *eye, int posterior, int order, double a,
                         double taper, kt_eye_departure *d, double *rms, double *max, int *npts, kt_err *e)
{
    kt_eye_geom g;
    if (kt_eye_geom_init(eye, &g, e)) return e->code;
    int np;
    double *xyz = cells(m, 0, 0, a, &np, e);
    if (!xyz) return e->code;
    int k = 0;
    for (int i = 0; i < np; i++) {
        double *q = xyz + 3 * i, z = kt_eye_base_sag(&g, eye, posterior, q[0], q[1]) + q[2]; /* q[2] = -value */
        if (!isfinite(z)) continue;
        xyz[3 * k] = q[0], xyz[3 * k + 1] = q[1], xyz[3 * k + 2] = z;
        k++;
    }
    kt_fit f;
    int rc = kt_curv_fit(xyz, k, KT_FIT_ZERNIKE_AT, order, 2 * a, 0, 0, &f, NULL, 0, e);
    if (rc == KT_OK) {
        memset(d, 0, sizeof *d);
        d->conic = posterior ? 0 : eye->dep_ant.conic;
        d->order = f.order, d->radius = a, d->taper = taper;
        memcpy(d->coef, f.zern, sizeof(double) * (size_t)f.nterms);
        *rms = f.rms, *npts = f.npts, *max = 0;
        for (int i = 0; i < k; i++) {
            double z, zx, zy;
            kt_fit_eval(&f, xyz[3 * i], xyz[3 * i + 1], &z, &zx, &zy);
            *max = fmax(*max, fabs(xyz[3 * i + 2] - z));
        }
        /* The tilt (the map's decentration from the instrument's axis: a rigid turn of the
         * cornea that changes no curvature) is left out: the mesh keeps its apex on its axis. */
        d->coef[1] = d->coef[2] = 0;
        /* The posterior's radial profile is the one the pachymetry fixes (the thickness at the
         * centre and at the zone): its rotationally symmetric terms (m = 0) are left out. */
        for (int j = 0; posterior && j < f.nterms; j++) {
            int zn, zm;
            kt_zern_nm(j, &zn, &zm);
            if (zm == 0) d->coef[j] = 0;
        }
    }
    free(xyz);
    return rc;
}

/* The largest radius, a down to KT_SURFFIT_DEP_MIN_RADIUS in 0.25 mm steps, within which the
 * map measures at least KT_SURFFIT_DEP_COVER of the grid's cells; 0 when none. */
static double covered_radius(const kt_pentacam_map *m, double a)
{
    for (double r = a; r >= KT_SURFFIT_DEP_MIN_RADIUS - 1e-9; r -= 0.25) {
        int all = 0, have = 0;
        for (int j = 0; j < m->n; j++)
            for (int i = 0; i < m->n; i++)
                if (hypot(kt_pentacam_coord(i), kt_pentacam_coord(j)) <= r) all++, have += !isnan(m->v[j * m->n + i]);
        if (have >= KT_SURFFIT_DEP_COVER * all) return r;
    }
    return 0;
}

/* One map's departure into d and the residuals into s; the map read against the patient file
 * (kt_patient_read_map). */
static int measured_surface(const kt_patient *p, int posterior, const kt_eye *eye, double a, double taper,
                            kt_eye_departure *d, kt_surffit *s, kt_err *e)
{
    const char *path = posterior ? p->pentacam_back : p->pentacam_front;
    kt_pentacam_map m;
    if (kt_patient_read_map(p, posterior ? KT_PF_BACK : KT_PF_FRONT, &m, e)) return e->code;
    double r = covered_radius(&m, a);
    int rc = r > 0 ? kt_surffit_departure(&m, eye, posterior, KT_SURFFIT_DEP_ORDER, r, taper, d, &s->dep_rms,
                                          &s->dep_max, &s->dep_npts, e)
                   : kt_fail(e, KT_EINPUT, "%s: the map measures less than %.0f%% of every central disk from %g mm "
                             "across down to %g mm: too little for the mesh's %s surface", path,
                             100 * KT_SURFFIT_DEP_COVER, 2 * a, 2 * KT_SURFFIT_DEP_MIN_RADIUS,
                             posterior ? "posterior" : "anterior");
    kt_pentacam_free(&m);
    if (rc == KT_OK) s->dep_order = d->order, s->dep_radius = d->radius;
    return rc;
}

int kt_surffit_measured_eye(const kt_patient *p, kt_eye *eye, kt_surffit *ant, kt_surffit *post, kt_err *e)
{
    if (!p->pentacam_front[0]) return KT_OK;
    kt_eye_geom g;
    if (kt_eye_geom_init(eye, &g, e)) return e->code;
    /* The anterior base aspheric with the fit's Q; both departures fitted against the base
     * surfaces (the anterior's departure does not change the posterior's base). */
    kt_eye base = *eye;
    memset(&base.dep_ant, 0, sizeof base.dep_ant);
    memset(&base.dep_post, 0, sizeof base.dep_post);
    base.dep_ant.conic = ant->conic;
    kt_eye_departure da, dp = {0};
    if (measured_surface(p, 0, &base, KT_SURFFIT_ZONE / 2, g.rc, &da, ant, e)) return e->code;
    if (p->pentacam_back[0] && post && measured_surface(p, 1, &base, g.taper_in, g.taper_out, &dp, post, e))
        return e->code;
    eye->dep_ant = da, eye->dep_post = dp;
    kt_err le = {0};
    if (kt_eye_departure_check(&g, eye, &le))
        return kt_fail(e, KT_EINPUT, "%s: the measured cornea does not fit the eye model: %s", p->pentacam_front, le.msg);
    return KT_OK;
}
