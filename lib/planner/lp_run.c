/* lp_run.c: every family cut, solved and read in memory (lp_run.h). */
#include "lp_run.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bind.h"
#include "incise.h"
#include "lp_family.h"
#include "lp_read.h"
#include "lp_trim.h"
#include "pool.h"
#include "solver.h"

/* The physics the families share: solved once, adopted by every run on the same intact mesh. */
typedef struct shared {
    int solved;
    kt_physics ph;
    kt_fem_sens S;
    uint64_t hash;
    int nn, ne;
} shared;

/* One family's run; everything it allocates is freed by frun_free (which leaves it empty). */
typedef struct frun {
    const kt_lp_opts *o;
    kt_lp_answer *a;
    int fi;
    kt_plan *plan;
    kt_mesh m;                  /* the intact mesh as the run cuts it (the tunnel's snapping in) */
    kt_edits_plan ep;
    kt_mesh final;              /* the final cut mesh, until the solver is set up */
    kt_fem_problem fp;
    int bound;
    kt_aug_problem prob;
    kt_physics own_ph;          /* when the shared physics is another mesh's */
    kt_fem_sens own_S;
    const kt_physics *ph;
    const kt_fem_sens *S;
    kt_solver *sv;
    kt_lp_reader rd;
    double (*cpu)(void);        /* the CPU clock of its figures: the process's, or its thread's */
    const int *stop;            /* NULL, or the pool's flag (pool.h), with its job number: */
    int job;                    /* an earlier family failed, this one's answer is not needed */
} frun;

static void frun_free(frun *r)
{
    kt_solver_free(r->sv);
    kt_lp_reader_free(&r->rd);
    kt_physics_free(&r->own_ph);
    kt_fem_sens_free(&r->own_S);
    if (r->bound) kt_fem_problem_free(&r->fp);
    kt_mesh_free(&r->final);
    kt_edits_plan_free(&r->ep);
    kt_mesh_free(&r->m);
    free(r->plan);
    *r = (frun){.o = r->o, .a = r->a, .fi = r->fi, .cpu = r->cpu}; /* freed twice: nothing */
}

/* A cut the model refuses (KT_EINPUT: a piece cut off, an element left hanging by one face)
 * said again in the surgeon's terms: the patient file and what to change, without the
 * in-memory plan's name or a node number ("plan:line:col: " dropped, "(node N at" -> "(at",
 * "tunnel 1" -> "the main incision", "incision 1" -> "the <family> arcs"). Others unchanged. */
static int cut_refused(const kt_lp_answer *a, const kt_lp_family *f, const kt_plan *p, kt_err *e)
{
    if (e->code != KT_EINPUT) return e->code;
    char why[sizeof e->msg], arcs[48], *w = why, *end = why + sizeof why - 1;
    const char *m = e->msg;
    snprintf(arcs, sizeof arcs, "the %s arcs", f->name);
    if (strncmp(m, p->path, strlen(p->path)) == 0) { /* "PLAN:line:col: " */
        m += strlen(p->path);
        for (int colons = 0; *m && colons < 2; m++) colons += *m == ':';
        while (*m == ':' || *m == ' ') m++;
    }
    while (*m && w < end) {
        const char *at = strncmp(m, "(node ", 6) == 0 ? strstr(m, " at ") : NULL, *put = NULL;
        if (at) m = at + 4, put = "(at ";
        else if (strncmp(m, "tunnel 1", 8) == 0) m += 8, put = "the main incision";
        else if (strncmp(m, "incision 1", 10) == 0) m += 10, put = arcs;
        if (!put) *w++ = *m++;
        for (; put && *put && w < end; put++) *w++ = *put;
    }
    *w = '\0';
    return kt_fail(e, KT_EINPUT, "%s: %s (before any solve); change main_incision (meridian, width) or constraints "
                   "(max_arc, clearance)", a->eye.p.path, why);
}

/* The family's plan cut on a copy of the intact mesh, every step into the solver's plan; the
 * leading steps labelled "(tunnel ...)" are the main incision's. */
