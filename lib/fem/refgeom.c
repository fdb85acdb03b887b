/* refgeom.c: stress-free reference geometry: solve X + u(X) = Xm for X by Anderson-accelerated
 * fixed-point iteration on g(X) = Xm - u(X).
 *
 * Why not the plain iteration X <- Xm - u(X): on the default eye (cornea 0.3 MPa, limbus
 * 1 MPa, nu 0.49) it diverges: the residual falls from 387 um to 142 um, then grows without
 * bound (measured on a 27k-node P2 eye; damping by 0.5 diverges too, so du/dX has an
 * eigenvalue below -1). Anderson acceleration (Walker & Ni 2011, SIAM J Numer Anal 49:1715),
 * a multisecant quasi-Newton method, solves the same equation through such modes: 1 um in
 * about 10 solves, 0.01 um in about 20 on that eye.
 *
 * Each solve is K(X) u = f(X) by conjugate gradients preconditioned with a CHOLMOD factor of
 * an earlier K (a few iterations, since X moves by a fraction of a millimetre); when CG slows
 * down the current K is factored again, on the same symbolic analysis. */
#include "refgeom.h"

#include <cholmod.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "bind.h"
#include "chol.h"

#define DEFAULT_TOL 3e-5   /* mm (0.03 um): K within about 0.01 D on a 3 mm zone (0.05 um of sag
                            * at 1.5 mm from the apex is 0.016 D) */
#define DEFAULT_MAXIT 40
#define AA_MEMORY 10       /* Anderson history: 10 beat 3 and 6 on the eye (fewest solves) */
#define CG_TOL 1e-11       /* relative residual of each solve */
#define CG_REFACTOR 25     /* CG iterations before the current K is factored afresh */

void kt_refgeom_opts_default(const kt_scene *s, kt_refgeom_opts *o)
{
    o->tol = s && s->reference_tol > 0 ? s->reference_tol : DEFAULT_TOL;
    o->maxit = DEFAULT_MAXIT;
    o->quiet = 0;
}

/* ---- the elastic problem on the current coordinates ---------------------------------------- */

typedef struct problem {
    const kt_scene *s;
    const kt_mesh *m;
    size_t n;                   /* DOFs */
    kt_fem_problem fem;         /* the scene on the mesh: materials, fixed DOFs, the scene's values */
    double *g;                  /* prescribed values: lambda times the scene's */
    double lambda;              /* fraction of the loads applied (continuation) */
    int lift;                   /* some prescribed value is not zero */
    cholmod_common c;
    cholmod_factor *L;          /* factor of K at an earlier iterate (preconditioner) */
    int factors, cg_iters;      /* work done, for the log */
} problem;

static int problem_init(problem *p, const kt_scene *s, const kt_mesh *m, kt_err *e)
{
    memset(p, 0, sizeof *p);
    p->s = s;
    p->m = m;
    p->n = 3 * (size_t)m->nn;
    kt_chol_start(&p->c);
    p->lambda = 1;
    p->g = kt_calloc(p->n, sizeof(double), e);
    if (!p->g || kt_fem_bind(s, m, &p->fem, e)) return e->code;
    memcpy(p->g, p->fem.g, p->n * sizeof(double));
    for (size_t i = 0; i < p->n; i++) p->lift |= p->g[i] != 0;
    return KT_OK;
}

static void problem_free(problem *p)
{
    cholmod_free_factor(&p->L, &p->c);
    cholmod_finish(&p->c);
    kt_fem_problem_free(&p->fem);
    free(p->g);
}

/* Apply the fraction lambda of every load (pressures and prescribed values). */
static void set_lambda(problem *p, double lambda)
{
    p->lambda = lambda;
    for (size_t i = 0; i < p->n; i++) p->g[i] = lambda * p->fem.g[i];
}

/* K with identity rows and columns on the fixed DOFs, and f lifted to match. */
static cholmod_sparse *assemble_system(problem *p, double *f, kt_err *e)
{
    if (kt_fem_problem_loads(&p->fem, p->m, p->lambda, f, e)) return NULL;
    if (p->lift) {
        cholmod_sparse *K = kt_fem_assemble(p->m, &p->fem.mats, NULL, &p->c, e);
        if (!K) return NULL;
        kt_fem_lift(K, p->fem.fixed, p->g, f, e);
        cholmod_free_sparse(&K, &p->c);
        if (e->code) return NULL;
    } else {
        for (size_t i = 0; i < p->n; i++)
            if (p->fem.fixed[i]) f[i] = 0;
    }
    return kt_fem_assemble(p->m, &p->fem.mats, p->fem.fixed, &p->c, e);
}

