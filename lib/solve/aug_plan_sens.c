/* aug_plan_sens.c: the planned method's derivatives (aug_plan_sens.h). */
#include "aug_plan_sens.h"

#include <stdlib.h>
#include <string.h>

void kt_plan_sens_free(kt_plan_sens *D)
{
    if (D->started) {
        for (int k = 0; k < KT_UQ_N; k++) cholmod_free_sparse(&D->dA[k], &D->c);
        cholmod_finish(&D->c);
    }
    for (int k = 0; k < KT_UQ_N; k++) free(D->dfe[k]);
    free(D->r);
    free(D->tf);
    free(D->y);
    free(D->dv);
    free(D->b);
    free(D->z);
    free(D->want);
    memset(D, 0, sizeof *D);
}

/* The variables' matrix as triplets (lower: v >= w); T NULL only counts. */
typedef struct tsink {
    cholmod_triplet *T;
    size_t nt;
} tsink;

static void tput(void *ctx, int v, int w, double x)
{
    tsink *s = ctx;
    if (s->T) {
        ((int *)s->T->i)[s->nt] = v;
        ((int *)s->T->j)[s->nt] = w;
        ((double *)s->T->x)[s->nt] = x;
    }
    s->nt++;
}

static cholmod_sparse *variable_matrix(kt_plan_sens *D, const kt_edits_plan *p,
                                       const cholmod_sparse *K, kt_err *e)
{
    tsink count = {NULL, 0};
    if (kt_plan_transform(p, K, tput, &count, e)) return NULL;
    size_t nt = count.nt;
    cholmod_triplet *T = cholmod_allocate_triplet(D->nvar, D->nvar, nt ? nt : 1, -1,
                                                  CHOLMOD_REAL, &D->c);
    if (!T) {
        kt_fail(e, KT_ERUN, "out of memory for a matrix derivative");
        return NULL;
    }
    cholmod_sparse *A = NULL;
    tsink fill = {T, 0};
    if (kt_plan_transform(p, K, tput, &fill, e) == KT_OK) {
        nt = fill.nt;
        T->nnz = nt;
        A = cholmod_triplet_to_sparse(T, nt, &D->c);
        if (!A) kt_fail(e, KT_ERUN, "out of memory for a matrix derivative");
    }
    cholmod_free_triplet(&T, &D->c);
    return A;
}

int kt_plan_sens_init(kt_plan_sens *D, const kt_fem_sens *S, const kt_edits_plan *p,
                      const kt_mesh *final, const kt_materials *mats, kt_err *e)
{
    double t0 = kt_now();
    memset(D, 0, sizeof *D);
    D->S = S;
    D->nvar = 3 * p->nn;
    cholmod_start(&D->c);
    D->started = 1;
    size_t n = (size_t)D->nvar;
    D->r = kt_calloc(n, sizeof(double), e);
    D->tf = kt_calloc(n, sizeof(double), e);
    D->y = kt_calloc(n, sizeof(double), e);
    D->dv = kt_calloc(n, sizeof(double), e);
    D->b = kt_calloc(n, sizeof(double), e);
    D->z = kt_calloc(n, sizeof(double), e);
    if (e->code) return e->code;
    const kt_mesh *m0 = final;
    int nv = kt_tet_nv(m0->order);
    size_t ld = 3 * (size_t)nv;
    for (int k = 0; k < S->nd; k++) {
        kt_materials dm = kt_fem_sens_mats(S, k, mats);
        if (!S->d[k].dK_zero) {
            cholmod_sparse *K = kt_fem_assemble(final, &dm, NULL, &D->c, e);
            if (!K) return e->code;
            D->dA[k] = variable_matrix(D, p, K, e);
            cholmod_free_sparse(&K, &D->c);
            if (!D->dA[k]) return e->code;
        }
        if (S->d[k].td.sig) { /* a tet's forces do not change with the cut: computed once */
            if (!(D->dfe[k] = kt_calloc((size_t)m0->ne * ld, sizeof(double), e))) return e->code;
            for (int el = 0; el < m0->ne; el++)
                if (kt_fem_element_release(m0, &dm, el, D->dfe[k] + el * ld, e)) return e->code;
        }
    }
    D->t_setup = kt_now() - t0;
    return KT_OK;
}

