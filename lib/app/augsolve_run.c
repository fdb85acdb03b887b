/* augsolve_run.c: the augsolve tool's work: mesh + scene + edits stream -> run folder with one VTK
 * per step, steps.tsv and run.yaml (all written atomically). */
#define _XOPEN_SOURCE 700
#define _DEFAULT_SOURCE /* flock */
#include <fcntl.h>
#include <sys/file.h>
#include <errno.h>
#include <inttypes.h>
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "augsolve_run.h"

#include "aug.h"
#include "aug_plan.h"
#include "bind.h"
#include "msh.h"
#include "physics.h"
#include "scene.h"
#include "vtk.h"

/* Everything the run holds, freed in one place. */
typedef struct run {
    kt_mesh mesh;
    kt_scene scene;
    kt_fem_problem fem;
    kt_physics phys;            /* per-tet physics; fem.mats.td points into it */
    kt_aug_problem prob;
    FILE *edits;
    kt_edits_reader rd;
    kt_step step;
    kt_aug *aug;
    kt_plan plan;               /* the whole stream when it was read to its end */
    int plan_read, next;        /* steps come from plan.step[next] */
    kt_mesh final;              /* the planned method's final cut mesh */
    kt_plan_factor F;
    kt_plan_state S;
    unsigned char *want;        /* nsteps+1: steps to write (planned: to solve) */
    unsigned char *outmask;     /* nodes of the --output surface (planned), NULL: all */
    double *ufresh;
    const char *fallback;       /* why the planned method did not apply */
    int fallback_method;        /* and what runs instead */
    char why[256];              /* the fallback's reason when the factor was refused */
    double t_setup;             /* ms: the planned method's assembly, ordering, factorization */
    kt_out tsv;
    int tsv_open;
    char scene_path[PATH_MAX];
    int quiet;
    int locked, lock_fd;    /* the run folder's lock (claim_run_dir) */
    char lock_path[PATH_MAX];
} run;

static void run_free(run *r)
{
    kt_aug_free(r->aug);
    kt_step_free(&r->step);
    kt_plan_state_free(&r->S);
    kt_plan_factor_free(&r->F);
    kt_mesh_free(&r->final);
    kt_plan_free(&r->plan);
    free(r->want);
    free(r->outmask);
    free(r->ufresh);
    if (r->edits && r->edits != stdin) fclose(r->edits);
    if (r->tsv_open) kt_out_abort(&r->tsv);
    kt_fem_problem_free(&r->fem);
    kt_physics_free(&r->phys);
    kt_mesh_free(&r->mesh);
    if (r->locked) {
        unlink(r->lock_path);
        close(r->lock_fd);
    }
}

/* Claim the run folder: an exclusive lock on <dir>/.augsolve.lock (the kernel drops it when a
 * run ends or is killed), so a second augsolve into the same folder is refused instead of
 * mixing its steps with the first's; then the previous result's run.yaml and steps.tsv go, so
 * a re-run that fails or is killed leaves no run.yaml and no reader takes its mix of old and
 * new step files as a result. */
static int claim_run_dir(run *r, const char *dir, kt_err *e)
{
    char path[PATH_MAX];
    if (kt_mkdir_p(dir, e)) return e->code;
    if (snprintf(r->lock_path, sizeof r->lock_path, "%s/.augsolve.lock", dir) >= (int)sizeof r->lock_path)
        return kt_fail(e, KT_EINPUT, "%s: path too long", dir);
    int fd = open(r->lock_path, O_CREAT | O_RDWR | O_CLOEXEC, 0644);
    if (fd < 0) return kt_fail(e, KT_EINPUT, "%s: cannot create: %s", r->lock_path, strerror(errno));
    if (flock(fd, LOCK_EX | LOCK_NB) != 0) {
        close(fd);
        return kt_fail(e, KT_EINPUT, "%s: another augsolve is writing into this run folder (%s is "
                       "locked)", dir, r->lock_path);
    }
    r->lock_fd = fd;
    r->locked = 1;
    snprintf(path, sizeof path, "%s/run.yaml", dir);
    unlink(path);
    snprintf(path, sizeof path, "%s/steps.tsv", dir);
    unlink(path);
    return KT_OK;
}