static int factor(problem *p, cholmod_sparse *K, kt_err *e)
{
    if (!p->L) {
        int saved = p->c.supernodal;
        p->c.supernodal = CHOLMOD_SUPERNODAL;
        kt_err ae = {0};
        p->L = kt_chol_analyze(K, &p->c, &ae);
        p->c.supernodal = saved;
        if (!p->L) return kt_fail(e, ae.code, "reference: %s", ae.msg);
    }
    p->factors++;
    return kt_chol_factor(K, p->L, &p->c, "reference", e);
}

static double dot(const double *a, const double *b, size_t n)
{
    double s = 0;
    for (size_t i = 0; i < n; i++) s += a[i] * b[i];
    return s;
}

/* z = L \ r (the preconditioner). */
static int precond(problem *p, const double *r, double *z, kt_err *e)
{
    cholmod_dense R = kt_chol_column((double *)r, p->n);
    cholmod_dense *Z = cholmod_solve(CHOLMOD_A, p->L, &R, &p->c);
    if (!Z) return kt_fail(e, KT_ERUN, "reference: CHOLMOD solve failed (status %d)", p->c.status);
    memcpy(z, Z->x, p->n * sizeof(double));
    cholmod_free_dense(&Z, &p->c);
    return KT_OK;
}

/* y = K x (K symmetric, lower triangle stored). */
static void matvec(problem *p, cholmod_sparse *K, const double *x, double *y)
{
    cholmod_dense X = kt_chol_column((double *)x, p->n);
    cholmod_dense Y = kt_chol_column(y, p->n);
    double one[2] = {1, 0}, zero[2] = {0, 0};
    cholmod_sdmult(K, 0, one, zero, &X, &Y, &p->c);
}

/* Preconditioned CG from u (the previous solution is a good start); 1 when it stalls. */
static int pcg(problem *p, cholmod_sparse *K, const double *f, double *u, double *w, kt_err *e)
{
    size_t n = p->n;
    double *r = w, *z = w + n, *d = w + 2 * n, *q = w + 3 * n;
    matvec(p, K, u, q);
    for (size_t i = 0; i < n; i++) r[i] = f[i] - q[i];
    double fn = sqrt(dot(f, f, n)), rz = 0;
    for (int it = 0; it <= CG_REFACTOR; it++) {
        if (sqrt(dot(r, r, n)) <= CG_TOL * fn) return KT_OK;
        if (it == CG_REFACTOR) return 1;
        if (precond(p, r, z, e)) return e->code;
        double rz_new = dot(r, z, n);
        if (it == 0) memcpy(d, z, n * sizeof(double));
        else
            for (size_t i = 0; i < n; i++) d[i] = z[i] + rz_new / rz * d[i];
        rz = rz_new;
        matvec(p, K, d, q);
        double alpha = rz / dot(d, q, n);
        for (size_t i = 0; i < n; i++) u[i] += alpha * d[i], r[i] -= alpha * q[i];
        p->cg_iters++;
    }
    return 1;
}

/* u(X) on the mesh's current coordinates; u holds the previous solution on entry. */
static int solve(problem *p, double *u, double *f, double *w, kt_err *e)
{
    cholmod_sparse *K = assemble_system(p, f, e);
    if (!K) return e->code;
    int rc = p->L ? pcg(p, K, f, u, w, e) : 1;
    if (rc == 1) { /* no factor yet, or CG too slow: factor this K */
        rc = factor(p, K, e);
        if (rc == KT_OK) rc = pcg(p, K, f, u, w, e);
        if (rc == 1)
            rc = kt_fail(e, KT_ERUN, "reference: the solve missed its tolerance with a fresh factor");
    }
    cholmod_free_sparse(&K, &p->c);
    return rc;
}

