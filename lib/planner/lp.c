/* lp.c: the planner's front door (lp.h): the stages in order, each writing its own part of the
 * answer. */
#include "lp.h"

#include <math.h>
#include <string.h>

#include "aug_plan.h"

#include "lp_band.h"
#include "lp_choose.h"
#include "lp_family.h"
#include "lp_mesh.h"
#include "lp_patient.h"
#include "lp_run.h"
#include "lp_scene.h"
#include "lp_trim.h"

void kt_lp_opts_default(kt_lp_opts *o)
{
    memset(o, 0, sizeof *o);
    o->step = 5;
    o->plan_max_ratio = KT_PLAN_MAX_RATIO;
    o->state = KT_WOUND_HEALED;
}

int kt_lp_plan(const kt_lp_opts *o, kt_lp_answer *a, kt_err *e)
{
    memset(a, 0, sizeof *a);
    /* Everything that can be refused is refused before the mesh: patient, scene, families,
     * clearance. */
    if (kt_lp_patient(o, &a->eye, e) || kt_lp_scene_make(o, &a->eye, &a->scene, e) ||
        kt_lp_families_make(o, &a->eye, &a->fam, e) || kt_lp_trims_make(o, &a->eye, &a->scene, &a->fam, &a->trim, e))
        return e->code;
    int any = 0, why = 0;
    for (int i = 0; i < a->fam.n; i++) {
        any |= a->trim.t[i].nstep > 0;
        if (a->fam.f[i].kind == KT_LP_PAIRED) why = i; /* the pair's reason, as lri-plan(1) says it */
    }
    if (!any)
        return kt_fail(e, KT_EINPUT, "%s: no arc keeps %g deg clear of the wounds (%s); allow other arcs "
                       "(constraints.incisions), move the main incision (main_incision.meridian) or lower "
                       "constraints.clearance", a->eye.p.path, a->eye.p.clearance, a->trim.t[why].why);
    if (kt_lp_mesh_make(&a->scene.s, o->quiet, &a->mesh, e) || kt_lp_runs_make(o, a, e)) return e->code;
    kt_lp_choose(&a->eye, &a->fam, &a->run, &a->choice);
    if (a->choice.chosen < 0)
        return kt_fail(e, KT_ERUN, "%s: no family's predicted residual is a number (NaN in the solved readings): "
                       "numerical trouble in the solves, no plan written", a->eye.p.path);
    kt_lp_bands_make(o, a, &a->band);
    return KT_OK;
}

void kt_lp_answer_free(kt_lp_answer *a)
{
    kt_lp_mesh_free(&a->mesh);
}

double kt_lp_deg_mark(double deg)
{
    double d = fmod(round(deg), 360);
    return d < 0 ? d + 360 : d;
}

int kt_lp_res_digits(double r, double t)
{
    int d = 2;
    for (; d < 4 && r > t; d++) {
        double s = pow(10, d);
        if (round(r * s) > round(t * s)) break;
    }
    return d;
}
