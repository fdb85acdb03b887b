/* lriplan_run.c: the lri-plan tool: the planner (lib/planner/lp.h) answers; this writes the
 * answer into PLAN_DIR (lri-plan(1), FILES): the patient's scene and mesh, the chosen run's
 * step files and its report, plan.json, plan.html, and the summary. */
#define _POSIX_C_SOURCE 200809L
#include "lriplan_run.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "curvature_run.h"
#include "lp_family.h"
#include "lp_trim.h"
#include "lriplan_int.h"
#include "msh.h"
#include "outdir.h"
#include "scene_write.h"

#define PATHLEN 1200

void kt_lriplan_opts_default(kt_lriplan_opts *o)
{
    kt_lp_opts lo;
    kt_lp_opts_default(&lo);
    memset(o, 0, sizeof *o);
    o->step = lo.step, o->plan_max_ratio = lo.plan_max_ratio, o->state = lo.state;
}

int kt_lriplan_state(const char *s)
{
    return strcmp(s, "healed") == 0 ? KT_WOUND_HEALED : strcmp(s, "immediate") == 0 ? KT_WOUND_IMMEDIATE : -1;
}

static int join(char *dst, const char *dir, const char *name, kt_err *e)
{
    if (snprintf(dst, PATHLEN, "%s/%s", dir, name) >= PATHLEN) return kt_fail(e, KT_EINPUT, "%s/%s: path too long", dir, name);
    return KT_OK;
}

/* PLAN_DIR/scene.yaml and eye.msh: the patient's scene and its mesh, from which the tools
 * (mesh-prep, cutplan, augsolve) make the same again. */
static int write_eye(const kt_lp_answer *a, const kt_lriplan_opts *o, kt_err *e)
{
    char path[PATHLEN], head[1400];
    kt_out out;
    if (join(path, o->outdir, "scene.yaml", e) || kt_out_open(&out, path, e)) return e->code;
    snprintf(head, sizeof head, "the eye of patient %s, made by lri-plan from %s (keratome-patient(5))", a->eye.p.name,
             a->scene.base);
    if (kt_scene_write_eye(out.f, &a->scene.s, head, e)) return kt_out_abort(&out), e->code;
    if (kt_out_commit(&out, e) || join(path, o->outdir, "eye.msh", e)) return e->code;
    return kt_msh_write(path, &a->mesh.m, 1, e);
}

/* The chosen plan in memory for its report: the chosen arcs (not the family's longest), after
 * the main incision's tunnel when it is simulated, and the target: the pre-operative
 * keratometric astigmatism (with the surgeon's SIA) the arcs correct. */
static int chosen_plan(const kt_lp_answer *a, const kt_lriplan_opts *o, kt_plan *p, kt_err *e)
{
    int c = a->choice.chosen;
    kt_lp_family f = kt_lp_family_cut(a, c);
    if (kt_lp_family_plan(&a->scene, &a->eye, &f, o->step, a->choice.best[c], p, e)) return e->code;
    p->target.set = 1;
    p->target.magnitude = a->choice.pre_kerato.mag;
    p->target.axis = fmod(a->choice.pre_kerato.axis, 180);
    return KT_OK;
}

/* The main incision as the report draws it. */
static void report_main(const kt_lp_answer *a, kt_report_main *m)
{
    const kt_patient *p = &a->eye.p;
    memset(m, 0, sizeof *m);
    m->present = p->main_present;
    m->meridian = p->main_meridian, m->width = p->main_width;
    m->simulated = a->scene.main_sim;
    m->sia = a->choice.main_vec;
}

/* The chosen run's teaching report: curvature on PLAN_DIR/run (its plan.yaml the chosen plan),
 * step 0 and the step that holds the chosen arcs, into PLAN_DIR/report/. */
