/* aug_lset.c: Lset, J and H, in the variables the augmented system is written in.
 *
 * A DOF added since the base (a node split off by a dup) is written as an increment over the
 * DOF it was split from: u_j = v_j + u_par(j), u = P v, and the system solved is the congruent
 * P^T K P v = P^T f^. Why: R knows nothing of a new DOF (identity padding), so in the plain
 * variables its column applies an unbalanced force to the uncut body; on a slender beam that
 * bends the whole beam and the Schur complement gets entries of 1e7 next to entries of 1 (GMRES
 * stalls, answers lose all digits). In the increments every column seen by R sums the tets of
 * a whole split cluster and is self-equilibrated, so its R^-1 response stays local. A DOF that
 * is constrained is its own variable (par -1), so Dirichlet data stays on single variables. */
#include <stdlib.h>
#include <string.h>

#include "aug_impl.h"

static int base_fixed(const kt_aug *A, int i)
{
    return i < A->base->n0 && A->base->B[i];
}

double aug_padv(const kt_aug *A, int j) { return A->pad[j] > 0 ? A->pad[j] : 1.0; }

static int lset_add(kt_aug *A, int dof, kt_err *e)
{
    if (A->Lpos[dof] >= 0) return KT_OK;
    if (A->m == A->mcap) {
        int cap = A->mcap ? 2 * A->mcap : 64;
        int *L = kt_realloc(A->Ldof, (size_t)cap, sizeof(int), e);
        if (!L) return e->code;
        A->Ldof = L;
        aug_col *J = kt_realloc(A->J, (size_t)cap, sizeof(aug_col), e);
        if (!J) return e->code;
        memset(J + A->mcap, 0, (size_t)(cap - A->mcap) * sizeof(aug_col));
        A->J = J;
        double *a2 = kt_realloc(A->a2, (size_t)cap, sizeof(double), e);
        if (!a2) return e->code;
        A->a2 = a2;
        double *rhs = kt_realloc(A->rhs, (size_t)cap, sizeof(double), e);
        if (!rhs) return e->code;
        A->rhs = rhs;
        A->mcap = cap;
    }
    A->Lpos[dof] = A->m;
    A->Ldof[A->m] = dof;
    A->J[A->m].n = 0;
    A->a2[A->m] = 0; /* the others keep last step's values: GMRES starts from them */
    A->m++;
    return KT_OK;
}

/* J column of Lset entry k from the transformed column col of its variable: s e_j (s its
 * diagonal) for a DOF constrained since the base, else the column with the rows of B zeroed. */
static int set_jcol(kt_aug *A, int k, const aug_col *col, kt_err *e)
{
    int j = A->Ldof[k];
    aug_col *J = &A->J[k];
    double s = 1;
    for (int p = 0; p < col->n; p++)
        if (col->i[p] == j) s = col->x[p];
    if (j >= A->base->n0 && A->pad[j] == 0 && s > 0) A->pad[j] = s;
    if (A->cons[j]) {
        if (aug_col_reserve(J, 1, e)) return e->code;
        J->i[0] = j;
        J->x[0] = s > 0 ? s : 1;
        J->n = 1;
        return KT_OK;
    }
    if (aug_col_reserve(J, col->n, e)) return e->code;
    J->n = 0;
    for (int p = 0; p < col->n; p++)
        if (!base_fixed(A, col->i[p]) && col->x[p] != 0) {
            J->i[J->n] = col->i[p];
            J->x[J->n++] = col->x[p];
        }
    return KT_OK;
}

/* ------------------------------------------------------- clusters and folds */

/* The DOFs whose parent chain reaches j (j first): K P e_j sums their columns. */
static int cluster(const kt_aug *A, int j, int *out, int cap)
{
    int n = 0, head = 0;
    out[n++] = j;
    while (head < n) {
        int q = out[head++], a = q / 3, c = q % 3;
        for (int k = 0; k < A->kids_n[a]; k++) {
            int d = 3 * A->kids[a][k] + c;
            if (A->par[d] == q && n < cap) out[n++] = d;
        }
    }
    return n;
}

/* Accumulate val at row r of the dense acc, listing new rows in col. */
static int acc_add(kt_aug *A, double *acc, aug_col *col, int r, double val, kt_err *e)
{
    if (A->dmark[r] != A->dstamp) {
        A->dmark[r] = A->dstamp;
        if (aug_col_reserve(col, col->n + 1, e)) return e->code;
        col->i[col->n++] = r;
        acc[r] = 0;
    }
    acc[r] += val;
    return KT_OK;
}

