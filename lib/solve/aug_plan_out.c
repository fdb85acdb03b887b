/* aug_plan_out.c: restricted output for the planned method: the supernodes of L that the back
 * substitution needs for the DOFs of an output node set (their ancestors in the supernodal
 * elimination tree), and the back substitution limited to them. */
#include "aug_plan.h"

#include <stdlib.h>
#include <string.h>

/* The supernode holding each column, and each supernode's parent (-1: a root). */
static int super_tree(const cholmod_factor *L, int *col_super, int *parent)
{
    const int *S = L->super, *pi = L->pi, *Ls = L->s;
    int ns = (int)L->nsuper;
    for (int s = 0; s < ns; s++)
        for (int j = S[s]; j < S[s + 1]; j++) col_super[j] = s;
    for (int s = 0; s < ns; s++) {
        int nscol = S[s + 1] - S[s], nsrow = pi[s + 1] - pi[s];
        parent[s] = nsrow > nscol ? col_super[Ls[pi[s] + nscol]] : -1;
    }
    return ns;
}

int kt_plan_factor_restrict(kt_plan_factor *F, const kt_plan *p, const unsigned char *nodes,
                            kt_err *e)
{
    free(F->want);
    free(F->rwork);
    F->want = NULL;
    F->rwork = NULL;
    F->want_cols = 0;
    const cholmod_factor *L = F->L;
    if (!L->is_super || !nodes) return KT_OK;
    int n = F->nfree, ns = (int)L->nsuper;
    int maxrow = 1;
    for (int s = 0; s < ns; s++)
        if (((const int *)L->pi)[s + 1] - ((const int *)L->pi)[s] > maxrow)
            maxrow = ((const int *)L->pi)[s + 1] - ((const int *)L->pi)[s];
    if (!(F->rwork = kt_calloc((size_t)maxrow, sizeof(double), e))) return e->code;
    int *col_super = kt_calloc((size_t)n ? (size_t)n : 1, sizeof(int), e);
    int *parent = kt_calloc((size_t)ns ? (size_t)ns : 1, sizeof(int), e);
    int *ipos = kt_calloc((size_t)n ? (size_t)n : 1, sizeof(int), e);
    unsigned char *need = kt_calloc((size_t)p->nn, 1, e);
    F->want = kt_calloc((size_t)ns ? (size_t)ns : 1, 1, e);
    if (!e->code) {
        super_tree(L, col_super, parent);
        const int *Perm = L->Perm;
        for (int q = 0; q < n; q++) ipos[Perm[q]] = q;
        for (int a = 0; a < p->nn; a++) /* an output node needs its ancestors' variables */
            if (nodes[a])
                for (int b = a; b >= 0 && !need[b]; b = p->parent[b]) need[b] = 1;
        for (int v = 0; v < F->nvar; v++) {
            if (!need[v / 3] || F->pos[v] < 0) continue;
            for (int s = col_super[ipos[F->pos[v]]]; s >= 0 && !F->want[s]; s = parent[s])
                F->want[s] = 1;
        }
        const int *S = L->super;
        for (int s = 0; s < ns; s++)
            if (F->want[s]) F->want_cols += S[s + 1] - S[s];
    }
    free(col_super);
    free(parent);
    free(ipos);
    free(need);
    return e->code;
}

/* x . y over n entries, four partial sums (the compiler keeps them in registers). */
static double dot4(const double *x, const double *y, int n)
{
    double s0 = 0, s1 = 0, s2 = 0, s3 = 0;
    int q = 0;
    for (; q + 4 <= n; q += 4) {
        s0 += x[q] * y[q];
        s1 += x[q + 1] * y[q + 1];
        s2 += x[q + 2] * y[q + 2];
        s3 += x[q + 3] * y[q + 3];
    }
    for (; q < n; q++) s0 += x[q] * y[q];
    return (s0 + s1) + (s2 + s3);
}

/* y := L^-T y on the wanted supernodes only (in place, permuted numbering); the entries of the
 * others are left as they were. Exact there: a supernode's rows lie in its ancestors. Each
 * supernode gathers its rows' values into F->rwork once, so its columns are contiguous dot
 * products. */
void kt_plan_back_restricted(const kt_plan_factor *F, double *y)
{
    const cholmod_factor *L = F->L;
    const int *S = L->super, *pi = L->pi, *px = L->px, *Ls = L->s;
    const double *Lx = L->x;
    double *w = F->rwork;
    for (int s = (int)L->nsuper - 1; s >= 0; s--) {
        if (!F->want[s]) continue;
        int k1 = S[s], nscol = S[s + 1] - k1, nsrow = pi[s + 1] - pi[s];
        const int *rows = Ls + pi[s];
        const double *X = Lx + px[s];
        for (int q = 0; q < nsrow; q++) w[q] = y[rows[q]];
        for (int jj = nscol - 1; jj >= 0; jj--) {
            const double *col = X + (size_t)jj * nsrow;
            w[jj] = (w[jj] - dot4(col + jj + 1, w + jj + 1, nsrow - jj - 1)) / col[jj];
        }
        for (int jj = 0; jj < nscol; jj++) y[k1 + jj] = w[jj];
    }
}
