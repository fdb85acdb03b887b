/* patient_scene.c: the patient's eye scene (kt_patient_scene): the base scene with the
 * patient's cornea, thickness profile, white-to-white, IOP, incision ring, age-scaled moduli
 * and the ordering centred where the arcs are cut (keratome-patient(5), THE PATIENT'S SCENE). */
#include <math.h>
#include <string.h>

#include "eye.h"
#include "patient.h"

/* The peripheral (limbal) thickness that gives the eye thickness t at radius r, by bisection
 * on the model's profile (kt_eye_thickness rises with t_peripheral); NAN when out of reach. */
static double solve_peripheral(kt_eye eye, double r, double t)
{
    /* Bracket: from the central thickness up in 50 um steps, while the geometry is valid. */
    double lo = eye.t_central, hi = lo;
    eye.t_peripheral = lo;
    if (!(kt_eye_thickness(&eye, r) - t <= 0)) return NAN;
    for (;;) {
        hi += 0.05;
        if (hi > 2.0) return NAN;
        eye.t_peripheral = hi;
        double f = kt_eye_thickness(&eye, r) - t;
        if (isnan(f)) return NAN;
        if (f >= 0) break;
        lo = hi;
    }
    for (int it = 0; it < 60; it++) {
        double mid = 0.5 * (lo + hi);
        eye.t_peripheral = mid;
        double f = kt_eye_thickness(&eye, r) - t;
        if (isnan(f)) return NAN;
        if (f < 0) lo = mid;
        else hi = mid;
    }
    return 0.5 * (lo + hi);
}

int kt_patient_scene(const kt_patient *p, const kt_scene *base, kt_scene *s, kt_err *e)
{
    if (base->model != KT_MODEL_EYE) return kt_fail(e, KT_EINPUT, "%s: expected an eye scene as the base", base->path);
    *s = *base;
    /* The scene's name: the patient's, with what a group name cannot hold as '-'. */
    snprintf(s->name, sizeof s->name, "%s", p->name);
    for (char *c = s->name; *c; c++)
        if (!((*c >= 'a' && *c <= 'z') || (*c >= 'A' && *c <= 'Z') || (*c >= '0' && *c <= '9') || *c == '.' || *c == '_'))
            *c = '-';
    kt_eye *eye = &s->eye;
    eye->r_ant_steep = p->ant.r_steep;
    eye->r_ant_flat = p->ant.r_flat;
    eye->steep_axis = p->ant.axis;
    /* The posterior, measured or the population default of the anterior (fitted by now),
     * toric in the mesh (eye_warp.c). */
    kt_toric post = p->post;
    if (post.source == KT_SOURCE_DEFAULT) kt_patient_default_posterior(&p->ant, &post);
    eye->r_post_steep = post.r_steep, eye->r_post_flat = post.r_flat;
    eye->post_axis = post.axis;
    eye->r_post = 2 / (1 / post.r_steep + 1 / post.r_flat);
    eye->t_central = p->t_central;
    eye->wtw = p->wtw;
    eye->wtw_v = p->wtw_v;
    eye->nring = 1;
    kt_ring *ring = &eye->ring[0];
    memset(ring, 0, sizeof *ring);
    snprintf(ring->name, sizeof ring->name, "incision-ring-1");
    ring->diameter = p->zone;
    ring->depth_fraction = p->depth_fraction;
    ring->depth = p->depth;
    if (!isnan(p->t_zone)) {
        double tp = solve_peripheral(*eye, p->zone / 2, p->t_zone);
        if (isnan(tp)) /* named where the value came from: the field, else the pachymetry map */
            return kt_patient_fail(p, e, p->mark[KT_PF_T_ZONE][0] ? KT_PF_T_ZONE : KT_PF_PACHYMETRY, KT_PF_CORNEA,
                                   "%g um at the %g mm zone: expected a pachymetry the eye model can reach there from "
                                   "the central %g um (a limbal thickness of at most 2000 um) with the anterior radii "
                                   "%.3f / %.3f mm (K %.2f / %.2f D: %s)", 1000 * p->t_zone, p->zone, 1000 * p->t_central,
                                   p->ant.r_steep, p->ant.r_flat, kt_patient_k(p->ant.r_steep), kt_patient_k(p->ant.r_flat),
                                   p->ant.source == KT_SOURCE_PENTACAM ? "the front map's fit" : "cornea.keratometry");
        eye->t_peripheral = tp;
    }
    if (eye->optical_zone >= p->zone) eye->optical_zone = 0.5 * (p->zone + 5);
    double f = kt_patient_age_factor(p->age);
    s->unc.age = p->age; /* the cornea's moduli are the age rule's: age_slope applies */
    for (int i = 0; i < s->nmat; i++) {
        kt_region_mat *m = &s->mat[i];
        if (strcmp(m->region, "cornea") != 0) continue;
        m->E *= f, m->E1 *= f, m->E2 *= f, m->Gt *= f;
    }
    for (int i = 0; i < s->npressure; i++) s->pressure[i].p = p->iop;
    s->ordering_set[0] = '\0';
    s->ordering_centre = p->ant.axis;
    /* Arcs of up to max_arc centred on the steep meridian, with 5 deg to spare each side. */
    s->ordering_sector = fmin(p->max_arc / 2 + 5, 89.9);
    eye->floor_centre = s->ordering_centre, eye->floor_sector = s->ordering_sector;
    kt_eye_geom g;
    double top[2], dir[2], depth;
    kt_err ge = {0}; /* the patient's eye that does not make a geometry: named at its cornea */
    if (kt_eye_geom_init(eye, &g, &ge) || kt_eye_geom_ring(&g, eye, 0, top, dir, &depth, &ge))
        return kt_patient_fail(p, e, KT_PF_CORNEA, -1, "the patient's eye: %s", ge.msg);
    return KT_OK;
}
