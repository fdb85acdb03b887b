/* krylov.h: restarted GMRES with right preconditioning, CG and preconditioned CG, on operators
 * given as callbacks (matrix-free), so the augmented Schur complement never has to be formed. */
#ifndef KT_KRYLOV_H
#define KT_KRYLOV_H

#include "util.h"

/* y = Op x for vectors of length n; returns KT_OK or an error code with e set. */
typedef int (*kt_krylov_op)(void *ctx, const double *x, double *y, kt_err *e);

typedef struct kt_krylov_opts {
    double tol;   /* stop when ||b - A x|| <= tol ||b|| */
    int restart;  /* GMRES: Krylov basis size before a restart */
    int maxit;    /* iteration cap (GMRES: all cycles together) */
} kt_krylov_opts;

typedef struct kt_krylov_stats {
    int iters;      /* iterations done (operator applications, not counting residual checks) */
    double relres;  /* final ||b - A x|| / ||b||, recomputed from A at the end */
    int converged;
    int stagnated;  /* stopped early: no 10% gain in 5 restart cycles and 50 iterations */
} kt_krylov_stats;

/* Solve A x = b by restarted GMRES with right preconditioning: A M^-1 y = b, x = M^-1 y.
 * M may be NULL (no preconditioner). x holds the initial guess on entry. Not converging is not
 * an error here: check st->converged. */
int kt_krylov_gmres(int n, kt_krylov_op A, void *actx, kt_krylov_op M, void *mctx,
                    const double *b, double *x, const kt_krylov_opts *o, kt_krylov_stats *st,
                    kt_err *e);

/* Solve A x = b, A symmetric positive definite, by CG; with dinv (n values, the inverse of the
 * diagonal of A) by Jacobi-preconditioned CG. x holds the initial guess on entry. */
int kt_krylov_cg(int n, kt_krylov_op A, void *actx, const double *dinv, const double *b,
                 double *x, const kt_krylov_opts *o, kt_krylov_stats *st, kt_err *e);

#endif
