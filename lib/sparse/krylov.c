/* krylov.c: (Jacobi-preconditioned) CG on a matrix-free operator; convergence is always
 * confirmed on the true residual b - A x, never on the recurrence alone. */
#include "krylov.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

static double dot(int n, const double *x, const double *y)
{
    double s = 0;
    for (int i = 0; i < n; i++) s += x[i] * y[i];
    return s;
}

static double nrm2(int n, const double *x) { return sqrt(dot(n, x, x)); }

static void axpy(int n, double a, const double *x, double *y)
{
    for (int i = 0; i < n; i++) y[i] += a * x[i];
}

/* r = b - A x; returns ||r||, or -1 on an operator error. */
static double residual(int n, kt_krylov_op A, void *ctx, const double *b, const double *x,
                       double *r, kt_err *e)
{
    if (A(ctx, x, r, e)) return -1;
    for (int i = 0; i < n; i++) r[i] = b[i] - r[i];
    return nrm2(n, r);
}

/* Plain or Jacobi-preconditioned CG iterations from the residual r until the recurrence says
 * converged or the budget ends. */
static int cg_run(int n, kt_krylov_op A, void *actx, const double *dinv, double *x, double *r,
                  double *z, double *p, double *q, double target, int budget, int *iters, kt_err *e)
{
    for (int i = 0; i < n; i++) z[i] = dinv ? dinv[i] * r[i] : r[i];
    memcpy(p, z, sizeof(double) * n);
    double rz = dot(n, r, z);
    for (int it = 0; it < budget; it++) {
        if (nrm2(n, r) <= target) break;
        if (A(actx, p, q, e)) return e->code;
        (*iters)++;
        double pq = dot(n, p, q);
        if (!(pq > 0))
            return kt_fail(e, KT_ERUN, "CG: p'Ap = %.3g at iteration %d: the matrix is not positive"
                           " definite", pq, *iters);
        double alpha = rz / pq;
        axpy(n, alpha, p, x);
        axpy(n, -alpha, q, r);
        for (int i = 0; i < n; i++) z[i] = dinv ? dinv[i] * r[i] : r[i];
        double rz1 = dot(n, r, z), beta = rz1 / rz;
        rz = rz1;
        for (int i = 0; i < n; i++) p[i] = z[i] + beta * p[i];
    }
    return KT_OK;
}

int kt_krylov_cg(int n, kt_krylov_op A, void *actx, const double *dinv, const double *b,
                 double *x, const kt_krylov_opts *o, kt_krylov_stats *st, kt_err *e)
{
    memset(st, 0, sizeof *st);
    double bn = nrm2(n, b);
    if (!isfinite(bn)) /* the target tol ||b|| would be met by any residual, NaN included */
        return kt_fail(e, KT_ERUN, "CG: the right-hand side's norm is %g (loads out of double "
                       "precision's range?)", bn);
    if (n == 0 || bn == 0) {
        if (n) memset(x, 0, sizeof(double) * n);
        st->converged = 1;
        return KT_OK;
    }
    double *r = kt_calloc((size_t)n, sizeof(double), e), *z = kt_calloc((size_t)n, sizeof(double), e);
    double *p = kt_calloc((size_t)n, sizeof(double), e), *q = kt_calloc((size_t)n, sizeof(double), e);
    double target = o->tol * bn;
    while (e->code == KT_OK) {
        double rn = residual(n, A, actx, b, x, r, e);
        if (rn < 0) break;
        st->relres = rn / bn;
        if (rn <= target) { /* false for NaN */
            st->converged = 1;
            break;
        }
        if (st->iters >= o->maxit) break;
        int before = st->iters;
        if (cg_run(n, A, actx, dinv, x, r, z, p, q, target, o->maxit - st->iters, &st->iters, e))
            break;
        if (st->iters == before) break; /* recurrence converged, true residual did not: stop */
    }
    free(r);
    free(z);
    free(p);
    free(q);
    return e->code;
}