static int cut(frun *r, kt_err *e)
{
    const kt_lp_answer *a = r->a;
    const kt_lp_family fc = kt_lp_family_cut(a, r->fi), *f = &fc;
    kt_lp_run *run = &r->a->run.r[r->fi];
    double c0 = r->cpu();
    kt_incise *c = NULL;
    kt_step s;
    memset(&s, 0, sizeof s);
    if (!(r->plan = kt_calloc(1, sizeof *r->plan, e)) ||
        kt_lp_family_plan(&a->scene, &a->eye, f, r->o->step, a->trim.t[r->fi].nstep, r->plan, e) ||
        kt_mesh_copy(&r->m, &a->mesh.m, e) || kt_plan_check_mesh(r->plan, &r->m, "the patient's mesh", e))
        return e->code;
    if (kt_incise_begin(&c, r->plan, &r->m, 1, e)) return kt_incise_end(c), cut_refused(a, f, r->plan, e);
    int more, lead = 1;
    while ((more = kt_incise_next(c, &s, e)) > 0) {
        lead = lead && strstr(s.label, "(tunnel ") != NULL;
        run->skip += lead;
        if (kt_edits_plan_add(&r->ep, &s, e)) break;
    }
    kt_step_free(&s);
    kt_incise_end(c);
    if (more < 0) cut_refused(a, f, r->plan, e);
    if (!e->code && r->ep.nsteps == 0) kt_fail(e, KT_ERUN, "%s arcs: the plan makes no step on the mesh", f->name);
    run->cpu_cut = r->cpu() - c0;
    return e->code;
}

/* The shared physics, solved on mesh m (its own binding of the scene). */
static int shared_solve(shared *sh, const kt_scene *s, const kt_mesh *m, int band, kt_err *e)
{
    kt_fem_problem fp;
    if (kt_fem_bind(s, m, &fp, e)) return e->code;
    if (band) kt_fem_sens_plan(s, &fp, &sh->S);
    int rc = band ? kt_physics_finish_sens(s, m, &fp, &sh->ph, &sh->S, e) : kt_physics_finish(s, m, &fp, &sh->ph, e);
    kt_fem_problem_free(&fp);
    if (rc) return rc;
    sh->solved = 1, sh->hash = kt_mesh_hash(m), sh->nn = m->nn, sh->ne = m->ne;
    return KT_OK;
}

/* The band's quantities, from the shared physics's derivative data. */
static void quantities(kt_lp_runs *rs, const kt_fem_sens *S)
{
    rs->nq = 0, rs->left[0] = '\0';
    for (int k = 0; k < S->nd && k < KT_LP_MAXQ; k++, rs->nq++) rs->q[k] = S->d[k].q, rs->sd[k] = S->sd[S->d[k].q];
    for (int q = 0; q < KT_UQ_N; q++) {
        if (S->method[q] != KT_SENS_FD || !(S->sd[q] > 0)) continue;
        size_t n = strlen(rs->left);
        snprintf(rs->left + n, sizeof rs->left - n, "%s%s", n ? ", " : "", kt_uq_name(q));
    }
}

/* The run's problem: the scene bound on its mesh, the stream checked against it, the physics
 * (the shared one when it is this mesh's, else its own), as augsolve sets them up. */
static int problem(frun *r, shared *sh, kt_err *e)
{
    const kt_scene *s = &r->a->scene.s;
    int band = !r->o->no_band;
    if (kt_fem_bind(s, &r->m, &r->fp, e)) return e->code;
    r->bound = 1;
    r->prob = kt_aug_problem_of(&r->m, &r->fp);
    if (kt_edits_plan_check(&r->ep, r->plan->path, &r->prob, &r->final, e)) return e->code;
    if (!sh->solved) {
        double c0 = r->cpu();
        if (shared_solve(sh, s, &r->m, band, e)) return e->code;
        r->a->run.cpu_physics += r->cpu() - c0;
        kt_log(r->o->quiet, "lri-plan: the families' shared prestress (CPU %.1f s)\n", r->a->run.cpu_physics);
        if (band) quantities(&r->a->run, &sh->S);
    }
    if (sh->nn == r->m.nn && sh->ne == r->m.ne && sh->hash == kt_mesh_hash(&r->m)) {
        r->ph = &sh->ph, r->S = &sh->S;
        kt_physics_adopt(r->ph, &r->m, &r->fp);
    } else {
        kt_log(r->o->quiet, "lri-plan: %s arcs: the shared physics is another mesh's: solving its own\n",
               r->a->fam.f[r->fi].name);
        if (band) kt_fem_sens_plan(s, &r->fp, &r->own_S);
        if (band ? kt_physics_finish_sens(s, &r->m, &r->fp, &r->own_ph, &r->own_S, e)
                 : kt_physics_finish(s, &r->m, &r->fp, &r->own_ph, e))
            return e->code;
        r->ph = &r->own_ph, r->S = &r->own_S;
    }
    r->prob.perm = r->ph->perm; /* the prestress solve's order: the planned method's too */
    if (r->ph->prestressed) kt_edits_plan_zero_values(&r->ep);
    return KT_OK;
}

