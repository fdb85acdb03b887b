/* wound.c: the healed wound's bridge across cut face pairs (wound.h): the intact mesh's face
 * adjacency, the cut pairs of a mesh, the face mass matrix and the one assembly kernel every
 * method uses (nodal DOFs or the planned method's increment variables). */
#include "wound.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fem_int.h"
#include "topology.h"

int kt_wound_on(const kt_materials *mats)
{
    return mats && mats->wound && mats->wound->k > 0;
}

int kt_wound_face_local(int order, int f, int *loc)
{
    for (int q = 0; q < 3; q++) loc[q] = kt_tet_face[f][q];
    if (order != 2) return 3;
    for (int q = 0; q < 3; q++) {
        int a = loc[q], b = loc[(q + 1) % 3];
        for (int k = 0; k < 6; k++)
            if ((kt_tet_edge[k][0] == a && kt_tet_edge[k][1] == b) ||
                (kt_tet_edge[k][0] == b && kt_tet_edge[k][1] == a))
                loc[3 + q] = 4 + k;
    }
    return 6;
}

void kt_wound_free(kt_wound *w)
{
    free(w->mate);
    free(w->map);
    memset(w, 0, sizeof *w);
}

/* The global nodes of slot s's face on mesh m into g; returns fv. */
static int face_nodes(const kt_mesh *m, int s, int *g)
{
    int nv = kt_tet_nv(m->order), loc[6], fv = kt_wound_face_local(m->order, s % 4, loc);
    const int *t = m->tet + (size_t)(s / 4) * nv;
    for (int i = 0; i < fv; i++) g[i] = t[loc[i]];
    return fv;
}

/* mate[] and map[] of the pair of slots s, o (a shared face of the intact mesh m). */
static int link(kt_wound *w, const kt_mesh *m, int s, int o, kt_err *e)
{
    int gs[6], go[6], fv = face_nodes(m, s, gs);
    face_nodes(m, o, go);
    w->mate[s] = o;
    w->mate[o] = s;
    for (int i = 0; i < fv; i++) {
        int js = -1, jo = -1;
        for (int j = 0; j < fv; j++) {
            if (go[j] == gs[i]) js = j;
            if (gs[j] == go[i]) jo = j;
        }
        if (js < 0 || jo < 0)
            return kt_fail(e, KT_EINPUT, "tets %d and %d share corners but not their face's nodes",
                           s / 4 + 1, o / 4 + 1);
        w->map[6 * (size_t)s + i] = (signed char)js;
        w->map[6 * (size_t)o + i] = (signed char)jo;
    }
    return KT_OK;
}

int kt_wound_build(kt_wound *w, const kt_mesh *m, double k, kt_err *e)
{
    memset(w, 0, sizeof *w);
    if (!(k >= 0) || !isfinite(k))
        return kt_fail(e, KT_EINPUT, "wound: bridge stiffness %g MPa/mm (expected finite, >= 0)", k);
    if (m->order != 1 && m->order != 2)
        return kt_fail(e, KT_EINPUT, "mesh order %d (expected 1 or 2)", m->order);
    w->k = k, w->ne = m->ne, w->order = m->order;
    size_t ns = 4 * (size_t)(m->ne ? m->ne : 1);
    kt_face *F = NULL;
    w->mate = kt_calloc(ns, sizeof(int), e);
    w->map = kt_calloc(6 * ns, 1, e);
    if (e->code || kt_mesh_tet_faces(m, &F, e)) goto fail;
    for (size_t s = 0; s < ns; s++) w->mate[s] = -1;
    int nf = 4 * m->ne;
    for (int i = 0; i < nf; i++) {
        int j = i;
        while (j + 1 < nf && kt_face_cmp_v(&F[i], &F[j + 1]) == 0) j++;
        if (j - i > 1) {
            kt_fail(e, KT_EINPUT, "a face of tet %d is shared by %d tets", F[i].id / 4 + 1, j - i + 1);
            goto fail;
        }
        if (j == i + 1 && link(w, m, F[i].id, F[j].id, e)) goto fail;
        i = j;
    }
    free(F);
    return KT_OK;
fail:
    free(F);
    kt_wound_free(w);
    return e->code;
}

