/* solver.c: the front door (solver.h): the backend chosen (with the planned method's
 * fallbacks), the steps, and the one place every method's step ends: the output restriction,
 * the verification against a fresh factorization and the row of steps.tsv. */
#include "solver.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

struct kt_solver {
    const kt_solver_backend *be;
    void *st;
    kt_aug_opts o;              /* as run (after a fallback) */
    const kt_edits_plan *plan;
    unsigned char *want;        /* nsteps+1: the steps solved */
    int last;                   /* the last of them */
    int step;
    int fell_back;
    char why[600];              /* the fallback's reason */
    kt_solver_view v;           /* the backend's last solved step */
    double *u, *ref;            /* 3 nn: the field as written, the fresh reference */
    unsigned char *on;          /* nn: the output set's nodes (NULL: all) */
    size_t cap;                 /* values u and ref hold room for */
    kt_aug_row row;
    const kt_aug_problem *prob;
    const kt_fem_sens *sens;    /* NULL: no derivatives */
    double *du;                 /* sens->nd x 3 nn: the derivatives as written */
    size_t ducap;
    double t_sens;
};

/* The nodes of the output set on mesh m into on (nn, zeroed here): the surface or region. */
static int set_nodes(const kt_mesh *m, const char *name, unsigned char *on, kt_err *e)
{
    const kt_group *g = kt_mesh_find_group(m, 2, name);
    if (!g) g = kt_mesh_find_group(m, 3, name);
    if (!g)
        return kt_fail(e, KT_EINPUT, "--output %s: no surface or region of that name in the mesh",
                       name);
    int *nodes = NULL, cnt = 0;
    if (kt_mesh_group_nodes(m, g, &nodes, &cnt, e)) return e->code;
    memset(on, 0, (size_t)m->nn);
    for (int k = 0; k < cnt; k++) on[nodes[k]] = 1;
    free(nodes);
    return KT_OK;
}

static int room(kt_solver *sv, size_t n, kt_err *e)
{
    if (n <= sv->cap) return KT_OK;
    double *u = kt_realloc(sv->u, n, sizeof(double), e);
    if (u) sv->u = u;
    double *r = u ? kt_realloc(sv->ref, n, sizeof(double), e) : NULL;
    if (r) sv->ref = r;
    unsigned char *on = r ? kt_realloc(sv->on, n / 3, 1, e) : NULL;
    if (!on) return e->code;
    sv->on = on;
    sv->cap = n;
    return KT_OK;
}

/* --verify: the step against a fresh factorization over the output set's DOFs. */
static int verify(kt_solver *sv, kt_err *e)
{
    int n = 3 * sv->v.mesh->nn;
    double t = 0, dmax = 0, rmax = 0;
    if (sv->be->fresh(sv->st, sv->ref, &t, e)) return e->code;
    for (int i = 0; i < n; i++) {
        if (sv->o.output[0] && !sv->on[i / 3]) continue;
        dmax = kt_nanmax(dmax, fabs(sv->v.u[i] - sv->ref[i])); /* NaN stays NaN (util.h) */
        rmax = kt_nanmax(rmax, fabs(sv->ref[i]));
    }
    sv->row.verify_rel_diff = rmax == 0 ? dmax : dmax / rmax;
    sv->row.t_verify = 1e3 * t;
    if (!(sv->row.verify_rel_diff <= sv->o.verify_tol))
        return kt_fail(e, KT_ERUN, "step %d: --verify: %s and a fresh factorization differ by "
                       "%.3g (relative, max norm) > --verify-tol %.3g", sv->step,
                       kt_aug_method_name(sv->o.method), sv->row.verify_rel_diff,
                       sv->o.verify_tol);
    return KT_OK;
}

/* Whether the intact scene's field is zero for every value of the quantities (sens.h,
 * zero_at_0: a prestressed scene) with the plan's prescribed values, all zero at step 0 (the
 * intact mesh, no edits yet): then so is every derivative of step 0, exactly, and none is
 * solved for. */
