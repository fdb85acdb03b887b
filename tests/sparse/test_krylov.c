/* test_krylov.c: CG and Jacobi-preconditioned CG on small operators whose solutions are known:
 * the 1D Laplacian, a varying diagonal, a matrix with three eigenvalues, an indefinite matrix
 * (refused), and an operator that fails. */
#include <stdlib.h>
#include <string.h>

#include "krylov.h"
#include "kt_test.h"

/* A tridiagonal matrix: row i is lo[i] x[i-1] + di[i] x[i] + up[i] x[i+1]. */
typedef struct tri {
    int n;
    double *lo, *di, *up;
    int calls, fail_at; /* operator applications so far; fail on call fail_at (0: never) */
} tri;

static int tri_apply(void *ctx, const double *x, double *y, kt_err *e)
{
    tri *t = ctx;
    if (++t->calls == t->fail_at) return kt_fail(e, KT_ERUN, "operator failed on call %d", t->calls);
    for (int i = 0; i < t->n; i++) {
        y[i] = t->di[i] * x[i];
        if (i > 0) y[i] += t->lo[i] * x[i - 1];
        if (i + 1 < t->n) y[i] += t->up[i] * x[i + 1];
    }
    return KT_OK;
}

static void tri_make(tri *t, int n, double lo, double di, double up)
{
    memset(t, 0, sizeof *t);
    t->n = n;
    t->lo = malloc(sizeof(double) * n);
    t->di = malloc(sizeof(double) * n);
    t->up = malloc(sizeof(double) * n);
    if (!t->lo || !t->di || !t->up) exit(1);
    for (int i = 0; i < n; i++) t->lo[i] = lo, t->di[i] = di, t->up[i] = up;
}

static void tri_free(tri *t)
{
    free(t->lo);
    free(t->di);
    free(t->up);
}

static double norm(int n, const double *x)
{
    double s = 0;
    for (int i = 0; i < n; i++) s += x[i] * x[i];
    return sqrt(s);
}

/* ||b - A x|| / ||b||, computed here from the operator. */
static double relres(tri *t, const double *b, const double *x)
{
    int n = t->n;
    double *r = malloc(sizeof(double) * n);
    kt_err e = {0};
    if (!r) exit(1);
    tri_apply(t, x, r, &e);
    t->calls--;
    for (int i = 0; i < n; i++) r[i] = b[i] - r[i];
    double v = norm(n, r) / norm(n, b);
    free(r);
    return v;
}

/* max_i |x_i - xs_i| / max_i |xs_i| */
static double err_rel(int n, const double *x, const double *xs)
{
    double d = 0, m = 0;
    for (int i = 0; i < n; i++) {
        d = fmax(d, fabs(x[i] - xs[i]));
        m = fmax(m, fabs(xs[i]));
    }
    return d / m;
}

/* b = A xs for xs_i = sin(0.3 i) + i / n. */
static void make_rhs(tri *t, double *xs, double *b)
{
    kt_err e = {0};
    for (int i = 0; i < t->n; i++) xs[i] = sin(0.3 * i) + (double)i / t->n;
    tri_apply(t, xs, b, &e);
    t->calls = 0;
}

/* CG on the 1D Laplacian tridiag(-1, 2, -1), n = 40 (condition number about 660). */
static void test_cg_laplacian(void)
{
    enum { N = 40 };
    tri t;
    tri_make(&t, N, -1, 2, -1);
    double xs[N], b[N], x[N] = {0};
    make_rhs(&t, xs, b);
    kt_krylov_opts o = {1e-12, 1000};
    kt_krylov_stats st;
    kt_err e = {0};
    CHECK(kt_krylov_cg(N, tri_apply, &t, NULL, b, x, &o, &st, &e) == KT_OK, "%s", e.msg);
    CHECK(st.converged, "converged %d", st.converged);
    double rr = relres(&t, b, x);
    CHECK(rr <= 1e-12, "true relative residual %.3g", rr);
    CHECK_NEAR(st.relres, rr, 1e-6, "reported relres is the true one");
    /* error <= cond * relres: 660 * 1e-12 */
    CHECK(err_rel(N, x, xs) < 1e-9, "error %.3g", err_rel(N, x, xs));
    /* CG on an n x n SPD matrix: at most n steps in exact arithmetic; allow rounding slack */
    CHECK(st.iters >= 5 && st.iters <= 2 * N, "iterations %d", st.iters);
    tri_free(&t);
}

