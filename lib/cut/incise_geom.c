/* incise_geom.c: the geometry the cutter measures: angles about the eye axis and along an
 * arc, the blade travel at which a face is cut, node depths below the anterior surface, and
 * the median edge of a surface. */
#include "incise_int.h"

#include <math.h>
#include <stdlib.h>
#include <stdio.h>
#include <string.h>

double kt_incise_theta(const double *x) { return atan2(x[1], x[0]) * (180.0 / M_PI); }


/* ---- distance to the anterior surface ---- */

static double dot3(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

static double seg_dist2(const double *p, const double *a, const double *b)
{
    double ab[3], ap[3];
    for (int k = 0; k < 3; k++) {
        ab[k] = b[k] - a[k];
        ap[k] = p[k] - a[k];
    }
    double L = dot3(ab, ab), t = L > 0 ? dot3(ap, ab) / L : 0.0;
    t = t < 0 ? 0 : t > 1 ? 1 : t;
    double d2 = 0;
    for (int k = 0; k < 3; k++) {
        double q = ap[k] - t * ab[k];
        d2 += q * q;
    }
    return d2;
}

/* Squared distance from p to triangle abc: the projection if it falls inside, else the nearest
 * edge. */
static double tri_dist2(const double *p, const double *a, const double *b, const double *c)
{
    double u[3], v[3], w[3], n[3];
    for (int k = 0; k < 3; k++) {
        u[k] = b[k] - a[k];
        v[k] = c[k] - a[k];
        w[k] = p[k] - a[k];
    }
    n[0] = u[1] * v[2] - u[2] * v[1];
    n[1] = u[2] * v[0] - u[0] * v[2];
    n[2] = u[0] * v[1] - u[1] * v[0];
    double nn = dot3(n, n);
    if (nn > 0) {
        double uu = dot3(u, u), uv = dot3(u, v), vv = dot3(v, v), wu = dot3(w, u), wv = dot3(w, v);
        double den = uu * vv - uv * uv;
        double s = (vv * wu - uv * wv) / den, t = (uu * wv - uv * wu) / den;
        if (s >= 0 && t >= 0 && s + t <= 1) {
            double h = dot3(w, n);
            return h * h / nn;
        }
    }
    double d = seg_dist2(p, a, b), d2 = seg_dist2(p, b, c), d3 = seg_dist2(p, c, a);
    return fmin(d, fmin(d2, d3));
}

/* A uniform grid over the xy extent of the surface triangles (the anterior surface is a graph
 * over xy, so a square of half-width rho around a point's xy holds every triangle within
 * distance rho of it). */
typedef struct sgrid {
    double x0, y0, h;
    int nx, ny;
    int *cp, *ci;       /* cell -> triangles (CSR) */
} sgrid;

static void cell_range(const sgrid *g, double lo, double hi, double o, int n, int *a, int *b)
{
    *a = (int)floor((lo - o) / g->h);
    *b = (int)floor((hi - o) / g->h);
    if (*a < 0) *a = 0;
    if (*b > n - 1) *b = n - 1;
}

/* The x-y bounding box (xmin, xmax, ymin, ymax) of the corners of triangle t. */
static void tri_box(const kt_mesh *m, int t, double tb[4])
{
    int fv = kt_tri_nv(m->order);
    tb[0] = tb[2] = HUGE_VAL;
    tb[1] = tb[3] = -HUGE_VAL;
    for (int k = 0; k < 3; k++) {
        const double *x = m->xyz + 3 * (size_t)m->tri[(size_t)t * fv + k];
        tb[0] = fmin(tb[0], x[0]), tb[1] = fmax(tb[1], x[0]);
        tb[2] = fmin(tb[2], x[1]), tb[3] = fmax(tb[3], x[1]);
    }
}

static int sgrid_build(sgrid *g, const kt_mesh *m, const int *tris, int nt, kt_err *e)
{
    double bb[4] = {HUGE_VAL, -HUGE_VAL, HUGE_VAL, -HUGE_VAL}, ext = 0;
    for (int i = 0; i < nt; i++) {
        double tb[4];
        tri_box(m, tris[i], tb);
        ext = fmax(ext, fmax(tb[1] - tb[0], tb[3] - tb[2]));
        bb[0] = fmin(bb[0], tb[0]), bb[1] = fmax(bb[1], tb[1]);
        bb[2] = fmin(bb[2], tb[2]), bb[3] = fmax(bb[3], tb[3]);
    }
    double area = (bb[1] - bb[0]) * (bb[3] - bb[2]);
    g->h = fmax(ext, sqrt(area / (nt + 1.0)) * 2.0);
    if (!(g->h > 0)) g->h = 1.0;
    g->x0 = bb[0];
    g->y0 = bb[2];
    g->nx = (int)((bb[1] - bb[0]) / g->h) + 1;
    g->ny = (int)((bb[3] - bb[2]) / g->h) + 1;
    size_t ncell = (size_t)g->nx * g->ny;
    g->cp = kt_calloc(ncell + 1, sizeof(int), e);
    if (!g->cp) return e->code;
    for (int pass = 0; pass < 2; pass++) {
        for (int i = 0; i < nt; i++) {
            double tb[4];
            tri_box(m, tris[i], tb);
            int ia, ib, ja, jb;
            cell_range(g, tb[0], tb[1], g->x0, g->nx, &ia, &ib);
            cell_range(g, tb[2], tb[3], g->y0, g->ny, &ja, &jb);
            for (int j = ja; j <= jb; j++)
                for (int ii = ia; ii <= ib; ii++) {
                    size_t cell = (size_t)j * g->nx + ii;
                    if (pass == 0) g->cp[cell + 1]++;
                    else g->ci[g->cp[cell]++] = tris[i];
                }
        }
        if (pass == 0) {
            for (size_t k = 0; k < ncell; k++) g->cp[k + 1] += g->cp[k];
            g->ci = kt_calloc((size_t)g->cp[ncell], sizeof(int), e);
            if (!g->ci) return e->code;
        } else {
            for (size_t k = ncell; k > 0; k--) g->cp[k] = g->cp[k - 1];
            g->cp[0] = 0;
        }
    }
    return KT_OK;
}

static double sgrid_dist(const sgrid *g, const kt_mesh *m, const double *p)
{
    int fv = kt_tri_nv(m->order);
    double best2 = HUGE_VAL;
    for (double rho = g->h;; rho *= 2) {
        int ia, ib, ja, jb;
        cell_range(g, p[0] - rho, p[0] + rho, g->x0, g->nx, &ia, &ib);
        cell_range(g, p[1] - rho, p[1] + rho, g->y0, g->ny, &ja, &jb);
        for (int j = ja; j <= jb; j++)
            for (int i = ia; i <= ib; i++) {
                size_t cell = (size_t)j * g->nx + i;
                for (int q = g->cp[cell]; q < g->cp[cell + 1]; q++) {
                    const int *t = m->tri + (size_t)g->ci[q] * fv;
                    double d2 = tri_dist2(p, m->xyz + 3 * (size_t)t[0], m->xyz + 3 * (size_t)t[1],
                                          m->xyz + 3 * (size_t)t[2]);
                    if (d2 < best2) best2 = d2;
                }
            }
        int all = ia == 0 && ja == 0 && ib == g->nx - 1 && jb == g->ny - 1;
        if (best2 <= rho * rho || all) break;
    }
    return sqrt(best2);
}

int kt_incise_depths(const kt_mesh *m, const int *nodes, int n, double *depth, kt_err *e)
{
    const kt_group *ga = kt_mesh_find_group(m, 2, "anterior"), *go = kt_mesh_find_group(m, 2, "outer");
    if (!ga) return kt_fail(e, KT_EINPUT, "mesh: expected a surface group 'anterior' to measure "
                                          "incision depth from");
    int nt = 0;
    for (int i = 0; i < m->nf; i++)
        nt += m->tri_tag[i] == ga->tag || (go && m->tri_tag[i] == go->tag);
    int *tris = kt_calloc((size_t)nt, sizeof(int), e);
    if (!tris) return e->code;
    nt = 0;
    for (int i = 0; i < m->nf; i++)
        if (m->tri_tag[i] == ga->tag || (go && m->tri_tag[i] == go->tag)) tris[nt++] = i;
    sgrid g = {0};
    if (sgrid_build(&g, m, tris, nt, e) == KT_OK)
        for (int i = 0; i < n; i++) depth[i] = sgrid_dist(&g, m, m->xyz + 3 * (size_t)nodes[i]);
    free(tris);
    free(g.cp);
    free(g.ci);
    return e->code;
}

/* ---- arcs on a ring ---- */

/* Signed angle of theta from the arc centre, in (-180, 180]. */
double kt_incise_rel_angle(double theta, double centre)
{
    double d = remainder(theta - centre, 360.0);
    return d <= -180.0 ? d + 360.0 : d;
}

/* Blade travel (deg) at which a point at relative angle d is reached. */
static double travel(int dir, double half, double d)
{
    if (dir == KT_BLADE_CCW) return d + half;
    if (dir == KT_BLADE_CW) return half - d;
    return 2.0 * fabs(d);
}

/* Key of a face of vertex angles d[3] on an arc (side 1: the opposite arc of a pair, which
 * may be shorter or longer, arc_opposite, and grows in proportion: its key is scaled to the
 * main arc's travel); -1 when the face is not on the arc. */
double kt_incise_arc_key(const kt_incision *inc, const double *d, int side)
{
    double arc = side && inc->arc_opposite > 0 ? inc->arc_opposite : inc->arc, scale = inc->arc / arc;
    double half = 0.5 * arc, lo = fmin(d[0], fmin(d[1], d[2])), hi = fmax(d[0], fmax(d[1], d[2]));
    const double tol = 1e-7;
    if (hi - lo > 180.0) /* straddles the back of a full ring: cut last */
        return arc >= 360.0 - tol ? inc->arc : -1.0;
    if (lo < -half - tol || hi > half + tol) return -1.0;
    double key = 0;
    for (int k = 0; k < 3; k++) key = fmax(key, travel(inc->direction, half, d[k]));
    return fmin(key * scale, inc->arc);
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Median edge length of the listed triangles (a length scale for tolerances). */
double kt_incise_median_edge(const kt_mesh *m, const int *tris, int nt, kt_err *e)
{
    int fv = kt_tri_nv(m->order);
    double *len = kt_calloc((size_t)3 * nt, sizeof(double), e);
    if (!len) return 0;
    for (int i = 0; i < nt; i++)
        for (int k = 0; k < 3; k++) {
            const double *a = m->xyz + 3 * (size_t)m->tri[(size_t)tris[i] * fv + k];
            const double *b = m->xyz + 3 * (size_t)m->tri[(size_t)tris[i] * fv + (k + 1) % 3];
            len[3 * i + k] = sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                                  (a[2] - b[2]) * (a[2] - b[2]));
        }
    qsort(len, (size_t)3 * nt, sizeof(double), cmp_double);
    double h = len[(3 * nt) / 2];
    free(len);
    return h;
}

void kt_incise_arc_phase(const kt_incision *inc, int index, kt_phase *ph)
{
    ph->kind = KT_PHASE_CUT;
    snprintf(ph->name, sizeof ph->name, "incision %d", index + 1);
    ph->key_unit = KT_KEY_DEG;
    ph->total = inc->arc;
    ph->dps = inc->prog.nodes_per_step > 0 ? 0 : inc->prog.degrees_per_step;
    ph->nps = inc->prog.nodes_per_step;
}
