/* lriplan_run.c: lri-plan's run: the patient, its fit and scene, one mesh, a centre-out run per
 * family of arcs, their curvature tables (keratome-patient(5), lri-plan(1)). */
#define _POSIX_C_SOURCE 200809L
#include "lriplan_run.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <unistd.h>

#include "augsolve_run.h"
#include "outdir.h"
#include "curvature_run.h"
#include "cutplan_run.h"
#include "lriplan_int.h"
#include "meshprep_run.h"
#include "msh.h"
#include "scene_write.h"
#include "tsv.h"

#define PATHLEN 1200

void kt_lriplan_opts_default(kt_lriplan_opts *o)
{
    memset(o, 0, sizeof *o);
    o->step = 5;
}

/* The process's CPU seconds so far (user + system, every thread): the phases' cost on a shared
 * machine, where their wall seconds are the load's (lri-plan(1), BENCHMARK). */
static double cpu_now(void)
{
    struct rusage ru;
    if (getrusage(RUSAGE_SELF, &ru) != 0) return NAN;
    return (double)(ru.ru_utime.tv_sec + ru.ru_stime.tv_sec) +
           1e-6 * (double)(ru.ru_utime.tv_usec + ru.ru_stime.tv_usec);
}

static int join(char *dst, const char *dir, const char *name, kt_err *e)
{
    if (snprintf(dst, PATHLEN, "%s/%s", dir, name) >= PATHLEN) return kt_fail(e, KT_EINPUT, "%s/%s: path too long", dir, name);
    return KT_OK;
}

/* The cornea from the Pentacam maps: anterior (required), posterior and pachymetry. */
static int fit_pentacam(kt_lri_answer *a, kt_err *e)
{
    kt_patient *p = &a->p;
    kt_pentacam_map m;
    if (kt_patient_read_map(p, KT_PF_FRONT, &m, e)) return e->code;
    int rc = kt_surffit_elevation(&m, KT_SURFFIT_ZONE, &a->fit_ant, e);
    if (rc == KT_OK) rc = kt_surffit_halves(&m, &a->fit_ant, &a->halves, e);
    kt_pentacam_free(&m);
    if (rc == KT_OK) a->halves_ok = 1;
    if (rc) return rc;
    p->ant.r_steep = a->fit_ant.r_steep, p->ant.r_flat = a->fit_ant.r_flat;
    p->ant.axis = a->fit_ant.axis, p->ant.conic = a->fit_ant.conic;
    if (p->pentacam_back[0]) {
        if (kt_patient_read_map(p, KT_PF_BACK, &m, e)) return e->code;
        rc = kt_surffit_elevation(&m, KT_SURFFIT_ZONE, &a->fit_post, e);
        kt_pentacam_free(&m);
        if (rc) return rc;
        a->fit_post_ok = 1;
        p->post.r_steep = a->fit_post.r_steep, p->post.r_flat = a->fit_post.r_flat;
        p->post.axis = a->fit_post.axis, p->post.conic = a->fit_post.conic;
    }
    if (p->pentacam_pachy[0]) {
        if (kt_patient_read_map(p, KT_PF_PACHYMETRY, &m, e)) return e->code;
        double rmax = fmin(p->zone / 2 + 0.5, KT_PENTACAM_HALF);
        rc = kt_surffit_pachymetry(&m, a->fit_ant.ax, a->fit_ant.ay, rmax, &a->fit_pachy, e);
        kt_pentacam_free(&m);
        if (rc) return rc;
        a->fit_pachy_ok = 1;
        p->t_central = a->fit_pachy.t0;
        if (isnan(p->t_zone)) p->t_zone = kt_pachyfit_at(&a->fit_pachy, p->zone / 2);
    }
    a->fitted = 1;
    return kt_patient_check_fit(p, a->fit_post_ok, a->fit_pachy_ok, e);
}