int kt_refgeom_solve(const kt_scene *s, const kt_mesh *m, double *u, kt_err *e)
{
    problem p;
    double *f = NULL, *w = NULL;
    if (problem_init(&p, s, m, e) == KT_OK) {
        f = kt_calloc(p.n, sizeof(double), e);
        w = kt_calloc(4 * p.n, sizeof(double), e);
        if (f && w) {
            memset(u, 0, p.n * sizeof(double));
            solve(&p, u, f, w, e);
        }
    }
    free(f);
    free(w);
    problem_free(&p);
    return e->code;
}

/* ---- Anderson acceleration -------------------------------------------------------------- */

typedef struct anderson {
    size_t n;
    int mem, k;                 /* capacity, columns held */
    double **dF, **dG;          /* differences of residuals f = g(X) - X and of g(X) */
    double *fprev, *gprev, *q;  /* last f and g; QR scratch (mem columns of n) */
    int have_prev;
} anderson;

static int aa_init(anderson *a, size_t n, int mem, kt_err *e)
{
    memset(a, 0, sizeof *a);
    a->n = n;
    a->mem = mem;
    a->dF = kt_calloc((size_t)mem, sizeof(double *), e);
    a->dG = kt_calloc((size_t)mem, sizeof(double *), e);
    a->fprev = kt_calloc(n, sizeof(double), e);
    a->gprev = kt_calloc(n, sizeof(double), e);
    a->q = kt_calloc(n * (size_t)mem, sizeof(double), e);
    for (int j = 0; j < mem && !e->code; j++) {
        a->dF[j] = kt_calloc(n, sizeof(double), e);
        a->dG[j] = kt_calloc(n, sizeof(double), e);
    }
    return e->code;
}

static void aa_free(anderson *a)
{
    for (int j = 0; j < a->mem; j++) {
        if (a->dF) free(a->dF[j]);
        if (a->dG) free(a->dG[j]);
    }
    free(a->dF);
    free(a->dG);
    free(a->fprev);
    free(a->gprev);
    free(a->q);
}

/* gamma = argmin |f - dF gamma| by modified Gram-Schmidt QR; a column that is (numerically) in
 * the span of the earlier ones gets gamma 0. */
static void aa_lsq(anderson *a, const double *f, double *gamma)
{
    size_t n = a->n;
    double R[AA_MEMORY][AA_MEMORY] = {{0}}, b[AA_MEMORY];
    for (int j = 0; j < a->k; j++) {
        double *qj = a->q + (size_t)j * n;
        memcpy(qj, a->dF[j], n * sizeof(double));
        double norm0 = sqrt(dot(qj, qj, n));
        for (int i = 0; i < j; i++) {
            double *qi = a->q + (size_t)i * n;
            R[i][j] = R[i][i] > 0 ? dot(qi, qj, n) : 0;
            for (size_t l = 0; l < n; l++) qj[l] -= R[i][j] * qi[l];
        }
        double nr = sqrt(dot(qj, qj, n));
        R[j][j] = nr > 1e-10 * norm0 ? nr : 0;
        for (size_t l = 0; l < n; l++) qj[l] = R[j][j] > 0 ? qj[l] / nr : 0;
        b[j] = dot(qj, f, n);
    }
    for (int j = a->k - 1; j >= 0; j--) {
        double t = b[j];
        for (int i = j + 1; i < a->k; i++) t -= R[j][i] * gamma[i];
        gamma[j] = R[j][j] > 0 ? t / R[j][j] : 0;
    }
}

/* X_new = g - dG gamma, from g = g(X) and f = g - X. */
static void aa_step(anderson *a, const double *g, const double *f, double *X)
{
    size_t n = a->n;
    if (a->have_prev) {
        if (a->k == a->mem) { /* drop the oldest difference */
            double *F0 = a->dF[0], *G0 = a->dG[0];
            memmove(a->dF, a->dF + 1, (size_t)(a->mem - 1) * sizeof(double *));
            memmove(a->dG, a->dG + 1, (size_t)(a->mem - 1) * sizeof(double *));
            a->dF[a->mem - 1] = F0;
            a->dG[a->mem - 1] = G0;
            a->k--;
        }
        for (size_t i = 0; i < n; i++) {
            a->dF[a->k][i] = f[i] - a->fprev[i];
            a->dG[a->k][i] = g[i] - a->gprev[i];
        }
        a->k++;
    }
    memcpy(a->fprev, f, n * sizeof(double));
    memcpy(a->gprev, g, n * sizeof(double));
    a->have_prev = 1;
    double gamma[AA_MEMORY] = {0};
    if (a->k) aa_lsq(a, f, gamma);
    for (size_t i = 0; i < n; i++) {
        double x = g[i];
        for (int j = 0; j < a->k; j++) x -= gamma[j] * a->dG[j][i];
        X[i] = x;
    }
}

