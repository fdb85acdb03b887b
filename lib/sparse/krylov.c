/* krylov.c: restarted right-preconditioned GMRES (modified Gram-Schmidt, reorthogonalized, with
 * Givens rotations) and (Jacobi-preconditioned) CG; convergence is always confirmed on the true
 * residual b - A x, never on the recurrence alone. */
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

typedef struct gmres_ws {
    int n, k;
    double *V;    /* (k+1) basis vectors of length n */
    double *H;    /* (k+1) x k Hessenberg, column-major */
    double *cs, *sn, *g, *y, *w, *z;
    double *xbest; /* the iterate with the smallest true residual so far */
} gmres_ws;

static void gmres_ws_free(gmres_ws *w)
{
    free(w->V);
    free(w->H);
    free(w->cs);
    free(w->sn);
    free(w->g);
    free(w->y);
    free(w->w);
    free(w->z);
    free(w->xbest);
}

static int gmres_ws_alloc(gmres_ws *w, int n, int k, kt_err *e)
{
    memset(w, 0, sizeof *w);
    w->n = n;
    w->k = k;
    w->V = kt_calloc((size_t)(k + 1) * n, sizeof(double), e);
    w->H = kt_calloc((size_t)(k + 1) * k, sizeof(double), e);
    w->cs = kt_calloc((size_t)k, sizeof(double), e);
    w->sn = kt_calloc((size_t)k, sizeof(double), e);
    w->g = kt_calloc((size_t)k + 1, sizeof(double), e);
    w->y = kt_calloc((size_t)k, sizeof(double), e);
    w->w = kt_calloc((size_t)n, sizeof(double), e);
    w->z = kt_calloc((size_t)n, sizeof(double), e);
    w->xbest = kt_calloc((size_t)n, sizeof(double), e);
    if (e->code) gmres_ws_free(w);
    return e->code;
}

/* Orthogonalize w against V[0..j] twice (MGS); H column j gets the coefficients. */
static void orthogonalize(gmres_ws *W, int j, double *h)
{
    int n = W->n;
    for (int pass = 0; pass < 2; pass++)
        for (int i = 0; i <= j; i++) {
            double c = dot(n, W->w, W->V + (size_t)i * n);
            h[i] += c;
            axpy(n, -c, W->V + (size_t)i * n, W->w);
        }
}

/* Rotate column j of H by the previous rotations, then make a new one zeroing H[j+1][j]. */
static void givens(gmres_ws *W, int j)
{
    double *h = W->H + (size_t)j * (W->k + 1);
    for (int i = 0; i < j; i++) {
        double t = W->cs[i] * h[i] + W->sn[i] * h[i + 1];
        h[i + 1] = -W->sn[i] * h[i] + W->cs[i] * h[i + 1];
        h[i] = t;
    }
    double r = hypot(h[j], h[j + 1]);
    W->cs[j] = r > 0 ? h[j] / r : 1;
    W->sn[j] = r > 0 ? h[j + 1] / r : 0;
    h[j] = r;
    h[j + 1] = 0;
    W->g[j + 1] = -W->sn[j] * W->g[j];
    W->g[j] = W->cs[j] * W->g[j];
}

/* x += M^-1 (V y) for the j basis vectors built in this cycle. A numerically zero diagonal of
 * the triangular factor (A singular on the Krylov space, e.g. an inconsistent system) ends the
 * solve at the columns before it: their least-squares solution, instead of a division by
 * rounding noise that would throw x far away. */
static int update_solution(gmres_ws *W, int j, kt_krylov_op M, void *mctx, double *x, kt_err *e)
{
    int n = W->n, ld = W->k + 1;
    double rmax = 0;
    for (int i = 0; i < j; i++) rmax = fmax(rmax, fabs(W->H[(size_t)i * ld + i]));
    for (int i = 0; i < j; i++)
        if (fabs(W->H[(size_t)i * ld + i]) <= DBL_EPSILON * rmax || rmax == 0) {
            j = i;
            break;
        }
    for (int i = j - 1; i >= 0; i--) {
        double s = W->g[i];
        for (int l = i + 1; l < j; l++) s -= W->H[(size_t)l * ld + i] * W->y[l];
        W->y[i] = s / W->H[(size_t)i * ld + i];
    }
    memset(W->w, 0, sizeof(double) * n);
    for (int i = 0; i < j; i++) axpy(n, W->y[i], W->V + (size_t)i * n, W->w);
    if (M) {
        if (M(mctx, W->w, W->z, e)) return e->code;
        axpy(n, 1.0, W->z, x);
    } else {
        axpy(n, 1.0, W->w, x);
    }
    return KT_OK;
}