static void abs_path(const char *p, char *out, size_t n)
{
    char buf[PATH_MAX];
    if (strcmp(p, "-") != 0 && realpath(p, buf)) snprintf(out, n, "%s", buf);
    else snprintf(out, n, "%s", p);
}

/* The edits stream's header, checked against the mesh: counts, and the content hash when the
 * header has one (headers written before the hash are checked by their counts alone). */
static int open_edits(run *r, const char *path, const char *mesh, kt_err *e)
{
    r->edits = strcmp(path, "-") == 0 ? stdin : fopen(path, "r");
    if (!r->edits)
        return kt_fail(e, KT_EINPUT, "%s: cannot open the edits stream: %s", path, strerror(errno));
    if (kt_edits_open(&r->rd, r->edits, strcmp(path, "-") == 0 ? "<stdin>" : path, e))
        return e->code;
    if (r->rd.h.nn != r->mesh.nn || r->rd.h.ne != r->mesh.ne)
        return kt_fail(e, KT_EINPUT, "%s: the edits apply to a mesh of %d nodes and %d tets, "
                       "expected the %d nodes and %d tets of the mesh given", path, r->rd.h.nn,
                       r->rd.h.ne, r->mesh.nn, r->mesh.ne);
    uint64_t mine = kt_mesh_hash(&r->mesh);
    if (r->rd.h.has_hash && r->rd.h.hash != mine)
        return kt_fail(e, KT_EINPUT, "%s: the edits were made for another mesh: header hash "
                       "%016" PRIx64 ", mesh %s hashes to %016" PRIx64 " (same counts, other "
                       "coordinates or tets)", path, r->rd.h.hash, mesh, mine);
    return KT_OK;
}

/* Materials, fixation and pressures of the scene on this mesh, with its physics (fibre
 * matrices, the prestress of the measured geometry): kt_physics_problem. */
static int load_problem(run *r, const char *scene, kt_err *e)
{
    if (!scene || !scene[0])
        return kt_fail(e, KT_EINPUT, "%s: the edits header names no scene: give --scene",
                       r->rd.name);
    abs_path(scene, r->scene_path, sizeof r->scene_path);
    if (kt_scene_load(scene, &r->scene, e) ||
        kt_physics_problem(&r->scene, &r->mesh, &r->fem, &r->phys, e))
        return e->code;
    if (r->phys.prestressed)
        kt_log(r->quiet, "augsolve: prestress of the measured geometry under its loads (%.1f s): "
               "apex membrane stress %.4g kPa\n", r->phys.t_build, 1000 * r->phys.sig_apex);
    r->prob = kt_aug_problem_of(&r->mesh, &r->fem);
    return KT_OK;
}

/* What a step writes: the cut mesh, its displacement, origins and reactions (NULL: none). */
typedef struct view {
    const kt_mesh *mesh;
    int step;
    const double *u, *react;
    const int *origin;
    const kt_aug_row *row;
} view;

static int write_vtk(const kt_aug_run_opts *o, const view *v, kt_err *e)
{
    if (!o->vtk) return KT_OK;
    const kt_mesh *m = v->mesh;
    char path[PATH_MAX];
    snprintf(path, sizeof path, "%s/step-%04d.vtk", o->run_dir, v->step);
    double *origin = kt_calloc((size_t)m->nn, sizeof(double), e);
    if (!origin) return e->code;
    for (int i = 0; i < m->nn; i++) origin[i] = v->origin[i] + 1;
    kt_vtk_field f[3] = {{"displacement", 3, 0, 0, (double *)v->u},
                         {"origin", 1, 0, 1, origin},
                         {"reaction", 3, 0, 0, (double *)v->react}};
    kt_vtk_write_tets(path, m, f, v->react ? 3 : 2, o->binary, e);
    free(origin);
    return e->code;
}

/* The iterative methods' step as a view; reactions need u around the supports. */
static int aug_view(run *r, const kt_aug_run_opts *o, view *v, kt_err *e)
{
    *v = (view){kt_aug_mesh(r->aug), kt_aug_last(r->aug)->step, kt_aug_displacement(r->aug),
                NULL, kt_aug_origin(r->aug), kt_aug_last(r->aug)};
    if (o->vtk && !o->aug.output[0] && !(v->react = kt_aug_reaction(r->aug, e))) return e->code;
    return KT_OK;
}

static void tsv_num(FILE *f, double v, const char *fmt)
{
    if (isnan(v)) fputs("NaN", f);
    else fprintf(f, fmt, v);
}

