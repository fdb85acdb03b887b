/* newton.c: load-incremented Newton with a line search on the total Lagrangian problem. */
#include "newton.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "chol.h"

void kt_newton_defaults(kt_newton_opts *o)
{
    memset(o, 0, sizeof *o);
    o->increments = 10;
    o->max_iter = 25;
    o->max_cuts = 12;
    o->rtol = 1e-12;
}

typedef struct work {
    const kt_newton_problem *p;
    size_t n;
    double *r, *fint, *du, *trial, *save, *prev; /* prev: the converged state before save */
    cholmod_common *c;
    cholmod_factor *L;
} work;

static double norm2(const double *x, size_t n)
{
    double s = 0;
    for (size_t i = 0; i < n; i++) s += x[i] * x[i];
    return sqrt(s);
}

/* r := R(u, lambda) with fixed DOFs zeroed, from r = r(u; ps) as computed. */
static void path_residual(const work *w, double lambda, double *r)
{
    const kt_newton_problem *p = w->p;
    for (size_t i = 0; i < w->n; i++) {
        if (p->fdead) r[i] -= lambda * p->fdead[i];
        if (p->r0) r[i] -= (1 - lambda) * p->r0[i];
        if (p->fixed && p->fixed[i]) r[i] = 0;
    }
}

/* The force scale of the convergence test: || sum_e |fe| + |lambda fdead| + |(1 - lambda) r0| ||
 * over all DOFs at u, the size of the terms R sums (its rounding floor is about eps times it;
 * ||f_int|| alone is no scale: at a small load it is as small as the floor of the terms that
 * cancel into it). */
static int force_scale(work *w, const double *u, double lambda, double ps, double *scale,
                       kt_err *e)
{
    const kt_newton_problem *p = w->p;
    if (kt_fem_nl_residual(p->m, p->mats, u, ps, w->trial, w->fint, e)) return e->code;
    double s = 0;
    for (size_t i = 0; i < w->n; i++) {
        double a = w->fint[i];
        if (p->fdead) a += fabs(lambda * p->fdead[i]);
        if (p->r0) a += fabs((1 - lambda) * p->r0[i]);
        s += a * a;
    }
    *scale = s > 0 ? sqrt(s) : 1.0;
    return KT_OK;
}

static double dot(const double *x, const double *y, size_t n)
{
    double s = 0;
    for (size_t i = 0; i < n; i++) s += x[i] * y[i];
    return s;
}

/* The slope du . R_free(u + alpha du) of the energy along the step (trial := u + alpha du);
 * KT_ERUN when an element inverts. */
static int trial_slope(work *w, const double *u, double alpha, double lambda, double ps,
                       double *s, kt_err *e)
{
    for (size_t i = 0; i < w->n; i++) w->trial[i] = u[i] + alpha * w->du[i];
    if (kt_fem_nl_residual(w->p->m, w->p->mats, w->trial, ps, w->r, NULL, e)) return e->code;
    path_residual(w, lambda, w->r);
    *s = dot(w->du, w->r, w->n);
    return KT_OK;
}

/* The line search (Crisfield, Non-linear Finite Element Analysis of Solids and Structures,
 * vol. 1, 1991, sec. 9.5): the residual is the gradient of the energy, so s(alpha) = du . R(u +
 * alpha du) is the energy's slope along the step, s(0) = -du . K du < 0. Accept alpha when
 * s(alpha) <= 0.5 |s(0)| (the energy still falls there or has passed its minimum by little);
 * otherwise move alpha to the secant root of s on [0, alpha], kept within [0.1, 0.9] alpha, or
 * halve it if an element inverted. 0: u := u + alpha du; 1: no acceptable alpha in 12 trials. */
static int line_search(work *w, double *u, double s0, double lambda, double ps, double *alpha)
{
    double a = 1;
    for (int h = 0; h < 12; h++) {
        kt_err te = {0};
        double s = 0;
        if (trial_slope(w, u, a, lambda, ps, &s, &te)) {
            a *= 0.5;
            continue;
        }
        if (s <= 0.5 * fabs(s0)) {
            memcpy(u, w->trial, w->n * sizeof(double));
            *alpha = a;
            return 0;
        }
        a = fmax(0.1 * a, fmin(0.9 * a, a * s0 / (s0 - s)));
    }
    return 1;
}