int kt_wound_cut(const kt_wound *w, const kt_mesh *m, int s)
{
    int o = w->mate[s];
    if (o < 0) return 0;
    int gs[6], go[6], fv = face_nodes(m, s, gs);
    face_nodes(m, o, go);
    for (int i = 0; i < fv; i++)
        if (gs[i] != go[w->map[6 * (size_t)s + i]]) return 1;
    return 0;
}

static int check_mesh(const kt_wound *w, const kt_mesh *m, kt_err *e)
{
    if (m->ne != w->ne || m->order != w->order)
        return kt_fail(e, KT_EINPUT, "wound: mesh of %d order-%d tets, the bridge was built for %d "
                       "order-%d tets", m->ne, m->order, w->ne, w->order);
    return KT_OK;
}

int kt_wound_pairs(const kt_wound *w, const kt_mesh *m, int **slots, int *n, kt_err *e)
{
    *slots = NULL;
    *n = 0;
    if (check_mesh(w, m, e)) return e->code;
    int cnt = 0, ns = 4 * m->ne;
    for (int s = 0; s < ns; s++) cnt += w->mate[s] > s && kt_wound_cut(w, m, s);
    if (!(*slots = kt_calloc(cnt ? cnt : 1, sizeof(int), e))) return e->code;
    for (int s = 0; s < ns; s++)
        if (w->mate[s] > s && kt_wound_cut(w, m, s)) (*slots)[(*n)++] = s;
    return KT_OK;
}

static void cross(const double *u, const double *v, double *c)
{
    c[0] = u[1] * v[2] - u[2] * v[1];
    c[1] = u[2] * v[0] - u[0] * v[2];
    c[2] = u[0] * v[1] - u[1] * v[0];
}

void kt_wound_face_mass(int order, const double *xf, double *M)
{
    if (order != 2) {
        double u[3], v[3], n[3];
        for (int k = 0; k < 3; k++) u[k] = xf[3 + k] - xf[k], v[k] = xf[6 + k] - xf[k];
        cross(u, v, n);
        double A = 0.5 * sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++) M[3 * i + j] = A / 12 * (i == j ? 2 : 1);
        return;
    }
    memset(M, 0, 36 * sizeof(double));
    for (int q = 0; q < 7; q++) {
        double N[6], dN[6][2], xs[3] = {0}, xt[3] = {0}, n[3];
        kt_fem_tri6_shape(kt_fem_t7_p[q][0], kt_fem_t7_p[q][1], N, dN);
        for (int a = 0; a < 6; a++)
            for (int k = 0; k < 3; k++) {
                xs[k] += xf[3 * a + k] * dN[a][0];
                xt[k] += xf[3 * a + k] * dN[a][1];
            }
        cross(xs, xt, n);
        double wq = 0.5 * kt_fem_t7_w[q] * sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        for (int i = 0; i < 6; i++)
            for (int j = 0; j < 6; j++) M[6 * i + j] += wq * N[i] * N[j];
    }
}

/* A face node's jump as terms: nodes and signs (+ side s, - its mate). */
typedef struct jump {
    int n;
    int node[2 * KT_WOUND_CHAIN_MAX];
    signed char sign[2 * KT_WOUND_CHAIN_MAX];
} jump;

/* The chain of node a (a and its ancestors) into c; -1 when deeper than the maximum. */
static int chain(const int *parent, int a, int *c)
{
    int n = 0;
    for (; a >= 0; a = parent[a]) {
        if (n == KT_WOUND_CHAIN_MAX) return -1;
        c[n++] = a;
    }
    return n;
}

