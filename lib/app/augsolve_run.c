/* augsolve_run.c: the augsolve tool's work: mesh + scene + edits stream -> run folder with one VTK
 * per step, steps.tsv and run.yaml (all written atomically). */
#define _XOPEN_SOURCE 700
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "augsolve_run.h"

#include "aug.h"
#include "bind.h"
#include "msh.h"
#include "scene.h"
#include "vtk.h"

/* Everything the run holds, freed in one place. */
typedef struct run {
    kt_mesh mesh;
    kt_scene scene;
    kt_fem_problem fem;
    kt_aug_problem prob;
    FILE *edits;
    kt_edits_reader rd;
    kt_step step;
    kt_aug *aug;
    kt_out tsv;
    int tsv_open;
    char scene_path[PATH_MAX];
} run;

static void run_free(run *r)
{
    kt_aug_free(r->aug);
    kt_step_free(&r->step);
    if (r->edits && r->edits != stdin) fclose(r->edits);
    if (r->tsv_open) kt_out_abort(&r->tsv);
    kt_fem_problem_free(&r->fem);
    kt_mesh_free(&r->mesh);
}

static void abs_path(const char *p, char *out, size_t n)
{
    char buf[PATH_MAX];
    if (strcmp(p, "-") != 0 && realpath(p, buf)) snprintf(out, n, "%s", buf);
    else snprintf(out, n, "%s", p);
}

static int open_edits(run *r, const char *path, kt_err *e)
{
    r->edits = strcmp(path, "-") == 0 ? stdin : fopen(path, "r");
    if (!r->edits) return kt_fail(e, KT_EINPUT, "%s: cannot open the edits stream", path);
    if (kt_edits_open(&r->rd, r->edits, strcmp(path, "-") == 0 ? "<stdin>" : path, e))
        return e->code;
    if (r->rd.h.nn != r->mesh.nn || r->rd.h.ne != r->mesh.ne)
        return kt_fail(e, KT_EINPUT, "%s: the edits apply to a mesh of %d nodes and %d tets, "
                       "expected the %d nodes and %d tets of the mesh given", path, r->rd.h.nn,
                       r->rd.h.ne, r->mesh.nn, r->mesh.ne);
    return KT_OK;
}

/* Materials, fixation and pressures of the scene on this mesh. */
static int load_problem(run *r, const char *scene, kt_err *e)
{
    if (!scene || !scene[0])
        return kt_fail(e, KT_EINPUT, "%s: the edits header names no scene: give --scene",
                       r->rd.name);
    abs_path(scene, r->scene_path, sizeof r->scene_path);
    if (kt_scene_load(scene, &r->scene, e) || kt_fem_bind(&r->scene, &r->mesh, &r->fem, e))
        return e->code;
    r->prob = (kt_aug_problem){&r->mesh, &r->fem.mats, r->fem.fixed, r->fem.g, r->fem.npress,
                               r->fem.press, r->fem.nfix, r->fem.fix};
    return KT_OK;
}

static int write_vtk(run *r, const kt_aug_run_opts *o, kt_err *e)
{
    if (!o->vtk) return KT_OK;
    const kt_mesh *m = kt_aug_mesh(r->aug);
    char path[PATH_MAX];
    snprintf(path, sizeof path, "%s/step-%04d.vtk", o->run_dir, kt_aug_last(r->aug)->step);
    double *origin = kt_calloc((size_t)m->nn, sizeof(double), e);
    if (!origin) return e->code;
    const int *org = kt_aug_origin(r->aug);
    for (int i = 0; i < m->nn; i++) origin[i] = org[i] + 1;
    kt_vtk_field f[3] = {{"displacement", 3, 0, 0, (double *)kt_aug_displacement(r->aug)},
                         {"origin", 1, 0, 1, origin},
                         {"reaction", 3, 0, 0, NULL}};
    int nf = 2;
    if (!o->aug.output[0]) { /* reactions need u around the supports */
        f[2].v = (double *)kt_aug_reaction(r->aug, e);
        nf = f[2].v ? 3 : 2;
    }
    if (!e->code) kt_vtk_write_tets(path, m, f, nf, o->binary, e);
    free(origin);
    return e->code;
}

