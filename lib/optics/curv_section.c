/* curv_section.c: a meridional section of a step mesh through an incision. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "curv_report.h"

void kt_section_free(kt_section *s)
{
    free(s->nv), free(s->base), free(s->def);
    memset(s, 0, sizeof *s);
}

static int grow(kt_section *s, int *cap, kt_err *e)
{
    if (s->n < *cap) return KT_OK;
    int c = *cap ? 2 * *cap : 1024;
    int *nv = kt_realloc(s->nv, c, sizeof(int), e);
    if (!nv) return e->code;
    s->nv = nv;
    double *b = kt_realloc(s->base, (size_t)8 * c, sizeof(double), e);
    if (!b) return e->code;
    s->base = b;
    double *d = kt_realloc(s->def, (size_t)8 * c, sizeof(double), e);
    if (!d) return e->code;
    s->def = d;
    *cap = c;
    return KT_OK;
}

/* Corner positions (pre-operative shape) and displacements since step 0 of point i. */
static void corner(const kt_vtk *v, const kt_vtk_field *u, const kt_vtk_field *org, const double *u0,
                   int i, double p[3], double d[3])
{
    int o = (int)org->v[i] - 1;
    for (int k = 0; k < 3; k++) {
        double z0 = u0 ? u0[3 * o + k] : 0;
        p[k] = v->xyz[3 * i + k] + z0;
        d[k] = u->v[3 * i + k] - z0;
    }
}

/* Order the polygon's corners by angle around their centroid. */
static void order_corners(double *b, double *d, int m)
{
    double cx = 0, cz = 0, ang[4];
    for (int i = 0; i < m; i++) cx += b[2 * i] / m, cz += b[2 * i + 1] / m;
    for (int i = 0; i < m; i++) ang[i] = atan2(b[2 * i + 1] - cz, b[2 * i] - cx);
    for (int i = 1; i < m; i++)
        for (int j = i; j > 0 && ang[j] < ang[j - 1]; j--) {
            double t = ang[j];
            ang[j] = ang[j - 1], ang[j - 1] = t;
            for (int k = 0; k < 2; k++) {
                t = b[2 * j + k], b[2 * j + k] = b[2 * (j - 1) + k], b[2 * (j - 1) + k] = t;
                t = d[2 * j + k], d[2 * j + k] = d[2 * (j - 1) + k], d[2 * (j - 1) + k] = t;
            }
        }
}

/* One tet cut by the plane n.x = 0 (meridian direction dir): 0, 3 or 4 corners. */
static int cut_tet(const kt_vtk *v, const kt_vtk_field *u, const kt_vtk_field *org, const double *u0,
                   const int *t, const double nrm[2], const double dir[2], double *b, double *d)
{
    double p[4][3], q[4][3], sd[4];
    for (int i = 0; i < 4; i++) {
        corner(v, u, org, u0, t[i], p[i], q[i]);
        sd[i] = nrm[0] * p[i][0] + nrm[1] * p[i][1];
        if (sd[i] == 0) sd[i] = 1e-300;
    }
    int m = 0;
    for (int i = 0; i < 4; i++)
        for (int j = i + 1; j < 4; j++) {
            if ((sd[i] > 0) == (sd[j] > 0)) continue;
            double a = sd[i] / (sd[i] - sd[j]), x[3], w[3];
            for (int k = 0; k < 3; k++) x[k] = p[i][k] + a * (p[j][k] - p[i][k]), w[k] = q[i][k] + a * (q[j][k] - q[i][k]);
            b[2 * m] = dir[0] * x[0] + dir[1] * x[1], b[2 * m + 1] = x[2];
            d[2 * m] = dir[0] * w[0] + dir[1] * w[1], d[2 * m + 1] = w[2];
            m++;
        }
    if (m >= 3) order_corners(b, d, m);
    return m;
}

typedef struct split_pt {
    int origin;
    double u[3];
} split_pt;

static int cmp_split(const void *a, const void *b)
{
    int x = ((const split_pt *)a)->origin, y = ((const split_pt *)b)->origin;
    return (x > y) - (x < y);
}