/* One restart cycle from the residual in V[0]*beta; returns the basis size used, -1 on error. */
static int gmres_cycle(gmres_ws *W, kt_krylov_op A, void *actx, kt_krylov_op M, void *mctx,
                       double beta, double target, int budget, int *iters, kt_err *e)
{
    int n = W->n, ld = W->k + 1, j = 0;
    memset(W->H, 0, sizeof(double) * (size_t)ld * W->k);
    memset(W->g, 0, sizeof(double) * (size_t)ld);
    W->g[0] = beta;
    while (j < W->k && j < budget) {
        const double *v = W->V + (size_t)j * n;
        if (M) {
            if (M(mctx, v, W->z, e)) return -1;
            v = W->z;
        }
        if (A(actx, v, W->w, e)) return -1;
        (*iters)++;
        double *h = W->H + (size_t)j * ld;
        orthogonalize(W, j, h);
        h[j + 1] = nrm2(n, W->w);
        if (h[j + 1] > 0) {
            double inv = 1.0 / h[j + 1];
            double *vn = W->V + (size_t)(j + 1) * n;
            for (int i = 0; i < n; i++) vn[i] = W->w[i] * inv;
        }
        int breakdown = !(h[j + 1] > 0);
        givens(W, j);
        j++;
        if (fabs(W->g[j]) <= target || breakdown) break;
    }
    return j;
}

/* GMRES gives up when the true residual has not fallen 10% below its best for this many restart
 * cycles and iterations (near the floor the cycles are short: the recurrence claims convergence
 * that the true residual does not show, yet a few more cycles may still get there) */
#define STALL_CYCLES 5
#define STALL_ITERS 50

int kt_krylov_gmres(int n, kt_krylov_op A, void *actx, kt_krylov_op M, void *mctx,
                    const double *b, double *x, const kt_krylov_opts *o, kt_krylov_stats *st,
                    kt_err *e)
{
    memset(st, 0, sizeof *st);
    double bn = nrm2(n, b);
    if (n == 0 || bn == 0) {
        if (n) memset(x, 0, sizeof(double) * n);
        st->converged = 1;
        return KT_OK;
    }
    int k = o->restart < 1 ? 1 : (o->restart > n ? n : o->restart);
    gmres_ws W;
    if (gmres_ws_alloc(&W, n, k, e)) return e->code;
    double target = o->tol * bn, best = HUGE_VAL, lowest = HUGE_VAL, last = HUGE_VAL;
    int cycles_since = 0, iters_best = 0;
    for (;;) {
        double beta = residual(n, A, actx, b, x, W.w, e);
        if (beta < 0) break;
        st->relres = beta / bn;
        last = beta;
        if (beta <= target) {
            st->converged = 1;
            break;
        }
        if (beta < lowest) {
            lowest = beta;
            memcpy(W.xbest, x, sizeof(double) * n);
        }
        if (st->iters >= o->maxit) break;
        /* no 10% gain over several cycles and iterations: the floor rounding in A sets */
        if (beta < 0.9 * best) {
            best = beta;
            cycles_since = 0;
            iters_best = st->iters;
        } else if (++cycles_since >= STALL_CYCLES && st->iters - iters_best >= STALL_ITERS) {
            st->stagnated = 1;
            break;
        }
        for (int i = 0; i < n; i++) W.V[i] = W.w[i] / beta;
        int j = gmres_cycle(&W, A, actx, M, mctx, beta, target, o->maxit - st->iters, &st->iters, e);
        if (j < 0 || update_solution(&W, j, M, mctx, x, e)) break;
    }
    /* not converged: return the best iterate seen, not the last (on a singular or inconsistent
     * system rounding can carry the last one far away) */
    if (!e->code && !st->converged && lowest < last) {
        memcpy(x, W.xbest, sizeof(double) * n);
        st->relres = lowest / bn;
    }
    gmres_ws_free(&W);
    return e->code;
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
        if (rn <= target) {
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