/* y := A v on the variables present (< n), A lower-stored symmetric. */
static void symv(const cholmod_sparse *A, int n, const double *v, double *y)
{
    const int *Ap = A->p, *Ai = A->i;
    const double *Ax = A->x;
    memset(y, 0, (size_t)n * sizeof(double));
    for (int j = 0; j < n; j++)
        for (int q = Ap[j]; q < Ap[j + 1]; q++) {
            int i = Ai[q];
            if (i >= n) break; /* row indices sorted */
            y[i] += Ax[q] * v[j];
            if (i != j) y[j] += Ax[q] * v[i];
        }
}

/* z := A_k^-1 z on the first N positions (L's numbering), rows >= N zero. */
static int substitute(kt_plan_sens *D, kt_plan_state *s, const kt_plan_factor *F, int N,
                      double *z, kt_err *e)
{
    kt_plan_forward(F, s->rwork, 0, N, z);
    memset(z + N, 0, (size_t)(F->nfree - N) * sizeof(double));
    if (F->L->is_super) {
        kt_plan_back(F, D->want, s->rwork, N, z);
        return KT_OK;
    }
    cholmod_dense Z = {(size_t)F->nfree, 1, (size_t)F->nfree, (size_t)F->nfree, z, NULL,
                       CHOLMOD_REAL, CHOLMOD_DOUBLE};
    cholmod_dense *X = cholmod_solve(F->L->is_ll ? CHOLMOD_Lt : CHOLMOD_DLt, F->L, &Z, &D->c);
    if (!X) return kt_fail(e, KT_ERUN, "CHOLMOD solve failed (status %d)", D->c.status);
    memcpy(z, X->x, (size_t)F->nfree * sizeof(double));
    cholmod_free_dense(&X, &D->c);
    return KT_OK;
}

int kt_plan_sens_solve(kt_plan_sens *D, kt_plan_state *s, const kt_edits_plan *p,
                       const kt_plan_factor *F, double *du, kt_err *e)
{
    double t0 = kt_now();
    const kt_fem_sens *S = D->S;
    const kt_mesh *m = &s->mesh;
    int nn = m->nn, n = 3 * nn, N = F->nfree_at[s->step], nv = kt_tet_nv(m->order);
    const int *Perm = F->L->Perm;
    for (int k = 0; k < S->nd; k++) {
        const kt_fem_dparam *d = &S->d[k];
        /* df/dq on the cut mesh: pressures (the step's pressure view), the release */
        memset(D->r, 0, (size_t)n * sizeof(double));
        for (int i = 0; i < S->npress; i++)
            if (d->dpress[i] != 0 && kt_fem_pressure(&s->pview, S->ptag[i], d->dpress[i], D->r, e))
                return e->code;
        if (D->dfe[k])
            for (int el = 0; el < m->ne; el++) {
                const int *t = m->tet + (size_t)el * nv;
                const double *fe = D->dfe[k] + (size_t)el * 3 * nv;
                for (int a = 0; a < nv; a++)
                    for (int c = 0; c < 3; c++) D->r[3 * (size_t)t[a] + c] += fe[3 * a + c];
            }
        /* T^T df/dq - (dA/dq)_k v on the free variables, into L's numbering */
        memset(D->tf, 0, (size_t)n * sizeof(double));
        for (int i = 0; i < n; i++)
            for (int a = i / 3; a >= 0; a = p->parent[a]) D->tf[3 * a + i % 3] += D->r[i];
        if (D->dA[k]) symv(D->dA[k], n, s->v, D->y);
        else memset(D->y, 0, (size_t)n * sizeof(double));
        memset(D->b, 0, (size_t)F->nfree * sizeof(double));
        for (int v = 0; v < n; v++)
            if (F->pos[v] >= 0) D->b[F->pos[v]] = D->tf[v] - D->y[v];
        for (int q = 0; q < F->nfree; q++) D->z[q] = q < N ? D->b[Perm[q]] : 0;
        if (substitute(D, s, F, N, D->z, e)) return e->code;
        for (int q = 0; q < F->nfree; q++) D->b[Perm[q]] = D->z[q];
        /* dv (constrained variables: their values do not depend on q), du = T dv */
        double *o = du + (size_t)k * n;
        for (int v = 0; v < n; v++) D->dv[v] = F->pos[v] >= 0 ? D->b[F->pos[v]] : 0;
        for (int a = 0; a < nn; a++)
            for (int c = 0; c < 3; c++)
                o[3 * a + c] = D->dv[3 * a + c] + (p->parent[a] >= 0 ? o[3 * p->parent[a] + c] : 0);
    }
    D->t_steps += kt_now() - t0;
    return KT_OK;
}
