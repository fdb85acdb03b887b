/* fem_assemble.c: the global stiffness in CHOLMOD form: the node pattern, scattering the element
 * matrices, identity rows and columns for fixed DOFs. */
#include "fem.h"

#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "chol.h"
#include "topology.h"
#include "wound.h"

/* ------------------------------------------------------------------ pattern */

/* Node adjacency, lower part: for node j, Ni[Np[j]..Np[j+1]) lists j itself and then, in
 * increasing order, every node i > j that shares a tet with j. */
typedef struct node_pattern {
    int *Np, *Ni;
} node_pattern;

static void pattern_free(node_pattern *P)
{
    free(P->Np);
    free(P->Ni);
}

static int cmp_int(const void *a, const void *b)
{
    int x = *(const int *)a, y = *(const int *)b;
    return (x > y) - (x < y);
}

/* The couplings beyond the tets: the cut face pairs of a healed wound (wound.h), each an
 * element of both faces' nodes (nv of them), and node -> elements in CSR form (Xp, Xi). */
typedef struct extra_elems {
    int n, nv;
    int *node, *Xp, *Xi;
} extra_elems;

static void extra_free(extra_elems *X)
{
    free(X->node);
    free(X->Xp);
    free(X->Xi);
    memset(X, 0, sizeof *X);
}

static int extra_build(const kt_mesh *m, const kt_wound *w, extra_elems *X, kt_err *e)
{
    memset(X, 0, sizeof *X);
    int *slots = NULL, loc[6], fv = kt_wound_face_local(m->order, 0, loc);
    if (kt_wound_pairs(w, m, &slots, &X->n, e)) return e->code;
    X->nv = 2 * fv;
    int tnv = kt_tet_nv(m->order);
    X->node = kt_calloc((size_t)(X->n ? X->n : 1) * X->nv, sizeof(int), e);
    X->Xp = kt_calloc((size_t)m->nn + 1, sizeof(int), e);
    X->Xi = kt_calloc((size_t)(X->n ? X->n : 1) * X->nv, sizeof(int), e);
    for (int q = 0; q < X->n && !e->code; q++)
        for (int side = 0; side < 2; side++) {
            int s = side ? w->mate[slots[q]] : slots[q];
            kt_wound_face_local(m->order, s % 4, loc);
            for (int i = 0; i < fv; i++)
                X->node[(size_t)q * X->nv + side * fv + i] = m->tet[(size_t)(s / 4) * tnv + loc[i]];
        }
    free(slots);
    if (e->code) return e->code;
    for (size_t k = 0; k < (size_t)X->n * X->nv; k++) X->Xp[X->node[k] + 1]++;
    for (int j = 0; j < m->nn; j++) X->Xp[j + 1] += X->Xp[j];
    int *fill = kt_calloc((size_t)m->nn + 1, sizeof(int), e);
    if (!fill) return e->code;
    for (size_t k = 0; k < (size_t)X->n * X->nv; k++) {
        int a = X->node[k];
        X->Xi[X->Xp[a] + fill[a]++] = (int)(k / X->nv);
    }
    free(fill);
    return KT_OK;
}

/* Mark and list the nodes i > j of one element. */
static int gather_elem(const int *t, int nv, int j, int *mark, int *list, int cnt)
{
    for (int a = 0; a < nv; a++)
        if (t[a] > j && mark[t[a]] != j) {
            mark[t[a]] = j;
            list[cnt++] = t[a];
        }
    return cnt;
}

/* Gather node j's neighbours i > j into list (marking them in mark), return the count. */
static int gather(const kt_mesh *m, int j, const int *Ep, const int *Ei, const extra_elems *X,
                  int *mark, int *list)
{
    int nv = kt_tet_nv(m->order), cnt = 0;
    mark[j] = j;
    list[cnt++] = j;
    for (int q = Ep[j]; q < Ep[j + 1]; q++)
        cnt = gather_elem(m->tet + (size_t)Ei[q] * nv, nv, j, mark, list, cnt);
    for (int q = X->Xp ? X->Xp[j] : 0; X->Xp && q < X->Xp[j + 1]; q++)
        cnt = gather_elem(X->node + (size_t)X->Xi[q] * X->nv, X->nv, j, mark, list, cnt);
    return cnt;
}

