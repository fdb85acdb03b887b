/* augsolve_run.c: the augsolve tool's work: mesh + scene + edits stream -> run folder with one VTK
 * per step, steps.tsv and run.yaml (all written atomically). */
#define _XOPEN_SOURCE 700
#define _DEFAULT_SOURCE /* flock */
#include <dirent.h>
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
#include "newton.h"
#include "solver.h"
#include "bind.h"
#include "msh.h"
#include "physics.h"
#include "runrec.h"
#include "scene.h"
#include "sens.h"
#include "vtk.h"
#include "wound.h"
#include "yml.h"

/* Everything the run holds, freed in one place. */
typedef struct run {
    kt_mesh mesh;
    kt_scene scene;
    kt_fem_problem fem;
    kt_physics phys;            /* the run's own physics (none when borrowed) */
    kt_fem_sens sens;           /* its own --uncertainty quantities and derivative data */
    const kt_physics *ph;       /* the physics the run solves with: &phys or the caller's
                                   (kt_aug_run_opts.physics); fem.mats.td points into it */
    const kt_fem_sens *S;       /* likewise &sens or the caller's */
    uint64_t mesh_hash;         /* kt_mesh_hash(&mesh) */
    kt_aug_problem prob;
    FILE *edits;
    kt_edits_reader rd;
    kt_edits_plan plan;               /* the whole stream, read to its end and checked */
    kt_mesh final;              /* its final cut mesh */
    unsigned char *want;        /* nsteps+1: steps to write (--steps) */
    kt_solver *sv;
    kt_out tsv;
    kt_tsvw tw;                 /* steps.tsv's writer */
    int tsv_open;
    char scene_path[PATH_MAX];
    unsigned long long plan_hash; /* the header's plan file as it was when the run started */
    int has_plan_hash;
    int quiet;
    int locked, lock_fd;    /* the run folder's lock (claim_run_dir) */
    char lock_path[PATH_MAX];
} run;

static void run_free(run *r)
{
    kt_solver_free(r->sv);
    kt_mesh_free(&r->final);
    kt_edits_plan_free(&r->plan);
    free(r->want);
    if (r->edits && r->edits != stdin) fclose(r->edits);
    if (r->tsv_open) kt_out_abort(&r->tsv);
    kt_fem_problem_free(&r->fem);
    kt_physics_free(&r->phys);
    kt_fem_sens_free(&r->sens);
    kt_mesh_free(&r->mesh);
    if (r->locked) {
        unlink(r->lock_path);
        close(r->lock_fd);
    }
}

/* A file a run or its curvature writes: step-NNNN.vtk, surface-NNNN.vtk, axial-NNNN.png, and
 * (was_run: the folder held a run) curvature.tsv, meridians.tsv, report.html, steps.pvd
 * (augsolve(1), FILES). */
static int run_file(const char *name, int was_run)
{
    static const char *const whole[] = {"curvature.tsv", "meridians.tsv", "report.html",
                                        "steps.pvd"};
    static const char *const pre[] = {"step-", "surface-", "axial-"};
    static const char *const ext[] = {".vtk", ".vtk", ".png"};
    for (size_t i = 0; was_run && i < sizeof whole / sizeof *whole; i++)
        if (strcmp(name, whole[i]) == 0) return 1;
    for (int i = 0; i < 3; i++) {
        size_t np = strlen(pre[i]), n = strlen(name), d = 0;
        if (strncmp(name, pre[i], np) != 0 || n < np + 4 || strcmp(name + n - 4, ext[i]) != 0)
            continue;
        for (size_t k = np; k < n - 4; k++, d++)
            if (name[k] < '0' || name[k] > '9') d = 99;
        if (d >= 4 && d < 99) return 1;
    }
    return 0;
}

/* A run folder holds one run: the previous run's files go, so a shorter plan run into the
 * folder of a longer one leaves no step file a reader would take as part of it. */
