/* solver_planned.c: the planned method as a backend of the front door (solver.h): one
 * factorization of the final augmented matrix (kt_plan_factor, immutable once built), the
 * steps' state (kt_plan_state: the cut mesh, the loads, the forward substitution continued
 * from step to step). */
#include "solver.h"

#include "aug_plan_sens.h"

#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct planned {
    const kt_edits_plan *plan;
    const kt_aug_problem *prob;
    double tol;
    int quiet;
    kt_plan_factor F;
    kt_plan_state S;
    kt_plan_sens D;             /* --uncertainty: the derivatives (D.S NULL: none) */
} planned;

static void planned_free(void *st)
{
    planned *P = st;
    kt_plan_sens_free(&P->D);
    kt_plan_state_free(&P->S);
    kt_plan_factor_free(&P->F);
    free(P);
}

/* The derivative matrices (kt_plan_sens_matrices), on a thread of their own beside the
 * factorization: they read the plan, the final mesh and the materials, as the factorization
 * does, and write only their own kt_plan_sens; the numbers are the same either way. Not under
 * an address-space or data limit, where the two would race for the room left and the failure
 * said would depend on which came first: there the matrices follow the factor, as they do when
 * no thread can be started. On a busy machine the thread costs nothing the work did not. */
typedef struct sens_job {
    kt_plan_sens *D;
    const kt_solver_in *in;
    kt_err e;
} sens_job;

static void *sens_matrices(void *arg)
{
    sens_job *j = arg;
    kt_thread_start();
    kt_plan_sens_matrices(j->D, j->in->sens, j->in->plan, j->in->final, j->in->prob->mats, &j->e);
    return NULL;
}

/* Factor the plan, with the derivative matrices beside it (sens_job) when they may be. */
static int factor_and_matrices(planned *P, const kt_solver_in *in, kt_err *e)
{
    sens_job job = {&P->D, in, {0}};
    pthread_t th;
    int beside = in->sens && !kt_as_limited() &&
                 pthread_create(&th, NULL, sens_matrices, &job) == 0;
    kt_plan_factor_build_with(&P->F, in->plan, in->final, in->prob->mats, in->o->ordering,
                              in->prob->perm, in->o->factor, in->o->plan_panel,
                              in->plan_max_ratio, e);
    if (beside) pthread_join(th, NULL);
    else if (in->sens && !e->code && !P->F.refused) sens_matrices(&job);
    if (!e->code && job.e.code) *e = job.e;
    return e->code;
}

static int planned_create(void **st, const kt_solver_in *in, char *why, size_t n, kt_err *e)
{
    *st = NULL;
    if (!in->plan->usable) {
        snprintf(why, n, "%s", in->plan->why);
        return KT_OK;
    }
    planned *P = kt_calloc(1, sizeof *P, e);
    if (!P) return e->code;
    P->plan = in->plan;
    P->prob = in->prob;
    P->tol = in->o->tol;
    P->quiet = in->o->quiet;
    kt_plan_factor *F = &P->F;
    if (factor_and_matrices(P, in, e)) goto fail;
    kt_log(P->quiet, "augsolve: planned: its flops (sum of squared column counts) %.3g: intact "
           "block %.3g, increment rows of the intact columns %.3g, increments' block %.3g "
           "(METIS on the intact block %.3g); values %.3g: %.3g, %.3g, %.3g; %d supernodes, the "
           "last %d columns\n", F->fl_K + F->fl_W + F->fl_S, F->fl_K, F->fl_W, F->fl_S,
           F->fl_ref, F->x_K + F->x_W + F->x_S, F->x_K, F->x_W, F->x_S, F->nsuper, F->root_cols);
    if (F->refused) {
        snprintf(why, n, "%s", F->why);
        planned_free(P);
        return KT_OK;
    }
    if (kt_plan_state_init(&P->S, in->plan, F, in->prob, e) ||
        (in->out_final && kt_plan_state_restrict(&P->S, in->plan, F, in->out_final, e)))
        goto fail;
    if (in->sens) {
        /* The derivatives' right-hand sides read every variable of the step's solution: the
         * step's own back substitution is whole, the derivatives' are restricted instead. */
        if (kt_plan_sens_bind(&P->D, F, e)) goto fail;
        P->D.want = P->S.want;
        P->S.want = NULL;
        P->S.want_cols = 0;
        kt_log(P->quiet, "augsolve: planned: %d derivative quantities, their matrices in %.2f s\n",
               in->sens->nd, P->D.t_setup);
    }
    kt_log(P->quiet, "augsolve: planned: %d steps, %d free DOFs + %d increments, factor %.0f "
           "nonzeros (%.3gx METIS on the intact block; flops %.3gx) in %.2f s (assembly %.2f s, "
           "ordering %.2f s%s)\n", in->plan->nsteps, F->nK, F->nfree - F->nK, F->nnzL,
           F->lnz_plan / F->lnz_ref, F->fl_plan / F->fl_ref, F->t_factor, F->t_assemble,
           F->t_order, F->reused_order ? ": the prestress solve's" : "");
    if (kt_plan_solve(&P->S, P->plan, F, P->prob, P->tol, e)) goto fail;
    double setup = 1e3 * (F->t_assemble + F->t_order + F->t_factor); /* step 0 holds the factor */
    P->S.row.t_update += setup;
    P->S.row.t_total += setup;
    *st = P;
    return KT_OK;
fail:
    planned_free(P);
    return e->code;
}

static int planned_step(void *st, const kt_step *s, int mode, kt_err *e)
{
    planned *P = st;
    if (s->index != P->S.step + 1)
        return kt_fail(e, KT_EINPUT, "step %d follows step %d (expected step %d)", s->index,
                       P->S.step, P->S.step + 1);
    if (kt_plan_advance(&P->S, P->plan, e)) return e->code;
    if (mode == KT_SOLVER_SOLVE) kt_plan_solve(&P->S, P->plan, &P->F, P->prob, P->tol, e);
    else if (mode == KT_SOLVER_CARRY) kt_plan_continue(&P->S, P->plan, &P->F, P->prob, e);
    if (!e->code && P->S.step == P->plan->nsteps)
        kt_log(P->quiet, "augsolve: planned: %d of the steps after step 0 continued its forward "
               "substitution (the others started it over)\n", P->S.ncont);
    return e->code;
}

static void planned_view(void *st, kt_solver_view *v)
{
    planned *P = st;
    *v = (kt_solver_view){&P->S.mesh, P->S.u, P->S.origin, P->S.row};
}

static const double *planned_reaction(void *st, kt_err *e)
{
    (void)e;
    planned *P = st;
    return P->S.want ? NULL : P->S.react; /* a restricted step computes none */
}

static int planned_dudp(void *st, double *du, kt_err *e)
{
    planned *P = st;
    return kt_plan_sens_solve(&P->D, &P->S, P->plan, &P->F, du, e);
}

static int planned_fresh(void *st, double *u, double *t, kt_err *e)
{
    planned *P = st;
    return kt_plan_fresh(&P->S, P->plan, P->prob, u, t, e);
}

const kt_solver_backend kt_solver_planned = {"planned", planned_create, planned_step,
                                             planned_view, planned_reaction, planned_fresh,
                                             planned_free, planned_dudp, 0};
