/* quality.c: shape quality of a tet mesh (dihedral angles, radius ratio). */
#include "quality.h"

#include "topology.h"

#include <math.h>


/* ---- quality ------------------------------------------------------------------------------- */

static void sub(const double *a, const double *b, double *r)
{
    for (int k = 0; k < 3; k++) r[k] = a[k] - b[k];
}

static void cross(const double *a, const double *b, double *r)
{
    r[0] = a[1] * b[2] - a[2] * b[1];
    r[1] = a[2] * b[0] - a[0] * b[2];
    r[2] = a[0] * b[1] - a[1] * b[0];
}

static double dot(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/* Dihedral extremes and radius ratio of the tet p[0..3]. */
static double tet_quality(const double *p[4], double *dmin, double *dmax)
{
    double n[4][3], area = 0;
    for (int k = 0; k < 4; k++) {
        double u[3], v[3];
        sub(p[kt_tet_face[k][1]], p[kt_tet_face[k][0]], u);
        sub(p[kt_tet_face[k][2]], p[kt_tet_face[k][0]], v);
        cross(u, v, n[k]);
        area += 0.5 * sqrt(dot(n[k], n[k]));
    }
    /* Faces k and l meet at the edge of the other two vertices; the dihedral angle there is
     * pi minus the angle between their outward normals. */
    for (int k = 0; k < 4; k++)
        for (int l = k + 1; l < 4; l++) {
            double c = dot(n[k], n[l]) / sqrt(dot(n[k], n[k]) * dot(n[l], n[l]));
            double ang = 180.0 - acos(fmax(-1.0, fmin(1.0, c))) * 180.0 / KT_PI;
            if (ang < *dmin) *dmin = ang;
            if (ang > *dmax) *dmax = ang;
        }
    double a[3], b[3], c[3], bc[3], ca[3], ab[3], o[3];
    sub(p[1], p[0], a);
    sub(p[2], p[0], b);
    sub(p[3], p[0], c);
    cross(b, c, bc);
    cross(c, a, ca);
    cross(a, b, ab);
    double det = dot(a, bc); /* 6 V */
    for (int k = 0; k < 3; k++)
        o[k] = (dot(a, a) * bc[k] + dot(b, b) * ca[k] + dot(c, c) * ab[k]) / (2 * det);
    double r_circ = sqrt(dot(o, o)), r_in = 3 * fabs(det / 6) / area;
    return 3 * r_in / r_circ;
}

void kt_mesh_quality(const kt_mesh *m, kt_quality *q)
{
    int nv = kt_tet_nv(m->order);
    q->dihedral_min = 180;
    q->dihedral_max = 0;
    q->ratio_min = HUGE_VAL;
    q->ratio_mean = 0;
    q->worst = -1;
    for (int t = 0; t < m->ne; t++) {
        const int *v = m->tet + (size_t)t * nv;
        const double *p[4] = {m->xyz + 3 * (size_t)v[0], m->xyz + 3 * (size_t)v[1],
                              m->xyz + 3 * (size_t)v[2], m->xyz + 3 * (size_t)v[3]};
        double r = tet_quality(p, &q->dihedral_min, &q->dihedral_max);
        q->ratio_mean += r;
        if (r < q->ratio_min) {
            q->ratio_min = r;
            q->worst = t;
        }
    }
    if (m->ne) q->ratio_mean /= m->ne;
}