static int build_pattern(const kt_mesh *m, const kt_wound *w, node_pattern *P, kt_err *e)
{
    memset(P, 0, sizeof *P);
    int *Ep = NULL, *Ei = NULL;
    extra_elems X = {0};
    if (w && w->k > 0 && extra_build(m, w, &X, e)) {
        extra_free(&X);
        return e->code;
    }
    if (kt_mesh_node_tets(m, &Ep, &Ei, e)) {
        extra_free(&X);
        return e->code;
    }
    int nv = kt_tet_nv(m->order), maxdeg = 1; /* a gather writes at most 1 + nv per element */
    for (int j = 0; j < m->nn; j++) {
        int d = (Ep[j + 1] - Ep[j]) * nv + 1 + (X.Xp ? (X.Xp[j + 1] - X.Xp[j]) * X.nv : 0);
        if (d > maxdeg) maxdeg = d;
    }
    int *mark = kt_calloc(m->nn ? m->nn : 1, sizeof(int), e);
    int *list = kt_calloc(maxdeg, sizeof(int), e);
    P->Np = kt_calloc((size_t)m->nn + 1, sizeof(int), e);
    if (e->code) goto done;
    for (int i = 0; i < m->nn; i++) mark[i] = -1;
    size_t total = 0;
    for (int j = 0; j < m->nn; j++) {
        total += gather(m, j, Ep, Ei, &X, mark, list);
        if (total > INT_MAX) {
            kt_fail(e, KT_ERUN, "node adjacency too large for a 32-bit CHOLMOD matrix");
            goto done;
        }
        P->Np[j + 1] = (int)total;
    }
    P->Ni = kt_calloc(total ? total : 1, sizeof(int), e);
    if (e->code) goto done;
    for (int i = 0; i < m->nn; i++) mark[i] = -1;
    for (int j = 0; j < m->nn; j++) {
        int cnt = gather(m, j, Ep, Ei, &X, mark, P->Ni + P->Np[j]);
        qsort(P->Ni + P->Np[j] + 1, cnt - 1, sizeof(int), cmp_int);
    }
done:
    free(Ep);
    free(Ei);
    free(mark);
    free(list);
    extra_free(&X);
    if (e->code) pattern_free(P);
    return e->code;
}

/* Entries of the DOF matrix: node j's column block holds a 3x3 lower-triangular diagonal block
 * (6 entries) and a full 3x3 block for each neighbour i > j. */
static size_t dof_nnz(const kt_mesh *m, const node_pattern *P)
{
    size_t nnz = 0;
    for (int j = 0; j < m->nn; j++) nnz += 6 + 9 * (size_t)(P->Np[j + 1] - P->Np[j] - 1);
    return nnz;
}

static void fill_structure(const kt_mesh *m, const node_pattern *P, cholmod_sparse *A)
{
    int *Ap = A->p, *Ai = A->i, q = 0;
    for (int j = 0; j < m->nn; j++)
        for (int c = 0; c < 3; c++) {
            Ap[3 * j + c] = q;
            for (int r = c; r < 3; r++) Ai[q++] = 3 * j + r;
            for (int k = P->Np[j] + 1; k < P->Np[j + 1]; k++)
                for (int r = 0; r < 3; r++) Ai[q++] = 3 * P->Ni[k] + r;
        }
    Ap[3 * m->nn] = q;
}

/* ----------------------------------------------------------------- assembly */