static int clear_run_dir(const char *dir, int was_run, kt_err *e)
{
    DIR *d = opendir(dir);
    if (!d) return kt_fail(e, KT_EINPUT, "%s: cannot open the run folder: %s", dir, strerror(errno));
    struct dirent *de;
    char path[PATH_MAX];
    while (e->code == KT_OK && (de = readdir(d)) != NULL) {
        if (!run_file(de->d_name, was_run)) continue;
        snprintf(path, sizeof path, "%s/%s", dir, de->d_name);
        if (unlink(path) != 0 && errno != ENOENT)
            kt_fail(e, KT_EINPUT, "%s: cannot remove a previous run's file: %s", path,
                    strerror(errno));
    }
    closedir(d);
    return e->code;
}

/* Claim the run folder: an exclusive lock on <dir>/.augsolve.lock (the kernel drops it when a
 * run ends or is killed), so a second augsolve into the same folder is refused instead of
 * mixing its steps with the first's; then the previous result's run.yaml and steps.tsv go, so
 * a re-run that fails or is killed leaves no run.yaml, and with them every step and
 * curvature file of the previous run (clear_run_dir). */
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
    snprintf(path, sizeof path, "%s/step-0000.vtk", dir);
    int was_run = access(path, F_OK) == 0; /* a run folder: its curvature's files go too */
    snprintf(path, sizeof path, "%s/run.yaml", dir);
    was_run |= access(path, F_OK) == 0;
    unlink(path);
    snprintf(path, sizeof path, "%s/steps.tsv", dir);
    unlink(path);
    snprintf(path, sizeof path, "%s/uncertainty.tsv", dir);
    unlink(path);
    return clear_run_dir(dir, was_run, e);
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
    kt_err ignored = {0}; /* a plan that cannot be read gets no hash (curvature needs it anyway) */
    r->has_plan_hash = r->rd.h.plan[0] && kt_fnv1a_file(r->rd.h.plan, &r->plan_hash, &ignored) == KT_OK;
    uint64_t mine = r->mesh_hash = kt_mesh_hash(&r->mesh);
    if (r->rd.h.has_hash && r->rd.h.hash != mine)
        return kt_fail(e, KT_EINPUT, "%s: the edits were made for another mesh: header hash "
                       "%016" PRIx64 ", mesh %s hashes to %016" PRIx64 " (same counts, other "
                       "coordinates or tets)", path, r->rd.h.hash, mesh, mine);
    return KT_OK;
}

/* Materials, fixation and pressures of the scene on this mesh, bound (kt_fem_bind: no solve);
 * the physics (fibre matrices, the prestress solve) comes later, in solve_physics, once every
 * input has been checked. */
static int bind_problem(run *r, const char *scene, kt_err *e)
{
    if (!scene || !scene[0])
        return kt_fail(e, KT_EINPUT, "%s: the edits header names no scene: give --scene",
                       r->rd.name);
    abs_path(scene, r->scene_path, sizeof r->scene_path);
    if (kt_scene_load(scene, &r->scene, e) || kt_fem_bind(&r->scene, &r->mesh, &r->fem, e))
        return e->code;
    r->prob = kt_aug_problem_of(&r->mesh, &r->fem);
    return KT_OK;
}

/* The physics of scene sc on mesh m bound as fp (kt_physics_finish: the prestress of the
 * measured geometry under its loads; with uncertainty the quantities' derivative data too). */
static int physics_solve(const kt_scene *sc, const kt_mesh *m, kt_fem_problem *fp, int uncertainty,
                         kt_physics *ph, kt_fem_sens *S, kt_err *e)
{
    if (!uncertainty) return kt_physics_finish(sc, m, fp, ph, e);
    kt_fem_sens_plan(sc, fp, S);
    return kt_physics_finish_sens(sc, m, fp, ph, S, e);
}

static void prestress_line(int quiet, const kt_physics *ph)
{
    kt_log(quiet, "augsolve: prestress of the measured geometry under its loads (%.1f s): apex "
           "membrane stress %.4g kPa\n", ph->t_build, 1000 * ph->sig_apex);
}