/* J := u_a - u_b: nodal (parent NULL), or the two chains without their common tail. */
static int jump_terms(const int *parent, int a, int b, jump *J, kt_err *e)
{
    J->n = 0;
    if (a == b) return KT_OK;
    if (!parent) {
        J->node[0] = a, J->sign[0] = 1;
        J->node[1] = b, J->sign[1] = -1;
        J->n = 2;
        return KT_OK;
    }
    int ca[KT_WOUND_CHAIN_MAX], cb[KT_WOUND_CHAIN_MAX];
    int na = chain(parent, a, ca), nb = chain(parent, b, cb);
    if (na < 0 || nb < 0)
        return kt_fail(e, KT_EINPUT, "node %d is split more than %d times", (na < 0 ? a : b) + 1,
                       KT_WOUND_CHAIN_MAX);
    while (na > 0 && nb > 0 && ca[na - 1] == cb[nb - 1]) na--, nb--;
    for (int i = 0; i < na; i++) J->node[J->n] = ca[i], J->sign[J->n++] = 1;
    for (int i = 0; i < nb; i++) J->node[J->n] = cb[i], J->sign[J->n++] = -1;
    return KT_OK;
}

int kt_wound_pair_put(const kt_wound *w, const kt_mesh *m, int s, const int *parent, double scale,
                      int all, kt_wound_put_fn put, void *ctx, kt_err *e)
{
    int o = w->mate[s];
    if (o < 0) return KT_OK;
    int gs[6], go[6], fv = face_nodes(m, s, gs);
    face_nodes(m, o, go);
    double xf[18] = {0}, M[36];
    for (int i = 0; i < fv; i++) memcpy(xf + 3 * i, m->xyz + 3 * (size_t)gs[i], 3 * sizeof(double));
    kt_wound_face_mass(m->order, xf, M);
    jump *J = kt_calloc(6, sizeof *J, e);
    if (!J) return e->code;
    for (int i = 0; i < fv && !e->code; i++)
        jump_terms(parent, gs[i], go[w->map[6 * (size_t)s + i]], &J[i], e);
    for (int i = 0; i < fv && !e->code; i++)
        for (int j = 0; j < fv; j++) {
            double x = scale * w->k * M[fv * i + j];
            for (int a = 0; a < J[i].n; a++)
                for (int b = 0; b < J[j].n; b++) {
                    double y = x * J[i].sign[a] * J[j].sign[b];
                    for (int c = 0; c < 3; c++) {
                        int v = 3 * J[i].node[a] + c, u = 3 * J[j].node[b] + c;
                        if (all || v >= u) put(ctx, v, u, y);
                    }
                }
        }
    free(J);
    return e->code;
}

int kt_wound_assemble(const kt_wound *w, const kt_mesh *m, const int *parent, double scale,
                      kt_wound_put_fn put, void *ctx, kt_err *e)
{
    int *slots, n;
    if (kt_wound_pairs(w, m, &slots, &n, e)) return e->code;
    for (int q = 0; q < n && !e->code; q++) kt_wound_pair_put(w, m, slots[q], parent, scale, 0, put, ctx, e);
    free(slots);
    return e->code;
}

typedef struct apply_ctx {
    const double *u;
    double *y;
} apply_ctx;

static void apply_put(void *ctx, int v, int w, double x)
{
    apply_ctx *a = ctx;
    a->y[v] += x * a->u[w];
}

int kt_wound_apply(const kt_wound *w, const kt_mesh *m, const double *u, double scale, double *y,
                   kt_err *e)
{
    int *slots, n;
    if (kt_wound_pairs(w, m, &slots, &n, e)) return e->code;
    apply_ctx a = {u, y};
    for (int q = 0; q < n && !e->code; q++) kt_wound_pair_put(w, m, slots[q], NULL, scale, 1, apply_put, &a, e);
    free(slots);
    return e->code;
}
