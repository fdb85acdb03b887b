/* krylov.h: CG and Jacobi-preconditioned CG on operators given as callbacks (matrix-free): the
 * cg and pcg-jacobi baselines of augsolve. */
#ifndef KT_KRYLOV_H
#define KT_KRYLOV_H

#include "util.h"

/* y = Op x for vectors of length n; returns KT_OK or an error code with e set. */
typedef int (*kt_krylov_op)(void *ctx, const double *x, double *y, kt_err *e);

typedef struct kt_krylov_opts {
    double tol;   /* stop when ||b - A x|| <= tol ||b|| */
    int maxit;    /* iteration cap */
} kt_krylov_opts;

typedef struct kt_krylov_stats {
    int iters;      /* iterations done (operator applications, not counting residual checks) */
    double relres;  /* final ||b - A x|| / ||b||, recomputed from A at the end */
    int converged;
} kt_krylov_stats;

/* Solve A x = b, A symmetric positive definite, by CG; with dinv (n values, the inverse of the
 * diagonal of A) by Jacobi-preconditioned CG. x holds the initial guess on entry. */
int kt_krylov_cg(int n, kt_krylov_op A, void *actx, const double *dinv, const double *b,
                 double *x, const kt_krylov_opts *o, kt_krylov_stats *st, kt_err *e);

#endif