/* The halves of the steep meridian: which is steeper and the ratio of their astigmatism (the
 * unequal pair's arcs); keratometry alone is symmetric. */
static void asymmetry(kt_lri_answer *a)
{
    a->ratio = 1, a->steep_half = a->p.ant.axis;
    if (!a->halves_ok) return;
    a->half_a = a->halves.k_a - a->halves.k_flat, a->half_b = a->halves.k_b - a->halves.k_flat;
    double big = fmax(a->half_a, a->half_b), small = fmin(a->half_a, a->half_b);
    if (a->half_b > a->half_a) a->steep_half = fmod(a->p.ant.axis + 180, 360);
    if (big > 0) a->ratio = fmin(1, fmax(KT_LRIPLAN_RATIO_MIN, small / big));
}

/* Pachymetry at the zone and the blade depth; a blade deeper than 90% of it is bad input. */
static int blade(kt_lri_answer *a, kt_err *e)
{
    kt_patient *p = &a->p;
    a->t_zone = isnan(p->t_zone) ? kt_patient_model_zone_thickness(p) : p->t_zone;
    a->blade = p->depth_fraction > 0 ? p->depth_fraction * a->t_zone : p->depth;
    if (!(a->blade <= KT_PATIENT_DEPTH_MAX * a->t_zone + 1e-12))
        return kt_patient_fail(p, e, KT_PF_DEPTH, KT_PF_PACHYMETRY, "expected at most %g%% of the pachymetry at the zone (%.0f um), got %.0f um",
                               100 * KT_PATIENT_DEPTH_MAX, 1000 * KT_PATIENT_DEPTH_MAX * a->t_zone, 1000 * a->blade);
    return KT_OK;
}

/* The patient's scene from the base (checked before anything is written). */
static int make_scene(const kt_lriplan_opts *o, const kt_lri_answer *a, kt_scene *s, char *base, kt_err *e)
{
    if (o->base) snprintf(base, PATHLEN, "%s", o->base);
    else snprintf(base, PATHLEN, "%s/../plans/eye.yaml", KT_SHARE_DIR);
    kt_scene *b = kt_calloc(1, sizeof *b, e);
    int rc = b ? KT_OK : e->code;
    if (rc == KT_OK) rc = kt_scene_load(base, b, e);
    if (rc == KT_OK) rc = kt_patient_scene(&a->p, b, s, e);
    if (rc == KT_OK && o->fast) {
        /* --fast: coarse sizes; the base's incision-floor refinement kept at a coarser size
         * (lri-plan(1), --fast: without it the arcs' effect is under-predicted by 20-30%); a
         * base without one gets none. */
        s->eye.h_optical = 0.6, s->eye.h_incision = 0.3, s->eye.h_cornea = 0.8, s->eye.h_sclera = 2.5;
        s->eye.h_floor = s->eye.h_floor > 0 ? fmax(s->eye.h_floor, KT_LRIPLAN_FAST_FLOOR) : 0;
    }
    free(b);
    return rc;
}

static int write_scene(const kt_lri_answer *a, const kt_scene *s, const char *base, const char *path, kt_err *e)
{
    kt_out out;
    if (kt_out_open(&out, path, e)) return e->code;
    char head[1400];
    snprintf(head, sizeof head, "the eye of patient %s, made by lri-plan from %s (keratome-patient(5))", a->p.name, base);
    int rc = kt_scene_write_eye(out.f, s, head, e);
    return rc ? (kt_out_abort(&out), rc) : kt_out_commit(&out, e);
}

