/* aug_cg.c: what a user would otherwise run each step, on the same state: a fresh assembly and
 * CHOLMOD factorization ("refactor", also the --verify reference), CG and Jacobi-PCG. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "aug_impl.h"
#include "chol.h"
#include "krylov.h"

double kt_aug_ms(double seconds) { return 1e3 * seconds; }

int kt_aug_analyze(cholmod_sparse *K, int ordering, int factor, cholmod_common *c,
                cholmod_factor **L, kt_err *e)
{
    c->nmethods = 1;
    c->method[0].ordering = ordering == KT_AUG_ORDER_AMD     ? CHOLMOD_AMD
                            : ordering == KT_AUG_ORDER_METIS ? CHOLMOD_METIS
                                                             : CHOLMOD_NATURAL;
    /* natural: keep mesh-prep's elimination order exactly (no postordering) */
    c->postorder = ordering != KT_AUG_ORDER_NATURAL;
    c->supernodal = factor == KT_AUG_FACTOR_SIMPLICIAL ? CHOLMOD_SIMPLICIAL : CHOLMOD_SUPERNODAL;
    c->final_ll = 0;
    *L = kt_chol_analyze(K, c, e);
    return e->code;
}

/* Identity rows and columns at the constrained DOFs of a lower-stored K. */
static void set_identity(cholmod_sparse *K, const unsigned char *cons)
{
    int *Kp = K->p, *Ki = K->i, n = (int)K->ncol;
    double *Kx = K->x;
    for (int j = 0; j < n; j++)
        for (int p = Kp[j]; p < Kp[j + 1]; p++)
            if (cons[Ki[p]] || cons[j]) Kx[p] = Ki[p] == j ? 1.0 : 0.0;
}

/* K with identity at C and b = f lifted (g on C rows), loads recomputed from the mesh. */
static cholmod_sparse *assemble(kt_aug *A, double *b, cholmod_common *c, kt_err *e)
{
    if (kt_aug_stream_loads(&A->s, e)) return NULL;
    memcpy(b, A->s.f, 3 * (size_t)A->s.mesh.nn * sizeof(double));
    cholmod_sparse *K = kt_fem_assemble(&A->s.mesh, &A->s.mats, NULL, c, e);
    if (!K) return NULL;
    if (kt_fem_lift(K, A->s.cons, A->s.g, b, e)) {
        cholmod_free_sparse(&K, c);
        return NULL;
    }
    set_identity(K, A->s.cons);
    return K;
}

/* ||(K u - b)_free|| / ||b_free||: the constrained rows hold u = g exactly. */
static double free_residual(kt_aug *A, cholmod_sparse *K, const double *u, const double *b,
                            cholmod_common *c)
{
    int n = (int)K->nrow;
    cholmod_dense U, *R = cholmod_zeros(n, 1, CHOLMOD_REAL, c);
    if (!R) return NAN;
    memset(&U, 0, sizeof U);
    U.nrow = U.nzmax = U.d = n;
    U.ncol = 1;
    U.x = (void *)u;
    U.xtype = CHOLMOD_REAL;
    U.dtype = CHOLMOD_DOUBLE;
    double one[2] = {1, 0}, zero[2] = {0, 0};
    cholmod_sdmult(K, 0, one, zero, &U, R, c);
    double num = 0, den = 0, *r = R->x;
    for (int i = 0; i < n; i++)
        if (!A->s.cons[i]) {
            num += (r[i] - b[i]) * (r[i] - b[i]);
            den += b[i] * b[i];
        }
    cholmod_free_dense(&R, c);
    return den == 0 ? sqrt(num) : sqrt(num / den); /* NaN stays NaN */
}

static int fresh_with(kt_aug *A, cholmod_common *c, int use_opts, double *u, double *t,
                      double *relres, kt_err *e)
{
    size_t n = 3 * (size_t)A->s.mesh.nn;
    double t0 = kt_now();
    double *b = kt_calloc(n, sizeof(double), e);
    if (!b) return e->code;
    cholmod_sparse *K = assemble(A, b, c, e);
    cholmod_factor *L = NULL;
    double t1 = kt_now(), t2 = t1, t3 = t1;
    if (K) {
        if (use_opts) kt_aug_analyze(K, A->o.ordering, A->o.factor, c, &L, e);
        else kt_aug_analyze(K, KT_AUG_ORDER_METIS, KT_AUG_FACTOR_SUPERNODAL, c, &L, e);
    }
    t2 = kt_now();
    if (L) {
        char what[32];
        snprintf(what, sizeof what, "step %d", A->s.step);
        kt_chol_factor(K, L, c, what, e);
    }
    t3 = kt_now();
    if (!e->code && use_opts) A->row.nnz_L = c->lnz;
    if (!e->code) {
        cholmod_dense B = kt_chol_column(b, n), *X;
        X = cholmod_solve(CHOLMOD_A, L, &B, c);
        if (!X) kt_fail(e, KT_ERUN, "CHOLMOD solve failed (status %d)", c->status);
        else memcpy(u, X->x, n * sizeof(double));
        cholmod_free_dense(&X, c);
    }
    double t4 = kt_now();
    if (!e->code && relres) *relres = free_residual(A, K, u, b, c);
    if (t) {
        t[0] = t1 - t0;
        t[1] = t2 - t1;
        t[2] = t3 - t2;
        t[3] = t4 - t3;
    }
    cholmod_free_factor(&L, c);
    cholmod_free_sparse(&K, c);
    free(b);
    return e->code;
}

