/* aug_border.c: the variables a stream appends to the intact ones, in release order, and the
 * factor of the bordered matrix they make.
 *
 * A new node's DOF is written as an increment over its parent's (u = u_parent + d; a node
 * split twice chains), so the intact block K never changes: a step appends the columns of its
 * increments, A(:, d) = T^T K_now(:, dof) (T: variables -> displacements of the current mesh),
 * and, for a DOF constrained after step 0, a multiplier whose column is s T(dof, :)^T (s: the
 * DOF's diagonal stiffness, for balance). Tets only move from a node to its new child, so an
 * appended column never changes afterwards. With W = L^-1 P C the Schur complement
 * S = D - W^T W grows by the new rows and columns; its dense factor Ls Ds Ls^T is extended
 * block by block (BLAS 3), no pivoting: S is positive definite on the increments and each
 * multiplier comes after every variable its row holds (quasi-definite in that order). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <cblas.h>

#include "aug_impl.h"

int kt_aug_border_init(aug_border *B, const aug_intact *F, kt_err *e)
{
    memset(B, 0, sizeof *B);
    B->wb = kt_calloc((size_t)F->nsuper + 1, sizeof(aug_wblock), e);
    return e->code;
}

void kt_aug_border_free(aug_border *B, const aug_intact *F)
{
    for (int q = 0; q < B->m; q++) {
        kt_aug_col_free(&B->var[q].C);
        kt_aug_col_free(&B->var[q].D);
    }
    for (int s = 0; B->wb && s < F->nsuper; s++) {
        free(B->wb[s].col);
        free(B->wb[s].x);
    }
    free(B->wb);
    free(B->var);
    free(B->apos);
    free(B->mpos);
    free(B->Ls);
    free(B->Ds);
    free(B->tmp);
    memset(B, 0, sizeof *B);
}

/* Room for m appended variables (Ls keeps its values under a new leading dimension) and for
 * the DOFs of nn nodes. */
static int reserve(aug_border *B, int m, int nn, kt_err *e)
{
    if (3 * nn > B->dof_cap) {
        int n = 3 * nn;
        int *a = kt_realloc(B->apos, (size_t)n, sizeof(int), e);
        if (a) B->apos = a;
        int *b = a ? kt_realloc(B->mpos, (size_t)n, sizeof(int), e) : NULL;
        if (!b) return e->code;
        B->mpos = b;
        for (int j = B->dof_cap; j < n; j++) B->apos[j] = B->mpos[j] = -1;
        B->dof_cap = n;
    }
    if (m <= B->cap) return KT_OK;
    int cap = B->cap ? 2 * B->cap : 64;
    while (cap < m) cap *= 2;
    aug_var *v = kt_realloc(B->var, (size_t)cap, sizeof *v, e);
    if (!v) return e->code;
    B->var = v;
    memset(B->var + B->cap, 0, (size_t)(cap - B->cap) * sizeof *v);
    double *Ls = kt_calloc((size_t)cap * cap, sizeof(double), e);
    double *Ds = kt_realloc(B->Ds, (size_t)cap, sizeof(double), e);
    if (Ds) B->Ds = Ds;
    double *tmp = kt_realloc(B->tmp, (size_t)cap, sizeof(double), e);
    if (tmp) B->tmp = tmp;
    if (!Ls || !Ds || !tmp) {
        free(Ls);
        return e->code;
    }
    for (int j = 0; j < B->m; j++)
        memcpy(Ls + (size_t)j * cap, B->Ls + (size_t)j * B->cap, (size_t)B->m * sizeof(double));
    free(B->Ls);
    B->Ls = Ls;
    B->cap = cap;
    return KT_OK;
}

/* A dense accumulator with the list of its touched entries. */
typedef struct acc {
    double *x;
    int *list, *mark, n;
} acc;

static void acc_add(acc *a, int i, double v)
{
    if (!a->mark[i]) {
        a->mark[i] = 1;
        a->list[a->n++] = i;
        a->x[i] = 0;
    }
    a->x[i] += v;
}

/* Move the accumulated entries into col and clear the accumulator. */
static int acc_take(acc *a, aug_col *col, kt_err *e)
{
    if (kt_aug_col_reserve(col, a->n ? a->n : 1, e)) return e->code;
    col->n = 0;
    for (int k = 0; k < a->n; k++) {
        int i = a->list[k];
        if (a->x[i] != 0) {
            col->i[col->n] = i;
            col->x[col->n++] = a->x[i];
        }
        a->mark[i] = 0;
    }
    a->n = 0;
    return KT_OK;
}