static int write_plan(const kt_lriplan_opts *o, const kt_lri_answer *a, const kt_scene *s, const kt_lri_family *f,
                      const char *path, kt_err *e)
{
    const kt_patient *p = &a->p;
    kt_out out;
    if (kt_out_open(&out, path, e)) return e->code;
    int nstep = f->nstep, paired = f->paired;
    fprintf(out.f, "# lri-plan: %s arcs on the steep meridian, cut centre-out to %g deg", f->name, nstep * o->step);
    if (f->unequal) fprintf(out.f, " (the opposite arc %.4g x as long, growing in proportion)", f->ratio);
    fprintf(out.f, "\nname: lri-%s\nscene: scene.yaml\nincisions:\n", f->name);
    fprintf(out.f, "  - meridian: %.17g deg\n    arc: %.17g deg\n", f->meridian, nstep * o->step);
    if (f->unequal) fprintf(out.f, "    arc_opposite: %.17g deg\n", f->ratio * nstep * o->step);
    if (p->depth_fraction > 0) fprintf(out.f, "    depth_fraction: %.17g\n", p->depth_fraction);
    else fprintf(out.f, "    depth: %.17g mm\n", p->depth);
    fprintf(out.f, "    position: {surface: incision-ring-1}\n    paired: %s\n    direction: centre-out\n",
            paired ? "true" : "false");
    fprintf(out.f, "progression: {degrees_per_step: %.17g deg}\n", o->step);
    if (kt_lri_main_plan(out.f, p, s) && !kt_out_failed(&out, e)) kt_fail(e, KT_ERUN, "%s: write failed", path);
    if (e->code) return kt_out_abort(&out), e->code;
    return kt_out_commit(&out, e);
}

/* The family's curvature.tsv: keratometric and total astigmatism per step; the first `skip`
 * steps after step 0 are the simulated main incision's (step 0 is kept as the intact eye). */
static int read_table(const char *path, kt_lri_family *f, double step, int skip, kt_err *e)
{
    static const char *const want[4] = {"cyl_D", "axis_steep_deg", "total_cyl_D", "total_axis_deg"};
    if (access(path, F_OK) != 0) return kt_fail(e, KT_ERUN, "%s: cannot open", path);
    kt_tsv t;
    if (kt_tsv_open(&t, path, e)) return e->code;
    int col[4], row = 0;
    for (int c = 0; c < 4 && !e->code; c++) col[c] = kt_tsv_need(&t, want[c], "a table of curvature(1)");
    while (!e->code && kt_tsv_next(&t) > 0) {
        double v[4];
        for (int c = 0; c < 4 && !e->code; c++) kt_tsv_num(&t, col[c], KT_TSV_NAN | KT_TSV_INF, &v[c]);
        if (e->code) break;
        if (row == 0) {
            f->kerato_intact.mag = v[0], f->kerato_intact.axis = v[1];
            f->total_intact.mag = v[2], f->total_intact.axis = v[3];
        }
        int at = row - skip;
        if (at >= 0 && at <= KT_LRIPLAN_MAXSTEP) {
            f->kerato[at].mag = v[0], f->kerato[at].axis = v[1];
            f->total[at].mag = v[2], f->total[at].axis = v[3];
            f->arc[at] = at * step;
            f->arc_opp[at] = f->paired ? at * step * f->ratio : 0;
        }
        row++;
    }
    kt_tsv_close(&t);
    if (!e->code && row - 1 != f->nstep + skip)
        kt_fail(e, KT_ERUN, "%s: expected %d steps after step 0, found %d", path, f->nstep + skip, row - 1);
    return e->code;
}

/* A cut lri-plan wrote that cutplan refuses (KT_EINPUT: a piece cut off, an element left
 * hanging) is refused again in the surgeon's terms: the patient file and what to change, without
 * the plan file it wrote or a node number. Other errors pass unchanged. */