int kt_aug_physics_solve(kt_aug_physics *p, const char *mesh, const char *scene, int uncertainty,
                         int quiet, kt_err *e)
{
    memset(p, 0, sizeof *p);
    double t0 = kt_now();
    kt_mesh m;
    memset(&m, 0, sizeof m);
    kt_scene *sc = kt_calloc(1, sizeof *sc, e);
    kt_fem_problem fp;
    int bound = 0;
    if (!sc || kt_msh_read(mesh, &m, e) || kt_fnv1a_file(scene, &p->scene_hash, e) ||
        kt_scene_load(scene, sc, e) || kt_fem_bind(sc, &m, &fp, e))
        goto done;
    bound = 1;
    if (physics_solve(sc, &m, &fp, uncertainty, &p->ph, &p->sens, e)) goto done;
    p->uncertainty = uncertainty != 0;
    p->mesh_hash = kt_mesh_hash(&m);
    p->nn = m.nn, p->ne = m.ne;
    p->solved = 1;
    p->seconds = kt_now() - t0;
    if (p->ph.prestressed) prestress_line(quiet, &p->ph);
done:
    if (bound) kt_fem_problem_free(&fp);
    kt_mesh_free(&m);
    free(sc);
    if (e->code) memset(p, 0, sizeof *p); /* physics_solve freed its own on failure */
    return e->code;
}

void kt_aug_physics_free(kt_aug_physics *p)
{
    kt_fem_sens_free(&p->sens);
    kt_physics_free(&p->ph);
    memset(p, 0, sizeof *p);
}

/* Why the caller's physics p is not this run's (NULL: it is: the same mesh and scene bytes,
 * solved with the run's uncertainty). */
static const char *not_ours(const run *r, const kt_aug_physics *p, int uncertainty)
{
    if (!p->solved) return "not solved";
    if (p->uncertainty != (uncertainty != 0))
        return uncertainty ? "solved without --uncertainty's derivatives"
                           : "solved with --uncertainty's derivatives";
    if (p->nn != r->mesh.nn || p->ne != r->mesh.ne || p->mesh_hash != r->mesh_hash)
        return "solved on another mesh";
    unsigned long long h = 0;
    kt_err ignored = {0};
    if (kt_fnv1a_file(r->scene_path, &h, &ignored) != KT_OK || h != p->scene_hash)
        return "solved for another scene";
    return NULL;
}

/* The scene's physics on the bound problem: the caller's when it lends the run this mesh's and
 * scene's (kt_aug_run_opts.physics), else solved here (kt_physics_finish: the prestress of the
 * measured geometry under its loads); the plan's prescribed values follow the problem's. */
static int solve_physics(run *r, const kt_aug_run_opts *o, kt_err *e)
{
    const char *why = o->physics ? not_ours(r, o->physics, o->uncertainty) : "";
    if (!why) {
        r->ph = &o->physics->ph, r->S = &o->physics->sens;
        kt_physics_adopt(r->ph, &r->mesh, &r->fem);
    } else {
        if (o->physics)
            kt_log(r->quiet, "augsolve: the caller's physics is not this run's (%s): solving "
                   "its own\n", why);
        if (physics_solve(&r->scene, &r->mesh, &r->fem, o->uncertainty, &r->phys, &r->sens, e))
            return e->code;
        r->ph = &r->phys, r->S = &r->sens;
    }
    r->prob.perm = r->ph->perm; /* the prestress solve's order: the planned method's too */
    if (r->ph->prestressed) {
        kt_edits_plan_zero_values(&r->plan);
        if (why) prestress_line(r->quiet, r->ph);
        else
            kt_log(r->quiet, "augsolve: prestress of the measured geometry: the caller's, solved "
                   "once for this mesh and scene (%.1f s)\n", o->physics->ph.t_build);
    }
    return KT_OK;
}

/* The healed wound's bridge on the step's cut mesh as a cell field (written for a healed wound
 * only): its k (MPa/mm) on every tet with a bridged (cut) face, 0 elsewhere (keratome-vtk(5)). */
static int bridge_field(const kt_wound *w, const kt_mesh *m, double *b, kt_err *e)
{
    if (!w || !(w->k > 0)) return KT_OK;
    int *slots, n;
    if (kt_wound_pairs(w, m, &slots, &n, e)) return e->code;
    for (int q = 0; q < n; q++) b[slots[q] / 4] = b[w->mate[slots[q]] / 4] = w->k;
    free(slots);
    return KT_OK;
}