static int zero_at_0(const kt_solver *sv)
{
    if (sv->step != 0 || !sv->sens->zero_at_0) return 0;
    for (int i = 0; i < 3 * sv->plan->nn0; i++)
        if (sv->plan->fixed[i] && sv->plan->g[i] != 0) return 0;
    return 1;
}

/* The step's derivatives: the backend's, or from scratch on its cut mesh and field (zero at
 * step 0 of a prestressed scene, unsolved); NaN off the output set. */
static int derivatives(kt_solver *sv, kt_err *e)
{
    double t0 = kt_now();
    int nd = sv->sens->nd;
    size_t n = 3 * (size_t)sv->v.mesh->nn, need = n * (size_t)(nd ? nd : 1);
    if (need > sv->ducap) {
        double *d = kt_realloc(sv->du, need, sizeof(double), e);
        if (!d) return e->code;
        sv->du = d;
        sv->ducap = need;
    }
    if (nd == 0) return KT_OK;
    if (zero_at_0(sv))
        memset(sv->du, 0, n * (size_t)nd * sizeof(double));
    else if (sv->be->dudp ? sv->be->dudp(sv->st, sv->du, e)
                          : kt_fem_sens_fresh(sv->sens, sv->v.mesh, sv->prob->mats,
                                              sv->plan->fixed, sv->v.u, sv->du, e))
        return e->code;
    for (int k = 0; k < nd; k++)
        for (size_t i = 0; i < n; i++)
            if (sv->o.output[0] && !sv->on[i / 3]) sv->du[k * n + i] = NAN;
    sv->t_sens += kt_now() - t0;
    return KT_OK;
}

/* The end of every solved step: the backend's field restricted to the output set, verified,
 * its row. */
static int finish(kt_solver *sv, kt_err *e)
{
    sv->be->view(sv->st, &sv->v);
    size_t n = 3 * (size_t)sv->v.mesh->nn;
    if (room(sv, n, e)) return e->code;
    sv->row = sv->v.row;
    sv->row.verify_rel_diff = sv->row.t_verify = NAN;
    if (sv->o.output[0] && set_nodes(sv->v.mesh, sv->o.output, sv->on, e)) return e->code;
    for (size_t i = 0; i < n; i++)
        sv->u[i] = !sv->o.output[0] || sv->on[i / 3] ? sv->v.u[i] : NAN;
    if (sv->sens && derivatives(sv, e)) return e->code;
    return sv->o.verify ? verify(sv, e) : KT_OK;
}

/* The planned backend, or the stream method it falls back to; the nonlinear reference. */
static int start(kt_solver *sv, const kt_solver_in *in, kt_err *e)
{
    if (sv->o.method == KT_AUG_NEWTON) {
        sv->be = &kt_solver_newton;
        char none[8]; /* it applies to every plan */
        return sv->be->create(&sv->st, in, none, sizeof none, e);
    }
    if (sv->o.method == KT_AUG_PLANNED) {
        sv->be = &kt_solver_planned;
        if (sv->be->create(&sv->st, in, sv->why, sizeof sv->why, e)) return e->code;
        if (sv->st) return KT_OK;
        sv->fell_back = 1;
        if (in->plan->usable) { /* a fresh METIS factorization per step: cheaper, as exact */
            sv->o.method = KT_AUG_REFACTOR;
            sv->o.ordering = KT_AUG_ORDER_METIS;
        } else {
            sv->o.method = KT_AUG_AUGMENTED;
            sv->o.factor = KT_AUG_FACTOR_SUPERNODAL; /* its W is kept by supernode */
        }
    }
    sv->be = &kt_solver_stream;
    kt_solver_in in2 = *in;
    in2.o = &sv->o;
    char none[8]; /* the stream methods apply to every plan */
    return sv->be->create(&sv->st, &in2, none, sizeof none, e);
}

