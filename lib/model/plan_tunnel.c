/* plan_tunnel.c: the plan's tunnels (keratome-plan(5), TUNNELS): the main cataract incision as
 * a flat keratome blade makes it, a planar shelved tunnel through the full corneal thickness.
 *
 * Geometry, in the meridional plane of the tunnel's meridian m (rho along e_m = (cos m, sin m),
 * z the eye axis): the external entry E = (entry_diameter / 2, outer surface height there); the
 * internal (Descemet) opening I = the point of the posterior corneal surface, nearer the axis,
 * at distance `length` from E. The blade's plane holds the chord E-I and the circumferential
 * tangent e_t = (-sin m, cos m, 0) at the meridian; the tunnel is the part of that plane within
 * |(x - E) . e_t| <= width / 2, from the outer surface to the posterior one. */
#include "plan_tunnel.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "eye_geom.h"
#include "scene_int.h"

static const char *const TUNNEL_KEYS[] = {"meridian", "width", "length", "entry_diameter", "steps", NULL};

int kt_plan_tunnel_steps(const kt_plan *p)
{
    int n = 0;
    for (int i = 0; i < p->ntunnel; i++) n += p->tunnel[i].steps;
    return n;
}

/* Distance in the meridional plane from (re, ze) to the posterior surface at rho. */
static double reach(const kt_eye_geom *g, double re, double ze, double rho)
{
    return hypot(re - rho, ze - kt_eye_geom_post_z(g, rho));
}

int kt_tunnel_derive(const kt_eye *eye, kt_tunnel *t, const char **field, char *msg, size_t size)
{
    kt_err ge = {0};
    kt_eye_geom gg, *g = &gg;
    *field = "meridian";
    if (kt_eye_geom_init(eye, g, &ge)) {
        snprintf(msg, size, "expected a valid eye: %s", ge.msg);
        return KT_EINPUT;
    }
    double re = t->entry_diameter / 2, m = t->meridian * KT_PI / 180, optical = eye->optical_zone;
    double em[2] = {cos(m), sin(m)};
    *field = "entry_diameter";
    if (!(re > optical / 2 && re < g->rL)) {
        snprintf(msg, size, "expected the entry on the peripheral cornea or the limbus, a diameter in (%g, %g) mm, got %g mm",
                 optical, 2 * g->rL, t->entry_diameter);
        return KT_EINPUT;
    }
    /* On an oval cornea the entry lies as far inside (or outside) the corneal edge in its
     * meridian as entry_diameter / 2 lies from the horizontal edge (keratome-plan(5)). */
    re = kt_eye_geom_oval_rho(g, re, em[0], em[1]);
    double ze = kt_eye_geom_outer_z(g, re * em[0], re * em[1]);
    /* The internal opening: reach() falls from its value at the axis to the one at the
     * posterior surface's edge; bisection for reach = length. */
    double hi = g->Pp[0], lo = 0;
    double rmin = reach(g, re, ze, hi), rmax = reach(g, re, ze, lo);
    *field = "length";
    if (!(t->length > rmin && t->length < rmax)) {
        snprintf(msg, size, "expected a tunnel that reaches the anterior chamber through the stroma from its entry, "
                 "a length in (%.3g, %.3g) mm, got %g mm", rmin, rmax, t->length);
        return KT_EINPUT;
    }
    for (int it = 0; it < 100; it++) {
        double mid = 0.5 * (lo + hi);
        if (reach(g, re, ze, mid) > t->length) lo = mid;
        else hi = mid;
    }
    double ri = 0.5 * (lo + hi), zi = kt_eye_geom_post_z(g, ri);
    if (!isfinite(ze) || !isfinite(zi)) {
        snprintf(msg, size, "expected a tunnel inside the eye model's cornea");
        return KT_EINPUT;
    }
    t->entry[0] = re * em[0], t->entry[1] = re * em[1], t->entry[2] = ze;
    t->exit[0] = ri * em[0], t->exit[1] = ri * em[1], t->exit[2] = zi;
    double len = 0;
    for (int k = 0; k < 3; k++) t->along[k] = t->exit[k] - t->entry[k], len += t->along[k] * t->along[k];
    for (int k = 0; k < 3; k++) t->along[k] /= sqrt(len);
    t->across[0] = -em[1], t->across[1] = em[0], t->across[2] = 0;
    const double *a = t->across, *b = t->along;
    t->normal[0] = a[1] * b[2] - a[2] * b[1];
    t->normal[1] = a[2] * b[0] - a[0] * b[2];
    t->normal[2] = a[0] * b[1] - a[1] * b[0];
    if (t->normal[2] < 0) /* towards the roof (the anterior lip) */
        for (int k = 0; k < 3; k++) t->normal[k] = -t->normal[k];
    /* The blade's width: a chord of at most a quarter of the entry circle. */
    *field = "width";
    if (!(t->width <= re * sqrt(2.0))) {
        snprintf(msg, size, "expected at most %.3g mm at an entry diameter of %g mm, got %g mm", re * sqrt(2.0),
                 t->entry_diameter, t->width);
        return KT_EINPUT;
    }
    return KT_OK;
}