static void write_row(run *r, const kt_aug_row *w)
{
    FILE *f = r->tsv.f;
    fprintf(f, "%d\t%d\t%d\t%d\t%d\t%d", w->step, w->n_dofs, w->m, w->new_dofs, w->iters,
            w->closure_max);
    double t[5] = {w->t_update, w->t_step1, w->t_step2, w->t_step3, w->t_total};
    for (int k = 0; k < 5; k++) {
        fputc('\t', f);
        tsv_num(f, t[k], "%.4f");
    }
    fputc('\t', f);
    tsv_num(f, w->rel_residual, "%.3e");
    fprintf(f, "\t%s\t", w->refactor);
    tsv_num(f, w->verify_rel_diff, "%.3e");
    fprintf(f, "\t%.0f\t", w->nnz_L);
    tsv_num(f, w->t_verify, "%.1f");
    fputc('\n', f);
}

static void progress(const kt_aug_row *w, int quiet)
{
    if (quiet) return;
    int tty = isatty(STDERR_FILENO);
    if (!tty && w->step % 10 != 0 && strcmp(w->refactor, "-") == 0) return;
    fprintf(stderr, "%saugsolve: step %d: %d DOFs, m %d, %d iterations, %.2f ms%s%s%s", tty ? "\r" : "",
            w->step, w->n_dofs, w->m, w->iters, w->t_total,
            strcmp(w->refactor, "-") ? ", refactor " : "", strcmp(w->refactor, "-") ? w->refactor : "",
            tty ? "   " : "\n");
}

/* A YAML double-quoted scalar: paths may hold ':' '#' or be "-", which plain scalars can't. */
static void yaml_str(FILE *f, const char *key, const char *v)
{
    fprintf(f, "%s: \"", key);
    for (; *v; v++) {
        if (*v == '"' || *v == '\\') fputc('\\', f);
        fputc(*v, f);
    }
    fputs("\"\n", f);
}

static int write_run_yaml(run *r, const kt_aug_run_opts *o, int steps, kt_err *e)
{
    char path[PATH_MAX], buf[PATH_MAX];
    snprintf(path, sizeof path, "%s/run.yaml", o->run_dir);
    kt_out out;
    if (kt_out_open(&out, path, e)) return e->code;
    /* paths relative to the run folder: a tree holding the run and its inputs can move */
    kt_path_relative(o->mesh, o->run_dir, buf, sizeof buf);
    yaml_str(out.f, "mesh", buf);
    kt_path_relative(r->scene_path, o->run_dir, buf, sizeof buf);
    yaml_str(out.f, "scene", buf);
    if (r->rd.h.plan[0]) {
        kt_path_relative(r->rd.h.plan, o->run_dir, buf, sizeof buf);
        yaml_str(out.f, "plan", buf);
    }
    kt_path_relative(o->edits, o->run_dir, buf, sizeof buf);
    yaml_str(out.f, "edits", buf);
    fprintf(out.f, "method: %s\norder: %d\nsteps: %d\n", kt_aug_method_name(o->aug.method),
            r->mesh.order, steps);
    static const char *const ORD[] = {"natural", "amd", "metis"};
    fprintf(out.f, "tol: %g\nordering: %s\nfactor: %s\n", o->aug.tol, ORD[o->aug.ordering],
            o->aug.factor == KT_AUG_FACTOR_SIMPLICIAL ? "simplicial" : "supernodal");
    if (o->aug.output[0]) yaml_str(out.f, "output", o->aug.output);
    if (r->fallback) yaml_str(out.f, "fallback", r->fallback);
    if (o->steps) yaml_str(out.f, "written_steps", o->steps);
    return kt_out_commit(&out, e);
}

static int open_tsv(run *r, const kt_aug_run_opts *o, kt_err *e)
{
    char path[PATH_MAX];
    snprintf(path, sizeof path, "%s/steps.tsv", o->run_dir);
    if (kt_out_open(&r->tsv, path, e)) return e->code;
    r->tsv_open = 1;
    fputs("step\tn_dofs\tm\tnew_dofs\titers\tclosure_max\tt_update_ms\tt_step1_ms\tt_step2_ms\t"
          "t_step3_ms\tt_total_ms\trel_residual\trefactor\tverify_rel_diff\tnnz_L\tt_verify_ms\n", r->tsv.f);
    return KT_OK;
}