/* Jacobi-preconditioned CG on a matrix with a varying diagonal, and CG on diag(1, 2, 3, ...)
 * repeated: three distinct eigenvalues, so CG is exact after three steps. */
static void test_cg_jacobi_and_three_eigenvalues(void)
{
    enum { N = 60 };
    tri t;
    tri_make(&t, N, -1, 0, -1);
    double dinv[N];
    for (int i = 0; i < N; i++) t.di[i] = 2.5 + i, dinv[i] = 1 / t.di[i];
    double xs[N], b[N], x[N] = {0}, x2[N] = {0};
    make_rhs(&t, xs, b);
    kt_krylov_opts o = {1e-12, 1000};
    kt_krylov_stats st, st2;
    kt_err e = {0};
    CHECK(kt_krylov_cg(N, tri_apply, &t, dinv, b, x, &o, &st, &e) == KT_OK && st.converged, "%s", e.msg);
    CHECK(err_rel(N, x, xs) < 1e-10, "Jacobi-PCG error %.3g", err_rel(N, x, xs));
    CHECK(kt_krylov_cg(N, tri_apply, &t, NULL, b, x2, &o, &st2, &e) == KT_OK && st2.converged, "%s", e.msg);
    /* the diagonal varies 25-fold: scaling it away must save iterations */
    CHECK(st.iters < st2.iters, "Jacobi %d iterations, plain %d", st.iters, st2.iters);

    tri d;
    tri_make(&d, N, 0, 0, 0);
    for (int i = 0; i < N; i++) d.di[i] = 1 + i % 3;
    double xd[N] = {0};
    make_rhs(&d, xs, b);
    CHECK(kt_krylov_cg(N, tri_apply, &d, NULL, b, xd, &o, &st, &e) == KT_OK && st.converged, "%s", e.msg);
    CHECK(st.iters <= 4, "three eigenvalues took %d CG iterations", st.iters);
    CHECK(err_rel(N, xd, xs) < 1e-12, "three eigenvalues: error %.3g", err_rel(N, xd, xs));
    tri_free(&d);

    /* an indefinite matrix is refused by CG, loudly */
    tri ind;
    tri_make(&ind, 4, 0, 1, 0);
    ind.di[2] = -1;
    double bi[4] = {1, 1, 1, 1}, xi[4] = {0};
    kt_err ei = {0};
    CHECK(kt_krylov_cg(4, tri_apply, &ind, NULL, bi, xi, &o, &st, &ei) == KT_ERUN &&
          strstr(ei.msg, "not positive definite"), "indefinite: '%s'", ei.msg);
    tri_free(&ind);
    tri_free(&t);
}

/* An operator that fails on call k: CG returns its error and its message. */
static void test_operator_failure(void)
{
    enum { N = 20 };
    int when[3] = {1, 2, 7};
    for (int w = 0; w < 3; w++) {
        tri t;
        tri_make(&t, N, -1, 2, -1);
        double xs[N], b[N], x[N] = {0};
        make_rhs(&t, xs, b);
        t.fail_at = when[w];
        kt_krylov_opts o = {1e-12, 1000};
        kt_krylov_stats st;
        char want[64];
        snprintf(want, sizeof want, "operator failed on call %d", when[w]);
        kt_err e2 = {0};
        CHECK(kt_krylov_cg(N, tri_apply, &t, NULL, b, x, &o, &st, &e2) == KT_ERUN &&
              strcmp(e2.msg, want) == 0 && !st.converged, "CG, failure at call %d: '%s'", when[w], e2.msg);
        CHECK(t.calls == when[w], "CG went on after the failure: %d calls", t.calls);
        tri_free(&t);
    }
}

int main(void)
{
    test_cg_laplacian();
    test_cg_jacobi_and_three_eigenvalues();
    test_operator_failure();
    return kt_test_done("test_krylov");
}
