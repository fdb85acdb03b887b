/* aug_plan_subst.c: the planned method's substitutions with the factor of the final matrix,
 * limited to what a step reads: the released prefix of the variables (positions [0, N); the
 * rest are zero in every step) and, for restricted output, the wanted supernodes. They work
 * on the factor in place (no copy of any block) with BLAS 2 per supernode.
 *
 * Positions are L's (permuted) numbering. In a supernode s the first nscol rows are its own
 * columns S[s]..S[s+1]-1; the rest of its row list lies after them. When the row lists are
 * sorted (F->rows_sorted, checked at the build) the rows below a column that are released form
 * a prefix of the list, and the substitutions stop there. */
#include "aug_plan.h"

#include <cblas.h>

/* Rows of supernode s's row list after its own columns that are < N. */
static int rows_below(const kt_plan_factor *F, int s, int N)
{
    const cholmod_factor *L = F->L;
    const int *S = L->super, *pi = L->pi, *Ls = L->s;
    int nscol = S[s + 1] - S[s], lo = pi[s] + nscol, hi = pi[s + 1];
    if (!F->rows_sorted) return hi - lo; /* the unreleased rows are zero in the vector */
    while (lo < hi) {
        int mid = lo + (hi - lo) / 2;
        if (Ls[mid] < N) lo = mid + 1;
        else hi = mid;
    }
    return lo - (pi[s] + nscol);
}

int kt_plan_subst_init(kt_plan_factor *F, kt_err *e)
{
    const cholmod_factor *L = F->L;
    F->rows_sorted = 1;
    if (!L->is_super) return KT_OK;
    const int *S = L->super, *pi = L->pi, *Ls = L->s;
    int maxrow = 1;
    for (int s = 0; s < (int)L->nsuper; s++) {
        int nscol = S[s + 1] - S[s];
        if (pi[s + 1] - pi[s] > maxrow) maxrow = pi[s + 1] - pi[s];
        for (int q = pi[s] + nscol + 1; q < pi[s + 1]; q++)
            if (Ls[q] <= Ls[q - 1]) F->rows_sorted = 0;
    }
    F->rwork = kt_calloc((size_t)maxrow, sizeof(double), e);
    return e->code;
}

/* Simplicial: columns j in [nK, N), the diagonal first; LDL^T keeps a unit L. */
static void forward_trailing_simplicial(const kt_plan_factor *F, int N, double *y)
{
    const cholmod_factor *L = F->L;
    const int *Lp = L->p, *Li = L->i, *Lnz = L->nz;
    const double *Lx = L->x;
    for (int j = F->nK; j < N; j++) {
        int p0 = Lp[j], p1 = Lp[j] + Lnz[j];
        double yj = L->is_ll ? y[j] / Lx[p0] : y[j];
        y[j] = yj;
        for (int p = p0 + 1; p < p1; p++)
            if (Li[p] < N) y[Li[p]] -= Lx[p] * yj;
    }
}

void kt_plan_forward_trailing(const kt_plan_factor *F, int N, double *y)
{
    const cholmod_factor *L = F->L;
    if (!L->is_super) {
        forward_trailing_simplicial(F, N, y);
        return;
    }
    const int *S = L->super, *pi = L->pi, *px = L->px, *Ls = L->s;
    const double *Lx = L->x;
    double *w = F->rwork;
    int ns = (int)L->nsuper, s = ns;
    while (s > 0 && S[s] > F->nK) s--; /* the first supernode ending after nK */
    for (; s < ns && S[s] < N; s++) {
        int k1 = S[s], nscol = S[s + 1] - k1, nsrow = pi[s + 1] - pi[s];
        int c0 = (k1 > F->nK ? k1 : F->nK) - k1, c1 = (k1 + nscol < N ? k1 + nscol : N) - k1;
        const double *X = Lx + px[s];
        double *top = y + k1 + c0;
        cblas_dtrsv(CblasColMajor, CblasLower, CblasNoTrans, CblasNonUnit, c1 - c0,
                    X + c0 + (size_t)c0 * nsrow, nsrow, top, 1);
        if (c1 < nscol) break; /* N falls inside s: every row below is unreleased */
        int nr = rows_below(F, s, N);
        if (nr == 0) continue;
        cblas_dgemv(CblasColMajor, CblasNoTrans, nr, c1 - c0, 1.0, X + nscol + (size_t)c0 * nsrow,
                    nsrow, top, 1, 0.0, w, 1);
        const int *rows = Ls + pi[s] + nscol;
        for (int q = 0; q < nr; q++)
            if (rows[q] < N) y[rows[q]] -= w[q];
    }
}

void kt_plan_back(const kt_plan_factor *F, int N, double *y)
{
    const cholmod_factor *L = F->L;
    const int *S = L->super, *pi = L->pi, *px = L->px, *Ls = L->s;
    const double *Lx = L->x;
    double *w = F->rwork;
    for (int s = (int)L->nsuper - 1; s >= 0; s--) {
        int k1 = S[s], nscol = S[s + 1] - k1, nsrow = pi[s + 1] - pi[s];
        if (k1 >= N || (F->want && !F->want[s])) continue;
        int nc = k1 + nscol < N ? nscol : N - k1;
        const double *X = Lx + px[s];
        double *top = y + k1;
        int nr = nc < nscol ? 0 : rows_below(F, s, N);
        if (nr > 0) {
            const int *rows = Ls + pi[s] + nscol;
            for (int q = 0; q < nr; q++) w[q] = y[rows[q]];
            cblas_dgemv(CblasColMajor, CblasTrans, nr, nc, -1.0, X + nscol, nsrow, w, 1, 1.0, top, 1);
        }
        cblas_dtrsv(CblasColMajor, CblasLower, CblasTrans, CblasNonUnit, nc, X, nsrow, top, 1);
    }
}