/* Add x at every variable that DOF i's displacement sums (the DOF's node and its ancestors):
 * intact free ones into C, appended ones up to index q into D; the intact scene's constrained
 * ones are the lifting's (aug_solve.c). */
static void spread(const aug_border *B, const aug_intact *F, const aug_stream *s, int i, double x,
                   int q, acc *C, acc *D)
{
    int c = i % 3;
    for (int a = i / 3; a >= 0; a = s->parent[a]) {
        int v = 3 * a + c;
        if (a < s->nn0) {
            if (F->pos[v] >= 0) acc_add(C, F->pos[v], x);
        } else if (B->apos[v] >= 0 && B->apos[v] <= q) {
            acc_add(D, B->apos[v], x);
        }
    }
}

/* The C and D parts of the step's new variables m_old..B->m. */
static int columns(aug_border *B, const aug_intact *F, aug_stream *s, int m_old, acc *C, acc *D,
                   kt_err *e)
{
    aug_col col[3] = {{0}};
    int have = -1;
    for (int q = m_old; q < B->m && !e->code; q++) {
        aug_var *v = &B->var[q];
        int a = v->dof / 3, c = v->dof % 3;
        if (have != a && kt_aug_node_columns(s, a, col, e)) break;
        have = a;
        if (v->kind == AUG_INCREMENT) {
            for (int p = 0; p < col[c].n; p++) spread(B, F, s, col[c].i[p], col[c].x[p], q, C, D);
        } else {
            v->scale = 1;
            for (int p = 0; p < col[c].n; p++)
                if (col[c].i[p] == v->dof) v->scale = col[c].x[p];
            spread(B, F, s, v->dof, v->scale, q - 1, C, D);
        }
        if (acc_take(C, &v->C, e) || acc_take(D, &v->D, e)) break;
    }
    for (int k = 0; k < 3; k++) kt_aug_col_free(&col[k]);
    return e->code;
}

/* Append appended column q with values x on the columns of supernode s. */
static int wblock_add(aug_wblock *w, int ncol, int q, const double *x, kt_err *e)
{
    if (w->n == w->cap) {
        int cap = w->cap ? 2 * w->cap : 8;
        int *c = kt_realloc(w->col, (size_t)cap, sizeof(int), e);
        if (c) w->col = c;
        double *v = c ? kt_realloc(w->x, (size_t)cap * ncol, sizeof(double), e) : NULL;
        if (!v) return e->code;
        w->x = v;
        w->cap = cap;
    }
    w->col[w->n] = q;
    memcpy(w->x + (size_t)w->n * ncol, x, (size_t)ncol * sizeof(double));
    w->n++;
    return KT_OK;
}

/* W columns of the new variables: a forward substitution on the closure of each C column. */
static int w_columns(aug_border *B, const aug_intact *F, int m_old, int *touched, int *nt,
                     kt_err *e)
{
    const int *S = F->L->super;
    double *x = kt_calloc((size_t)F->nK, sizeof(double), e);
    double *tmp = kt_calloc((size_t)F->maxrow + 1, sizeof(double), e);
    int *rows = kt_calloc((size_t)F->nK, sizeof(int), e);
    int *sup = kt_calloc((size_t)F->nsuper + 1, sizeof(int), e);
    int *mark = kt_calloc((size_t)F->nsuper + 1, sizeof(int), e);
    *nt = 0;
    B->closure_max = 0;
    for (int q = m_old; q < B->m && !e->code; q++) {
        const aug_col *C = &B->var[q].C;
        if (C->n == 0) continue;
        for (int p = 0; p < C->n; p++) {
            rows[p] = F->iperm[C->i[p]];
            x[rows[p]] = C->x[p];
        }
        int ns = kt_aug_intact_closure(F, rows, C->n, sup, mark, q + 1), cols = 0;
        kt_aug_intact_forward_on(F, sup, ns, x, tmp);
        for (int k = 0; k < ns && !e->code; k++) {
            int s = sup[k], k1 = S[s], ncol = S[s + 1] - k1;
            aug_wblock *w = &B->wb[s];
            if (w->n == 0 || w->col[w->n - 1] < m_old) touched[(*nt)++] = s;
            if (wblock_add(w, ncol, q, x + k1, e)) break;
            memset(x + k1, 0, (size_t)ncol * sizeof(double));
            B->wnnz += ncol;
            cols += ncol;
        }
        if (cols > B->closure_max) B->closure_max = cols;
    }
    free(x);
    free(tmp);
    free(rows);
    free(sup);
    free(mark);
    return e->code;
}