/* ---- the iteration ------------------------------------------------------------------------ */

/* Largest node distance |a - b| over 3-vectors. */
static double max_dist(const double *a, const double *b, size_t n3)
{
    double dmax = 0;
    for (size_t i = 0; i < n3; i += 3) {
        double d2 = 0;
        for (int k = 0; k < 3; k++) d2 += (a[i + k] - b[i + k]) * (a[i + k] - b[i + k]);
        dmax = kt_nanmax(dmax, sqrt(d2));
    }
    return dmax;
}

static int has_loads(const kt_scene *s)
{
    for (int i = 0; i < s->npressure; i++)
        if (s->pressure[i].p != 0) return 1;
    for (int i = 0; i < s->nfix; i++)
        if (s->fix[i].value[0] != 0 || s->fix[i].value[1] != 0 || s->fix[i].value[2] != 0) return 1;
    return 0;
}

typedef struct work {
    double *Xm, *u, *f, *g, *res, *w;
} work;

static int work_init(work *w, size_t n, kt_err *e)
{
    w->Xm = kt_calloc(n, sizeof(double), e);
    w->u = kt_calloc(n, sizeof(double), e);
    w->f = kt_calloc(n, sizeof(double), e);
    w->g = kt_calloc(n, sizeof(double), e);
    w->res = kt_calloc(n, sizeof(double), e);
    w->w = kt_calloc(4 * n, sizeof(double), e);
    return e->code;
}

static void work_free(work *w)
{
    free(w->Xm);
    free(w->u);
    free(w->f);
    free(w->g);
    free(w->res);
    free(w->w);
}

/* The best iterate so far, to restart from when Anderson's secant model goes astray. */
typedef struct best {
    double r;
    double *X, *g;
    int restarted;      /* restarted from this iterate already */
    int it;             /* the solve that found it */
} best;

#define STAGNATION 10   /* solves without a new best: this attempt has failed */
#define MAX_STAGES 4    /* continuation: the loads in at most this many stages */

/* Anderson iteration from the mesh's coordinates to tolerance tol at the current lambda;
 * 1 when it fails to get there. */
static int iterate(problem *p, anderson *a, work *w, best *b, kt_mesh *m, const kt_refgeom_opts *o,
                   double tol, kt_refgeom_stats *st, kt_err *e)
{
    size_t n = p->n;
    double prev = NAN;
    b->r = HUGE_VAL;
    b->restarted = 0;
    b->it = 0;
    a->k = 0;
    a->have_prev = 0;
    for (int it = 0; it < o->maxit && it - b->it <= STAGNATION; it++) {
        if (solve(p, w->u, w->f, w->w, e)) return e->code;
        st->iters++;
        for (size_t i = 0; i < n; i++) {
            w->g[i] = w->Xm[i] - w->u[i];   /* g(X) */
            w->res[i] = w->g[i] - m->xyz[i]; /* -(X + u(X) - Xm) */
        }
        double r = max_dist(w->g, m->xyz, n);
        if (st->iters == 1) st->initial = r;
        st->rate = r / prev;
        st->residual = r;
        prev = r;
        kt_log(o->quiet, "reference: solve %d (%.0f%% of the loads): max |X0 + u(X0) - X_measured| = %.3g um "
               "(%d factor%s, %d CG iterations)\n", st->iters, 100 * p->lambda, 1000 * r, p->factors,
               p->factors == 1 ? "" : "s", p->cg_iters);
        if (r <= tol) return KT_OK;
        if (!(r < 1e3 * st->initial)) break; /* runaway */
        if (r < b->r) {
            b->r = r;
            b->it = it;
            b->restarted = 0;
            memcpy(b->X, m->xyz, n * sizeof(double));
            memcpy(b->g, w->g, n * sizeof(double));
        } else if (r > 2 * b->r) {
            /* Restart once: forget the secants, half a plain step from the best iterate. A second
             * runaway from there means no secant model reaches a root: give up. */
            if (b->restarted) break;
            b->restarted = 1;
            a->k = 0;
            a->have_prev = 0;
            for (size_t i = 0; i < n; i++) m->xyz[i] = b->X[i] + 0.5 * (b->g[i] - b->X[i]);
            kt_log(o->quiet, "reference: restarting from the best iterate (%.3g um)\n", 1000 * b->r);
            continue;
        }
        aa_step(a, w->g, w->res, m->xyz);
    }
    return 1;
}

