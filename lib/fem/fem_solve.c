/* fem_solve.c: Dirichlet lifting and the checked direct solve of a whole-mesh problem. */
#include "fem.h"

#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "chol.h"
#include "topology.h"

/* ------------------------------------------------------------ lift and solve */

int kt_fem_lift(const cholmod_sparse *K, const unsigned char *fixed, const double *g, double *f,
                kt_err *e)
{
    if (K->xtype != CHOLMOD_REAL || K->itype != CHOLMOD_INT || K->nrow != K->ncol)
        return kt_fail(e, KT_ERUN, "lift: expected a square real CHOLMOD matrix (int indices)");
    if (!fixed) return KT_OK;
    const int *Kp = K->p, *Ki = K->i, *Knz = K->nz;
    const double *Kx = K->x;
    int n = (int)K->ncol;
    for (int j = 0; j < n; j++) {
        int end = K->packed ? Kp[j + 1] : Kp[j] + Knz[j];
        for (int p = Kp[j]; p < end; p++) {
            int i = Ki[p];
            if (i == j || (K->stype < 0 && i < j) || (K->stype > 0 && i > j)) continue;
            double gj = g ? g[j] : 0.0, gi = g ? g[i] : 0.0;
            if (!fixed[i] && fixed[j]) f[i] -= Kx[p] * gj;
            if (K->stype != 0 && fixed[i] && !fixed[j]) f[j] -= Kx[p] * gi; /* mirrored entry */
        }
    }
    for (int i = 0; i < n; i++)
        if (fixed[i]) f[i] = g ? g[i] : 0.0;
    return KT_OK;
}

/* A dense column wrapped around caller memory (no copy). */
static double norm2(const double *x, size_t n)
{
    double s = 0;
    for (size_t i = 0; i < n; i++) s += x[i] * x[i];
    return sqrt(s);
}

/* || |A| |x| + |b| ||_2: the size of the terms that the residual A x - b sums, so the floor
 * that rounding alone puts under it (A symmetric, one triangle stored). */
static double residual_scale(const cholmod_sparse *A, const double *x, const double *b, double *s)
{
    const int *Ap = A->p, *Ai = A->i;
    const double *Ax = A->x;
    size_t n = A->ncol;
    for (size_t i = 0; i < n; i++) s[i] = fabs(b[i]);
    for (size_t j = 0; j < n; j++)
        for (int p = Ap[j]; p < Ap[j + 1]; p++) {
            size_t i = Ai[p];
            s[i] += fabs(Ax[p] * x[j]);
            if (i != j) s[j] += fabs(Ax[p] * x[i]);
        }
    return norm2(s, n);
}

/* The residual check of one solution u of A u = b: ||A u - b|| <= 1e-10 || |A||u| + |b| ||. The
 * plain ||A u - b|| / ||b|| cannot meet 1e-10 on a slender body: a double u has a residual floor
 * near eps || |A||u| ||, and a bending cantilever's |A||u| is 1e5 times |b| (see
 * test_fem_beam). */
static int check_solution(cholmod_sparse *A, const double *b, const double *u, cholmod_common *c,
                          kt_err *e)
{
    size_t n = A->nrow;
    double *r = kt_calloc(n, sizeof(double), e), *s = kt_calloc(n, sizeof(double), e);
    if (e->code) {
        free(r);
        free(s);
        return e->code;
    }
    memcpy(r, b, n * sizeof(double));
    cholmod_dense R = kt_chol_column(r, n), X = kt_chol_column((double *)u, n);
    double one[2] = {1, 0}, minus_one[2] = {-1, 0};
    cholmod_sdmult(A, 0, one, minus_one, &X, &R, c); /* r = A u - b */
    double nr = norm2(r, n), nb = norm2(b, n), scale = residual_scale(A, u, b, s);
    free(r);
    free(s);
    if (!(nr <= 1e-10 * scale))
        return kt_fail(e, KT_ERUN,
                       "direct solve: residual ||K u - f|| = %.3g is %.3g of || |K||u| + |f| || "
                       "(limit 1e-10) and %.3g of ||f||", nr, nr / scale, nb > 0 ? nr / nb : nr);
    return KT_OK;
}