int kt_aug_step_vtk(const char *path, const kt_aug_step_fields *sf, int binary, kt_err *e)
{
    const kt_mesh *m = sf->mesh;
    double *origin = kt_calloc((size_t)m->nn, sizeof(double), e);
    double *bridge = kt_calloc((size_t)(m->ne ? m->ne : 1), sizeof(double), e);
    if (!origin || !bridge || bridge_field(sf->wound, m, bridge, e)) {
        free(origin), free(bridge);
        return e->code;
    }
    for (int i = 0; i < m->nn; i++) origin[i] = sf->origin[i] + 1;
    kt_vtk_field f[4 + KT_UQ_N + KT_PHYSICS_NFIELD] = {
        {"displacement", 3, 0, 0, (double *)sf->u}, {"origin", 1, 0, 1, origin}, {"reaction", 3, 0, 0, (double *)sf->react}};
    int nf = sf->react ? 3 : 2;
    for (int k = 0; sf->sens && k < sf->sens->nd; k++, nf++) { /* du/dq, mm per unit of q */
        memset(&f[nf], 0, sizeof f[nf]);
        snprintf(f[nf].name, sizeof f[nf].name, "dudp_%s", kt_uq_name(sf->sens->d[k].q));
        f[nf].ncomp = 3;
        f[nf].v = (double *)sf->dudp[k];
    }
    if (sf->wound) f[nf++] = (kt_vtk_field){"bridge", 1, 1, 0, bridge}; /* a healed wound's */
    for (int k = 0; sf->ph && k < sf->ph->ncell; k++) f[nf++] = sf->ph->cell[k];
    kt_vtk_write_tets(path, m, f, nf, binary, e);
    free(origin), free(bridge);
    return e->code;
}

/* The step's VTK: the cut mesh, its displacement (NaN off the --output set), origins and
 * reactions (none with --output); step 0's also the per-tet inputs of the physics (the cut
 * keeps the tets, so step 0's fields hold on every step: written once, keratome-vtk(5)). */
static int write_vtk(run *r, const kt_aug_run_opts *o, kt_err *e)
{
    if (!o->vtk) return KT_OK;
    const double *react = kt_solver_reaction(r->sv, e);
    if (e->code) return e->code;
    char path[PATH_MAX];
    snprintf(path, sizeof path, "%s/step-%04d.vtk", o->run_dir, kt_solver_at(r->sv));
    const double *dudp[KT_UQ_N];
    for (int k = 0; o->uncertainty && k < r->S->nd; k++) dudp[k] = kt_solver_dudp(r->sv, k);
    kt_aug_step_fields sf = {kt_solver_mesh(r->sv), kt_solver_u(r->sv), kt_solver_origin(r->sv), react,
                             o->uncertainty ? r->S : NULL, dudp, kt_solver_at(r->sv) == 0 ? r->ph : NULL, r->fem.wound};
    return kt_aug_step_vtk(path, &sf, o->binary, e);
}

void kt_aug_steps_head(kt_tsvw *w)
{
    static const char *const H[] = {"step", "n_dofs", "m", "new_dofs", "iters", "closure_max", "t_update_ms",
                                    "t_step1_ms", "t_step2_ms", "t_step3_ms", "t_total_ms", "rel_residual",
                                    "verify_rel_diff", "nnz_L", "t_verify_ms"};
    for (size_t k = 0; k < sizeof H / sizeof *H; k++) kt_tsvw_text(w, H[k]);
    kt_tsvw_end(w);
}

void kt_aug_steps_row(kt_tsvw *w, const kt_aug_row *r)
{
    long long n[6] = {r->step, r->n_dofs, r->m, r->new_dofs, r->iters, r->closure_max};
    for (int k = 0; k < 6; k++) kt_tsvw_int(w, n[k]);
    double t[5] = {r->t_update, r->t_step1, r->t_step2, r->t_step3, r->t_total};
    for (int k = 0; k < 5; k++) kt_tsvw_num(w, t[k], "%.4f");
    kt_tsvw_num(w, r->rel_residual, "%.3e");
    kt_tsvw_num(w, r->verify_rel_diff, "%.3e");
    kt_tsvw_num(w, r->nnz_L, "%.0f"); /* newton: NaN */
    kt_tsvw_num(w, r->t_verify, "%.1f");
    kt_tsvw_end(w);
}