/* Sb (m x k, leading dimension m: the new columns of S) = D part - W^T W_new. */
static void schur_block(const aug_border *B, const aug_intact *F, int m_old, const int *touched,
                        int nt, double *Sb, double *G)
{
    int m = B->m;
    for (int q = m_old; q < m; q++) {
        const aug_col *D = &B->var[q].D;
        for (int p = 0; p < D->n; p++) {
            int r = D->i[p];
            Sb[r + (size_t)(q - m_old) * m] += D->x[p];
            if (r >= m_old && r != q) Sb[q + (size_t)(r - m_old) * m] += D->x[p];
        }
    }
    const int *S = F->L->super;
    for (int k = 0; k < nt; k++) {
        const aug_wblock *w = &B->wb[touched[k]];
        int ncol = S[touched[k] + 1] - S[touched[k]], nold = 0;
        while (w->col[nold] < m_old) nold++;
        int nnew = w->n - nold;
        cblas_dgemm(CblasColMajor, CblasTrans, CblasNoTrans, w->n, nnew, ncol, 1.0, w->x, ncol,
                    w->x + (size_t)nold * ncol, ncol, 0.0, G, w->n);
        for (int j = 0; j < nnew; j++)
            for (int i = 0; i < w->n; i++)
                Sb[w->col[i] + (size_t)(w->col[nold + j] - m_old) * m] -= G[i + (size_t)j * w->n];
    }
}

/* Extend Ls, Ds by the k = m - m_old new rows: L21 = S21 L11^-T D1^-1, then the dense
 * LDL^T of S22 - L21 D1 L21^T. A pivot of the wrong sign is a numerical failure. */
static int extend(aug_border *B, int m_old, double *Sb, kt_err *e)
{
    int m = B->m, k = m - m_old, cap = B->cap;
    double *L = B->Ls, *Dv = B->Ds, *S22 = Sb + m_old;
    if (m_old > 0) {
        double *Z = kt_calloc((size_t)m_old * k, sizeof(double), e);
        if (!Z) return e->code;
        cblas_dtrsm(CblasColMajor, CblasLeft, CblasLower, CblasNoTrans, CblasUnit, m_old, k, 1.0,
                    L, cap, Sb, m);
        for (int j = 0; j < k; j++)
            for (int i = 0; i < m_old; i++) Z[i + (size_t)j * m_old] = Sb[i + (size_t)j * m] / Dv[i];
        cblas_dgemm(CblasColMajor, CblasTrans, CblasNoTrans, k, k, m_old, -1.0, Sb, m, Z, m_old,
                    1.0, S22, m);
        for (int i = 0; i < k; i++)
            for (int j = 0; j < m_old; j++) L[(m_old + i) + (size_t)j * cap] = Z[j + (size_t)i * m_old];
        free(Z);
    }
    for (int j = 0; j < k; j++) {
        int J = m_old + j;
        double d = S22[j + (size_t)j * m];
        for (int p = 0; p < j; p++) {
            double l = L[J + (size_t)(m_old + p) * cap];
            d -= l * l * Dv[m_old + p];
        }
        int want = B->var[J].kind == AUG_INCREMENT ? 1 : -1;
        if (!(d * want > 0))
            return kt_fail(e, KT_ERUN, "the bordered matrix is not quasi-definite at its appended "
                           "variable %d (%s of DOF %d of node %d: pivot %.3g): is a part of the "
                           "body free to move rigidly, or a DOF fixed twice?", J + 1,
                           want > 0 ? "increment" : "multiplier", B->var[J].dof % 3 + 1,
                           B->var[J].dof / 3 + 1, d);
        Dv[J] = d;
        L[J + (size_t)J * cap] = 1;
        for (int i = j + 1; i < k; i++) {
            double v = S22[i + (size_t)j * m];
            for (int p = 0; p < j; p++)
                v -= L[m_old + i + (size_t)(m_old + p) * cap] * L[J + (size_t)(m_old + p) * cap] *
                     Dv[m_old + p];
            L[m_old + i + (size_t)J * cap] = v / d;
        }
    }
    return KT_OK;
}