void kt_aug_run_opts_default(kt_aug_run_opts *o)
{
    memset(o, 0, sizeof *o);
    o->vtk = 1;
    kt_aug_opts_default(&o->aug);
    o->aug.method = KT_AUG_PLANNED;
    o->aug.ordering = KT_AUG_ORDER_DEFAULT;
    o->plan_max_ratio = KT_PLAN_MAX_RATIO;
}

/* "1,4,7-9" -> want[k] for k in 1..nsteps; step 0 is always written. */
static int parse_steps(run *r, const char *list, int nsteps, kt_err *e)
{
    r->want = kt_calloc((size_t)nsteps + 1, 1, e);
    if (!r->want) return e->code;
    r->want[0] = 1;
    if (!list) {
        memset(r->want, 1, (size_t)nsteps + 1);
        return KT_OK;
    }
    const char *p = list;
    while (*p) {
        char *end;
        long a = strtol(p, &end, 10), b = a;
        if (end == p) break;
        p = end;
        if (*p == '-') {
            b = strtol(p + 1, &end, 10);
            if (end == p + 1) break;
            p = end;
        }
        if (a < 0 || b < a || b > nsteps)
            return kt_fail(e, KT_EINPUT, "--steps %s: expected steps in 0..%d, found %ld-%ld", list,
                           nsteps, a, b);
        for (long k = a; k <= b; k++) r->want[k] = 1;
        if (*p == ',') p++;
        else if (*p) break;
    }
    if (*p || !*list)
        return kt_fail(e, KT_EINPUT, "--steps %s: expected a list like 1,4,7-9", list);
    return KT_OK;
}

static int next_step(run *r, kt_err *e)
{
    if (!r->plan_read) return kt_edits_next(&r->rd, &r->step, e);
    if (r->next == r->plan.nsteps) return 0;
    kt_step_clear(&r->step);
    const kt_step *s = &r->plan.step[r->next++];
    r->step.index = s->index;
    memcpy(r->step.label, s->label, sizeof r->step.label);
    for (int i = 0; i < s->n; i++)
        if (kt_step_add(&r->step, &s->edit[i], e)) return -1;
    return 1;
}

/* The iterative methods and the baselines: each step solved as it arrives. */
static int run_stream(run *r, const kt_aug_run_opts *o, int *steps, kt_err *e)
{
    view v;
    if (kt_aug_create(&r->aug, &r->prob, &o->aug, e) || aug_view(r, o, &v, e) ||
        write_vtk(o, &v, e))
        return e->code;
    write_row(r, v.row);
    progress(v.row, o->aug.quiet);
    int rc;
    while ((rc = next_step(r, e)) == 1) {
        if (kt_aug_step(r->aug, &r->step, e)) return e->code;
        (*steps)++;
        if (r->want && (r->step.index > r->plan.nsteps || !r->want[r->step.index])) continue;
        if (aug_view(r, o, &v, e) || write_vtk(o, &v, e)) return e->code;
        write_row(r, v.row);
        progress(v.row, o->aug.quiet);
    }
    return rc < 0 ? e->code : KT_OK;
}

/* Nodes of the --output surface on the current cut mesh. */
static int output_nodes(run *r, const char *name, kt_err *e)
{
    const kt_mesh *m = &r->S.mesh;
    const kt_group *g = kt_mesh_find_group(m, 2, name);
    if (!g) return kt_fail(e, KT_EINPUT, "--output %s: expected a surface group of the mesh", name);
    free(r->outmask);
    if (!(r->outmask = kt_calloc((size_t)m->nn, 1, e))) return e->code;
    int fv = kt_tri_nv(m->order);
    for (int t = 0; t < m->nf; t++)
        if (m->tri_tag[t] == g->tag)
            for (int a = 0; a < fv; a++) r->outmask[m->tri[(size_t)t * fv + a]] = 1;
    return KT_OK;
}