/* The solver's step as the planner shows it. */
static void view(const frun *r, kt_lp_step *v)
{
    memset(v, 0, sizeof *v);
    v->family = r->fi, v->step = kt_solver_at(r->sv), v->nsteps = r->ep.nsteps, v->skip = r->a->run.r[r->fi].skip;
    v->mesh = kt_solver_mesh(r->sv), v->u = kt_solver_u(r->sv), v->origin = kt_solver_origin(r->sv);
    if (!r->o->no_band) {
        v->sens = r->S, v->nd = r->S->nd;
        for (int k = 0; k < v->nd; k++) v->dudp[k] = kt_solver_dudp(r->sv, k);
    }
    v->ph = r->ph, v->row = kt_solver_row(r->sv), v->wound = r->fp.wound;
    v->method = kt_solver_method(r->sv), v->fallback = kt_solver_fallback(r->sv);
}

/* Step v's readings into the family's run: step 0 is the intact eye; arc step k is the run's
 * step k + skip. */
static void store(kt_lp_run *run, const kt_lp_family *f, double step, int s, const kt_lp_reading *rd)
{
    if (s == 0) run->kerato_intact = rd->kerato, run->total_intact = rd->total;
    int k = s - run->skip;
    if (k < 0 || k > KT_LP_MAXSTEP) return;
    run->kerato[k] = rd->kerato, run->total[k] = rd->total;
    run->arc[k] = k * step;
    run->arc_opp[k] = f->paired ? k * step * f->ratio : 0;
    memcpy(run->dsia[k], rd->dsia, sizeof rd->dsia);
}

/* The solved step: read, kept, shown to the sink. */
static int step_done(frun *r, kt_err *e)
{
    kt_lp_run *run = &r->a->run.r[r->fi];
    kt_lp_step v;
    kt_lp_reading rd;
    view(r, &v);
    double c0 = r->cpu();
    if (kt_lp_read(&r->rd, &v, &rd, e)) return e->code;
    double c1 = r->cpu();
    store(run, &r->a->fam.f[r->fi], r->o->step, v.step, &rd);
    run->cpu_read += c1 - c0;
    if (r->o->sink && r->o->sink(r->o->sink_ctx, &v, e)) return e->code;
    run->cpu_sink += r->cpu() - c1;
    return KT_OK;
}

/* The planned method's fallback, loud: on stderr and in the family's run (plan.json). */
static void fallback(frun *r)
{
    kt_lp_run *run = &r->a->run.r[r->fi];
    const char *why = kt_solver_fallback(r->sv);
    run->method = kt_solver_method(r->sv);
    if (!why) return;
    snprintf(run->fallback, sizeof run->fallback, "%s", why);
    fprintf(stderr, "lri-plan: %s arcs: the planned method does not apply (%s): falling back to --method %s\n",
            r->a->fam.f[r->fi].name, why, run->method == KT_AUG_REFACTOR ? "refactor --ordering metis" : "augmented");
}

/* Whether an earlier family has failed (the pool's stop, pool.h): then this one stops, said on
 * stderr, where it is (after step k of n; k = -1: before its factorization). */
static int stopped(const frun *r, int k, int n)
{
    if (!r->stop || !kt_pool_stopped(r->stop, r->job)) return 0;
    if (k < 0) kt_log(r->o->quiet, "lri-plan: %s arcs: stopped before the factorization: an earlier family failed\n",
                      r->a->fam.f[r->fi].name);
    else kt_log(r->o->quiet, "lri-plan: %s arcs: stopped after step %d of %d: an earlier family failed\n",
                r->a->fam.f[r->fi].name, k, n);
    return 1;
}

/* Every step through the solver's front door, one factorization for the family; before it and
 * between two steps it stops (KT_POOL_STOPPED, e untouched) when an earlier family has failed. */
static int solve(frun *r, kt_err *e)
{
    kt_lp_run *run = &r->a->run.r[r->fi];
    double c0 = r->cpu();
    kt_solver_opts so;
    memset(&so, 0, sizeof so);
    kt_aug_opts_default(&so.aug);
    so.aug.method = KT_AUG_PLANNED, so.aug.ordering = KT_AUG_ORDER_METIS, so.aug.quiet = r->o->quiet;
    so.plan_max_ratio = r->o->plan_max_ratio;
    so.sens = r->o->no_band ? NULL : r->S;
    if (stopped(r, -1, r->ep.nsteps)) return KT_POOL_STOPPED;
    if (kt_solver_create(&r->sv, &r->prob, &r->ep, &r->final, &so, e)) return e->code;
    kt_mesh_free(&r->final);
    fallback(r);
    int rc = kt_lp_reader_init(&r->rd, &r->m, r->a->trim.t[r->fi].meridian, e);
    if (rc == KT_OK) rc = step_done(r, e);
    for (int k = 1; rc == KT_OK && k <= r->ep.nsteps; k++) {
        if (stopped(r, k - 1, r->ep.nsteps)) {
            rc = KT_POOL_STOPPED;
            break;
        }
        int solved = 0;
        rc = kt_solver_step(r->sv, &solved, e);
        if (rc == KT_OK && solved) rc = step_done(r, e);
    }
    if (rc == KT_OK && !r->o->no_band)
        kt_log(r->o->quiet, "lri-plan: %s arcs: %d derivative quantities, %.2f s in the steps' derivatives\n",
               r->a->fam.f[r->fi].name, r->S->nd, kt_solver_t_sens(r->sv));
    run->cpu_solve = r->cpu() - c0 - run->cpu_read - run->cpu_sink;
    return rc;
}