static void progress(const kt_aug_row *w, int quiet)
{
    if (quiet) return;
    int tty = isatty(STDERR_FILENO);
    if (!tty && w->step % 10 != 0) return;
    fprintf(stderr, "%saugsolve: step %d: %d DOFs, m %d, %d iterations, %.2f ms%s", tty ? "\r" : "",
            w->step, w->n_dofs, w->m, w->iters, w->t_total, tty ? "   " : "\n");
}

/* key: "value" (kt_yml_put_quoted). */
static void yaml_str(FILE *f, const char *key, const char *v)
{
    fprintf(f, "%s: ", key);
    kt_yml_put_quoted(f, v);
    fputc('\n', f);
}

int kt_aug_run_yaml(const kt_aug_run_info *ri, kt_err *e)
{
    const kt_aug_opts *a = ri->aug;
    char path[PATH_MAX], buf[PATH_MAX];
    snprintf(path, sizeof path, "%s/run.yaml", ri->run_dir);
    kt_out out;
    if (kt_out_open(&out, path, e)) return e->code;
    /* paths relative to the run folder: a tree holding the run and its inputs can move */
    const char *keys[4] = {"mesh", "scene", "plan", "edits"}, *paths[4] = {ri->mesh, ri->scene, ri->plan, ri->edits};
    for (int k = 0; k < 4; k++) {
        if (!paths[k] || !paths[k][0]) continue;
        kt_path_relative(paths[k], ri->run_dir, buf, sizeof buf);
        yaml_str(out.f, keys[k], buf);
    }
    fprintf(out.f, "method: %s\norder: %d\nsteps: %d\n", kt_aug_method_name(a->method), ri->order, ri->steps);
    /* what curvature cross-checks: the mesh's content hash and node count, the plan's bytes */
    fprintf(out.f, "mesh_hash: \"%016" PRIx64 "\"  # kt_mesh_hash: FNV-1a of the nodes and tets\n"
            "mesh_nodes: %d\nmesh_tets: %d\n", ri->hash, ri->nn, ri->ne);
    if (ri->has_plan_hash) fprintf(out.f, "plan_hash: \"%016llx\"\n", ri->plan_hash);
    static const char *const ORD[] = {"natural", "amd", "metis"};
    kt_newton_opts nl;
    kt_newton_defaults(&nl);
    if (a->method == KT_AUG_NEWTON) /* its rtol; CHOLMOD orders its tangent itself */
        fprintf(out.f, "tol: %g\nordering: cholmod\nfactor: supernodal\n", nl.rtol);
    else
        fprintf(out.f, "tol: %g\nordering: %s\nfactor: %s\n", a->tol, ORD[a->ordering],
                a->factor == KT_AUG_FACTOR_SIMPLICIAL ? "simplicial" : "supernodal");
    if (ri->output && ri->output[0]) yaml_str(out.f, "output", ri->output);
    if (ri->fallback) yaml_str(out.f, "fallback", ri->fallback);
    if (ri->written_steps) yaml_str(out.f, "written_steps", ri->written_steps);
    if (ri->step_files) { /* the step files written, exactly: what curvature reads (augsolve(1), FILES) */
        fputs("step_files: [", out.f);
        for (int k = 0, first = 1; k < ri->nstep_files; k++)
            if (ri->step_files[k]) fprintf(out.f, first ? "%d" : ", %d", k), first = 0;
        fputs("]\n", out.f);
    }
    if (ri->uncertainty) fputs("uncertainty: on\n", out.f);
    if (kt_runrec_write(out.f, ri->run_dir, ri->scene_s, e)) return kt_out_abort(&out), e->code;
    return kt_out_commit(&out, e);
}