/* out = P^T (sum of the node columns of the cluster), component c. cols[q] holds the three
 * columns of the q-th node of the list nodes. */
static int fold_column(kt_aug *A, int j, const int *nodes, int nn, aug_col (*cols)[3],
                       aug_col *out, kt_err *e)
{
    int members[64], nm = cluster(A, j, members, 64), c = j % 3;
    double *acc = A->w2; /* zero outside use */
    A->dstamp++;
    out->n = 0;
    for (int q = 0; q < nm && !e->code; q++) {
        int a = members[q] / 3, slot = 0;
        while (slot < nn && nodes[slot] != a) slot++;
        const aug_col *k = &cols[slot][c];
        for (int p = 0; p < k->n && !e->code; p++)
            for (int r = k->i[p]; r >= 0 && !e->code; r = A->par[r]) acc_add(A, acc, out, r, k->x[p], e);
    }
    for (int p = 0; p < out->n; p++) {
        out->x[p] = acc[out->i[p]];
        acc[out->i[p]] = 0;
    }
    return e->code;
}

/* Recompute the J columns of node a's Lset DOFs. */
static int refresh_node(kt_aug *A, int a, kt_err *e)
{
    int nodes[64], nn = 0, members[64];
    for (int c = 0; c < 3; c++) {
        if (A->Lpos[3 * a + c] < 0) continue;
        int nm = cluster(A, 3 * a + c, members, 64);
        for (int q = 0; q < nm; q++) {
            int b = members[q] / 3, have = 0;
            for (int t = 0; t < nn; t++) have |= nodes[t] == b;
            if (!have && nn < 64) nodes[nn++] = b;
        }
    }
    if (nn == 0) return KT_OK;
    aug_col (*cols)[3] = kt_calloc((size_t)nn, sizeof *cols, e);
    aug_col out = {0};
    if (!cols) return e->code;
    for (int t = 0; t < nn && !e->code; t++) aug_node_columns(A, nodes[t], cols[t], e);
    for (int c = 0; c < 3 && !e->code; c++)
        if (A->Lpos[3 * a + c] >= 0 && fold_column(A, 3 * a + c, nodes, nn, cols, &out, e) == KT_OK)
            set_jcol(A, A->Lpos[3 * a + c], &out, e);
    for (int t = 0; t < nn; t++)
        for (int c = 0; c < 3; c++) aug_col_free(&cols[t][c]);
    free(cols);
    aug_col_free(&out);
    return e->code;
}

/* ------------------------------------------------------------- node sets */

typedef struct nodeset {
    int n, cap, *v;
} nodeset;

static int set_add(kt_aug *A, nodeset *s, int a, kt_err *e)
{
    if (A->nmark[a] == A->nstamp) return KT_OK;
    A->nmark[a] = A->nstamp;
    if (s->n == s->cap) {
        int cap = s->cap ? 2 * s->cap : 64;
        int *p = kt_realloc(s->v, (size_t)cap, sizeof(int), e);
        if (!p) return e->code;
        s->v = p;
        s->cap = cap;
    }
    s->v[s->n++] = a;
    return KT_OK;
}

/* a and the nodes its DOFs hang on, up the parent chains. */
static int add_with_ancestors(kt_aug *A, nodeset *s, int a, kt_err *e)
{
    if (set_add(A, s, a, e)) return e->code;
    for (int c = 0; c < 3; c++)
        for (int r = A->par[3 * a + c]; r >= 0; r = A->par[r])
            if (set_add(A, s, r / 3, e)) return e->code;
    return KT_OK;
}

/* A new constraint changes P around its node: the node, its kids, their neighbours. */
static int add_around(kt_aug *A, nodeset *s, int a, kt_err *e)
{
    int nv = kt_tet_nv(A->mesh.order);
    int list[65], nl = 0;
    list[nl++] = a;
    for (int k = 0; k < A->kids_n[a] && nl < 65; k++) list[nl++] = A->kids[a][k];
    for (int q = 0; q < nl; q++)
        for (int t = 0; t < A->adj_n[list[q]]; t++)
            for (int l = 0; l < nv; l++)
                if (add_with_ancestors(A, s, A->mesh.tet[(size_t)A->adj[list[q]][t] * nv + l], e))
                    return e->code;
    return KT_OK;
}