/* A family's first half: cut and problem (the first family's solves the shared physics). */
static int family_begin(frun *r, shared *sh, kt_err *e)
{
    const kt_lp_family *f = &r->a->fam.f[r->fi];
    kt_log(r->o->quiet, "lri-plan: %s arcs%s: cut, solve, read\n", f->name, r->a->scene.main_sim ? " after the main incision" : "");
    if (cut(r, e) == KT_OK) problem(r, sh, e);
    return e->code;
}

/* Its second half: the solve; its run complete (or stopped: KT_POOL_STOPPED), everything it
 * holds freed. */
static int family_end(frun *r, kt_err *e)
{
    kt_lp_run *run = &r->a->run.r[r->fi];
    const kt_lp_family *f = &r->a->fam.f[r->fi];
    int rc = e->code;
    if (rc == KT_OK && (rc = solve(r, e)) == KT_OK) {
        run->nstep = r->ep.nsteps - run->skip;
        run->ran = 1;
        if (run->nstep != r->a->trim.t[r->fi].nstep)
            rc = kt_fail(e, KT_ERUN, "%s arcs: expected %d steps of arc after the main incision's %d, the cut made %d",
                         f->name, r->a->trim.t[r->fi].nstep, run->skip, run->nstep);
    }
    frun_free(r);
    kt_log(r->o->quiet || rc, "lri-plan: %s arcs: CPU %.1f s cut, %.1f s solve, %.1f s read, %.1f s out\n", f->name,
           run->cpu_cut, run->cpu_solve, run->cpu_read, run->cpu_sink);
    return rc;
}

/* The families side by side (pool.h): family i > 0 begun and ended on a pool thread, family 0
 * ended there after its begin on the caller's thread (the shared physics, only read after it).
 * Every family has its own frun; a failure stops the later families at their next step. */
typedef struct families {
    frun *r;
    shared *sh;
} families;

static int family_job(void *ctx, int i, const int *stop, kt_err *e)
{
    families *c = ctx;
    frun *r = &c->r[i];
    r->stop = stop, r->job = i;
    if (i > 0) family_begin(r, c->sh, e);
    return family_end(r, e);
}

/* How many families run at once: o->jobs when set, else 2 when the load leaves two cores free
 * and the memory holds two runs (KT_LP_JOB_BYTES each), else 1; never more than the families,
 * and 1 under an address-space or data limit (util.h: kt_as_limited). */
static int jobs_for(const kt_lp_opts *o, int nfam)
{
    int j = o->jobs;
    if (j <= 0) j = kt_cores_free() >= 2 && (double)kt_mem_room() >= 2 * KT_LP_JOB_BYTES ? 2 : 1;
    if (j > nfam) j = nfam;
    if (kt_as_limited()) j = 1;
    return j < 1 ? 1 : j;
}

int kt_lp_runs_make(const kt_lp_opts *o, kt_lp_answer *a, kt_err *e)
{
    memset(&a->run, 0, sizeof a->run);
    int fam[KT_LP_NFAM], n = 0;
    for (int i = 0; i < a->fam.n; i++)
        if (a->trim.t[i].nstep > 0) fam[n++] = i;
    shared *sh = kt_calloc(1, sizeof *sh, e);
    frun *r = sh ? kt_calloc(n ? (size_t)n : 1, sizeof *r, e) : NULL;
    if (!r) return free(sh), e->code;
    int jobs = jobs_for(o, n);
    a->run.jobs = jobs;
    for (int k = 0; k < n; k++)
        r[k].o = o, r[k].a = a, r[k].fi = fam[k], r[k].cpu = jobs > 1 ? kt_thread_cpu_now : kt_cpu_now;
    if (jobs > 1) kt_log(o->quiet, "lri-plan: %d families side by side, on %d threads\n", n, jobs);
    double t0 = kt_now();
    families c = {r, sh};
    if (n > 0 && family_begin(&r[0], sh, e) == KT_OK) /* one job: the families one at a time */
        kt_pool_run(n, jobs, family_job, &c, e);
    for (int k = 0; k < n; k++) frun_free(&r[k]); /* those a failure left unstarted */
    a->run.solve_seconds = kt_now() - t0;
    kt_physics_free(&sh->ph);
    kt_fem_sens_free(&sh->S);
    free(sh), free(r);
    return e->code;
}