/* --verify: the step against a fresh factorization of the cut mesh, over the output nodes. */
static int verify_planned(run *r, const kt_aug_run_opts *o, kt_err *e)
{
    double t, dmax = 0, rmax = 0;
    if (kt_plan_fresh(&r->S, &r->plan, &r->prob, r->ufresh, &t, e)) return e->code;
    for (int i = 0; i < 3 * r->S.mesh.nn; i++) {
        if (r->outmask && !r->outmask[i / 3]) continue;
        dmax = fmax(dmax, fabs(r->S.u[i] - r->ufresh[i]));
        rmax = fmax(rmax, fabs(r->ufresh[i]));
    }
    r->S.row.verify_rel_diff = rmax > 0 ? dmax / rmax : dmax;
    r->S.row.t_verify = 1e3 * t;
    if (!(r->S.row.verify_rel_diff <= o->aug.verify_tol))
        return kt_fail(e, KT_ERUN, "step %d: --verify: planned and a fresh factorization differ by "
                       "%.3g (relative, max norm) > --verify-tol %.3g", r->S.step,
                       r->S.row.verify_rel_diff, o->aug.verify_tol);
    return KT_OK;
}

static int planned_step(run *r, const kt_aug_run_opts *o, kt_err *e)
{
    if (kt_plan_solve(&r->S, &r->plan, &r->F, &r->prob, o->aug.tol, e)) return e->code;
    if (r->S.step == 0) { /* step 0's row holds the factorization, as the other methods' */
        r->S.row.t_update += r->t_setup;
        r->S.row.t_total += r->t_setup;
    }
    if (o->aug.output[0]) {
        if (output_nodes(r, o->aug.output, e)) return e->code;
        for (int i = 0; i < 3 * r->S.mesh.nn; i++)
            if (!r->outmask[i / 3]) r->S.u[i] = NAN;
    }
    if (o->aug.verify && verify_planned(r, o, e)) return e->code;
    view v = {&r->S.mesh, r->S.step, r->S.u, o->aug.output[0] ? NULL : r->S.react,
              r->S.origin, &r->S.row};
    if (write_vtk(o, &v, e)) return e->code;
    write_row(r, v.row);
    progress(v.row, o->aug.quiet);
    return KT_OK;
}

/* --output SET: the back substitution limited to what the set's nodes on the final mesh need
 * (they and their ancestors cover the set on every step's mesh). */
static int restrict_output(run *r, const kt_aug_run_opts *o, kt_err *e)
{
    if (!o->aug.output[0]) return KT_OK;
    const kt_mesh *m = &r->final;
    const kt_group *g = kt_mesh_find_group(m, 2, o->aug.output);
    if (!g) return kt_fail(e, KT_EINPUT, "--output %s: expected a surface group of the mesh",
                           o->aug.output);
    unsigned char *nodes = kt_calloc((size_t)m->nn, 1, e);
    if (!nodes) return e->code;
    int fv = kt_tri_nv(m->order);
    for (int t = 0; t < m->nf; t++)
        if (m->tri_tag[t] == g->tag)
            for (int a = 0; a < fv; a++) nodes[m->tri[(size_t)t * fv + a]] = 1;
    kt_plan_factor_restrict(&r->F, &r->plan, nodes, e);
    free(nodes);
    return e->code;
}

/* The planned method: the whole stream, checked, one factorization, then each wanted step.
 * Returns KT_OK with r->fallback set when the plan does not allow it. */
