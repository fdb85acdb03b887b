/* eye_warp.c: the toric anterior (and posterior) surfaces applied to a meshed eye of revolution, and the check
 * that no curved (P2) tet came out inverted. */
#include "eye_geom.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "topology.h"

/* ---- toric warp ------------------------------------------------------------------------ */

static void mark_group_nodes(const kt_mesh *m, int tag, char *mark)
{
    int fv = kt_tri_nv(m->order);
    for (int i = 0; i < m->nf; i++)
        if (m->tri_tag[i] == tag)
            for (int j = 0; j < fv; j++) mark[m->tri[(size_t)i * fv + j]] = 1;
}

/* Map the base eye to the toric one: z += delta(x, y) w(rho, z); anterior nodes (and the
 * limbus outer surface) are then put exactly on their surfaces. A toric posterior adds
 * (1 - h) delta_post(x, y), h the relative height through the cornea (0 on the posterior
 * surface): posterior nodes land exactly on the toric posterior, whose delta is 0 beyond
 * the taper's end (before the limbus). */
int kt_eye_warp_toric(const kt_eye_geom *g, kt_mesh *m, kt_err *e)
{
    char *ant = kt_calloc((size_t)m->nn, 1, e), *out = kt_calloc((size_t)m->nn, 1, e);
    if (!ant || !out) {
        free(ant);
        free(out);
        return e->code;
    }
    mark_group_nodes(m, KT_EYE_SURF_ANTERIOR, ant);
    mark_group_nodes(m, KT_EYE_SURF_OUTER, out);
    for (int i = 0; i < m->nn; i++) {
        double *p = m->xyz + 3 * (size_t)i, rho = hypot(p[0], p[1]);
        /* The toric posterior: its warp weighted by the depth below the anterior surface (1
         * on the posterior surface), from the base position, before the anterior warp. */
        double dpost = 0;
        if (!ant[i] && g->cp_half != 0 && rho < g->taper_out) {
            double h = kt_eye_geom_height(g, rho, p[2]);
            if (isfinite(h)) dpost = (1 - h) * kt_eye_geom_post_delta(g, p[0], p[1]);
        }
        if (ant[i]) {
            p[2] = kt_eye_geom_toric_z(g, p[0], p[1]);
        } else if (out[i] && atan2(rho, p[2]) < g->alphaL) {
            p[2] = kt_eye_geom_outer_z(g, p[0], p[1]);
        } else {
            double w = kt_eye_geom_weight(g, rho, p[2]);
            double delta = kt_eye_geom_toric_z(g, p[0], p[1]) - kt_eye_geom_sphere_z(g, rho);
            if (w > 0) p[2] += w * delta;
        }
        p[2] += dpost;
        if (!isfinite(p[2])) {
            free(ant);
            free(out);
            return kt_fail(e, KT_ERUN, "eye: node %d left the toric surface's domain", i + 1);
        }
    }
    free(ant);
    free(out);
    return KT_OK;
}

/* Jacobian determinant of a 10-node tet's quadratic map at barycentric point L (gmsh node
 * order: vertices, then edges 01 12 20 30 32 31). */
static double p2_detj(const double *xyz, const int *q, const double L[4])
{
    static const double dL[3][4] = {{-1, 1, 0, 0}, {-1, 0, 1, 0}, {-1, 0, 0, 1}};
    double J[3][3] = {{0}};
    for (int r = 0; r < 3; r++) {
        for (int a = 0; a < 4; a++)
            for (int c = 0; c < 3; c++) J[r][c] += (4 * L[a] - 1) * dL[r][a] * xyz[3 * q[a] + c];
        for (int j = 0; j < 6; j++) {
            int a = kt_tet_edge[j][0], b = kt_tet_edge[j][1];
            double dn = 4 * (L[a] * dL[r][b] + L[b] * dL[r][a]);
            for (int c = 0; c < 3; c++) J[r][c] += dn * xyz[3 * q[4 + j] + c];
        }
    }
    return J[0][0] * (J[1][1] * J[2][2] - J[1][2] * J[2][1]) -
           J[0][1] * (J[1][0] * J[2][2] - J[1][2] * J[2][0]) +
           J[0][2] * (J[1][0] * J[2][1] - J[1][1] * J[2][0]);
}

static const double CHECK_PTS[5][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1},
                                       {0.25, 0.25, 0.25, 0.25}};

/* Index of the first check point where tet t's Jacobian is not positive, or -1. */
static int inverted_at(const kt_mesh *m, int t)
{
    for (int k = 0; k < 5; k++)
        if (!(p2_detj(m->xyz, m->tet + 10 * (size_t)t, CHECK_PTS[k]) > 0)) return k;
    return -1;
}

int kt_eye_straighten_inverted(kt_mesh *m, int *nstraight, kt_err *e)
{
    *nstraight = 0;
    if (m->order != 2) return KT_OK;
    char *ant = kt_calloc((size_t)m->nn, 1, e);
    if (!ant) return e->code;
    mark_group_nodes(m, KT_EYE_SURF_ANTERIOR, ant);
    for (int t = 0; t < m->ne; t++) {
        if (inverted_at(m, t) < 0) continue;
        const int *q = m->tet + 10 * (size_t)t;
        for (int j = 0; j < 6; j++) {
            double *c = m->xyz + 3 * (size_t)q[4 + j];
            const double *a = m->xyz + 3 * (size_t)q[kt_tet_edge[j][0]];
            const double *b = m->xyz + 3 * (size_t)q[kt_tet_edge[j][1]];
            if (ant[q[4 + j]]) continue;
            int moved = 0;
            for (int k = 0; k < 3; k++) {
                double mid = 0.5 * (a[k] + b[k]);
                moved |= c[k] != mid;
                c[k] = mid;
            }
            *nstraight += moved;
        }
    }
    free(ant);
    return KT_OK;
}

/* Curved (P2) tets must stay valid after curving and the toric map: det J > 0 at the corners
 * and the centroid. */
int kt_eye_check_curved(const kt_mesh *m, kt_err *e)
{
    for (int t = 0; t < m->ne && m->order == 2; t++) {
        int k = inverted_at(m, t);
        if (k >= 0)
            return kt_fail(e, KT_ERUN, "eye: curved tet %d is inverted near its %s", t + 1,
                           k < 4 ? "corners" : "centroid");
    }
    return KT_OK;
}

