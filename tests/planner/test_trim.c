/* test_trim.c: the planner's clearance trimming (lib/planner/lp_trim.h): the decision on
 * synthetic clearance answers (nothing clashes: all kept; the first clash ends the arcs one step
 * before it; a clash at the first step leaves the family out; the reason is kept), the stage on
 * a patient scene (plans/eye.yaml, no mesh) with a clearance function given as data (arcs whose
 * ends come within 20 deg of 150 deg: the single arc at 90 deg would be trimmed to 80 deg, so
 * it goes on the other half, at 270 deg, whole), and the stage with the model's clearance
 * (lib/model/clearance.h) on a right eye against the rule with a nasal main incision at 0 deg:
 * the single arc at 0 deg and the pair are within 15 deg of its tunnel at their first step; the
 * single arc goes to 180 deg, whole; the pair is left out, said with theatre's words; and the
 * model's answers against kt_clear_family's longest clear arc. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "kt_test.h"
#include "lp_family.h"
#include "lp_patient.h"
#include "lp_scene.h"
#include "lp_trim.h"

static void decide(void)
{
    kt_lp_family f;
    memset(&f, 0, sizeof f);
    snprintf(f.name, sizeof f.name, "paired");
    f.nstep = 18;
    unsigned char clash[KT_LP_MAXSTEP + 1] = {0};
    const char *why[KT_LP_MAXSTEP + 1] = {0};
    kt_lp_trim t;
    kt_lp_trim_decide(&f, 5, clash, why, &t);
    CHECK(t.nstep == 18 && t.why[0] == '\0', "no clash: every step kept (%d)", t.nstep);
    for (int k = 8; k <= 18; k++) clash[k] = 1;
    why[8] = "its end 0.3 mm from the main incision";
    kt_lp_trim_decide(&f, 5, clash, why, &t);
    CHECK(t.nstep == 7, "a clash at 40 deg: trimmed to 35 deg (%d steps)", t.nstep);
    CHECK(strcmp(t.why, "paired arcs at most 35 deg: its end 0.3 mm from the main incision") == 0, "why: %s", t.why);
    clash[8] = 0; /* a clash ends the arcs even when a longer extent would clear again */
    kt_lp_trim_decide(&f, 5, clash, NULL, &t);
    CHECK(t.nstep == 8 && strstr(t.why, "within the clearance"), "the default reason: %s", t.why);
    clash[1] = 1;
    kt_lp_trim_decide(&f, 5, clash, why, &t);
    CHECK(t.nstep == 0 && strcmp(t.why, "paired arcs left out: within the clearance of the main incision") == 0,
          "a clash at the first step: left out (%s)", t.why);
}

/* The synthetic clearance: an arc end within 20 deg of 150 deg. */
static double angdist(double a, double b)
{
    double d = fmod(fabs(a - b), 360);
    return d > 180 ? 360 - d : d;
}

static int clear_150(void *ctx, const kt_plan *p, char *why, size_t n)
{
    int *calls = ctx;
    (*calls)++;
    for (int i = 0; i < p->ninc; i++) {
        const kt_incision *in = &p->inc[i];
        for (int side = 0; side <= in->paired; side++) {
            double c = in->meridian + 180 * side, h = (side && in->arc_opposite > 0 ? in->arc_opposite : in->arc) / 2;
            if (angdist(c + h, 150) < 20 || angdist(c - h, 150) < 20) {
                snprintf(why, n, "an end within 20 deg of 150 deg");
                return 1;
            }
        }
    }
    return 0;
}

static void stage(void)
{
    char path[64];
    snprintf(path, sizeof path, "/tmp/kt-test-trim-%d.yaml", (int)getpid());
    FILE *f = fopen(path, "w");
    if (!f) {
        CHECK(0, "cannot write %s", path);
        return;
    }
    fputs("name: trim\neye: OD\nage: 65\ncornea:\n  keratometry: {k_steep: 44.5 D, k_flat: 43.0 D, steep_axis: 90 deg}\n"
          "constraints: {incisions: either, max_arc: 90 deg}\n", f);
    fclose(f);
    static kt_lp_eye eye;
    static kt_lp_scene sc;
    static kt_lp_families fam;
    static kt_lp_trims tr;
    kt_lp_opts o;
    kt_lp_opts_default(&o);
    o.patient = path, o.quiet = 1; /* the base: the repository's plans/eye.yaml */
    int calls = 0;
    o.clear = clear_150, o.clear_ctx = &calls;
    kt_err e = {0};
    int rc = kt_lp_patient(&o, &eye, &e);
    if (rc == KT_OK) rc = kt_lp_scene_make(&o, &eye, &sc, &e);
    if (rc == KT_OK) rc = kt_lp_families_make(&o, &eye, &fam, &e);
    if (rc == KT_OK) rc = kt_lp_trims_make(&o, &eye, &sc, &fam, &tr, &e);
    CHECK(rc == KT_OK, "the stages: %s", e.msg);
    CHECK(fam.n == 2 && calls == 3 * 18, "two families, asked at each of 18 extents, the single arc on both halves (%d calls)",
          calls);
    /* the arc at 90 deg reaches 150 within 20 deg when its half exceeds 40 deg: 85 deg clashes;
     * at 270 deg its ends reach 225 and 315: clear */
    CHECK(tr.t[1].nstep == 16 && tr.t[1].meridian == 90 && !tr.t[1].moved, "the pair trimmed to 80 deg (%d steps at %g)",
          tr.t[1].nstep, tr.t[1].meridian);
    CHECK(tr.t[0].nstep == 18 && tr.t[0].meridian == 270 && tr.t[0].moved, "the single arc whole on the other half (%d at %g)",
          tr.t[0].nstep, tr.t[0].meridian);
    CHECK(strcmp(tr.t[0].why, "single arc on the other half, at 270 deg (on the steeper half, single arcs at most 80 deg: an "
                              "end within 20 deg of 150 deg)") == 0, "%s", tr.t[0].why);
    CHECK(strcmp(tr.t[1].why, "paired arcs at most 80 deg: an end within 20 deg of 150 deg") == 0, "%s", tr.t[1].why);
    remove(path);
}