static int run_planned(run *r, const kt_aug_run_opts *o, int *steps, kt_err *e)
{
    if (kt_plan_read(&r->plan, &r->rd, e)) return e->code;
    r->plan_read = 1;
    if (kt_plan_check(&r->plan, r->rd.name, &r->prob, &r->final, e) ||
        parse_steps(r, o->steps, r->plan.nsteps, e))
        return e->code;
    if (!r->plan.usable) {
        r->fallback = r->plan.why;
        r->fallback_method = KT_AUG_AUGMENTED;
        return KT_OK;
    }
    if (kt_plan_factor_build(&r->F, &r->plan, &r->final, &r->fem.mats, o->aug.ordering,
                             o->aug.factor, o->plan_max_ratio, e))
        return e->code;
    if (r->F.refused) { /* a fresh METIS factorization per step is cheaper and as exact */
        snprintf(r->why, sizeof r->why, "%s", r->F.why);
        r->fallback = r->why;
        r->fallback_method = KT_AUG_REFACTOR;
        kt_plan_factor_free(&r->F);
        kt_mesh_free(&r->final);
        return KT_OK;
    }
    r->t_setup = 1e3 * (r->F.t_assemble + r->F.t_order + r->F.t_factor);
    if (kt_plan_state_init(&r->S, &r->plan, &r->prob, e) || restrict_output(r, o, e))
        return e->code;
    kt_mesh_free(&r->final);
    if (o->aug.verify && !(r->ufresh = kt_calloc(3 * (size_t)r->plan.nn, sizeof(double), e)))
        return e->code;
    kt_log(o->aug.quiet, "augsolve: planned: %d steps, %d free DOFs + %d increments, factor %.0f "
           "nonzeros (%.3gx METIS on the intact block; flops %.3gx) in %.2f s (assembly %.2f s, "
           "ordering %.2f s)\n", r->plan.nsteps, r->F.nK, r->F.nfree - r->F.nK, r->F.nnzL,
           r->F.lnz_plan / r->F.lnz_ref, r->F.fl_plan / r->F.fl_ref, r->F.t_factor,
           r->F.t_assemble, r->F.t_order);
    if (planned_step(r, o, e)) return e->code;
    int last = 0; /* the last step to write; a step before it that is not written still
                     continues the forward substitution (bitwise the fields of a full run) */
    for (int k = 1; k <= r->plan.nsteps; k++)
        if (r->want[k]) last = k;
    for (int k = 1; k <= r->plan.nsteps; k++) {
        if (kt_plan_advance(&r->S, &r->plan, e)) return e->code;
        (*steps)++;
        if (r->want[k] && planned_step(r, o, e)) return e->code;
        if (!r->want[k] && k < last && kt_plan_continue(&r->S, &r->plan, &r->F, &r->prob, e))
            return e->code;
    }
    kt_log(o->aug.quiet, "augsolve: planned: %d of the %d steps after step 0 continued its forward "
           "substitution (the others started it over)\n", r->F.ncont, last);
    return KT_OK;
}

int kt_aug_run(const kt_aug_run_opts *o_in, kt_err *e)
{
    kt_aug_run_opts o = *o_in;
    if (o.aug.ordering == KT_AUG_ORDER_DEFAULT)
        o.aug.ordering = o.aug.method == KT_AUG_PLANNED || o.aug.method == KT_AUG_AUGMENTED
                             ? KT_AUG_ORDER_METIS : KT_AUG_ORDER_NATURAL;
    run *r = kt_calloc(1, sizeof *r, e);
    if (!r) return e->code;
    int steps = 0;
    r->quiet = o.aug.quiet;
    if (kt_msh_read(o.mesh, &r->mesh, e) || open_edits(r, o.edits, o.mesh, e) ||
        load_problem(r, o.scene ? o.scene : r->rd.h.scene, e) || claim_run_dir(r, o.run_dir, e) ||
        open_tsv(r, &o, e))
        goto done;
    if (o.aug.method == KT_AUG_PLANNED) {
        if (run_planned(r, &o, &steps, e)) goto done;
        if (r->fallback) {
            int ref = r->fallback_method == KT_AUG_REFACTOR;
            fprintf(stderr, "augsolve: the planned method does not apply (%s): falling back to "
                    "--method %s\n", r->fallback, ref ? "refactor --ordering metis" : "augmented");
            o.aug.method = r->fallback_method;
            if (ref) o.aug.ordering = KT_AUG_ORDER_METIS;
            else o.aug.factor = KT_AUG_FACTOR_SUPERNODAL; /* its W is kept by supernode */
        }
    } else if (o.steps) {
        if (kt_plan_read(&r->plan, &r->rd, e) || parse_steps(r, o.steps, r->plan.nsteps, e))
            goto done;
        r->plan_read = 1;
    }
    if (o.aug.method != KT_AUG_PLANNED && run_stream(r, &o, &steps, e)) goto done;
    if (kt_out_commit(&r->tsv, e)) goto done;
    r->tsv_open = 0;
    if (write_run_yaml(r, &o, steps, e)) { /* no result without its run.yaml: take back the table */
        char path[PATH_MAX];
        snprintf(path, sizeof path, "%s/steps.tsv", o.run_dir);
        unlink(path);
    }
    if (!e->code && !o.aug.quiet && isatty(STDERR_FILENO)) fputc('\n', stderr);
    kt_log(o.aug.quiet || e->code, "augsolve: %d steps written to %s\n", steps, o.run_dir);
done:
    run_free(r);
    free(r);
    return e->code;
}