static int cut_refused(const kt_lri_answer *a, const char *family, const char *plan, kt_err *e)
{
    if (e->code != KT_EINPUT) return e->code;
    char why[sizeof e->msg], *w = why;
    const char *m = e->msg;
    size_t n = strlen(plan);
    if (strncmp(m, plan, n) == 0) { /* "PLAN:line:col: " */
        m += n;
        for (int colons = 0; *m && colons < 2; m++) colons += *m == ':';
        while (*m == ':' || *m == ' ') m++;
    }
    while (*m && w < why + sizeof why - 1) {
        if (strncmp(m, "(node ", 6) == 0) { /* "(node N at x y z mm among them)" -> "(at ...)" */
            const char *at = strstr(m, " at ");
            if (at) m = at + 1, *w++ = '(';
        }
        if (strncmp(m, "tunnel 1", 8) == 0) m += 8, w += snprintf(w, (size_t)(why + sizeof why - w), "the main incision");
        else if (strncmp(m, "incision 1", 10) == 0)
            m += 10, w += snprintf(w, (size_t)(why + sizeof why - w), "the %s arcs", family);
        else *w++ = *m++;
        if (w >= why + sizeof why - 1) w = why + sizeof why - 1;
    }
    *w = '\0';
    return kt_fail(e, KT_EINPUT, "%s: %s (before any solve); change main_incision (meridian, width) or constraints "
                   "(max_arc, clearance)", a->p.path, why);
}

/* kind 0: one arc on the steeper half; 1: an equal pair; 2: an unequal pair, the longer arc on
 * the steeper half. pre (NULL: one family) is the physics the families share: solved here on
 * the first family's intact mesh (the snapped one with a main incision: the tunnel snaps the
 * same nodes in every family) and lent to every family's run, which borrows it when its mesh
 * and scene are the same bytes (kt_aug_run_opts.physics) and solves its own otherwise. */
static int run_family(const kt_lriplan_opts *o, kt_lri_answer *a, const kt_scene *s, int kind, double centre, int nstep,
                      const char *mesh, const char *scene, kt_aug_physics *pre, kt_err *e)
{
    static const char *const NAMES[] = {"single", "paired", "unequal"};
    const char *name = NAMES[kind];
    char plan[PATHLEN], edits[PATHLEN], run[PATHLEN], tsv[PATHLEN], leaf[64], cut[PATHLEN];
    kt_lri_family *f = &a->fam[a->nfam];
    memset(f, 0, sizeof *f);
    f->paired = kind > 0, f->unequal = kind == 2;
    snprintf(f->name, sizeof f->name, "%s", name);
    f->meridian = centre;
    f->ratio = kind == 2 ? a->ratio : 1;
    f->nstep = nstep;
    if (f->nstep > KT_LRIPLAN_MAXSTEP) return kt_fail(e, KT_EINPUT, "--step %g: expected at most %d steps to max_arc", o->step, KT_LRIPLAN_MAXSTEP);
    snprintf(leaf, sizeof leaf, "plan-%s.yaml", name);
    if (join(plan, o->outdir, leaf, e)) return e->code;
    snprintf(leaf, sizeof leaf, "%s.edits", name);
    if (join(edits, o->outdir, leaf, e)) return e->code;
    snprintf(leaf, sizeof leaf, "run-%s", name);
    if (join(run, o->outdir, leaf, e) || join(tsv, run, "curvature.tsv", e)) return e->code;
    if (write_plan(o, a, s, f, plan, e)) return e->code;
    kt_log(o->quiet, "lri-plan: %s arcs%s: cutplan, augsolve, curvature\n", name,
           a->main_steps ? " after the main incision" : "");
    /* The main incision's tunnel snaps nodes onto its plane: the run solves the snapped mesh. */
    snprintf(leaf, sizeof leaf, "mesh-%s.msh", name);
    if (join(cut, o->outdir, leaf, e)) return e->code;
    kt_cutplan_opts co = {plan, mesh, edits, a->main_steps ? cut : NULL, 1, 1};
    double w0 = kt_now(), c0 = cpu_now();
    if (kt_cutplan_run(&co, e)) return cut_refused(a, name, plan, e);
    double w1 = kt_now(), c1 = cpu_now();
    if (a->main_steps) mesh = cut;
    int solved_here = pre && !pre->solved;
    if (solved_here) {
        if (kt_aug_physics_solve(pre, mesh, scene, !o->no_band, o->quiet, e)) return e->code;
        a->solve_seconds += pre->seconds;
    }
    double w1p = kt_now(), c1p = cpu_now();
    kt_aug_run_opts ao;
    kt_aug_run_opts_default(&ao);
    ao.mesh = mesh, ao.edits = edits, ao.run_dir = run, ao.binary = 1, ao.aug.quiet = o->quiet;
    ao.uncertainty = !o->no_band; /* the band's derivatives (lriplan_band.c) */
    ao.physics = pre;
    if (kt_aug_run(&ao, e)) return e->code;
    double w2 = kt_now(), c2 = cpu_now();
    a->solve_seconds += w2 - w1p;
    kt_curv_opts cv;
    kt_curv_opts_default(&cv);
    cv.run_dir = run, cv.png = cv.vtk_out = cv.report = 0, cv.quiet = 1;
    FILE *sink = fopen("/dev/null", "w");
    if (!sink) return kt_fail(e, KT_ERUN, "/dev/null: cannot open");
    int rc = kt_curv_run(&cv, sink, e);
    fclose(sink);
    if (rc) return rc;
    char shared[96] = "";
    if (solved_here)
        snprintf(shared, sizeof shared, "; before it the families' shared prestress %.1f s (CPU %.1f s)",
                 w1p - w1, c1p - c1);
    kt_log(o->quiet, "lri-plan: %s arcs: cutplan %.1f s, augsolve %.1f s, curvature %.1f s (CPU %.1f, %.1f, "
           "%.1f s)%s\n", name, w1 - w0, w2 - w1p, kt_now() - w2, c1 - c0, c2 - c1p, cpu_now() - c2, shared);
    int skip = 0;
    if (a->main_steps && kt_lri_main_count(edits, &skip, e)) return e->code;
    if (read_table(tsv, f, o->step, skip, e)) return e->code;
    if (!o->no_band && kt_lri_band_read(run, f, skip, e)) return e->code;
    a->nfam++;
    return KT_OK;
}