static int parse_one(kt_yml *y, const yaml_node_t *n, int i, kt_plan *p, kt_err *e)
{
    char what[64];
    snprintf(what, sizeof what, "tunnels[%d]", i);
    kt_tunnel *t = &p->tunnel[i];
    memset(t, 0, sizeof *t);
    t->at.line = kt_yml_line(n), t->at.col = kt_yml_col(n);
    t->length = KT_TUNNEL_LENGTH;
    t->entry_diameter = p->scene.eye.wtw; /* the corneal edge: a clear-corneal entry */
    t->steps = KT_TUNNEL_STEPS;
    if (kt_yml_check_map(y, n, what, TUNNEL_KEYS, e) || !kt_yml_require(y, n, "meridian", what, e) ||
        !kt_yml_require(y, n, "width", what, e))
        return e->code;
    if (kt_yml_key_quantity(y, n, what, "meridian", KT_UNIT_ANGLE, (kt_yml_bounds){0, 360, 0, 1}, &t->meridian, e) ||
        kt_yml_key_quantity(y, n, what, "width", KT_UNIT_LENGTH, kt_scene_range(0.5, 8, 0, 0), &t->width, e) ||
        kt_yml_key_quantity(y, n, what, "length", KT_UNIT_LENGTH, kt_scene_range(0.2, 6, 0, 0), &t->length, e) ||
        kt_yml_key_quantity(y, n, what, "entry_diameter", KT_UNIT_LENGTH, kt_scene_range(2, 30, 0, 0),
                            &t->entry_diameter, e) ||
        kt_yml_key_int(y, n, what, "steps", 1, 100, &t->steps, e))
        return e->code;
    const char *field;
    char msg[400];
    if (kt_tunnel_derive(&p->scene.eye, t, &field, msg, sizeof msg)) {
        yaml_node_t *f = kt_yml_get(y, n, field);
        return kt_yml_fail(y, f ? f : n, e, "%s.%s: %s", what, field, msg);
    }
    return KT_OK;
}

int kt_plan_parse_tunnels(kt_yml *y, const yaml_node_t *n, kt_plan *p, kt_err *e)
{
    if (kt_yml_check_seq(y, n, "tunnels", 1, KT_PLAN_MAX, e)) return e->code;
    if (p->scene.model != KT_MODEL_EYE)
        return kt_yml_fail(y, n, e, "tunnels: expected an eye scene, %s is not one", p->scene_path);
    p->ntunnel = kt_yml_seq_len(n);
    for (int i = 0; i < p->ntunnel; i++)
        if (parse_one(y, kt_yml_seq_item(y, n, i), i, p, e)) return e->code;
    return KT_OK;
}
