/* lriplan_stage.c: the families' step files staged as the planner solves them, the chosen one
 * kept as PLAN_DIR/run/ (lriplan_int.h; lri-plan(1), FILES). */
#define _XOPEN_SOURCE 700
#include <dirent.h>
#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "augsolve_run.h"
#include "lriplan_int.h"
#include "msh.h"
#include "plan_write.h"

#define PATHLEN 1200

/* Remove the files of folder dir that a run or its staging wrote (its step files, its mesh and
 * tables), then the folder; a missing folder is fine. */
static int clear_dir(const char *dir, kt_err *e)
{
    DIR *d = opendir(dir);
    if (!d) return errno == ENOENT ? KT_OK : kt_fail(e, KT_ERUN, "%s: cannot open: %s", dir, strerror(errno));
    struct dirent *de;
    char path[PATHLEN + 300];
    while ((de = readdir(d)) != NULL) {
        const char *n = de->d_name;
        size_t l = strlen(n);
        int ours = (strncmp(n, "step-", 5) == 0 && l > 4 && strcmp(n + l - 4, ".vtk") == 0) ||
                   strcmp(n, "mesh.msh") == 0 || strcmp(n, "run.yaml") == 0 || strcmp(n, "steps.tsv") == 0 ||
                   strcmp(n, "uncertainty.tsv") == 0 || strcmp(n, "plan.yaml") == 0;
        if (!ours) continue;
        snprintf(path, sizeof path, "%s/%s", dir, n);
        if (unlink(path) != 0 && errno != ENOENT) {
            closedir(d);
            return kt_fail(e, KT_ERUN, "%s: cannot remove: %s", path, strerror(errno));
        }
    }
    closedir(d);
    if (rmdir(dir) != 0 && errno != ENOENT)
        return kt_fail(e, KT_ERUN, "%s: cannot remove (it holds files lri-plan did not write): %s", dir, strerror(errno));
    return KT_OK;
}

/* Step 0 of a family: its staging folder made afresh, the run's mesh and quantities in it. */
static int start(kt_lri_stage *st, const kt_lp_step *s, kt_err *e)
{
    int f = s->family;
    const kt_lp_family *fam = &st->a->fam.f[f];
    if (snprintf(st->dir[f], PATHLEN, "%s/.run-%s.tmp", st->outdir, fam->name) >= PATHLEN)
        return kt_fail(e, KT_EINPUT, "%s: path too long", st->outdir);
    char path[PATHLEN + 32];
    if (kt_mkdir_p(st->outdir, e) || clear_dir(st->dir[f], e) || kt_mkdir_p(st->dir[f], e)) return e->code;
    st->made[f] = 1;
    snprintf(path, sizeof path, "%s/mesh.msh", st->dir[f]);
    if (kt_msh_write(path, s->mesh, 1, e)) return e->code;
    st->order[f] = s->mesh->order, st->nn[f] = s->mesh->nn, st->ne[f] = s->mesh->ne, st->hash[f] = kt_mesh_hash(s->mesh);
    st->method[f] = s->method;
    snprintf(st->fallback[f], sizeof st->fallback[f], "%s", s->fallback ? s->fallback : "");
    return s->sens ? kt_aug_uncertainty_tsv(st->dir[f], s->sens, e) : KT_OK;
}

/* A step's row, kept for steps.tsv. */
static int keep_row(kt_lri_stage *st, int f, const kt_aug_row *w, kt_err *e)
{
    kt_lri_rows *r = &st->rows[f];
    if (r->n == r->cap) {
        int cap = r->cap ? 2 * r->cap : 32;
        kt_aug_row *p = kt_realloc(r->r, (size_t)cap, sizeof *p, e);
        if (!p) return e->code;
        r->r = p, r->cap = cap;
    }
    r->r[r->n++] = *w;
    return KT_OK;
}

int kt_lri_stage_sink(void *ctx, const kt_lp_step *s, kt_err *e)
{
    kt_lri_stage *st = ctx;
    int f = s->family;
    if (s->step == 0 && start(st, s, e)) return e->code;
    char path[PATHLEN + 32];
    snprintf(path, sizeof path, "%s/step-%04d.vtk", st->dir[f], s->step);
    kt_aug_step_fields sf = {s->mesh, s->u, s->origin, NULL, s->sens, s->dudp, s->step == 0 ? s->ph : NULL, s->wound};
    if (kt_aug_step_vtk(path, &sf, 1, e)) return e->code;
    st->steps[f] = s->step;
    return keep_row(st, f, s->row, e);
}

/* steps.tsv of the kept run: its rows up to `last`. */
static int write_steps(const kt_lri_stage *st, int f, const char *dir, int last, kt_err *e)
{
    char path[PATHLEN + 32];
    snprintf(path, sizeof path, "%s/steps.tsv", dir);
    kt_out out;
    if (kt_out_open(&out, path, e)) return e->code;
    kt_tsvw w;
    kt_tsvw_begin(&w, out.f);
    kt_aug_steps_head(&w);
    for (int k = 0; k < st->rows[f].n && st->rows[f].r[k].step <= last; k++) kt_aug_steps_row(&w, &st->rows[f].r[k]);
    if (kt_tsvw_finish(&w, path, e)) return kt_out_abort(&out), e->code;
    return kt_out_commit(&out, e);
}