static int chosen_report(const kt_lp_answer *a, const kt_lriplan_opts *o, kt_lri_files *fl, kt_err *e)
{
    int c = a->choice.chosen;
    if (c < 0 || !(kt_lp_chosen_arc(a) > 0)) return KT_OK;
    char run[PATHLEN], dir[PATHLEN];
    if (join(run, o->outdir, "run", e) || join(dir, o->outdir, "report", e)) return e->code;
    kt_log(o->quiet, "lri-plan: the chosen run's report (%s, step %d)\n", a->fam.f[c].name,
           a->choice.best[c] + a->run.r[c].skip);
    kt_curv_opts cv;
    kt_report_main m;
    report_main(a, &m);
    kt_curv_opts_default(&cv);
    char shown[PATHLEN];
    if (o->shown_outdir && join(shown, o->shown_outdir, "run", e)) return e->code;
    cv.run_dir = run, cv.outdir = dir, cv.vtk_out = 0, cv.quiet = 1;
    cv.shown_dir = o->shown_outdir ? shown : NULL;
    cv.step_sel = a->choice.best[c] + a->run.r[c].skip;
    cv.eye_os = a->eye.p.eye == KT_EYE_OS;
    cv.main = &m;
    int rc = kt_curv_run(&cv, NULL, e);
    if (rc == KT_OK) fl->report = "report/report.html";
    return rc;
}

/* The chosen run kept as PLAN_DIR/run with its plan (none without an arc), the other families'
 * staged steps removed. */
static int keep_run(const kt_lp_answer *a, const kt_lriplan_opts *o, kt_lri_stage *st, kt_err *e)
{
    int c = a->choice.chosen;
    if (c < 0) return kt_lri_stage_end(st, -1, 0, NULL, e);
    kt_plan *p = kt_lp_chosen_arc(a) > 0 ? kt_calloc(1, sizeof *p, e) : NULL;
    if (e->code || (p && chosen_plan(a, o, p, e))) return free(p), e->code;
    int rc = kt_lri_stage_end(st, c, a->choice.best[c] + a->run.r[c].skip, p, e);
    free(p);
    return rc;
}

/* The plan's date, YYYY-MM-DD (UTC): SOURCE_DATE_EPOCH's when set (a reproducible build's
 * convention), else today's. */
static void plan_date(char out[11])
{
    const char *sde = getenv("SOURCE_DATE_EPOCH");
    char *end = NULL;
    long long v = sde ? strtoll(sde, &end, 10) : -1;
    time_t t = sde && end != sde && !*end && v >= 0 ? (time_t)v : time(NULL);
    struct tm tm;
    if (!gmtime_r(&t, &tm) || !strftime(out, 11, "%Y-%m-%d", &tm)) snprintf(out, 11, "unknown");
}

/* Everything the answer writes into PLAN_DIR once the planner is done. */
static int write_outputs(const kt_lp_answer *a, const kt_lriplan_opts *o, kt_lri_stage *st, FILE *summary, kt_err *e)
{
    kt_lri_files fl = {NULL, NULL, {0}};
    char path[PATHLEN];
    plan_date(fl.date);
    int c = a->choice.chosen;
    int rc = kt_mkdir_p(o->outdir, e) || write_eye(a, o, e) ? e->code : KT_OK;
    if (rc == KT_OK) rc = keep_run(a, o, st, e);
    if (rc == KT_OK && c >= 0) fl.run = "run";
    if (rc == KT_OK) rc = chosen_report(a, o, &fl, e);
    if (rc == KT_OK) rc = join(path, o->outdir, "plan.json", e) || kt_lri_write_json(a, o, &fl, path, e) ? e->code : KT_OK;
    if (rc == KT_OK) rc = join(path, o->outdir, "plan.html", e) || kt_lri_write_html(a, o, &fl, path, e) ? e->code : KT_OK;
    if (rc == KT_OK && summary) kt_lri_summary(a, o, &fl, summary);
    return rc;
}