static void tsv_num(FILE *f, double v, const char *fmt)
{
    if (isnan(v)) fputs("NaN", f);
    else fprintf(f, fmt, v);
}

static void write_row(run *r)
{
    FILE *f = r->tsv.f;
    const kt_aug_row *w = kt_aug_last(r->aug);
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
    fprintf(f, "\t%.0f\n", w->nnz_L);
}

static void progress(const run *r, int quiet)
{
    if (quiet) return;
    const kt_aug_row *w = kt_aug_last(r->aug);
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
    abs_path(o->mesh, buf, sizeof buf);
    yaml_str(out.f, "mesh", buf);
    yaml_str(out.f, "scene", r->scene_path);
    if (r->rd.h.plan[0]) {
        abs_path(r->rd.h.plan, buf, sizeof buf);
        yaml_str(out.f, "plan", buf);
    }
    abs_path(o->edits, buf, sizeof buf);
    yaml_str(out.f, "edits", buf);
    fprintf(out.f, "method: %s\norder: %d\nsteps: %d\n", kt_aug_method_name(o->aug.method),
            r->mesh.order, steps);
    static const char *const PRE[] = {"none", "diag", "spai", "local"},
                             *const ORD[] = {"natural", "amd", "metis"};
    fprintf(out.f, "tol: %g\nprecond: %s\nordering: %s\nfactor: %s\n", o->aug.tol,
            PRE[o->aug.precond], ORD[o->aug.ordering],
            o->aug.factor == KT_AUG_FACTOR_SIMPLICIAL ? "simplicial" : "supernodal");
    if (o->aug.output[0]) yaml_str(out.f, "output", o->aug.output);
    return kt_out_commit(&out, e);
}

static int open_tsv(run *r, const kt_aug_run_opts *o, kt_err *e)
{
    char path[PATH_MAX];
    snprintf(path, sizeof path, "%s/steps.tsv", o->run_dir);
    if (kt_out_open(&r->tsv, path, e)) return e->code;
    r->tsv_open = 1;
    fputs("step\tn_dofs\tm\tnew_dofs\titers\tclosure_max\tt_update_ms\tt_step1_ms\tt_step2_ms\t"
          "t_step3_ms\tt_total_ms\trel_residual\trefactor\tverify_rel_diff\tnnz_L\n", r->tsv.f);
    return KT_OK;
}

int kt_aug_run(const kt_aug_run_opts *o, kt_err *e)
{
    run *r = kt_calloc(1, sizeof *r, e);
    if (!r) return e->code;
    int steps = 0;
    if (kt_msh_read(o->mesh, &r->mesh, e) || open_edits(r, o->edits, e) ||
        load_problem(r, o->scene ? o->scene : r->rd.h.scene, e) || kt_mkdir_p(o->run_dir, e) ||
        open_tsv(r, o, e))
        goto done;
    if (kt_aug_create(&r->aug, &r->prob, &o->aug, e) || write_vtk(r, o, e)) goto done;
    write_row(r);
    progress(r, o->aug.quiet);
    int rc;
    while ((rc = kt_edits_next(&r->rd, &r->step, e)) == 1) {
        if (kt_aug_step(r->aug, &r->step, e) || write_vtk(r, o, e)) goto done;
        write_row(r);
        progress(r, o->aug.quiet);
        steps++;
    }
    if (rc < 0) goto done;
    if (kt_out_commit(&r->tsv, e)) goto done;
    r->tsv_open = 0;
    write_run_yaml(r, o, steps, e);
    if (!e->code && !o->aug.quiet && isatty(STDERR_FILENO)) fputc('\n', stderr);
    kt_log(o->aug.quiet || e->code, "augsolve: %d steps written to %s\n", steps, o->run_dir);
done:
    run_free(r);
    free(r);
    return e->code;
}