/* U (n x ncol) = A \ B with the factor L, one substitution for every column, each checked. */
static int solve_with(cholmod_sparse *A, cholmod_factor *L, double *B, int ncol, double *U,
                      cholmod_common *c, kt_err *e)
{
    size_t n = A->nrow;
    cholmod_dense Bd = {n, (size_t)ncol, n * (size_t)ncol, n, B, NULL, CHOLMOD_REAL,
                        CHOLMOD_DOUBLE};
    cholmod_dense *X = cholmod_solve(CHOLMOD_A, L, &Bd, c);
    if (!X) return kt_fail(e, KT_ERUN, "CHOLMOD solve failed (status %d)", c->status);
    memcpy(U, X->x, n * (size_t)ncol * sizeof(double));
    cholmod_free_dense(&X, c);
    for (int k = 0; k < ncol; k++)
        if (check_solution(A, B + k * n, U + k * n, c, e)) return e->code;
    return KT_OK;
}

static int solve_more(const kt_mesh *m, const kt_materials *mats, const unsigned char *fixed,
                      const double *g, const double *f, double *u, int nmore,
                      kt_fem_more_rhs more, void *ctx, double *umore, int **perm,
                      cholmod_common *c, kt_err *e)
{
    cholmod_sparse *K = kt_fem_assemble(m, mats, NULL, c, e);
    if (!K) return e->code;
    size_t n = K->nrow;
    cholmod_factor *L = NULL;
    double *b = kt_calloc(n * (size_t)(nmore > 0 ? nmore : 1), sizeof(double), e);
    if (!b) goto done;
    memcpy(b, f, n * sizeof(double));
    if (fixed) {
        kt_fem_lift(K, fixed, g, b, e);
        kt_fem_apply_fixed(K, fixed);
    }
    if (e->code || !(L = kt_chol_analyze_factor(K, c, "direct solve", e)) ||
        solve_with(K, L, b, 1, u, c, e))
        goto done;
    if (perm) {
        if (!(*perm = kt_calloc(n ? n : 1, sizeof(int), e))) goto done;
        if (L->Perm) memcpy(*perm, L->Perm, n * sizeof(int));
        else
            for (size_t i = 0; i < n; i++) (*perm)[i] = (int)i;
    }
    if (nmore <= 0) goto done;
    memset(b, 0, n * (size_t)nmore * sizeof(double));
    if (more(ctx, u, b, e)) goto done;
    for (size_t i = 0; fixed && i < n * (size_t)nmore; i++) /* homogeneous Dirichlet data */
        if (fixed[i % n]) b[i] = 0;
    solve_with(K, L, b, nmore, umore, c, e);
done:
    free(b);
    if (L) cholmod_free_factor(&L, c);
    cholmod_free_sparse(&K, c);
    return e->code;
}

int kt_fem_solve_more(const kt_mesh *m, const kt_materials *mats, const unsigned char *fixed,
                      const double *g, const double *f, double *u, int nmore,
                      kt_fem_more_rhs more, void *ctx, double *umore, int **perm,
                      cholmod_common *c, kt_err *e)
{
    if (perm) *perm = NULL;
    return solve_more(m, mats, fixed, g, f, u, nmore, more, ctx, umore, perm, c, e);
}

int kt_fem_solve(const kt_mesh *m, const kt_materials *mats, const unsigned char *fixed,
                 const double *g, const double *f, double *u, cholmod_common *c, kt_err *e)
{
    return solve_more(m, mats, fixed, g, f, u, 0, NULL, NULL, NULL, NULL, c, e);
}

int kt_fem_solve_order(const kt_mesh *m, const kt_materials *mats, const unsigned char *fixed,
                       const double *g, const double *f, double *u, int **perm,
                       cholmod_common *c, kt_err *e)
{
    *perm = NULL;
    return solve_more(m, mats, fixed, g, f, u, 0, NULL, NULL, NULL, perm, c, e);
}