/* The step's new variables: increments of the new nodes, then multipliers. */
static void register_vars(aug_border *B, const aug_stream *s, int nn_old, const int *newc, int nc)
{
    for (int j = 3 * nn_old; j < 3 * s->mesh.nn; j++) {
        B->var[B->m] = (aug_var){.kind = AUG_INCREMENT, .dof = j};
        B->apos[j] = B->m++;
    }
    for (int k = 0; k < nc; k++) {
        if (newc[k] < 3 * s->nn0 && s->fixed0[newc[k]]) continue;
        B->var[B->m] = (aug_var){.kind = AUG_MULTIPLIER, .dof = newc[k]};
        B->mpos[newc[k]] = B->m++;
    }
}

int kt_aug_border_append(aug_border *B, const aug_intact *F, aug_stream *s, int nn_old,
                      const int *newc, int nc, kt_err *e)
{
    int m_old = B->m, k = 3 * (s->mesh.nn - nn_old) + nc;
    if (k == 0) return KT_OK;
    if (reserve(B, m_old + k, s->mesh.nn, e)) return e->code;
    register_vars(B, s, nn_old, newc, nc);
    k = B->m - m_old;
    acc C = {0}, D = {0};
    C.x = kt_calloc((size_t)F->nK, sizeof(double), e);
    C.list = kt_calloc((size_t)F->nK, sizeof(int), e);
    C.mark = kt_calloc((size_t)F->nK, sizeof(int), e);
    D.x = kt_calloc((size_t)B->m, sizeof(double), e);
    D.list = kt_calloc((size_t)B->m, sizeof(int), e);
    D.mark = kt_calloc((size_t)B->m, sizeof(int), e);
    int *touched = kt_calloc((size_t)F->nsuper + 1, sizeof(int), e), nt = 0;
    double *Sb = kt_calloc((size_t)B->m * k, sizeof(double), e);
    double *G = kt_calloc((size_t)B->m * k, sizeof(double), e);
    if (!e->code && !columns(B, F, s, m_old, &C, &D, e) && !w_columns(B, F, m_old, touched, &nt, e)) {
        schur_block(B, F, m_old, touched, nt, Sb, G);
        extend(B, m_old, Sb, e);
    }
    free(C.x);
    free(C.list);
    free(C.mark);
    free(D.x);
    free(D.list);
    free(D.mark);
    free(touched);
    free(Sb);
    free(G);
    return e->code;
}

void kt_aug_border_solve(const aug_border *B, double *r)
{
    if (B->m == 0) return;
    cblas_dtrsv(CblasColMajor, CblasLower, CblasNoTrans, CblasUnit, B->m, B->Ls, B->cap, r, 1);
    for (int i = 0; i < B->m; i++) r[i] /= B->Ds[i];
    cblas_dtrsv(CblasColMajor, CblasLower, CblasTrans, CblasUnit, B->m, B->Ls, B->cap, r, 1);
}

void kt_aug_border_wt(const aug_border *B, const aug_intact *F, const double *y, double *r)
{
    const int *S = F->L->super;
    for (int s = 0; B->m && s < F->nsuper; s++) {
        const aug_wblock *w = &B->wb[s];
        if (w->n == 0) continue;
        int k1 = S[s], ncol = S[s + 1] - k1;
        cblas_dgemv(CblasColMajor, CblasTrans, ncol, w->n, 1.0, w->x, ncol, y + k1, 1, 0.0, B->tmp, 1);
        for (int i = 0; i < w->n; i++) r[w->col[i]] -= B->tmp[i];
    }
}

void kt_aug_border_w(const aug_border *B, const aug_intact *F, const double *d, double *y)
{
    const int *S = F->L->super;
    for (int s = 0; B->m && s < F->nsuper; s++) {
        const aug_wblock *w = &B->wb[s];
        if (w->n == 0) continue;
        int k1 = S[s], ncol = S[s + 1] - k1;
        for (int i = 0; i < w->n; i++) B->tmp[i] = d[w->col[i]];
        cblas_dgemv(CblasColMajor, CblasNoTrans, ncol, w->n, -1.0, w->x, ncol, B->tmp, 1, 1.0, y + k1, 1);
    }
}