int kt_solver_create(kt_solver **out, const kt_aug_problem *prob, const kt_edits_plan *plan,
                     const kt_mesh *final, const kt_solver_opts *o, kt_err *e)
{
    *out = NULL;
    kt_solver *sv = kt_calloc(1, sizeof *sv, e);
    if (!sv) return e->code;
    sv->o = o->aug;
    sv->plan = plan;
    sv->prob = prob;
    sv->sens = o->sens;
    if (o->sens && o->aug.method == KT_AUG_NEWTON) {
        kt_fail(e, KT_EINPUT, "--uncertainty: --method newton gives no derivatives (the "
                "derivatives are of the linearized problem: use the planned method or a stream "
                "method)");
        kt_solver_free(sv);
        return e->code;
    }
    unsigned char *out_final = NULL;
    if (!(sv->want = kt_calloc((size_t)plan->nsteps + 1, 1, e))) goto fail;
    for (int k = 0; k <= plan->nsteps; k++) {
        sv->want[k] = !o->want || o->want[k] || k == 0;
        if (sv->want[k]) sv->last = k;
    }
    if (sv->o.output[0] && (!(out_final = kt_calloc((size_t)final->nn, 1, e)) ||
                            set_nodes(final, sv->o.output, out_final, e)))
        goto fail;
    kt_solver_in in = {prob, plan, final, out_final, &sv->o, o->plan_max_ratio, o->sens};
    if (start(sv, &in, e) || finish(sv, e)) goto fail;
    free(out_final);
    *out = sv;
    return KT_OK;
fail:
    free(out_final);
    kt_solver_free(sv);
    return e->code;
}

int kt_solver_step(kt_solver *sv, int *solved, kt_err *e)
{
    *solved = 0;
    int k = sv->step + 1;
    if (k > sv->plan->nsteps) return kt_fail(e, KT_ERUN, "step %d: the plan has %d", k, sv->plan->nsteps);
    int mode = sv->want[k] ? KT_SOLVER_SOLVE : k < sv->last ? KT_SOLVER_CARRY : KT_SOLVER_SKIP;
    if (sv->be->step(sv->st, &sv->plan->step[k - 1], mode, e)) return e->code;
    sv->step = k;
    if (mode != KT_SOLVER_SOLVE) return KT_OK;
    *solved = 1;
    return finish(sv, e);
}

void kt_solver_free(kt_solver *sv)
{
    if (!sv) return;
    if (sv->st) sv->be->free(sv->st);
    free(sv->want);
    free(sv->u);
    free(sv->ref);
    free(sv->on);
    free(sv->du);
    free(sv);
}

int kt_solver_at(const kt_solver *sv) { return sv->step; }
int kt_solver_method(const kt_solver *sv) { return sv->o.method; }
const kt_aug_opts *kt_solver_opts_used(const kt_solver *sv) { return &sv->o; }
const char *kt_solver_fallback(const kt_solver *sv) { return sv->fell_back ? sv->why : NULL; }
const kt_mesh *kt_solver_mesh(const kt_solver *sv) { return sv->v.mesh; }
const double *kt_solver_u(const kt_solver *sv) { return sv->u; }
const int *kt_solver_origin(const kt_solver *sv) { return sv->v.origin; }
const kt_aug_row *kt_solver_row(const kt_solver *sv) { return &sv->row; }

const double *kt_solver_reaction(kt_solver *sv, kt_err *e)
{
    return sv->o.output[0] ? NULL : sv->be->reaction(sv->st, e);
}

const double *kt_solver_dudp(const kt_solver *sv, int k)
{
    if (!sv->sens || k < 0 || k >= sv->sens->nd) return NULL;
    return sv->du + (size_t)k * 3 * sv->v.mesh->nn;
}

double kt_solver_t_sens(const kt_solver *sv) { return sv->t_sens; }