/* Largest separation of points sharing an origin near the section's window. */
static int wound_gape(const kt_vtk *v, const kt_vtk_field *u, const kt_vtk_field *org, const double nrm[2],
                      const double dir[2], double r0, double r1, double half, double *gape, kt_err *e)
{
    split_pt *sp = kt_calloc(v->nn, sizeof(split_pt), e);
    if (!sp) return e->code;
    int n = 0;
    for (int i = 0; i < v->nn; i++) {
        const double *x = v->xyz + 3 * i;
        double r = dir[0] * x[0] + dir[1] * x[1];
        if (fabs(nrm[0] * x[0] + nrm[1] * x[1]) > half || r < r0 || r > r1) continue;
        sp[n].origin = (int)org->v[i];
        memcpy(sp[n].u, u->v + 3 * i, sizeof sp[n].u);
        n++;
    }
    qsort(sp, n, sizeof *sp, cmp_split);
    *gape = 0;
    for (int i = 0; i < n;) {
        int j = i + 1;
        while (j < n && sp[j].origin == sp[i].origin) j++;
        for (int a = i; a < j; a++)
            for (int b = a + 1; b < j; b++) {
                double dx = sp[a].u[0] - sp[b].u[0], dy = sp[a].u[1] - sp[b].u[1], dz = sp[a].u[2] - sp[b].u[2];
                *gape = fmax(*gape, sqrt(dx * dx + dy * dy + dz * dz));
            }
        i = j;
    }
    free(sp);
    return KT_OK;
}

/* Highest z of the points within 0.25 mm of (rc along the meridian, in the plane). */
static double window_top(const kt_vtk *v, const double dir[2], const double nrm[2], double rc)
{
    double top = -INFINITY;
    for (int i = 0; i < v->nn; i++) {
        const double *x = v->xyz + 3 * i;
        if (fabs(dir[0] * x[0] + dir[1] * x[1] - rc) < 0.25 && fabs(nrm[0] * x[0] + nrm[1] * x[1]) < 0.5)
            top = fmax(top, x[2]);
    }
    return top;
}

int kt_curv_section(const kt_vtk *v, const double *u0, int mesh_nn, double meridian, double rc, double w,
                    kt_section *s, kt_err *e)
{
    memset(s, 0, sizeof *s);
    double r0 = rc - w, r1 = rc + w;
    s->meridian = meridian, s->r0 = r0, s->r1 = r1;
    const kt_vtk_field *u = kt_vtk_find(v, "displacement", 0), *org = kt_vtk_find(v, "origin", 0);
    if (!u || u->ncomp != 3 || !org || org->ncomp != 1)
        return kt_fail(e, KT_EINPUT, "section: expected POINT_DATA displacement and origin");
    for (int i = 0; i < v->nn; i++)
        if (!(org->v[i] >= 1 && org->v[i] <= mesh_nn))
            return kt_fail(e, KT_EINPUT, "section: origin %g of point %d outside 1..%d", org->v[i], i, mesh_nn);
    double t = meridian * KT_CURV_DEG, dir[2] = {cos(t), sin(t)}, nrm[2] = {-sin(t), cos(t)};
    double zmin = window_top(v, dir, nrm, rc) - 1.6 * w;
    int cap = 0, status = KT_OK;
    for (int c = 0; c < v->ncell && status == KT_OK; c++) {
        if (v->cell_type[c] != 10 && v->cell_type[c] != 24) continue;
        const int *tc = v->conn + v->cell_ptr[c];
        double cr = 0, cz = 0; /* the tet's centroid: the window, one side of the axis */
        for (int i = 0; i < 4; i++)
            cr += 0.25 * (dir[0] * v->xyz[3 * tc[i]] + dir[1] * v->xyz[3 * tc[i] + 1]), cz += 0.25 * v->xyz[3 * tc[i] + 2];
        if (cr < r0 || cr > r1 || cz < zmin) continue;
        if ((status = grow(s, &cap, e)) != KT_OK) break;
        int m = cut_tet(v, u, org, u0, tc, nrm, dir, s->base + 8 * s->n, s->def + 8 * s->n);
        if (m < 3) continue;
        s->nv[s->n] = m;
        for (int i = 0; i < m; i++)
            s->max_disp = fmax(s->max_disp, hypot(s->def[8 * s->n + 2 * i], s->def[8 * s->n + 2 * i + 1]));
        s->n++;
    }
    if (status == KT_OK) status = wound_gape(v, u, org, nrm, dir, r0, r1, 0.5, &s->gape, e);
    if (status == KT_OK) status = wound_gape(v, u, org, nrm, dir, -INFINITY, INFINITY, INFINITY, &s->gape_all, e);
    if (status != KT_OK) kt_section_free(s);
    return status;
}