static int write_run_yaml(run *r, const kt_aug_run_opts *o, int steps, kt_err *e)
{
    kt_aug_run_info ri = {o->run_dir, o->mesh, r->scene_path, r->rd.h.plan, o->edits, kt_solver_opts_used(r->sv),
                          r->mesh.order, r->mesh.nn, r->mesh.ne, kt_mesh_hash(&r->mesh), steps, r->has_plan_hash,
                          r->plan_hash, o->aug.output, kt_solver_fallback(r->sv), o->steps, o->vtk ? r->want : NULL,
                          r->plan.nsteps + 1, o->uncertainty, &r->scene};
    return kt_aug_run_yaml(&ri, e);
}

/* uncertainty.tsv (augsolve(1), FILES): every quantity of the scene's uncertainty section, its
 * value and sd, and how its band is found. */
int kt_aug_uncertainty_tsv(const char *run_dir, const kt_fem_sens *S, kt_err *e)
{
    static const char *const METHOD[] = {"none", "derivative", "fd"};
    static const char *const H[] = {"param", "unit", "value", "sd", "method", "source"};
    char path[PATH_MAX];
    snprintf(path, sizeof path, "%s/uncertainty.tsv", run_dir);
    kt_out out;
    if (kt_out_open(&out, path, e)) return e->code;
    kt_tsvw w;
    kt_tsvw_begin(&w, out.f);
    for (int k = 0; k < 6; k++) kt_tsvw_text(&w, H[k]);
    kt_tsvw_end(&w);
    for (int q = 0; q < KT_UQ_N; q++) {
        if (q == KT_UQ_HEAL && !isfinite(S->value[q])) continue; /* no bridge stiffness */
        kt_tsvw_text(&w, kt_uq_name(q)), kt_tsvw_text(&w, kt_uq_unit(q));
        kt_tsvw_num(&w, S->value[q], "%.6g"), kt_tsvw_num(&w, S->sd[q], "%.6g");
        kt_tsvw_text(&w, METHOD[S->method[q]]), kt_tsvw_text(&w, kt_uq_source(q));
        kt_tsvw_end(&w);
    }
    if (kt_tsvw_finish(&w, path, e)) return kt_out_abort(&out), e->code;
    return kt_out_commit(&out, e);
}

