/* solver_newton.c: the geometrically nonlinear reference (newton.h) as a backend of the front
 * door (solver.h): augsolve --method newton. Every solved step k is its own path: the intact
 * (prestressed) mesh, the cut of steps 1..k applied at once and released in load increments
 * (kt_newton_plan), Newton with a fresh factorization per iteration. A step is not continued
 * from the previous one: kt_newton_plan's path starts from the equilibrium u = 0 of the intact
 * mesh, which a cut state is not, and starting over makes a step's answer independent of how
 * the plan splits its cut into steps (as the linear methods' answers are). */
#include "solver.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "newton.h"

typedef struct newton {
    const kt_edits_plan *plan;
    const kt_mesh *intact;
    kt_fem_problem fp;       /* the intact problem as kt_newton_plan takes it (pointers into
                              * the kt_aug_problem, g owned when the problem has none) */
    double *g0;              /* owned zeros for fp.g, or NULL */
    int quiet;
    int step;                /* the step applied */
    kt_mesh mesh;            /* the cut mesh of the last solved step */
    int have_mesh;
    double *u;               /* 3 mesh.nn: its displacement */
    int *origin;             /* plan->nn: the input node each node descends from */
    kt_aug_row row;
} newton;

static void newton_free(void *st)
{
    newton *N = st;
    if (N->have_mesh) kt_mesh_free(&N->mesh);
    free(N->u);
    free(N->origin);
    free(N->g0);
    free(N);
}

/* Solve step k (the plan's steps 1..k from the intact mesh) into N->mesh, N->u, N->row. */
static int solve(newton *N, int k, kt_err *e)
{
    double t0 = kt_now();
    if (N->have_mesh) kt_mesh_free(&N->mesh);
    N->have_mesh = 0;
    free(N->u);
    N->u = NULL;
    if (kt_mesh_copy(&N->mesh, N->intact, e)) return e->code;
    N->have_mesh = 1;
    kt_newton_opts o;
    kt_newton_defaults(&o);
    kt_newton_stats st;
    memset(&st, 0, sizeof st);
    if (kt_newton_plan(&N->mesh, &N->fp, N->plan->step, k, &o, &N->u, &st, e)) {
        char msg[sizeof e->msg]; /* the step named in front (kt_fail keeps a first error) */
        snprintf(msg, sizeof msg, "%s", e->msg);
        int code = e->code;
        e->code = KT_OK;
        return kt_fail(e, code, "step %d: %s", k, msg);
    }
    if (N->mesh.nn != N->plan->nn_at[k])
        return kt_fail(e, KT_ERUN, "step %d: newton: %d nodes after the cut, the plan has %d", k,
                       N->mesh.nn, N->plan->nn_at[k]);
    double t = 1e3 * (kt_now() - t0);
    kt_aug_row *w = &N->row;
    memset(w, 0, sizeof *w);
    w->step = k;
    w->n_dofs = 3 * N->mesh.nn;
    w->new_dofs = k ? 3 * (N->plan->nn_at[k] - N->plan->nn_at[k - 1]) : 0;
    w->iters = st.iterations;
    w->t_step2 = 1e3 * st.t;      /* the Newton iterations: assembly, factorization, solve */
    w->t_update = t - w->t_step2; /* the copy, the cut, its constraints and r0 */
    w->t_step1 = w->t_step3 = NAN;
    w->t_total = t;
    w->rel_residual = st.nres ? st.res[st.nres - 1] : NAN;
    w->nnz_L = NAN;
    kt_log(N->quiet, "augsolve: newton: step %d: %d increments, %d cuts, %d iterations, "
           "relative residual %.3g, %.2f s\n", k, st.increments, st.cuts, st.iterations,
           w->rel_residual, 1e-3 * t);
    return KT_OK;
}

static int newton_create(void **st, const kt_solver_in *in, char *why, size_t n, kt_err *e)
{
    (void)why, (void)n;
    *st = NULL;
    const kt_aug_problem *p = in->prob;
    if (p->npress > KT_SCENE_MAX || p->nfix > KT_SCENE_MAX)
        return kt_fail(e, KT_EINPUT, "newton: %d pressures, %d fixations (at most %d each)",
                       p->npress, p->nfix, KT_SCENE_MAX);
    newton *N = kt_calloc(1, sizeof *N, e);
    if (!N) return e->code;
    N->plan = in->plan;
    N->intact = p->mesh;
    N->quiet = in->o->quiet;
    int nn0 = p->mesh->nn;
    N->fp.nn = nn0;
    N->fp.mats = *p->mats;
    N->fp.fixed = (unsigned char *)p->fixed; /* read only: kt_newton_plan copies them */
    if (p->g) N->fp.g = (double *)p->g;
    else if ((N->g0 = kt_calloc(3 * (size_t)nn0, sizeof(double), e))) N->fp.g = N->g0;
    N->fp.npress = p->npress;
    memcpy(N->fp.press, p->press, (size_t)p->npress * sizeof *p->press);
    N->fp.nfix = p->nfix;
    memcpy(N->fp.fix, p->fix, (size_t)p->nfix * sizeof *p->fix);
    if (!e->code) N->origin = kt_calloc((size_t)in->plan->nn, sizeof(int), e);
    if (e->code) goto fail;
    for (int i = 0; i < in->plan->nn; i++) /* a parent is created before its child */
        N->origin[i] = in->plan->parent[i] < 0 ? i : N->origin[in->plan->parent[i]];
    if (solve(N, 0, e)) goto fail;
    *st = N;
    return KT_OK;
fail:
    newton_free(N);
    return e->code;
}

static int newton_step(void *st, const kt_step *s, int mode, kt_err *e)
{
    newton *N = st;
    if (s->index != N->step + 1)
        return kt_fail(e, KT_EINPUT, "step %d follows step %d (expected step %d)", s->index,
                       N->step, N->step + 1);
    N->step = s->index;
    return mode == KT_SOLVER_SOLVE ? solve(N, N->step, e) : KT_OK; /* each step starts over */
}

static void newton_view(void *st, kt_solver_view *v)
{
    newton *N = st;
    *v = (kt_solver_view){&N->mesh, N->u, N->origin, N->row};
}

static const double *newton_reaction(void *st, kt_err *e)
{
    (void)st, (void)e;
    return NULL; /* the nonlinear support forces are not computed */
}

/* A nonlinear answer is not expected to equal a linear fresh factorization: augsolve refuses
 * --verify with this method before anything is solved; this is the backstop. */
static int newton_fresh(void *st, double *u, double *t, kt_err *e)
{
    (void)st, (void)u, (void)t;
    return kt_fail(e, KT_EINPUT, "--verify: --method newton has no fresh reference (compare it "
                   "with --method planned instead)");
}

const kt_solver_backend kt_solver_newton = {"newton", newton_create, newton_step, newton_view,
                                            newton_reaction, newton_fresh, newton_free, NULL, 1};
