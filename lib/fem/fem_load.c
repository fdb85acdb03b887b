/* fem_load.c: consistent nodal forces of a pressure on a surface group (3- and 6-node
 * triangles), oriented by the one tet each triangle bounds. */
#include "fem.h"
#include "fem_int.h"

#include "topology.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* A surface triangle found by its sorted vertex triple. */

/* The group's triangles, sorted by vertex triple. */
static kt_face *group_faces(const kt_mesh *m, int tag, int *count, kt_err *e)
{
    int fv = kt_tri_nv(m->order), n = 0;
    for (int i = 0; i < m->nf; i++) n += m->tri_tag[i] == tag;
    kt_face *F = kt_calloc(n ? n : 1, sizeof *F, e);
    if (!F) return NULL;
    n = 0;
    for (int i = 0; i < m->nf; i++)
        if (m->tri_tag[i] == tag) {
            memcpy(F[n].v, m->tri + (size_t)i * fv, 3 * sizeof(int));
            kt_sort3(F[n].v);
            F[n++].id = i;
        }
    qsort(F, n, sizeof *F, kt_face_cmp);
    *count = n;
    return F;
}

/* For each group triangle k: how many tets have it as a face, and the vertex opposite to it in
 * (the last) one of them. */
static void find_adjacent_tets(const kt_mesh *m, const kt_face *F, int nF, int *ntet, int *opp,
                               int *tet_of, int *face_of)
{
    int nv = kt_tet_nv(m->order);
    for (int el = 0; el < m->ne; el++) {
        const int *t = m->tet + (size_t)el * nv;
        for (int f = 0; f < 4; f++) {
            kt_face key = {{t[kt_tet_face[f][0]], t[kt_tet_face[f][1]], t[kt_tet_face[f][2]]}, -1};
            kt_sort3(key.v);
            const kt_face *hit = bsearch(&key, F, nF, sizeof *F, kt_face_cmp_v);
            if (!hit) continue;
            int k = (int)(hit - F);
            while (k > 0 && kt_face_cmp_v(&F[k - 1], &key) == 0) k--; /* duplicates: count each */
            for (; k < nF && kt_face_cmp_v(&F[k], &key) == 0; k++) {
                ntet[k]++;
                opp[k] = t[f];
                if (tet_of) tet_of[k] = el, face_of[k] = f;
            }
        }
    }
}

/* +1 if the vertex-normal (x1-x0) x (x2-x0) of triangle t points out of the tet whose vertex
 * opposite the face is o, else -1. */
static double outward_sign(const kt_mesh *m, const int *t, int o)
{
    const double *a = m->xyz + 3 * (size_t)t[0], *b = m->xyz + 3 * (size_t)t[1],
                 *c = m->xyz + 3 * (size_t)t[2], *d = m->xyz + 3 * (size_t)o;
    return kt_tet_volume(a, b, c, d) > 0 ? -1.0 : 1.0;
}

static void cross(const double *u, const double *v, double *w)
{
    w[0] = u[1] * v[2] - u[2] * v[1];
    w[1] = u[2] * v[0] - u[0] * v[2];
    w[2] = u[0] * v[1] - u[1] * v[0];
}

/* P1: each vertex takes a third of the force -p A n. */
static void tri3_forces(const kt_mesh *m, const int *t, double sign, double p, double *f)
{
    const double *x0 = m->xyz + 3 * (size_t)t[0], *x1 = m->xyz + 3 * (size_t)t[1],
                 *x2 = m->xyz + 3 * (size_t)t[2];
    double u[3], v[3], n2[3]; /* n2 = 2 A n */
    for (int k = 0; k < 3; k++) u[k] = x1[k] - x0[k], v[k] = x2[k] - x0[k];
    cross(u, v, n2);
    for (int a = 0; a < 3; a++)
        for (int k = 0; k < 3; k++) f[3 * (size_t)t[a] + k] -= p * sign * n2[k] / 6.0;
}