/* The chosen plan as plan.yaml (its scene: PLAN_DIR/scene.yaml), for the tools that read the
 * run (curvature's arcs, target and report). */
static int write_plan(const kt_plan *plan, const char *dir, unsigned long long *hash, kt_err *e)
{
    char path[PATHLEN + 32];
    snprintf(path, sizeof path, "%s/plan.yaml", dir);
    kt_out out;
    if (kt_out_open(&out, path, e)) return e->code;
    if (kt_plan_write_eye(out.f, plan, plan->path, "../scene.yaml",
                          "the chosen plan of lri-plan (keratome-plan(5)): its arcs, after the main incision's tunnel "
                          "when it is simulated; the target: the pre-operative keratometric astigmatism", e))
        return kt_out_abort(&out), e->code;
    if (kt_out_commit(&out, e)) return e->code;
    return kt_fnv1a_file(path, hash, e);
}

/* run.yaml of the kept run (augsolve(1), FILES): its mesh, the patient's scene, the plan, the
 * method. */
static int write_run_yaml(const kt_lri_stage *st, int f, const char *dir, int last, const kt_plan *plan, kt_err *e)
{
    char mesh[PATHLEN + 32], scene[PATHLEN + 32], planp[PATHLEN + 32];
    unsigned long long ph = 0;
    snprintf(mesh, sizeof mesh, "%s/mesh.msh", dir);
    snprintf(scene, sizeof scene, "%s/scene.yaml", st->outdir);
    snprintf(planp, sizeof planp, "%s/plan.yaml", dir);
    if (plan && write_plan(plan, dir, &ph, e)) return e->code;
    kt_aug_opts ao;
    kt_aug_opts_default(&ao);
    ao.method = st->method[f], ao.ordering = KT_AUG_ORDER_METIS;
    if (strlen(scene) >= sizeof st->a->scene.s.path) return kt_fail(e, KT_EINPUT, "%s: path too long", scene);
    kt_scene *sc = kt_calloc(1, sizeof *sc, e); /* the scene as written: PLAN_DIR/scene.yaml */
    if (!sc) return e->code;
    *sc = st->a->scene.s;
    memcpy(sc->path, scene, strlen(scene) + 1);
    kt_path_dir(scene, sc->dir, sizeof sc->dir);
    unsigned char *files = kt_calloc((size_t)last + 1, 1, e); /* run/ holds every step up to last */
    if (!files) return free(sc), e->code;
    memset(files, 1, (size_t)last + 1);
    kt_aug_run_info ri = {dir, mesh, scene, plan ? planp : NULL, NULL, &ao, st->order[f], st->nn[f], st->ne[f], st->hash[f],
                          last, plan != NULL, ph, NULL, st->fallback[f][0] ? st->fallback[f] : NULL, NULL, files, last + 1,
                          st->a->band.on, sc};
    int rc = kt_aug_run_yaml(&ri, e);
    free(sc), free(files);
    return rc;
}

/* The kept family's steps after `last` go; the folder becomes PLAN_DIR/run. */
static int keep(kt_lri_stage *st, int f, int last, const kt_plan *plan, kt_err *e)
{
    char path[PATHLEN + 32], run[PATHLEN];
    for (int k = last + 1; k <= st->steps[f]; k++) {
        snprintf(path, sizeof path, "%s/step-%04d.vtk", st->dir[f], k);
        if (unlink(path) != 0) return kt_fail(e, KT_ERUN, "%s: cannot remove: %s", path, strerror(errno));
    }
    snprintf(run, sizeof run, "%s/run", st->outdir);
    if (clear_dir(run, e)) return e->code;
    if (rename(st->dir[f], run) != 0) return kt_fail(e, KT_ERUN, "%s: cannot move to %s: %s", st->dir[f], run, strerror(errno));
    st->made[f] = 0;
    if (write_steps(st, f, run, last, e)) return e->code;
    return write_run_yaml(st, f, run, last, plan, e);
}

int kt_lri_stage_end(kt_lri_stage *st, int fam, int last, const kt_plan *plan, kt_err *e)
{
    int rc = fam >= 0 && st->made[fam] ? keep(st, fam, last, plan, e) : KT_OK;
    for (int f = 0; f < KT_LP_NFAM; f++) {
        kt_err e2 = {0};
        if (st->made[f] && clear_dir(st->dir[f], rc ? &e2 : e) && !rc) rc = e->code;
        st->made[f] = 0;
        free(st->rows[f].r);
        memset(&st->rows[f], 0, sizeof st->rows[f]);
    }
    return rc;
}