/* Each family's arcs kept clear of the wounds (keratome-patient(5), CLEARANCE), decided before
 * anything is meshed: centre[k] and nstep[k] (0: left out, fam[k] cleared), a note for each
 * family trimmed or left out. A single arc that would not keep clear on the steeper half goes on
 * the other half when that allows a longer one. No family left: KT_EINPUT naming the patient
 * file and what to change. */
static int clear_families(const kt_lriplan_opts *o, kt_lri_answer *a, const kt_scene *s, int fam[3], double centre[3],
                          int nstep[3], kt_err *e)
{
    static const char *const NAMES[] = {"single", "paired", "unequal"};
    kt_wound w[2];
    int nw, left = 0;
    if (kt_lri_wounds(&a->p, s, w, &nw, e)) return e->code;
    for (int k = 0; k < 3; k++) {
        centre[k] = k == 1 ? a->p.ant.axis : a->steep_half;
        kt_clear_result r;
        kt_clear_family(w, nw, centre[k], k > 0, k == 2 ? a->ratio : 1, a->p.max_arc, a->p.zone / 2, a->p.clearance, &r);
        if (k == 0 && r.trimmed) {
            kt_clear_result r2;
            double other = fmod(centre[0] + 180, 360);
            kt_clear_family(w, nw, other, 0, 1, a->p.max_arc, a->p.zone / 2, a->p.clearance, &r2);
            if (r2.arc > r.arc) centre[0] = other, r = r2;
        }
        nstep[k] = (int)floor(r.arc / o->step + 1e-9);
        if (nstep[k] > KT_LRIPLAN_MAXSTEP) return kt_fail(e, KT_EINPUT, "--step %g: expected at most %d steps to max_arc", o->step, KT_LRIPLAN_MAXSTEP);
        a->clear_note[k][0] = '\0';
        if (fam[k] && nstep[k] == 0) {
            snprintf(a->clear_note[k], sizeof a->clear_note[k], "%s arcs left out: %s", NAMES[k], r.reason);
            fam[k] = 0;
        } else if (fam[k] && r.trimmed) {
            snprintf(a->clear_note[k], sizeof a->clear_note[k], "%s arcs at most %g deg: %s", NAMES[k], nstep[k] * o->step,
                     r.reason);
        }
        left += fam[k];
        if (a->clear_note[k][0]) kt_log(o->quiet, "lri-plan: %s\n", a->clear_note[k]);
    }
    if (left == 0)
        return kt_fail(e, KT_EINPUT, "%s: no arc keeps %g deg clear of the wounds (%s); allow other arcs "
                       "(constraints.incisions), move the main incision (main_incision.meridian) or lower "
                       "constraints.clearance", a->p.path, a->p.clearance, a->clear_note[1][0] ? a->clear_note[1] : a->clear_note[0]);
    return KT_OK;
}