static int open_tsv(run *r, const kt_aug_run_opts *o, kt_err *e)
{
    char path[PATH_MAX];
    snprintf(path, sizeof path, "%s/steps.tsv", o->run_dir);
    if (kt_out_open(&r->tsv, path, e)) return e->code;
    r->tsv_open = 1;
    kt_tsvw_begin(&r->tw, r->tsv.f);
    kt_aug_steps_head(&r->tw);
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
        if (!(*p >= '0' && *p <= '9')) break; /* strtol would take blanks and signs */
        long a = strtol(p, &end, 10), b = a;
        if (end == p) break;
        p = end;
        if (*p == '-') {
            if (!(p[1] >= '0' && p[1] <= '9')) break;
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

/* A solved step: its VTK, its row, the progress line. */
static int write_step(run *r, const kt_aug_run_opts *o, kt_err *e)
{
    if (write_vtk(r, o, e)) return e->code;
    kt_aug_steps_row(&r->tw, kt_solver_row(r->sv));
    progress(kt_solver_row(r->sv), o->aug.quiet);
    return KT_OK;
}

/* Every step of the plan through the front door (solver.h); *steps counts those applied. */
static int solve_steps(run *r, const kt_aug_run_opts *o, int *steps, kt_err *e)
{
    kt_solver_opts so = {o->aug, o->plan_max_ratio, r->want, o->uncertainty ? r->S : NULL};
    if (kt_solver_create(&r->sv, &r->prob, &r->plan, &r->final, &so, e)) return e->code;
    kt_mesh_free(&r->final);
    const char *why = kt_solver_fallback(r->sv);
    if (why)
        fprintf(stderr, "augsolve: the planned method does not apply (%s): falling back to "
                "--method %s\n", why, kt_solver_method(r->sv) == KT_AUG_REFACTOR
                ? "refactor --ordering metis" : "augmented");
    if (write_step(r, o, e)) return e->code;
    for (int k = 1; k <= r->plan.nsteps; k++) {
        int solved = 0;
        if (kt_solver_step(r->sv, &solved, e)) return e->code;
        (*steps)++;
        if (solved && write_step(r, o, e)) return e->code;
    }
    if (o->uncertainty)
        kt_log(o->aug.quiet, "augsolve: --uncertainty: %d derivative quantities, %.2f s in the "
               "steps' derivatives\n", r->S->nd, kt_solver_t_sens(r->sv));
    return KT_OK;
}

/* Everything that can be checked before the first solve, cheapest first: option conflicts,
 * the mesh, the stream's header, the scene, --output, the run folder (claimed as soon as the
 * header is known good: a re-run's old result goes at once), then every step of the stream
 * (read to its end and applied to a copy of the mesh: cutplan never waits on augsolve) and
 * --steps. Nothing is solved before all of it passes. */
static int check_inputs(run *r, const kt_aug_run_opts *o, kt_err *e)
{
    if (o->aug.method == KT_AUG_AUGMENTED && o->aug.factor == KT_AUG_FACTOR_SIMPLICIAL)
        return kt_fail(e, KT_EINPUT, "--factor simplicial: the augmented method factors the "
                       "intact stiffness supernodally (its W columns are kept by supernode)");
    if (o->aug.method == KT_AUG_NEWTON && o->uncertainty)
        return kt_fail(e, KT_EINPUT, "--uncertainty: --method newton gives no derivatives (they "
                       "are of the linearized problem: use the planned method or a stream method)");
    if (o->aug.method == KT_AUG_NEWTON && o->aug.verify)
        return kt_fail(e, KT_EINPUT, "--verify: --method newton is the geometrically nonlinear "
                       "reference, not expected to equal a linear fresh factorization (compare "
                       "it with a --method planned run instead)");
    if (kt_msh_read(o->mesh, &r->mesh, e) || open_edits(r, o->edits, o->mesh, e) ||
        bind_problem(r, o->scene ? o->scene : r->rd.h.scene, e))
        return e->code;
    if (o->aug.output[0] && !kt_mesh_find_group(&r->mesh, 2, o->aug.output) &&
        !kt_mesh_find_group(&r->mesh, 3, o->aug.output))
        return kt_fail(e, KT_EINPUT, "--output %s: no surface or region of that name in the mesh",
                       o->aug.output);
    static const char *const written[] = {"run.yaml", "steps.tsv", "uncertainty.tsv", "step-*.vtk", ".augsolve.lock"};
    const char *in[] = {o->mesh, o->edits, o->scene ? o->scene : r->rd.h.scene};
    if (kt_outdir_distinct(o->run_dir, written, 5, in, 3, e)) return e->code;
    if (claim_run_dir(r, o->run_dir, e) || open_tsv(r, o, e) ||
        kt_edits_plan_read(&r->plan, &r->rd, e) ||
        kt_edits_plan_check(&r->plan, r->rd.name, &r->prob, &r->final, e) ||
        parse_steps(r, o->steps, r->plan.nsteps, e))
        return e->code;
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
    if (check_inputs(r, &o, e) || solve_physics(r, &o, e) || solve_steps(r, &o, &steps, e) ||
        (o.uncertainty && kt_aug_uncertainty_tsv(o.run_dir, r->S, e)))
        goto done;
    if (kt_tsvw_finish(&r->tw, "steps.tsv", e) || kt_out_commit(&r->tsv, e)) goto done;
    r->tsv_open = 0;
    if (write_run_yaml(r, &o, steps, e)) { /* no result without its run.yaml: take back the table */
        char path[PATH_MAX];
        snprintf(path, sizeof path, "%s/steps.tsv", o.run_dir);
        unlink(path);
        snprintf(path, sizeof path, "%s/uncertainty.tsv", o.run_dir);
        unlink(path);
    }
    if (!e->code && !o.aug.quiet && isatty(STDERR_FILENO)) fputc('\n', stderr);
    kt_log(o.aug.quiet || e->code, "augsolve: %d steps written to %s\n", steps, o.run_dir);
done:
    run_free(r);
    free(r);
    return e->code;
}
