/* aug_plan_subst.c: the planned method's substitutions with the factor of the final matrix,
 * limited to what a step reads: the released prefix of the variables (positions [0, N); the
 * rest are zero in every step) and, for restricted output, the wanted supernodes. They work
 * on the factor in place (no copy of any block) with BLAS 2 per supernode.
 *
 * Positions are L's (permuted) numbering. In a supernode s the first nscol rows are its own
 * columns S[s]..S[s+1]-1; the rest of its row list lies after them. When the row lists are
 * sorted (F->rows_sorted, checked at the build) the rows below a column that are released form
 * a prefix of the list, and the back substitution stops there. The forward substitution
 * updates every row below (the later rows keep the updates for the steps that release them). */
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

void kt_plan_subst_init(kt_plan_factor *F)
{
    const cholmod_factor *L = F->L;
    F->rows_sorted = 1;
    F->maxrow = 1;
    if (!L->is_super) return;
    const int *S = L->super, *pi = L->pi, *Ls = L->s;
    for (int s = 0; s < (int)L->nsuper; s++) {
        int nscol = S[s + 1] - S[s];
        if (pi[s + 1] - pi[s] > F->maxrow) F->maxrow = pi[s + 1] - pi[s];
        for (int q = pi[s] + nscol + 1; q < pi[s + 1]; q++)
            if (Ls[q] <= Ls[q - 1]) F->rows_sorted = 0;
    }
}

/* Simplicial: columns c0..c1-1, the diagonal first; LDL^T keeps a unit L. */
static void forward_simplicial(const cholmod_factor *L, int c0, int c1, double *y)
{
    const int *Lp = L->p, *Li = L->i, *Lnz = L->nz;
    const double *Lx = L->x;
    for (int j = c0; j < c1; j++) {
        int p0 = Lp[j], p1 = Lp[j] + Lnz[j];
        double yj = L->is_ll ? y[j] / Lx[p0] : y[j];
        y[j] = yj;
        for (int p = p0 + 1; p < p1; p++) y[Li[p]] -= Lx[p] * yj;
    }
}

/* The first supernode of L that ends after column c0 (nsuper when none). */
static int first_super(const cholmod_factor *L, int c0)
{
    const int *S = L->super;
    int lo = 0, hi = (int)L->nsuper;
    while (lo < hi) {
        int mid = lo + (hi - lo) / 2;
        if (S[mid + 1] <= c0) lo = mid + 1;
        else hi = mid;
    }
    return lo;
}

void kt_plan_forward(const kt_plan_factor *F, double *work, int c0, int c1, double *y)
{
    const cholmod_factor *L = F->L;
    if (!L->is_super) {
        forward_simplicial(L, c0, c1, y);
        return;
    }
    const int *S = L->super, *pi = L->pi, *px = L->px, *Ls = L->s;
    const double *Lx = L->x;
    double *w = work;
    int ns = (int)L->nsuper;
    for (int s = first_super(L, c0); s < ns && S[s] < c1; s++) {
        int k1 = S[s], nscol = S[s + 1] - k1, nsrow = pi[s + 1] - pi[s];
        int a = (k1 > c0 ? k1 : c0) - k1, b = (k1 + nscol < c1 ? k1 + nscol : c1) - k1;
        const double *X = Lx + px[s] + (size_t)a * nsrow;
        double *top = y + k1 + a;
        cblas_dtrsv(CblasColMajor, CblasLower, CblasNoTrans, CblasNonUnit, b - a, X + a, nsrow, top, 1);
        int nb = nsrow - b; /* rows below: s's own columns from b on, then its row list */
        if (nb == 0) continue;
        cblas_dgemv(CblasColMajor, CblasNoTrans, nb, b - a, 1.0, X + b, nsrow, top, 1, 0.0, w, 1);
        const int *rows = Ls + pi[s];
        for (int q = 0; q < nb; q++) y[rows[b + q]] -= w[q];
    }
}