/* Radon's 7-point rule (fem_int.h). */
#define RS15 3.8729833462074169 /* sqrt 15 */
#define RA1 ((6.0 - RS15) / 21.0)
#define RA2 ((6.0 + RS15) / 21.0)
#define RW1 ((155.0 - RS15) / 1200.0)
#define RW2 ((155.0 + RS15) / 1200.0)
const double kt_fem_t7_p[7][2] = {{1.0 / 3, 1.0 / 3}, {RA1, RA1}, {1 - 2 * RA1, RA1}, {RA1, 1 - 2 * RA1},
                                  {RA2, RA2}, {1 - 2 * RA2, RA2}, {RA2, 1 - 2 * RA2}};
const double kt_fem_t7_w[7] = {9.0 / 40, RW1, RW1, RW1, RW2, RW2, RW2};

void kt_fem_tri6_shape(double s, double t, double *N, double (*dN)[2])
{
    static const double dL[3][2] = {{-1, -1}, {1, 0}, {0, 1}};
    double L[3] = {1 - s - t, s, t};
    for (int a = 0; a < 3; a++) {
        N[a] = L[a] * (2 * L[a] - 1);
        for (int k = 0; k < 2; k++) dN[a][k] = (4 * L[a] - 1) * dL[a][k];
    }
    for (int q = 0; q < 3; q++) {
        int i = kt_tri_edge[q][0], j = kt_tri_edge[q][1];
        N[3 + q] = 4 * L[i] * L[j];
        for (int k = 0; k < 2; k++) dN[3 + q][k] = 4 * (L[i] * dL[j][k] + L[j] * dL[i][k]);
    }
}

/* P2: f_a = -p int N_a n dA on the isoparametric (possibly curved) triangle. */
static void tri6_forces(const kt_mesh *m, const int *t, double sign, double p, double *f)
{
    for (int q = 0; q < 7; q++) {
        double N[6], dN[6][2], xs[3] = {0}, xt[3] = {0}, nA[3];
        kt_fem_tri6_shape(kt_fem_t7_p[q][0], kt_fem_t7_p[q][1], N, dN);
        for (int a = 0; a < 6; a++)
            for (int k = 0; k < 3; k++) {
                xs[k] += m->xyz[3 * (size_t)t[a] + k] * dN[a][0];
                xt[k] += m->xyz[3 * (size_t)t[a] + k] * dN[a][1];
            }
        cross(xs, xt, nA);
        double w = -p * sign * 0.5 * kt_fem_t7_w[q];
        for (int a = 0; a < 6; a++)
            for (int k = 0; k < 3; k++) f[3 * (size_t)t[a] + k] += w * N[a] * nA[k];
    }
}

int kt_fem_pressure(const kt_mesh *m, int surf_tag, double p, double *f, kt_err *e)
{
    const kt_group *g = kt_mesh_find_tag(m, 2, surf_tag);
    if (!g) return kt_fail(e, KT_EINPUT, "pressure: no surface group with tag %d", surf_tag);
    if (m->order != 1 && m->order != 2)
        return kt_fail(e, KT_EINPUT, "mesh order %d (expected 1 or 2)", m->order);
    int nF = 0;
    kt_face *F = group_faces(m, surf_tag, &nF, e);
    if (!F) return e->code;
    int *ntet = kt_calloc(nF ? nF : 1, sizeof(int), e);
    int *opp = kt_calloc(nF ? nF : 1, sizeof(int), e);
    if (e->code) goto done;
    if (nF == 0) {
        kt_fail(e, KT_EINPUT, "pressure: surface '%s' (tag %d) has no triangles", g->name, surf_tag);
        goto done;
    }
    find_adjacent_tets(m, F, nF, ntet, opp, NULL, NULL);
    for (int k = 0; k < nF; k++)
        if (ntet[k] != 1) {
            kt_fail(e, KT_EINPUT,
                    "pressure: triangle %d of surface '%s' is a face of %d tets (expected exactly 1:"
                    " a pressure needs a boundary face)", F[k].id + 1, g->name, ntet[k]);
            goto done;
        }
    int fv = kt_tri_nv(m->order);
    for (int k = 0; k < nF; k++) {
        const int *t = m->tri + (size_t)F[k].id * fv;
        double sign = outward_sign(m, t, opp[k]);
        if (m->order == 1) tri3_forces(m, t, sign, p, f);
        else tri6_forces(m, t, sign, p, f);
    }
done:
    free(F);
    free(ntet);
    free(opp);
    return e->code;
}