int kt_aug_fresh_solve(kt_aug *A, int use_opts, double *u, double *t, double *relres, kt_err *e)
{
    if (use_opts) return fresh_with(A, &A->c, 1, u, t, relres, e);
    cholmod_common c; /* its own: METIS, postordered, supernodal (what a user would run) */
    kt_chol_start(&c);
    fresh_with(A, &c, 0, u, t, relres, e);
    cholmod_finish(&c);
    return e->code;
}

int kt_aug_solve_refactor(kt_aug *A, kt_err *e)
{
    double t[4];
    if (kt_aug_fresh_solve(A, 1, A->u, t, &A->row.rel_residual, e)) return e->code;
    if (!isfinite(A->row.rel_residual)) /* a direct solve has no tolerance, but NaN is no answer */
        return kt_fail(e, KT_ERUN, "step %d: the refactor solve's residual is %g (loads or "
                       "stiffness out of double precision's range?)", A->s.step, A->row.rel_residual);
    A->row.t_update += kt_aug_ms(t[0]);
    A->row.t_step1 = kt_aug_ms(t[1]);
    A->row.t_step2 = kt_aug_ms(t[2]);
    A->row.t_step3 = kt_aug_ms(t[3]);
    return KT_OK;
}

/* y = K x for K symmetric with its lower triangle stored. */
static int symv(void *ctx, const double *x, double *y, kt_err *e)
{
    (void)e;
    const cholmod_sparse *K = ctx;
    const int *Kp = K->p, *Ki = K->i;
    const double *Kx = K->x;
    int n = (int)K->ncol;
    memset(y, 0, sizeof(double) * n);
    for (int j = 0; j < n; j++) {
        double xj = x[j], s = 0;
        for (int p = Kp[j]; p < Kp[j + 1]; p++) {
            int i = Ki[p];
            if (i == j) {
                s += Kx[p] * xj;
            } else {
                y[i] += Kx[p] * xj;
                s += Kx[p] * x[i];
            }
        }
        y[j] += s;
    }
    return KT_OK;
}

static double *jacobi(const cholmod_sparse *K, kt_err *e)
{
    int n = (int)K->ncol;
    const int *Kp = K->p, *Ki = K->i;
    const double *Kx = K->x;
    double *d = kt_calloc((size_t)n, sizeof(double), e);
    if (!d) return NULL;
    for (int j = 0; j < n; j++) {
        d[j] = 1;
        for (int p = Kp[j]; p < Kp[j + 1]; p++)
            if (Ki[p] == j && Kx[p] > 0) d[j] = 1.0 / Kx[p];
    }
    return d;
}

/* CG on the free DOFs: b and x are zero on C, u = x + g there. The initial guess is the
 * previous step's displacement (a new node starts from the node it was split from). */
int kt_aug_solve_cg(kt_aug *A, int use_jacobi, kt_err *e)
{
    int n = 3 * A->s.mesh.nn;
    double t0 = kt_now();
    double *b = kt_calloc((size_t)n, sizeof(double), e);
    if (!b) return e->code;
    cholmod_sparse *K = assemble(A, b, &A->c, e);
    double *d = K && use_jacobi ? jacobi(K, e) : NULL;
    double t1 = kt_now();
    if (!e->code) {
        for (int i = 0; i < n; i++) {
            A->u[i] = A->s.cons[i] ? 0.0 : A->uprev[i];
            if (A->s.cons[i]) b[i] = 0;
        }
        kt_krylov_opts ko = {A->o.tol, A->o.maxit > 0 ? A->o.maxit : 20000};
        kt_krylov_stats st;
        if (kt_krylov_cg(n, symv, K, d, b, A->u, &ko, &st, e) == KT_OK) {
            A->row.iters = st.iters;
            A->row.rel_residual = st.relres;
            if (!st.converged)
                kt_fail(e, KT_ERUN, "step %d: %s did not reach the relative residual %.3g in %d "
                        "iterations (reached %.3g): raise --maxit or loosen --tol", A->s.step,
                        use_jacobi ? "Jacobi-PCG" : "CG", A->o.tol, st.iters, st.relres);
        }
        for (int i = 0; i < n; i++)
            if (A->s.cons[i]) A->u[i] = A->s.g[i];
    }
    double t2 = kt_now();
    A->row.t_update += kt_aug_ms(t1 - t0);
    A->row.t_step2 = kt_aug_ms(t2 - t1);
    free(d);
    free(b);
    cholmod_free_sparse(&K, &A->c);
    return e->code;
}
