/* test_krylov.c: CG and restarted GMRES on small operators whose solutions are known: the
 * 1D Laplacian, a convection-diffusion matrix, a matrix with three eigenvalues, the cyclic
 * shift (where GMRES(k < n) makes no progress at all), an inconsistent singular system, and
 * an operator that fails. */
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

/* y = T^-1 x by the Thomas algorithm (no pivoting: T diagonally dominant). */
static int tri_solve(void *ctx, const double *x, double *y, kt_err *e)
{
    const tri *t = ctx;
    int n = t->n;
    double *c = kt_calloc((size_t)n, sizeof(double), e);
    if (!c) return e->code;
    double den = t->di[0];
    c[0] = t->up[0] / den;
    y[0] = x[0] / den;
    for (int i = 1; i < n; i++) {
        den = t->di[i] - t->lo[i] * c[i - 1];
        c[i] = i + 1 < n ? t->up[i] / den : 0;
        y[i] = (x[i] - t->lo[i] * y[i - 1]) / den;
    }
    for (int i = n - 2; i >= 0; i--) y[i] -= c[i] * y[i + 1];
    free(c);
    return KT_OK;
}

/* y = D^-1 x, the Jacobi preconditioner as an operator. */
static int tri_jacobi(void *ctx, const double *x, double *y, kt_err *e)
{
    (void)e;
    const tri *t = ctx;
    for (int i = 0; i < t->n; i++) y[i] = x[i] / t->di[i];
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
    kt_krylov_opts o = {1e-12, 0, 1000};
    kt_krylov_stats st;
    kt_err e = {0};
    CHECK(kt_krylov_cg(N, tri_apply, &t, NULL, b, x, &o, &st, &e) == KT_OK, "%s", e.msg);
    CHECK(st.converged && !st.stagnated, "converged %d stagnated %d", st.converged, st.stagnated);
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
    kt_krylov_opts o = {1e-12, 0, 1000};
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
    /* and the same in GMRES: the Krylov space has dimension 3 */
    double xg[N] = {0};
    kt_krylov_opts og = {1e-12, 30, 1000};
    CHECK(kt_krylov_gmres(N, tri_apply, &d, NULL, NULL, b, xg, &og, &st, &e) == KT_OK && st.converged, "%s", e.msg);
    CHECK(st.iters <= 4, "three eigenvalues took %d GMRES iterations", st.iters);
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

/* GMRES on convection-diffusion tridiag(-1.6, 2, -0.4): nonsymmetric. */
static void test_gmres_nonsymmetric(void)
{
    enum { N = 50 };
    tri t;
    tri_make(&t, N, -1.6, 2, -0.4);
    double xs[N], b[N];
    make_rhs(&t, xs, b);
    kt_krylov_stats st;
    kt_err e = {0};
    /* full GMRES (restart = n), no preconditioner */
    double x[N] = {0};
    kt_krylov_opts o = {1e-11, N, 1000};
    CHECK(kt_krylov_gmres(N, tri_apply, &t, NULL, NULL, b, x, &o, &st, &e) == KT_OK, "%s", e.msg);
    CHECK(st.converged && st.iters <= N, "converged %d in %d", st.converged, st.iters);
    double rr = relres(&t, b, x);
    CHECK(rr <= 1e-11, "true residual %.3g", rr);
    CHECK_NEAR(st.relres, rr, 1e-6, "reported relres is the true one");
    CHECK(err_rel(N, x, xs) < 1e-8, "error %.3g", err_rel(N, x, xs));

    /* the exact inverse as preconditioner: one iteration */
    double xp[N] = {0};
    CHECK(kt_krylov_gmres(N, tri_apply, &t, tri_solve, &t, b, xp, &o, &st, &e) == KT_OK, "%s", e.msg);
    CHECK(st.converged && st.iters == 1, "exact preconditioner: %d iterations", st.iters);
    CHECK(err_rel(N, xp, xs) < 1e-12, "exact preconditioner: error %.3g", err_rel(N, xp, xs));

    /* Jacobi with a varying diagonal, restarted every 8 */
    for (int i = 0; i < N; i++) t.di[i] = 2 + 0.5 * i;
    make_rhs(&t, xs, b);
    double xj[N] = {0}, x0[N] = {0};
    kt_krylov_opts o8 = {1e-11, 8, 2000};
    kt_krylov_stats sj, s0;
    CHECK(kt_krylov_gmres(N, tri_apply, &t, tri_jacobi, &t, b, xj, &o8, &sj, &e) == KT_OK && sj.converged,
          "Jacobi GMRES(8): %s converged %d", e.msg, sj.converged);
    CHECK(kt_krylov_gmres(N, tri_apply, &t, NULL, NULL, b, x0, &o8, &s0, &e) == KT_OK && s0.converged,
          "GMRES(8): %s converged %d", e.msg, s0.converged);
    CHECK(err_rel(N, xj, xs) < 1e-9 && err_rel(N, x0, xs) < 1e-9, "errors %.3g %.3g", err_rel(N, xj, xs),
          err_rel(N, x0, xs));
    CHECK(relres(&t, b, xj) <= 1e-11 && relres(&t, b, x0) <= 1e-11, "true residuals");
    CHECK(sj.iters < s0.iters, "Jacobi %d iterations, none %d", sj.iters, s0.iters);

    /* an initial guess that is the solution: zero iterations */
    kt_krylov_stats sx;
    CHECK(kt_krylov_gmres(N, tri_apply, &t, NULL, NULL, b, xs, &o8, &sx, &e) == KT_OK && sx.converged &&
          sx.iters == 0, "start at the solution: %d iterations", sx.iters);
    /* b = 0: x = 0 */
    double z[N] = {0}, xz[N];
    for (int i = 0; i < N; i++) xz[i] = 1;
    CHECK(kt_krylov_gmres(N, tri_apply, &t, NULL, NULL, z, xz, &o8, &sx, &e) == KT_OK && sx.converged &&
          norm(N, xz) == 0, "b = 0 gives x = 0");
    tri_free(&t);
}

/* The cyclic shift Z (Z e_i = e_i+1, Z e_n = e_1) with b = e_1: x = e_n. GMRES(k < n) cannot
 * reduce the residual at all (b is orthogonal to Z K_k); full GMRES solves it in n steps. */
typedef struct shift {
    int n;
} shift;

static int shift_apply(void *ctx, const double *x, double *y, kt_err *e)
{
    (void)e;
    int n = ((shift *)ctx)->n;
    for (int i = 0; i < n; i++) y[(i + 1) % n] = x[i];
    return KT_OK;
}

static void test_gmres_restart(void)
{
    enum { N = 12 };
    shift z = {N};
    double b[N] = {1}, x[N] = {0};
    kt_krylov_opts full = {1e-12, N, 1000};
    kt_krylov_stats st;
    kt_err e = {0};
    CHECK(kt_krylov_gmres(N, shift_apply, &z, NULL, NULL, b, x, &full, &st, &e) == KT_OK, "%s", e.msg);
    CHECK(st.converged && st.iters == N, "full GMRES: converged %d after %d (want %d)", st.converged, st.iters, N);
    CHECK(fabs(x[N - 1] - 1) < 1e-12 && fabs(x[0]) < 1e-12, "x = e_n: x_n %.17g", x[N - 1]);

    double y[N] = {0};
    kt_krylov_opts rst = {1e-12, 5, 1000};
    CHECK(kt_krylov_gmres(N, shift_apply, &z, NULL, NULL, b, y, &rst, &st, &e) == KT_OK, "%s", e.msg);
    CHECK(!st.converged && st.stagnated, "GMRES(5): converged %d stagnated %d", st.converged, st.stagnated);
    CHECK(fabs(st.relres - 1) < 1e-12 && norm(N, y) < 1e-12, "GMRES(5) moved: relres %.17g |x| %.3g", st.relres,
          norm(N, y));
    /* it gives up after the documented 5 cycles and 50 iterations, long before maxit */
    CHECK(st.iters >= 50 && st.iters <= 60, "stagnation declared after %d iterations", st.iters);

    /* a cap below the stagnation window: neither converged nor stagnated, iters = maxit */
    double w[N] = {0};
    kt_krylov_opts cap = {1e-12, 5, 17};
    CHECK(kt_krylov_gmres(N, shift_apply, &z, NULL, NULL, b, w, &cap, &st, &e) == KT_OK, "%s", e.msg);
    CHECK(!st.converged && !st.stagnated && st.iters == 17, "capped: iters %d", st.iters);
}

/* An inconsistent system: A = diag(1, ..., 1, 0), b = ones. The least-squares residual is the
 * last component: relres = 1/sqrt(n); GMRES must get there, report stagnation, and keep x finite. */
static void test_gmres_inconsistent(void)
{
    enum { N = 16 };
    tri t;
    tri_make(&t, N, 0, 1, 0);
    t.di[N - 1] = 0;
    double b[N], x[N] = {0};
    for (int i = 0; i < N; i++) b[i] = 1;
    kt_krylov_opts o = {1e-10, 10, 5000};
    kt_krylov_stats st;
    kt_err e = {0};
    CHECK(kt_krylov_gmres(N, tri_apply, &t, NULL, NULL, b, x, &o, &st, &e) == KT_OK, "%s", e.msg);
    CHECK(!st.converged && st.stagnated, "converged %d stagnated %d after %d", st.converged, st.stagnated, st.iters);
    CHECK(st.iters < 5000, "stagnation not detected: %d iterations", st.iters);
    int finite = 1;
    for (int i = 0; i < N; i++) finite &= isfinite(x[i]);
    CHECK(finite, "x has a non-finite entry");
    CHECK_NEAR(st.relres, 1 / sqrt((double)N), 1e-10, "least-squares residual");
    if (finite) CHECK(fabs(x[0] - 1) < 1e-10 && fabs(x[N - 2] - 1) < 1e-10, "x on the range: %g", x[0]);
    CHECK_NEAR(relres(&t, b, x), st.relres, 1e-10, "reported relres is the true one");
    tri_free(&t);
}

/* An operator that fails on call k: both solvers return its error and its message. */
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
        kt_krylov_opts o = {1e-12, 5, 1000};
        kt_krylov_stats st;
        kt_err e = {0};
        char want[64];
        snprintf(want, sizeof want, "operator failed on call %d", when[w]);
        CHECK(kt_krylov_gmres(N, tri_apply, &t, NULL, NULL, b, x, &o, &st, &e) == KT_ERUN &&
              strcmp(e.msg, want) == 0 && !st.converged, "GMRES, failure at call %d: '%s'", when[w], e.msg);
        CHECK(t.calls == when[w], "GMRES went on after the failure: %d calls", t.calls);
        t.calls = 0;
        memset(x, 0, sizeof x);
        kt_err e2 = {0};
        CHECK(kt_krylov_cg(N, tri_apply, &t, NULL, b, x, &o, &st, &e2) == KT_ERUN &&
              strcmp(e2.msg, want) == 0 && !st.converged, "CG, failure at call %d: '%s'", when[w], e2.msg);
        CHECK(t.calls == when[w], "CG went on after the failure: %d calls", t.calls);
        tri_free(&t);
    }
    /* a failing preconditioner */
    tri t;
    tri_make(&t, N, -1, 2, -1);
    tri m = t;
    m.fail_at = 3;
    double xs[N], b[N], x[N] = {0};
    make_rhs(&t, xs, b);
    kt_krylov_opts o = {1e-12, 5, 1000};
    kt_krylov_stats st;
    kt_err e = {0};
    CHECK(kt_krylov_gmres(N, tri_apply, &t, tri_apply, &m, b, x, &o, &st, &e) == KT_ERUN &&
          strstr(e.msg, "operator failed on call 3"), "failing preconditioner: '%s'", e.msg);
    tri_free(&t);
}

int main(void)
{
    test_cg_laplacian();
    test_cg_jacobi_and_three_eigenvalues();
    test_gmres_nonsymmetric();
    test_gmres_restart();
    test_gmres_inconsistent();
    test_operator_failure();
    return kt_test_done("test_krylov");
}