/* The planner's answer written into o->outdir. */
static int run_plan(const kt_lriplan_opts *o, FILE *summary, kt_err *e)
{
    kt_lp_answer *a = kt_calloc(1, sizeof *a, e);
    kt_lri_stage *st = kt_calloc(1, sizeof *st, e);
    if (!a || !st) return free(a), free(st), e->code;
    kt_lp_opts lo;
    kt_lp_opts_default(&lo);
    lo.patient = o->patient, lo.base = o->base, lo.step = o->step, lo.fast = o->fast;
    lo.no_band = o->no_band, lo.quiet = o->quiet, lo.band_extra = o->band_extra, lo.state = o->state;
    lo.plan_max_ratio = o->plan_max_ratio, lo.jobs = o->jobs;
    st->outdir = o->outdir, st->a = a;
    lo.sink = kt_lri_stage_sink, lo.sink_ctx = st;
    int rc = kt_lp_plan(&lo, a, e);
    if (rc == KT_OK) rc = write_outputs(a, o, st, summary, e);
    if (rc != KT_OK) {
        kt_err e2 = {0};
        kt_lri_stage_end(st, -1, 0, NULL, &e2); /* a failed plan leaves no staged file */
    }
    kt_lp_answer_free(a);
    free(a), free(st);
    return rc;
}

/* The patient file loads, and none of the run's inputs lies in the plan folder, which is
 * replaced whole (the patient, its maps, --base). */
static int inputs_outside(const kt_lriplan_opts *o, kt_err *e)
{
    kt_patient *p = kt_calloc(1, sizeof *p, e);
    if (!p) return e->code;
    /* a patient file that does not load is refused here, before the plan folder is touched */
    int rc = kt_patient_load(o->patient, p, e);
    const char *in[] = {o->patient, p->pentacam_front, p->pentacam_back, p->pentacam_pachy, o->base};
    if (rc == KT_OK) rc = kt_outdir_distinct(o->outdir, NULL, 0, in, 5, e);
    free(p);
    return rc;
}

/* text with every occurrence of tmp said as dir, on f. */
static void put_renamed(FILE *f, const char *text, const char *tmp, const char *dir)
{
    size_t lt = strlen(tmp);
    for (const char *t = text, *hit; t && *t; t = hit + lt) {
        if (!(hit = strstr(t, tmp))) {
            fputs(t, f);
            break;
        }
        fprintf(f, "%.*s%s", (int)(hit - t), t, dir);
    }
}

/* The plan folder as a unit (kt_outdir, lib/core/outdir.h): locked, the run written into a
 * temporary folder beside it (its earlier plan removed first), renamed into place when whole;
 * the summary printed only then, naming PLAN_DIR. */
int kt_lriplan_run(const kt_lriplan_opts *o, FILE *summary, kt_err *e)
{
    if (inputs_outside(o, e)) return e->code;
    kt_outdir d;
    if (kt_outdir_begin(&d, o->outdir, e)) return e->code;
    kt_lriplan_opts w = *o;
    w.outdir = d.tmp, w.shown_outdir = d.path;
    char *text = NULL;
    size_t len = 0;
    FILE *mem = summary ? open_memstream(&text, &len) : NULL;
    int rc = summary && !mem ? kt_fail(e, KT_ERUN, "cannot hold the summary: %s", strerror(errno)) : KT_OK;
    if (rc == KT_OK) rc = run_plan(&w, mem, e);
    if (mem && fclose(mem) != 0 && rc == KT_OK) rc = kt_fail(e, KT_ERUN, "cannot hold the summary");
    char tmp[PATHLEN], dir[PATHLEN];
    snprintf(tmp, sizeof tmp, "%s", d.tmp), snprintf(dir, sizeof dir, "%s", d.path);
    if (rc == KT_OK) rc = kt_outdir_commit(&d, e);
    else kt_outdir_abort(&d);
    if (rc == KT_OK) put_renamed(summary, text, tmp, dir);
    free(text);
    return rc;
}