static int check_inputs(const kt_mesh *m, const kt_materials *mats, kt_err *e)
{
    if (m->order != 1 && m->order != 2)
        return kt_fail(e, KT_EINPUT, "mesh order %d (expected 1 or 2)", m->order);
    if (m->nn <= 0 || m->nn > INT_MAX / 3)
        return kt_fail(e, KT_EINPUT, "mesh has %d nodes (expected 1 to %d)", m->nn, INT_MAX / 3);
    int nv = kt_tet_nv(m->order);
    for (int el = 0; el < m->ne; el++) {
        for (int a = 0; a < nv; a++) {
            int n = m->tet[(size_t)el * nv + a];
            if (n < 0 || n >= m->nn)
                return kt_fail(e, KT_EINPUT, "tet %d names node %d (mesh has %d nodes)", el + 1,
                               n + 1, m->nn);
        }
        int t = m->tet_tag[el];
        if (t < 0 || t >= mats->nmat)
            return kt_fail(e, KT_EINPUT, "tet %d has region tag %d with no material (%d given)",
                           el + 1, t, mats->nmat);
    }
    if (mats->td && mats->td->ne != m->ne)
        return kt_fail(e, KT_EINPUT, "per-tet data for %d tets, mesh has %d", mats->td->ne, m->ne);
    for (int t = 0; t < mats->nmat; t++) {
        kt_err le = {0};
        if (!(mats->td && mats->td->C) && kt_mesh_find_tag(m, 3, t) &&
            kt_fem_check_material(mats->mat[t], &le))
            return kt_fail(e, le.code, "region %d: %s", t, le.msg);
    }
    return KT_OK;
}

/* Position of K(3i+r, 3j+c), i >= j, in node j's column block; k is i's index in j's list. */
static int entry_at(const int *Ap, int j, int c, int i, int r, int k)
{
    return Ap[3 * j + c] + (i == j ? r - c : (3 - c) + 3 * (k - 1) + r);
}

/* Index of node i in node j's neighbour list (0 when i == j). */
static int find_neighbour(const node_pattern *P, int j, int i)
{
    if (i == j) return 0;
    const int *lo = P->Ni + P->Np[j] + 1;
    const int *hit = bsearch(&i, lo, P->Np[j + 1] - P->Np[j] - 1, sizeof(int), cmp_int);
    return hit ? (int)(hit - lo) + 1 : -1;
}

/* Add one element matrix into the lower triangle of A. */
static void scatter(const node_pattern *P, const int *t, int nv, const double *Ke, cholmod_sparse *A)
{
    const int *Ap = A->p;
    double *Ax = A->x;
    int ld = 3 * nv;
    for (int b = 0; b < nv; b++)
        for (int a = 0; a < nv; a++) {
            int i = t[a], j = t[b];
            if (i < j) continue;
            int k = find_neighbour(P, j, i);
            for (int c = 0; c < 3; c++)
                for (int r = (i == j ? c : 0); r < 3; r++)
                    Ax[entry_at(Ap, j, c, i, r, k)] += Ke[(3 * a + r) * ld + 3 * b + c];
        }
}

/* The bridge's entries (v >= w, one component: v = 3i + c, w = 3j + c, i >= j) into A. */
typedef struct wound_sink {
    const node_pattern *P;
    cholmod_sparse *A;
} wound_sink;

static void wound_put(void *ctx, int v, int w, double x)
{
    wound_sink *s = ctx;
    int i = v / 3, j = w / 3, r = v % 3, c = w % 3;
    int k = find_neighbour(s->P, j, i);
    ((double *)s->A->x)[entry_at(s->A->p, j, c, i, r, k)] += x;
}

/* The total Lagrangian state to assemble at (NULL: the linear tangent of kt_fem_element). */
typedef struct nl_state {
    const double *u;
    double pscale;
    double *r; /* 3*nn: the residual, summed here */
} nl_state;

static int add_elements(const kt_mesh *m, const kt_materials *mats, nl_state *nl,
                        const node_pattern *P, cholmod_sparse *A, kt_err *e)
{
    int nv = kt_tet_nv(m->order);
    double Ke[900], fe[30];
    if (nl) memset(nl->r, 0, 3 * (size_t)m->nn * sizeof(double));
    for (int el = 0; el < m->ne; el++) {
        const int *t = m->tet + (size_t)el * nv;
        kt_err le = {0};
        if (nl ? kt_fem_nl_element(m, mats, el, nl->u, nl->pscale, fe, Ke, &le)
               : kt_fem_element(m, mats, el, Ke, &le))
            return kt_fail(e, le.code, "tet %d (region %d): %s", el + 1, m->tet_tag[el], le.msg);
        scatter(P, t, nv, Ke, A);
        if (nl)
            for (int a = 0; a < nv; a++)
                for (int c = 0; c < 3; c++) nl->r[3 * (size_t)t[a] + c] += fe[3 * a + c];
    }
    if (!kt_wound_on(mats)) return KT_OK;
    wound_sink ws = {P, A};
    if (kt_wound_assemble(mats->wound, m, NULL, 1.0, wound_put, &ws, e)) return e->code;
    return nl ? kt_wound_apply(mats->wound, m, nl->u, 1.0, nl->r, e) : KT_OK;
}

