/* scene_unc.c: the scene's `uncertainty:` section (keratome-scene(5), UNCERTAINTY): each
 * uncertain quantity's standard deviation and distribution, with the documented defaults and
 * their sources (docs/references.md, "Uncertainty"). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "scene_int.h"

/* Defaults: nothing here is fitted to an outcome.
 *   E_inplane 0.55 MPa: the in vivo spread 4.0 +- 1.1 MPa (Li et al. 2024), 27.5%, on 2.0 MPa.
 *   G_transverse 2.9 kPa: ex vivo torsion 9.48 +- 2.92 kPa (Petsche et al. 2012).
 *   iop 3.0 mmHg: the spread of IOP among adults (Beaver Dam Eye Study, Klein et al. 1992).
 *   limbal_density 0.45: 1.91 +- 0.45 (Zhou et al. 2019, WAXS).
 *   thickness 8 um: ultrasound pachymetry day to day, 95% limits of agreement -22..+24 um
 *     (Marsich and Bullimore 2000): sd of a difference 11.7 um, of one reading 11.7 / sqrt 2.
 *   depth 50 um: achieved minus set depth of a guarded diamond knife; histology finds cuts
 *     deeper than the calibrated blade and scattered (Unterman et al. 1984) without a usable sd:
 *     50 um is a stated assumption (about 10% of a 500-600 um cut), to be replaced by a measured
 *     one.
 *   age_slope 0.05 per decade: +0.30 +- 0.21 MPa per decade on 4.0 MPa (Li et al. 2024).
 *   heal 0.31: the natural logarithm of the healed wound's bridge stiffness (wound:): the
 *     posterior sd of ln k60 identified by plans/studies/calibrate (docs/validation.md), a
 *     factor 1.36 either way. The eye-to-eye spread of the outcome is uncertainty.nontissue_cv. */
static const struct {
    const char *name, *unit, *source;
    double sd;
} UQ[KT_UQ_N] = {
    {"E_inplane", "MPa", "li2024", 0.55},
    {"G_transverse", "kPa", "petsche2012", 2.9},
    {"iop", "mmHg", "klein1992", 3.0},
    {"limbal_density", "1", "zhou2019", 0.45},
    {"thickness", "um", "marsich2000", 8.0},
    {"depth", "um", "unterman1984", 50.0},
    {"age_slope", "1/decade", "li2024", 0.05},
    {"heal", "1", "calibrate2026", 0.31},
};

const char *kt_uq_name(int q) { return q >= 0 && q < KT_UQ_N ? UQ[q].name : "?"; }
const char *kt_uq_unit(int q) { return q >= 0 && q < KT_UQ_N ? UQ[q].unit : "?"; }
double kt_uq_default_sd(int q) { return q >= 0 && q < KT_UQ_N ? UQ[q].sd : NAN; }
const char *kt_uq_source(int q) { return q >= 0 && q < KT_UQ_N ? UQ[q].source : "?"; }

void kt_scene_unc_defaults(kt_uncertainty *u)
{
    for (int q = 0; q < KT_UQ_N; q++) {
        u->sd[q] = UQ[q].sd;
        u->dist[q] = KT_UQ_NORMAL;
    }
    u->age = NAN;
    u->nontissue_cv = KT_UQ_NONTISSUE_CV;
}

static const char *const ENTRY_KEYS[] = {"sd", "distribution", "age", NULL};
static const char *const DISTS[] = {"normal", "uniform", NULL};

int kt_scene_parse_uncertainty(kt_yml *y, const yaml_node_t *n, kt_uncertainty *u, kt_err *e)
{
    const char *keys[KT_UQ_N + 2];
    for (int q = 0; q < KT_UQ_N; q++) keys[q] = UQ[q].name;
    keys[KT_UQ_N] = "nontissue_cv", keys[KT_UQ_N + 1] = NULL;
    if (kt_yml_check_map(y, n, "uncertainty", keys, e) ||
        kt_yml_key_number(y, n, "uncertainty", "nontissue_cv", kt_scene_range(0, 5, 0, 0), &u->nontissue_cv, e))
        return e->code;
    for (int q = 0; q < KT_UQ_N; q++) {
        yaml_node_t *v = kt_yml_get(y, n, UQ[q].name);
        if (!v) continue;
        char what[64];
        snprintf(what, sizeof what, "uncertainty.%s", UQ[q].name);
        if (kt_yml_check_map(y, v, what, ENTRY_KEYS, e)) return e->code;
        if (!kt_yml_require(y, v, "sd", what, e)) return e->code;
        /* a plain number in the quantity's unit (kt_uq_unit): at most 1e6 of it */
        if (kt_yml_key_number(y, v, what, "sd", kt_scene_range(0, 1e6, 0, 0), &u->sd[q], e) ||
            kt_yml_key_choice(y, v, what, "distribution", DISTS, &u->dist[q], e))
            return e->code;
        yaml_node_t *age = kt_yml_get(y, v, "age");
        if (age && q != KT_UQ_AGE_SLOPE)
            return kt_yml_fail(y, age, e, "%s.age: expected only on age_slope", what);
        if (kt_yml_key_number(y, v, what, "age", kt_scene_range(0, 130, 0, 0), &u->age, e))
            return e->code;
    }
    return KT_OK;
}