/* ------------------------------------------------ follower-load stiffness */

/* Kf (3fv x 3fv, row-major) = d f / d u of the follower pressure p on one face: the nodal forces
 * f_a = -p int N_a n dA of the face in its current position, n = (x_s x x_t) / |x_s x x_t|
 * oriented as given (outward from the solid), differentiated with respect to the face's nodal
 * displacements:  Kf(3a+i, 3b+j) = -p int N_a eps_ijk (N_b,s x_t,k - N_b,t x_s,k) ds dt. */
void kt_fem_face_load_stiffness(int order, const double *xf, double p, double *Kf)
{
    int fv = order == 1 ? 3 : 6, ld = 3 * fv;
    memset(Kf, 0, sizeof(double) * ld * ld);
    int nq = order == 1 ? 1 : 7;
    for (int q = 0; q < nq; q++) {
        double N[6], dN[6][2], xs[3] = {0}, xt[3] = {0}, w;
        if (order == 1) {
            static const double d1[3][2] = {{-1, -1}, {1, 0}, {0, 1}};
            for (int a = 0; a < 3; a++) {
                N[a] = 1.0 / 3;
                dN[a][0] = d1[a][0];
                dN[a][1] = d1[a][1];
            }
            w = 0.5;
        } else {
            kt_fem_tri6_shape(kt_fem_t7_p[q][0], kt_fem_t7_p[q][1], N, dN);
            w = 0.5 * kt_fem_t7_w[q];
        }
        for (int a = 0; a < fv; a++)
            for (int k = 0; k < 3; k++) {
                xs[k] += xf[3 * a + k] * dN[a][0];
                xt[k] += xf[3 * a + k] * dN[a][1];
            }
        for (int b = 0; b < fv; b++) {
            double v[3]; /* N_b,s x_t - N_b,t x_s */
            for (int k = 0; k < 3; k++) v[k] = dN[b][0] * xt[k] - dN[b][1] * xs[k];
            /* M_ij = eps_ijk v_k */
            double M[3][3] = {{0, v[2], -v[1]}, {-v[2], 0, v[0]}, {v[1], -v[0], 0}};
            for (int a = 0; a < fv; a++)
                for (int i = 0; i < 3; i++)
                    for (int j = 0; j < 3; j++)
                        Kf[(3 * a + i) * ld + 3 * b + j] += -p * w * N[a] * M[i][j];
        }
    }
}

int kt_fem_pressure_faces(const kt_mesh *m, int surf_tag, double p, double *pface, kt_err *e)
{
    const kt_group *g = kt_mesh_find_tag(m, 2, surf_tag);
    if (!g) return kt_fail(e, KT_EINPUT, "pressure: no surface group with tag %d", surf_tag);
    int nF = 0;
    kt_face *F = group_faces(m, surf_tag, &nF, e);
    if (!F) return e->code;
    int n1 = nF ? nF : 1;
    int *ntet = kt_calloc(n1, sizeof(int), e), *opp = kt_calloc(n1, sizeof(int), e);
    int *tet_of = kt_calloc(n1, sizeof(int), e), *face_of = kt_calloc(n1, sizeof(int), e);
    if (!e->code) {
        find_adjacent_tets(m, F, nF, ntet, opp, tet_of, face_of);
        for (int k = 0; k < nF && !e->code; k++) {
            if (ntet[k] != 1)
                kt_fail(e, KT_EINPUT, "pressure: triangle %d of surface '%s' is a face of %d tets "
                        "(expected exactly 1)", F[k].id + 1, g->name, ntet[k]);
            else
                pface[4 * (size_t)tet_of[k] + face_of[k]] += p;
        }
    }
    free(F);
    free(ntet);
    free(opp);
    free(tet_of);
    free(face_of);
    return e->code;
}
