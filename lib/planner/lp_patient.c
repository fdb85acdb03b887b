/* lp_patient.c: the patient, its Pentacam fits, its halves and its blade (lp_patient.h). */
#include "lp_patient.h"

#include <math.h>
#include <string.h>

#include "pentacam.h"

/* The elevation map `which` fitted into *fit, and with halves not NULL the steep meridian's
 * half-meridians into *halves; the fit's radii, axis and asphericity copied to the patient's
 * surface *t. */
static int fit_map(kt_patient *p, int which, kt_surffit *fit, kt_halfmer *halves, kt_toric *t, kt_err *e)
{
    kt_pentacam_map m;
    if (kt_patient_read_map(p, which, &m, e)) return e->code;
    int rc = kt_surffit_elevation(&m, KT_SURFFIT_ZONE, fit, e);
    if (rc == KT_OK && halves) rc = kt_surffit_halves(&m, fit, halves, e);
    kt_pentacam_free(&m);
    if (rc) return rc;
    t->r_steep = fit->r_steep, t->r_flat = fit->r_flat, t->axis = fit->axis, t->conic = fit->conic;
    return KT_OK;
}

/* The anterior surface from the Pentacam elevation map, and its half-meridians. */
static int fit_front(kt_lp_eye *a, kt_err *e)
{
    if (fit_map(&a->p, KT_PF_FRONT, &a->fit_ant, &a->halves, &a->p.ant, e)) return e->code;
    a->halves_ok = 1;
    return KT_OK;
}

/* The posterior surface from the back map; without one, the population default of the fitted
 * anterior (kt_patient_default_posterior, Eom et al. 2015: the load applied it to an anterior not
 * yet known). */
static int fit_back(kt_lp_eye *a, kt_err *e)
{
    kt_patient *p = &a->p;
    if (!p->pentacam_back[0]) {
        if (p->post.source == KT_SOURCE_DEFAULT) kt_patient_default_posterior(&p->ant, &p->post);
        return KT_OK;
    }
    if (fit_map(p, KT_PF_BACK, &a->fit_post, NULL, &p->post, e)) return e->code;
    a->fit_post_ok = 1;
    return KT_OK;
}

static int fit_pachy(kt_lp_eye *a, kt_err *e)
{
    kt_patient *p = &a->p;
    if (!p->pentacam_pachy[0]) return KT_OK;
    kt_pentacam_map m;
    if (kt_patient_read_map(p, KT_PF_PACHYMETRY, &m, e)) return e->code;
    double rmax = fmin(p->zone / 2 + 0.5, KT_PENTACAM_HALF);
    int rc = kt_surffit_pachymetry(&m, a->fit_ant.ax, a->fit_ant.ay, rmax, &a->fit_pachy, e);
    kt_pentacam_free(&m);
    if (rc) return rc;
    a->fit_pachy_ok = 1;
    p->t_central = a->fit_pachy.t0;
    if (isnan(p->t_zone)) p->t_zone = kt_pachyfit_at(&a->fit_pachy, p->zone / 2);
    return KT_OK;
}

/* The cornea from the Pentacam maps (each read against the patient file: kt_patient_read_map):
 * anterior (required), posterior and pachymetry; the fits checked against the patient file's
 * ranges (kt_patient_check_fit), refused at the map's field. */
static int fit_pentacam(kt_lp_eye *a, kt_err *e)
{
    if (fit_front(a, e) || fit_back(a, e) || fit_pachy(a, e)) return e->code;
    a->fitted = 1;
    return kt_patient_check_fit(&a->p, a->fit_post_ok, a->fit_pachy_ok, e);
}

/* The halves of the steep meridian: which is steeper and the ratio of their astigmatism (the
 * unequal pair's arcs); keratometry alone is symmetric. */
static void asymmetry(kt_lp_eye *a)
{
    a->ratio = 1, a->steep_half = a->p.ant.axis;
    if (!a->halves_ok) return;
    a->half_a = a->halves.k_a - a->halves.k_flat, a->half_b = a->halves.k_b - a->halves.k_flat;
    double big = fmax(a->half_a, a->half_b), small = fmin(a->half_a, a->half_b);
    if (a->half_b > a->half_a) a->steep_half = fmod(a->p.ant.axis + 180, 360);
    if (big > 0) a->ratio = fmin(1, fmax(KT_LP_RATIO_MIN, small / big));
}

/* Pachymetry at the zone and the blade depth; a blade deeper than 90% of it is bad input. */
static int blade(kt_lp_eye *a, kt_err *e)
{
    const kt_patient *p = &a->p;
    a->t_zone = isnan(p->t_zone) ? kt_patient_model_zone_thickness(p) : p->t_zone;
    a->blade = p->depth_fraction > 0 ? p->depth_fraction * a->t_zone : p->depth;
    if (!(a->blade <= KT_PATIENT_DEPTH_MAX * a->t_zone + 1e-12))
        return kt_patient_fail(p, e, KT_PF_DEPTH, KT_PF_PACHYMETRY,
                               "expected at most %g%% of the pachymetry at the zone (%.0f um), got %.0f um",
                               100 * KT_PATIENT_DEPTH_MAX, 1000 * KT_PATIENT_DEPTH_MAX * a->t_zone, 1000 * a->blade);
    return KT_OK;
}

int kt_lp_patient(const kt_lp_opts *o, kt_lp_eye *eye, kt_err *e)
{
    memset(eye, 0, sizeof *eye);
    if (kt_patient_load(o->patient, &eye->p, e)) return e->code;
    if (eye->p.ant.source == KT_SOURCE_PENTACAM && fit_pentacam(eye, e)) return e->code;
    asymmetry(eye);
    if (blade(eye, e)) return e->code;
    if (!(o->step > 0 && o->step <= eye->p.max_arc))
        return kt_fail(e, KT_EINPUT, "--step %g: expected an angle in (0, max_arc = %g] deg", o->step, eye->p.max_arc);
    return KT_OK;
}