/* The chosen run's teaching report: curvature on its run folder, step 0 and the chosen step
 * only, into PLAN_DIR/report/ (report.html with its maps); *report: its path relative to
 * PLAN_DIR, NULL when no arc was chosen. */
static int chosen_report(const kt_lriplan_opts *o, const kt_lri_answer *a, const char **report, kt_err *e)
{
    const kt_lri_family *f = &a->fam[a->chosen];
    *report = NULL;
    if (a->nfam == 0 || f->best == 0) return KT_OK;
    char run[PATHLEN], dir[PATHLEN], leaf[64];
    snprintf(leaf, sizeof leaf, "run-%s", f->name);
    if (join(run, o->outdir, leaf, e) || join(dir, o->outdir, "report", e)) return e->code;
    kt_log(o->quiet, "lri-plan: the chosen run's report (%s, step %d)\n", f->name, f->best);
    kt_curv_opts cv;
    kt_curv_opts_default(&cv);
    cv.run_dir = run, cv.outdir = dir, cv.vtk_out = 0, cv.quiet = 1, cv.step_sel = f->best;
    cv.eye_os = a->p.eye == KT_EYE_OS;
    FILE *sink = fopen("/dev/null", "w");
    if (!sink) return kt_fail(e, KT_ERUN, "/dev/null: cannot open");
    int rc = kt_curv_run(&cv, sink, e);
    fclose(sink);
    if (rc == KT_OK) *report = "report/report.html";
    return rc;
}

