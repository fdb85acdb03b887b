/* lp_scene.c: the patient's eye scene and the main incision's tunnel (lp_scene.h). */
#include "lp_scene.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

double kt_lp_main_entry(const kt_patient *p, const kt_scene *s)
{
    return p->wtw + (p->main_kind == KT_MAIN_LIMBAL ? s->eye.limbus_width : 0);
}

/* The base scene, the patient's values on it, --fast's coarse sizes. */
static int make_scene(const kt_lp_opts *o, const kt_lp_eye *eye, kt_lp_scene *sc, kt_err *e)
{
    if (o->base) snprintf(sc->base, sizeof sc->base, "%s", o->base);
    else snprintf(sc->base, sizeof sc->base, "%s/../plans/eye.yaml", KT_SHARE_DIR);
    kt_scene *b = kt_calloc(1, sizeof *b, e);
    int rc = b ? kt_scene_load(sc->base, b, e) : e->code;
    if (rc == KT_OK) rc = kt_patient_scene(&eye->p, b, &sc->s, e);
    free(b);
    if (rc == KT_OK) sc->s.wound.state = o->state; /* lri-plan --state (the base's k, age rule, months) */
    if (rc == KT_OK && o->fast) {
        /* --fast: coarse sizes; the base's incision-floor refinement kept at a coarser size
         * (lri-plan(1), --fast: without it the arcs' effect is under-predicted by 20-30%); a
         * base without one gets none. */
        kt_eye *y = &sc->s.eye;
        y->h_optical = 0.6, y->h_incision = 0.3, y->h_cornea = 0.8, y->h_sclera = 2.5;
        y->h_floor = y->h_floor > 0 ? fmax(y->h_floor, KT_LP_FAST_FLOOR) : 0;
    }
    return rc;
}

/* The simulated main incision's tunnel, derived on the eye; the mesh follows its site: the
 * cylinder around the tunnel's rectangle (seen from the front) meshed at the incision's size. */
static int main_tunnel(const kt_patient *p, kt_lp_scene *sc, kt_err *e)
{
    sc->main_sim = p->main_present && p->main_simulate;
    if (!sc->main_sim) return KT_OK;
    kt_tunnel *t = &sc->main;
    memset(t, 0, sizeof *t);
    t->meridian = p->main_meridian, t->width = p->main_width, t->length = KT_TUNNEL_LENGTH;
    t->entry_diameter = kt_lp_main_entry(p, &sc->s), t->steps = KT_TUNNEL_STEPS;
    const char *field;
    char msg[400];
    if (kt_tunnel_derive(&sc->s.eye, t, &field, msg, sizeof msg))
        return kt_patient_fail(p, e, KT_PF_MAIN, -1, "its tunnel's %s: %s", field, msg);
    double re = hypot(t->entry[0], t->entry[1]), ri = hypot(t->exit[0], t->exit[1]);
    kt_eye *y = &sc->s.eye;
    y->site_meridian = p->main_meridian;
    y->site_distance = 0.5 * (re + ri);
    y->site_radius = hypot(0.5 * (re - ri), 0.5 * p->main_width);
    return KT_OK;
}

/* A Pentacam patient's measured surfaces (lib/optics/surffit.h, kt_surffit_measured_eye): the
 * maps' departures from the mesher's base surfaces into the scene's eye, so the mesh carries
 * the patient's own cornea; their residuals into mesh_ant and mesh_post. */
static int measured(const kt_lp_eye *eye, kt_lp_scene *sc, kt_err *e)
{
    if (!eye->fitted) return KT_OK;
    sc->mesh_ant = eye->fit_ant, sc->mesh_post = eye->fit_post;
    if (kt_surffit_measured_eye(&eye->p, &sc->s.eye, &sc->mesh_ant, eye->fit_post_ok ? &sc->mesh_post : NULL, e))
        return e->code;
    sc->measured = 1;
    return KT_OK;
}

int kt_lp_scene_make(const kt_lp_opts *o, const kt_lp_eye *eye, kt_lp_scene *sc, kt_err *e)
{
    memset(sc, 0, sizeof *sc);
    if (make_scene(o, eye, sc, e) || measured(eye, sc, e)) return e->code;
    return main_tunnel(&eye->p, sc, e);
}