/* The stages up to the trim with the model's clearance on a right eye against the rule (steep
 * 0 deg) with the main incision at `main_deg`; w: its wounds. */
static int model_stages(double main_deg, kt_lp_eye *eye, kt_lp_scene *sc, kt_lp_families *fam, kt_lp_trims *tr,
                        kt_lp_wounds *w, kt_err *e)
{
    char path[64];
    snprintf(path, sizeof path, "/tmp/kt-test-trim-m-%d.yaml", (int)getpid());
    FILE *f = fopen(path, "w");
    if (!f) return kt_fail(e, KT_ERUN, "cannot write %s", path);
    fprintf(f, "name: trim\neye: OD\nage: 65\ncornea:\n  keratometry: {k_steep: 44.5 D, k_flat: 43.0 D, steep_axis: 0 deg}\n"
               "main_incision: {meridian: %g deg, width: 2.4 mm}\nconstraints: {incisions: either, max_arc: 90 deg}\n",
            main_deg);
    fclose(f);
    kt_lp_opts o;
    kt_lp_opts_default(&o);
    o.patient = path, o.quiet = 1; /* o.clear NULL: the model's clearance */
    int rc = kt_lp_patient(&o, eye, e);
    if (rc == KT_OK) rc = kt_lp_scene_make(&o, eye, sc, e);
    if (rc == KT_OK) rc = kt_lp_families_make(&o, eye, fam, e);
    if (rc == KT_OK) rc = kt_lp_trims_make(&o, eye, sc, fam, tr, e);
    if (rc == KT_OK) rc = kt_lp_wounds_of(eye, sc, w, e);
    remove(path);
    return rc;
}

static void model(void)
{
    static kt_lp_eye eye;
    static kt_lp_scene sc;
    static kt_lp_families fam;
    static kt_lp_trims tr;
    kt_lp_wounds w;
    kt_err e = {0};
    int rc = model_stages(0, &eye, &sc, &fam, &tr, &w, &e); /* nasal in a right eye */
    CHECK(rc == KT_OK && fam.n == 2 && w.nw == 1, "the stages: %s", e.msg);
    if (rc) return;
    CHECK(tr.t[0].nstep == 18 && tr.t[0].meridian == 180 && tr.t[0].moved, "the single arc whole at 180 deg (%d at %g)",
          tr.t[0].nstep, tr.t[0].meridian);
    CHECK(strstr(tr.t[0].why, "single arcs left out: the arc at 0 deg would come within 15 deg of the main incision at 0 deg") != NULL,
          "%s", tr.t[0].why);
    CHECK(tr.t[1].nstep == 0 && strcmp(tr.t[1].why, "paired arcs left out: the arc at 0 deg would come within 15 deg of the "
                                                     "main incision at 0 deg (10.5 mm zone)") == 0, "%s", tr.t[1].why);
    /* the steps kept are the model's longest clear arc in whole steps (kt_clear_family) */
    double merid[] = {40, 50, 65, 300};
    for (int i = 0; i < 4; i++) {
        if (model_stages(merid[i], &eye, &sc, &fam, &tr, &w, &e)) {
            CHECK(0, "main at %g: %s", merid[i], e.msg);
            return;
        }
        kt_clear_result r;
        kt_clear_family(w.w, w.nw, fam.f[1].meridian, 1, 1, 90, w.zone, w.min, &r);
        int want = (int)floor(r.arc / 5 + 1e-9);
        CHECK(tr.t[1].nstep == want, "main at %g deg: the pair keeps %d steps, the model's longest clear arc %.2f deg", merid[i],
              tr.t[1].nstep, r.arc);
        CHECK(want < 18 && want > 0, "main at %g deg: trimmed, not left out (%.2f deg)", merid[i], r.arc);
    }
}

int main(void)
{
    decide();
    stage();
    model();
    return kt_test_done("test_trim");
}