/* Replace rows and columns of fixed DOFs by the identity, dropping their entries in place. */
void kt_fem_apply_fixed(cholmod_sparse *A, const unsigned char *fixed)
{
    int *Ap = A->p, *Ai = A->i, n = (int)A->ncol, q = 0;
    double *Ax = A->x;
    for (int j = 0; j < n; j++) {
        int start = Ap[j], end = Ap[j + 1];
        Ap[j] = q;
        for (int p = start; p < end; p++) {
            int i = Ai[p];
            if (fixed[i] || fixed[j]) {
                if (i != j) continue;
                Ai[q] = i;
                Ax[q++] = 1.0;
            } else {
                Ai[q] = i;
                Ax[q++] = Ax[p];
            }
        }
    }
    Ap[n] = q;
}

static cholmod_sparse *assemble(const kt_mesh *m, const kt_materials *mats, nl_state *nl,
                                const unsigned char *fixed, cholmod_common *c, kt_err *e)
{
    if (check_inputs(m, mats, e)) return NULL;
    node_pattern P;
    if (build_pattern(m, kt_wound_on(mats) ? mats->wound : NULL, &P, e)) return NULL;
    size_t nnz = dof_nnz(m, &P), n = 3 * (size_t)m->nn;
    if (nnz > INT_MAX) {
        pattern_free(&P);
        kt_fail(e, KT_ERUN, "stiffness matrix has %zu entries, too many for 32-bit CHOLMOD", nnz);
        return NULL;
    }
    cholmod_sparse *A = cholmod_allocate_sparse(n, n, nnz, 1, 1, -1, CHOLMOD_REAL, c);
    if (!A) {
        pattern_free(&P);
        kt_fail(e, KT_ERUN, "CHOLMOD could not allocate a %zu x %zu matrix with %zu entries "
                "(status %d)", n, n, nnz, c->status);
        return NULL;
    }
    fill_structure(m, &P, A);
    memset(A->x, 0, nnz * sizeof(double));
    int rc = add_elements(m, mats, nl, &P, A, e);
    pattern_free(&P);
    if (rc) {
        cholmod_free_sparse(&A, c);
        return NULL;
    }
    if (fixed) {
        kt_fem_apply_fixed(A, fixed);
        cholmod_reallocate_sparse(cholmod_nnz(A, c), A, c); /* give back the dropped entries */
    }
    return A;
}

cholmod_sparse *kt_fem_pattern(const kt_mesh *m, const kt_wound *wound, cholmod_common *c,
                               kt_err *e)
{
    if (m->order != 1 && m->order != 2) {
        kt_fail(e, KT_EINPUT, "mesh order %d (expected 1 or 2)", m->order);
        return NULL;
    }
    node_pattern P;
    if (build_pattern(m, wound, &P, e)) return NULL;
    size_t nnz = dof_nnz(m, &P), n = 3 * (size_t)m->nn;
    cholmod_sparse *A = nnz > INT_MAX ? NULL
                        : cholmod_allocate_sparse(n, n, nnz, 1, 1, -1, CHOLMOD_PATTERN, c);
    if (A) fill_structure(m, &P, A);
    else kt_fail(e, KT_ERUN, "no room for the pattern of a %zu x %zu matrix with %zu entries", n,
                 n, nnz);
    pattern_free(&P);
    return A;
}

cholmod_sparse *kt_fem_assemble(const kt_mesh *m, const kt_materials *mats,
                                const unsigned char *fixed, cholmod_common *c, kt_err *e)
{
    return assemble(m, mats, NULL, fixed, c, e);
}

cholmod_sparse *kt_fem_nl_assemble(const kt_mesh *m, const kt_materials *mats, const double *u,
                                   double pscale, const unsigned char *fixed, double *r,
                                   cholmod_common *c, kt_err *e)
{
    nl_state nl = {u, pscale, r};
    return assemble(m, mats, &nl, fixed, c, e);
}