static int run_plan(const kt_lriplan_opts *o, FILE *summary, kt_err *e)
{
    kt_lri_answer *a = kt_calloc(1, sizeof *a, e);
    if (!a) return e->code;
    char scene[PATHLEN], mesh[PATHLEN], json[PATHLEN], base[PATHLEN], html[PATHLEN];
    kt_scene *s = kt_calloc(1, sizeof *s, e);
    int rc = s ? kt_patient_load(o->patient, &a->p, e) : e->code;
    if (rc == KT_OK && a->p.ant.source == KT_SOURCE_PENTACAM) rc = fit_pentacam(a, e);
    if (rc == KT_OK) asymmetry(a), rc = blade(a, e);
    if (rc == KT_OK && !(o->step > 0 && o->step <= a->p.max_arc))
        rc = kt_fail(e, KT_EINPUT, "--step %g: expected an angle in (0, max_arc = %g] deg", o->step, a->p.max_arc);
    if (rc == KT_OK) rc = make_scene(o, a, s, base, e);
    if (rc == KT_OK) rc = kt_lri_main_check(&a->p, s, e);
    int fam[3] = {a->p.arcs != KT_ARCS_PAIRED, a->p.arcs != KT_ARCS_SINGLE,
                  a->p.arcs != KT_ARCS_SINGLE && a->ratio < KT_LRIPLAN_SYMMETRIC}, nstep[3];
    double centre[3];
    if (rc == KT_OK) rc = clear_families(o, a, s, fam, centre, nstep, e);
    if (rc == KT_OK) rc = kt_mkdir_p(o->outdir, e);
    if (rc == KT_OK) rc = join(scene, o->outdir, "scene.yaml", e) || join(mesh, o->outdir, "eye.msh", e) ||
                          join(json, o->outdir, "plan.json", e) ? e->code : KT_OK;
    if (rc == KT_OK) rc = write_scene(a, s, base, scene, e);
    if (rc == KT_OK) {
        kt_log(o->quiet, "lri-plan: meshing %s\n", scene);
        kt_prep_opts po = {scene, mesh, 0, 0, 1, o->quiet};
        /* The summary is not read: the chosen ordering alone (mesh-prep --chosen-only; the same mesh). */
        double t0 = kt_now(), c0 = cpu_now();
        FILE *sink = fopen("/dev/null", "w");
        rc = sink ? kt_prep_run_table(&po, KT_PREP_TABLE_CHOSEN, sink, e) : kt_fail(e, KT_ERUN, "/dev/null: cannot open");
        if (sink) fclose(sink);
        a->mesh_seconds = kt_now() - t0;
        kt_log(o->quiet || rc, "lri-plan: meshed in %.1f s (CPU %.1f s)\n", a->mesh_seconds, cpu_now() - c0);
    }
    if (rc == KT_OK) {
        /* The mesh's content hash (the one cutplan's edits header carries) and size. */
        kt_mesh m;
        rc = kt_msh_read(mesh, &m, e);
        if (rc == KT_OK) a->mesh_hash = kt_mesh_hash(&m), a->nodes = m.nn, kt_mesh_free(&m);
    }
    a->main_steps = kt_lri_main_steps(&a->p);
    /* The families run on one intact mesh and scene: with more than one, their physics (the
     * prestress, with the band its derivatives) is solved once and lent to every run. */
    kt_aug_physics *pre = NULL;
    if (rc == KT_OK && fam[0] + fam[1] + fam[2] > 1 && !(pre = kt_calloc(1, sizeof *pre, e))) rc = e->code;
    for (int k = 0; k < 3 && rc == KT_OK; k++)
        if (fam[k]) rc = run_family(o, a, s, k, centre[k], nstep[k], mesh, scene, pre, e);
    if (pre) kt_aug_physics_free(pre), free(pre);
    const char *report = NULL;
    if (rc == KT_OK) {
        kt_lri_choose(a);
        rc = chosen_report(o, a, &report, e);
    }
    if (rc == KT_OK) rc = kt_lri_write_json(a, o, report, json, e);
    if (rc == KT_OK) rc = join(html, o->outdir, "plan.html", e) || kt_lri_write_html(a, o, report, html, e) ? e->code : KT_OK;
    if (rc == KT_OK && summary) kt_lri_summary(a, o, summary);
    free(a), free(s);
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

/* The plan folder as a unit (kt_outdir, lib/core/outdir.h): locked, the run written into a
 * temporary folder beside it (its earlier plan removed first), renamed into place when whole;
 * the summary printed only then, naming PLAN_DIR. */
int kt_lriplan_run(const kt_lriplan_opts *o, FILE *summary, kt_err *e)
{
    if (inputs_outside(o, e)) return e->code;
    kt_outdir d;
    if (kt_outdir_begin(&d, o->outdir, e)) return e->code;
    kt_lriplan_opts w = *o;
    w.outdir = d.tmp;
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
    size_t lt = strlen(tmp);
    for (char *t = text, *hit; rc == KT_OK && t && *t; t = hit + lt) { /* the temporary's name is PLAN_DIR's */
        if (!(hit = strstr(t, tmp))) {
            fputs(t, summary);
            break;
        }
        fprintf(summary, "%.*s%s", (int)(hit - t), t, dir);
    }
    free(text);
    return rc;
}