/* One increment to lambda from the converged u: 0 converged, 1 to be cut (why in *cause). */
static int increment(work *w, double lambda, double *u, const kt_newton_opts *o,
                     kt_newton_stats *st, char *cause, size_t csz, kt_err *e)
{
    const kt_newton_problem *p = w->p;
    double ps = p->pressure_ramp ? lambda : 1.0;
    for (size_t i = 0; i < w->n; i++)
        if (p->fixed && p->fixed[i]) u[i] = p->g ? lambda * p->g[i] : 0.0;
    st->nres = 0;
    for (int it = 0;; it++) {
        kt_err le = {0};
        cholmod_sparse *K = kt_fem_nl_assemble(p->m, p->mats, u, ps, p->fixed, w->r, w->c, &le);
        double scale = 0;
        if (!K || force_scale(w, u, lambda, ps, &scale, &le)) {
            cholmod_free_sparse(&K, w->c);
            snprintf(cause, csz, "%.280s", le.msg);
            return 1;
        }
        path_residual(w, lambda, w->r);
        double nr = norm2(w->r, w->n), rel = nr / scale;
        if (st->nres < KT_NEWTON_HIST) st->res[st->nres++] = rel;
        if (o->log)
            fprintf(o->log, "newton: lambda %.6g iteration %d: ||R||/||f|| = %.3e\n", lambda, it, rel);
        if (!(rel == rel)) {
            cholmod_free_sparse(&K, w->c);
            snprintf(cause, csz, "residual is NaN");
            return 1;
        }
        if (rel <= o->rtol && !(o->linear && it == 0)) {
            cholmod_free_sparse(&K, w->c);
            return 0;
        }
        if (it == o->max_iter) {
            cholmod_free_sparse(&K, w->c);
            snprintf(cause, csz, "no convergence in %d iterations (||R||/||f|| = %.3g)", it, rel);
            return 1;
        }
        if (!w->L) {
            int saved = w->c->supernodal;
            w->c->supernodal = CHOLMOD_SUPERNODAL;
            kt_err ae = {0};
            w->L = kt_chol_analyze(K, w->c, &ae);
            w->c->supernodal = saved;
            if (!w->L) {
                cholmod_free_sparse(&K, w->c);
                return kt_fail(e, ae.code, "newton: %s", ae.msg);
            }
        }
        st->iterations++;
        int bad = kt_chol_factor(K, w->L, w->c, "tangent", &le);
        cholmod_free_sparse(&K, w->c);
        if (bad) {
            snprintf(cause, csz, "%.280s", le.msg);
            return 1;
        }
        for (size_t i = 0; i < w->n; i++) w->r[i] = -w->r[i];
        cholmod_dense B = kt_chol_column(w->r, w->n);
        cholmod_dense *X = cholmod_solve(CHOLMOD_A, w->L, &B, w->c);
        if (!X) return kt_fail(e, KT_ERUN, "newton: CHOLMOD solve failed (status %d)", w->c->status);
        memcpy(w->du, X->x, w->n * sizeof(double));
        cholmod_free_dense(&X, w->c);
        if (o->linear) {
            for (size_t i = 0; i < w->n; i++) u[i] += w->du[i];
            return 0;
        }
        double s0 = -dot(w->du, w->r, w->n), alpha = 0; /* w->r holds -R */
        if (!(s0 < 0)) {
            snprintf(cause, csz, "the step is not a descent direction (du . R = %.3g)", s0);
            return 1;
        }
        if (line_search(w, u, s0, lambda, ps, &alpha)) {
            snprintf(cause, csz, "line search: no step along du with du . R <= |du . R(u)| / 2");
            return 1;
        }
        if (o->log && alpha < 1) fprintf(o->log, "newton: step length %.3g\n", alpha);
    }
}

int kt_newton_solve(const kt_newton_problem *p, const kt_newton_opts *o, double *u,
                    kt_newton_stats *st, kt_err *e)
{
    kt_newton_stats local;
    if (!st) st = &local;
    memset(st, 0, sizeof *st);
    if (o->increments < 1 || o->max_iter < 1 || !(o->rtol > 0))
        return kt_fail(e, KT_EINPUT, "newton: increments %d, max_iter %d, rtol %g (expected >= 1, "
                       ">= 1, > 0)", o->increments, o->max_iter, o->rtol);
    double t0 = kt_now();
    cholmod_common c;
    kt_chol_start(&c);
    work w = {p, 3 * (size_t)p->m->nn, NULL, NULL, NULL, NULL, NULL, NULL, &c, NULL};
    w.r = kt_calloc(w.n, sizeof(double), e);
    w.fint = kt_calloc(w.n, sizeof(double), e);
    w.du = kt_calloc(w.n, sizeof(double), e);
    w.trial = kt_calloc(w.n, sizeof(double), e);
    w.save = kt_calloc(w.n, sizeof(double), e);
    w.prev = kt_calloc(w.n, sizeof(double), e);
    memset(u, 0, w.n * sizeof(double));
    double lambda = 0, dl = o->linear ? 1.0 : 1.0 / o->increments, dl_prev = 0;
    while (!e->code && lambda < 1) {
        double next = fmin(1.0, lambda + dl);
        if (1.0 - next < 1e-12) next = 1.0;
        char cause[300] = "";
        memcpy(w.save, u, w.n * sizeof(double));
        /* secant predictor: extrapolate the last increment's displacement */
        double ratio = dl_prev > 0 ? (next - lambda) / dl_prev : 0;
        for (size_t i = 0; i < w.n; i++) u[i] += ratio * (u[i] - w.prev[i]);
        int cut = increment(&w, next, u, o, st, cause, sizeof cause, e);
        if (e->code) break;
        if (!cut) {
            dl_prev = next - lambda;
            lambda = st->lambda = next;
            memcpy(w.prev, w.save, w.n * sizeof(double));
            st->increments++;
            continue;
        }
        memcpy(u, w.save, w.n * sizeof(double));
        snprintf(st->cause, sizeof st->cause, "%s", cause);
        if (++st->cuts > o->max_cuts) {
            kt_fail(e, KT_ERUN, "newton: no equilibrium at lambda %.6g after %d increment cuts: "
                    "%s", next, o->max_cuts, cause);
            break;
        }
        dl *= 0.5;
        if (o->log) fprintf(o->log, "newton: increment to lambda %.6g cut to %.6g: %s\n", next,
                            lambda + dl, cause);
    }
    cholmod_free_factor(&w.L, &c);
    cholmod_finish(&c);
    free(w.r);
    free(w.fint);
    free(w.du);
    free(w.trial);
    free(w.save);
    free(w.prev);
    st->t = kt_now() - t0;
    return e->code;
}