void kt_plan_back(const kt_plan_factor *F, const unsigned char *want, double *work, int N,
                  double *y)
{
    const cholmod_factor *L = F->L;
    const int *S = L->super, *pi = L->pi, *px = L->px, *Ls = L->s;
    const double *Lx = L->x;
    double *w = work;
    for (int s = (int)L->nsuper - 1; s >= 0; s--) {
        int k1 = S[s], nscol = S[s + 1] - k1, nsrow = pi[s + 1] - pi[s];
        if (k1 >= N || (want && !want[s])) continue;
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

/* ---------------------------------------------- several right-hand sides at once (BLAS 3) */

/* Simplicial, nrhs interleaved columns: columns c0..c1-1 of the forward substitution. */
static void forward_simplicial_multi(const cholmod_factor *L, int c0, int c1, int nrhs,
                                     double *Y)
{
    const int *Lp = L->p, *Li = L->i, *Lnz = L->nz;
    const double *Lx = L->x;
    for (int j = c0; j < c1; j++) {
        int p0 = Lp[j], p1 = Lp[j] + Lnz[j];
        double *yj = Y + (size_t)j * nrhs;
        if (L->is_ll)
            for (int k = 0; k < nrhs; k++) yj[k] /= Lx[p0];
        for (int p = p0 + 1; p < p1; p++) {
            double *yi = Y + (size_t)Li[p] * nrhs;
            for (int k = 0; k < nrhs; k++) yi[k] -= Lx[p] * yj[k];
        }
    }
}

/* Simplicial: Y[0..N) := L^-T (LL^T) or L^-T D^-1 (LDL^T) of it, rows >= N zero. */
static void back_simplicial_multi(const cholmod_factor *L, int N, int nrhs, double *Y)
{
    const int *Lp = L->p, *Li = L->i, *Lnz = L->nz;
    const double *Lx = L->x;
    for (int j = N - 1; j >= 0; j--) {
        int p0 = Lp[j], p1 = Lp[j] + Lnz[j];
        double *yj = Y + (size_t)j * nrhs;
        if (!L->is_ll)
            for (int k = 0; k < nrhs; k++) yj[k] /= Lx[p0];
        for (int p = p0 + 1; p < p1; p++) {
            const double *yi = Y + (size_t)Li[p] * nrhs;
            for (int k = 0; k < nrhs; k++) yj[k] -= Lx[p] * yi[k];
        }
        if (L->is_ll)
            for (int k = 0; k < nrhs; k++) yj[k] /= Lx[p0];
    }
}

/* Row-major blocks of nrhs values are column-major nrhs x rows matrices: the supernode's
 * triangle and rectangle apply from the right (Y^T L^T = B^T forward, Y^T L = B^T back). */
void kt_plan_forward_multi(const kt_plan_factor *F, double *work, int c0, int c1, int nrhs,
                           int upto, double *Y)
{
    const cholmod_factor *L = F->L;
    if (!L->is_super) {
        forward_simplicial_multi(L, c0, c1, nrhs, Y);
        return;
    }
    const int *S = L->super, *pi = L->pi, *px = L->px, *Ls = L->s;
    const double *Lx = L->x;
    int ns = (int)L->nsuper;
    for (int s = first_super(L, c0); s < ns && S[s] < c1; s++) {
        int k1 = S[s], nscol = S[s + 1] - k1, nsrow = pi[s + 1] - pi[s];
        int a = (k1 > c0 ? k1 : c0) - k1, b = (k1 + nscol < c1 ? k1 + nscol : c1) - k1;
        const double *X = Lx + px[s] + (size_t)a * nsrow;
        double *top = Y + (size_t)(k1 + a) * nrhs;
        cblas_dtrsm(CblasColMajor, CblasRight, CblasLower, CblasTrans, CblasNonUnit, nrhs, b - a,
                    1.0, X + a, nsrow, top, nrhs);
        /* rows below: s's own columns from b on, then its row list (sorted: those < upto a
         * prefix of it; else all of them) */
        int nb = k1 + nscol <= upto ? nscol - b + rows_below(F, s, upto)
                                    : (upto - k1 - b > 0 ? upto - k1 - b : 0);
        if (nb == 0) continue;
        cblas_dgemm(CblasColMajor, CblasNoTrans, CblasTrans, nrhs, nb, b - a, 1.0, top, nrhs,
                    X + b, nsrow, 0.0, work, nrhs);
        const int *rows = Ls + pi[s] + b;
        for (int q = 0; q < nb; q++) {
            double *yr = Y + (size_t)rows[q] * nrhs;
            const double *wq = work + (size_t)q * nrhs;
            for (int k = 0; k < nrhs; k++) yr[k] -= wq[k];
        }
    }
}

void kt_plan_back_multi(const kt_plan_factor *F, const unsigned char *want, double *work, int N,
                        int nrhs, double *Y)
{
    const cholmod_factor *L = F->L;
    if (!L->is_super) {
        back_simplicial_multi(L, N, nrhs, Y);
        return;
    }
    const int *S = L->super, *pi = L->pi, *px = L->px, *Ls = L->s;
    const double *Lx = L->x;
    for (int s = (int)L->nsuper - 1; s >= 0; s--) {
        int k1 = S[s], nscol = S[s + 1] - k1, nsrow = pi[s + 1] - pi[s];
        if (k1 >= N || (want && !want[s])) continue;
        int nc = k1 + nscol < N ? nscol : N - k1;
        const double *X = Lx + px[s];
        double *top = Y + (size_t)k1 * nrhs;
        int nr = nc < nscol ? 0 : rows_below(F, s, N);
        if (nr > 0) {
            const int *rows = Ls + pi[s] + nscol;
            for (int q = 0; q < nr; q++) {
                const double *yr = Y + (size_t)rows[q] * nrhs;
                for (int k = 0; k < nrhs; k++) work[(size_t)q * nrhs + k] = yr[k];
            }
            cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, nrhs, nc, nr, -1.0, work,
                        nrhs, X + nscol, nsrow, 1.0, top, nrhs);
        }
        cblas_dtrsm(CblasColMajor, CblasRight, CblasLower, CblasNoTrans, CblasNonUnit, nrhs, nc,
                    1.0, X, nsrow, top, nrhs);
    }
}