/* Union of the J patterns (it contains Lset: every J column holds its own diagonal). */
static int jpattern(kt_aug *A, kt_err *e)
{
    A->dstamp++;
    A->njpat = 0;
    for (int k = 0; k < A->m; k++)
        for (int p = 0; p < A->J[k].n; p++) {
            int i = A->J[k].i[p];
            if (A->dmark[i] == A->dstamp) continue;
            A->dmark[i] = A->dstamp;
            if (A->njpat == A->jpcap) {
                int cap = A->jpcap ? 2 * A->jpcap : 256;
                int *pp = kt_realloc(A->Jpat, (size_t)cap, sizeof(int), e);
                if (!pp) return e->code;
                A->Jpat = pp;
                A->jpcap = cap;
            }
            A->Jpat[A->njpat++] = i;
        }
    return KT_OK;
}

static int refresh_set(kt_aug *A, const nodeset *s, kt_err *e)
{
    for (int q = 0; q < s->n && !e->code; q++) refresh_node(A, s->v[q], e);
    if (!e->code) jpattern(A, e);
    return e->code;
}

int aug_update_lset(kt_aug *A, const int *touched, int nt, const int *newc, int nc, kt_err *e)
{
    nodeset s = {0};
    A->nstamp++;
    for (int q = 0; q < nt && !e->code; q++) {
        int a = touched[q];
        for (int c = 0; c < 3; c++)
            if (!base_fixed(A, 3 * a + c)) lset_add(A, 3 * a + c, e);
        add_with_ancestors(A, &s, a, e);
    }
    for (int q = 0; q < nc && !e->code; q++) {
        if (!base_fixed(A, newc[q])) lset_add(A, newc[q], e);
        add_around(A, &s, newc[q] / 3, e);
    }
    if (!e->code) refresh_set(A, &s, e);
    free(s.v);
    return e->code;
}

int aug_rebuild_lists(kt_aug *A, kt_err *e)
{
    const aug_base *b = A->base;
    for (int k = 0; k < A->m; k++) A->Lpos[A->Ldof[k]] = -1;
    A->m = 0;
    for (int k = 0; k < A->nd; k++) A->ind[A->dlist[k]] = 0;
    A->nd = 0;
    int n = 3 * A->mesh.nn;
    for (int j = 0; j < n && j < b->n0; j++) A->par[j] = -1; /* base DOFs are plain again */
    nodeset s = {0};
    A->nstamp++;
    for (int j = 0; j < n && !e->code; j++) {
        int fresh = j >= b->n0;
        if (!base_fixed(A, j) && (fresh || A->touch_step[j / 3] > b->step ||
                                  (A->cons[j] && A->cons_step[j] > b->step))) {
            lset_add(A, j, e);
            set_add(A, &s, j / 3, e);
        }
        if (fresh || A->rhs_step[j] > b->step) aug_dlist_add(A, j, e);
    }
    if (!e->code) refresh_set(A, &s, e);
    free(s.v);
    return e->code;
}

/* ------------------------------------------------------ transformed vectors */

static int dpat_add(kt_aug *A, int i, kt_err *e)
{
    if (A->dmark[i] == A->dstamp) return KT_OK;
    A->dmark[i] = A->dstamp;
    if (A->ndpat == A->dpcap) {
        int cap = A->dpcap ? 2 * A->dpcap : 256;
        int *p = kt_realloc(A->dpat, (size_t)cap, sizeof(int), e);
        if (!p) return e->code;
        A->dpat = p;
        A->dpcap = cap;
    }
    A->dpat[A->ndpat++] = i;
    return KT_OK;
}

int aug_load_d(kt_aug *A, double *w, kt_err *e)
{
    const aug_base *b = A->base;
    A->dstamp++;
    A->ndpat = 0;
    for (int q = 0; q < A->nd && !e->code; q++) {
        int i = A->dlist[q];
        double fi = A->fh[i];
        w[i] += fi - (i < b->n0 ? b->fh0[i] : 0.0);
        dpat_add(A, i, e);
        for (int r = A->par[i]; r >= 0 && !e->code; r = A->par[r]) { /* (P^T fh)_r */
            w[r] += fi;
            dpat_add(A, r, e);
        }
    }
    return e->code;
}

void aug_unfold(const kt_aug *A, double *u)
{
    for (int j = A->base->n0; j < 3 * A->mesh.nn; j++)
        if (A->par[j] >= 0) u[j] += u[A->par[j]];
}