/* The loads in n stages lambda = 1/n, 2/n, ..., 1, each started from the previous stress-free
 * shape extrapolated linearly in lambda (X0 - Xm is about proportional to the loads). */
static int staged(problem *p, anderson *a, work *w, best *b, kt_mesh *m, const kt_refgeom_opts *o,
                  int n, kt_refgeom_stats *st, kt_err *e)
{
    size_t nd = p->n;
    memcpy(m->xyz, w->Xm, nd * sizeof(double));
    double prev = 0;
    for (int j = 1; j <= n; j++) {
        double lambda = (double)j / n;
        if (j > 1)
            for (size_t i = 0; i < nd; i++) m->xyz[i] = w->Xm[i] + lambda / prev * (m->xyz[i] - w->Xm[i]);
        set_lambda(p, lambda);
        /* intermediate stages need only bring the next start close */
        int rc = iterate(p, a, w, b, m, o, j == n ? o->tol : fmax(o->tol, 1e-3), st, e);
        if (rc) return rc;
        prev = lambda;
    }
    return KT_OK;
}

/* All the loads at once; if that fails, in 2 and then 4 stages (continuation). */
static int continuation(problem *p, anderson *a, work *w, best *b, kt_mesh *m,
                        const kt_refgeom_opts *o, kt_refgeom_stats *st, kt_err *e)
{
    double best_r = HUGE_VAL;
    for (int n = 1; n <= MAX_STAGES; n *= 2) {
        if (n > 1)
            kt_log(o->quiet, "reference: no convergence with the loads in %d stage%s (best %.3g um): "
                   "trying %d stages\n", n / 2, n / 2 > 1 ? "s" : "", 1000 * b->r, n);
        int rc = staged(p, a, w, b, m, o, n, st, e);
        if (rc != 1) return rc;
        best_r = fmin(best_r, b->r);
    }
    b->r = best_r;
    return 1;
}

int kt_refgeom_unload(const kt_scene *s, kt_mesh *m, const kt_refgeom_opts *o,
                      kt_refgeom_stats *st, kt_err *e)
{
    memset(st, 0, sizeof *st);
    st->rate = NAN;
    if (!has_loads(s)) return KT_OK;
    problem p;
    anderson a;
    work w;
    best b = {0, NULL, NULL, 0, 0};
    memset(&a, 0, sizeof a);
    memset(&w, 0, sizeof w);
    int rc = problem_init(&p, s, m, e);
    if (rc == KT_OK) rc = aa_init(&a, p.n, AA_MEMORY, e);
    if (rc == KT_OK) rc = work_init(&w, p.n, e);
    if (rc == KT_OK) {
        b.X = kt_calloc(p.n, sizeof(double), e);
        b.g = kt_calloc(p.n, sizeof(double), e);
        rc = e->code;
    }
    if (rc == KT_OK) {
        memcpy(w.Xm, m->xyz, p.n * sizeof(double));
        rc = continuation(&p, &a, &w, &b, m, o, st, e);
        if (rc == 1) {
            st->residual = b.r;
            rc = kt_fail(e, KT_ERUN, "reference: the stress-free geometry did not converge: max "
                         "|X0 + u(X0) - X_measured| = %.3g um at best in %d solves, the loads applied in "
                         "up to %d stages (tolerance %.3g um, %.3g um at the start); the loads deform "
                         "this linear model too much to invert (a softer material or a higher pressure "
                         "than it can carry), or use loads.reference: unloaded", 1000 * b.r, st->iters,
                         MAX_STAGES, 1000 * o->tol, 1000 * st->initial);
        }
        /* The reported residual is that of the geometry kept: on success the last solve's. */
        st->shift = max_dist(w.Xm, m->xyz, p.n);
        if (rc) memcpy(m->xyz, w.Xm, p.n * sizeof(double));
    }
    free(b.X);
    free(b.g);
    aa_free(&a);
    work_free(&w);
    problem_free(&p);
    return rc;
}
