/* scene_eye.c: the scene's eye block: its defaults (with their sources in
 * keratome-scene(5)), the incision rings, mesh sizes and fibres, and the consistency checks. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "eye.h"
#include "scene_int.h"


/* Literature defaults of the eye; sources in man/man5/keratome-scene.5 and plans/eye.yaml. */
void kt_scene_eye_defaults(kt_eye *eye)
{
    memset(eye, 0, sizeof *eye);
    eye->r_ant_steep = eye->r_ant_flat = 7.8; /* Le Grand schematic eye */
    eye->steep_axis = 90.0;                   /* with-the-rule convention when toric */
    eye->r_post = 6.7;                        /* schematic eyes 6.5 (Le Grand) - 6.8 (Gullstrand) */
    eye->r_post_steep = eye->r_post_flat = 6.7; /* of revolution unless the scene says */
    eye->post_axis = 90.0;                    /* steep vertical when toric (Koch et al. 2012) */
    eye->t_central = 0.54;                    /* Doughty & Zaman 2000 */
    eye->t_peripheral = 0.67;                 /* Martola & Baum 1968 */
    eye->wtw = 11.7;                          /* Rufer et al. 2005 */
    eye->wtw_v = 10.6;                        /* 11.7 - KT_EYE_WTW_DIFF: vertical 10.63 mm */
    eye->limbus_width = 1.0;                  /* Van Buskirk 1989: about 1-1.5 mm */
    eye->sclera_thickness = 0.53;             /* Olsen et al. 1998, at the limbus */
    eye->globe_radius = 12.0;                 /* axial length about 24 mm */
    eye->extent = 90.0;                       /* anterior segment: cut at the equator */
    eye->optical_zone = 7.0;
    eye->fibre_band = 1.5;     /* lamellae turn within about 1-2 mm of the limbus (Meek & Newton) */
    eye->fibre_density = 1.91; /* limbal fibril density / central, WAXS (PMC6443175) */
    eye->h_optical = 0.25;
    eye->h_incision = 0.15;
    eye->h_cornea = 0.4;
    eye->h_sclera = 1.2;
    eye->floor_grading = KT_EYE_FLOOR_GRADING;
}

/* ---- eye ------------------------------------------------------------------------------- */

int kt_scene_parse_wtw(kt_yml *y, const yaml_node_t *map, const char *what, kt_yml_bounds bh, kt_yml_bounds bv,
                       double *h, double *v, kt_err *e)
{
    static const char *const KEYS[] = {"horizontal", "vertical", NULL};
    yaml_node_t *n = kt_yml_get(y, map, "white_to_white");
    if (!n) return KT_OK;
    char w[64];
    snprintf(w, sizeof w, "%s.white_to_white", what);
    double hv = *h, vv;
    if (n->type != YAML_MAPPING_NODE) {
        if (kt_yml_quantity(y, n, w, KT_UNIT_LENGTH, bh, &hv, e)) return e->code;
        *h = hv, *v = hv - KT_EYE_WTW_DIFF;
        return KT_OK;
    }
    if (kt_yml_check_map(y, n, w, KEYS, e) ||
        kt_yml_key_quantity(y, n, w, "horizontal", KT_UNIT_LENGTH, bh, &hv, e))
        return e->code;
    vv = hv - KT_EYE_WTW_DIFF;
    yaml_node_t *vn = kt_yml_get(y, n, "vertical");
    if (kt_yml_key_quantity(y, n, w, "vertical", KT_UNIT_LENGTH, bv, &vv, e)) return e->code;
    if (vv > hv)
        return kt_yml_fail(y, vn, e, "%s.vertical: expected at most the horizontal diameter (%g mm): the cornea is "
                           "horizontally oval, got %g mm", w, hv, vv);
    *h = hv, *v = vv;
    return KT_OK;
}

static const char *const RING_KEYS[] = {"name", "diameter", "depth", "depth_fraction", NULL};

static int parse_ring(kt_yml *y, const yaml_node_t *n, int i, kt_ring *r, kt_err *e)
{
    char what[64];
    snprintf(what, sizeof what, "eye.incision_rings[%d]", i);
    if (kt_yml_check_map(y, n, what, RING_KEYS, e)) return e->code;
    snprintf(r->name, sizeof r->name, "incision-ring-%d", i + 1);
    yaml_node_t *v = kt_yml_get(y, n, "name");
    char f[96];
    snprintf(f, sizeof f, "%s.name", what);
    if (v && kt_scene_name_field(y, v, f, r->name, e)) return e->code;
    if (!kt_yml_require(y, n, "diameter", what, e)) return e->code;
    if (kt_yml_key_quantity(y, n, what, "diameter", KT_UNIT_LENGTH, kt_scene_range(0, 30, 1, 0), &r->diameter, e))
        return e->code;
    yaml_node_t *d = kt_yml_get(y, n, "depth"), *df = kt_yml_get(y, n, "depth_fraction");
    if (!d == !df)
        return kt_yml_fail(y, d ? d : n, e, "%s: expected exactly one of 'depth' or 'depth_fraction'", what);
    if (kt_yml_key_quantity(y, n, what, "depth", KT_UNIT_LENGTH, kt_scene_range(0, 5, 1, 0), &r->depth, e))
        return e->code;
    return kt_yml_key_number(y, n, what, "depth_fraction", kt_scene_range(0, 1, 1, 1), &r->depth_fraction, e);
}

static int parse_rings(kt_yml *y, const yaml_node_t *n, kt_eye *eye, kt_err *e)
{
    if (kt_yml_check_seq(y, n, "eye.incision_rings", 0, KT_SCENE_MAX, e)) return e->code;
    eye->nring = kt_yml_seq_len(n);
    for (int i = 0; i < eye->nring; i++) {
        yaml_node_t *item = kt_yml_seq_item(y, n, i);
        if (parse_ring(y, item, i, &eye->ring[i], e)) return e->code;
        const char *name = eye->ring[i].name;
        if (kt_scene_in_list(kt_scene_eye_surfaces, name))
            return kt_yml_fail(y, item, e, "eye.incision_rings[%d].name: expected a new name, '%s' is a surface of the eye",
                               i, name);
        for (int j = 0; j < i; j++)
            if (strcmp(eye->ring[j].name, name) == 0)
                return kt_yml_fail(y, item, e, "eye.incision_rings[%d].name: expected a unique name, '%s' is used twice",
                                   i, name);
    }
    return KT_OK;
}

static const char *const SIZE_KEYS[] = {"optical_zone", "incision", "incision_floor", "floor_grading",
                                        "cornea", "sclera", "site", NULL};
static const char *const SITE_KEYS[] = {"meridian", "distance", "radius", NULL};

static int parse_sizes(kt_yml *y, const yaml_node_t *n, kt_eye *eye, kt_err *e)
{
    const char *w = "eye.mesh_size";
    if (kt_yml_check_map(y, n, w, SIZE_KEYS, e)) return e->code;
    kt_yml_bounds b = kt_scene_range(0.005, 20, 0, 0);
    if (kt_yml_key_quantity(y, n, w, "optical_zone", KT_UNIT_LENGTH, b, &eye->h_optical, e) ||
        kt_yml_key_quantity(y, n, w, "incision", KT_UNIT_LENGTH, b, &eye->h_incision, e) ||
        kt_yml_key_quantity(y, n, w, "cornea", KT_UNIT_LENGTH, b, &eye->h_cornea, e) ||
        kt_yml_key_quantity(y, n, w, "sclera", KT_UNIT_LENGTH, b, &eye->h_sclera, e))
        return e->code;
    /* The floor size: at least 5 um (a 90% incision leaves a 65 um bridge; finer costs nodes
     * without a use), at most the ring's size (it refines the ring's own mesh). */
    yaml_node_t *fl = kt_yml_get(y, n, "incision_floor");
    if (kt_yml_key_quantity(y, n, w, "incision_floor", KT_UNIT_LENGTH, kt_scene_range(0.005, 1, 0, 0),
                            &eye->h_floor, e))
        return e->code;
    if (fl && eye->h_floor > eye->h_incision)
        return kt_yml_fail(y, fl, e, "eye.mesh_size.incision_floor: expected at most mesh_size.incision (%g mm), got %g mm",
                           eye->h_incision, eye->h_floor);
    /* How fast the floor's size grows away from it (mm per mm, a number): 0.1 (the size about
     * doubled ten floor sizes away) to 2 (tripled one floor size away; steeper jumps leave
     * gmsh's graded meshes poorly shaped). Without incision_floor it has nothing to grade. */
    if (kt_yml_key_quantity(y, n, w, "floor_grading", KT_UNIT_NONE, kt_scene_range(0.1, 2, 0, 0), &eye->floor_grading, e))
        return e->code;
    /* A site meshed at the incision's size (the main incision's tunnel). */
    yaml_node_t *st = kt_yml_get(y, n, "site");
    if (st) {
        const char *ws = "eye.mesh_size.site";
        if (kt_yml_check_map(y, st, ws, SITE_KEYS, e) || !kt_yml_require(y, st, "meridian", ws, e) ||
            !kt_yml_require(y, st, "distance", ws, e) || !kt_yml_require(y, st, "radius", ws, e) ||
            kt_yml_key_quantity(y, st, ws, "meridian", KT_UNIT_ANGLE, (kt_yml_bounds){0, 360, 0, 1}, &eye->site_meridian, e) ||
            kt_yml_key_quantity(y, st, ws, "distance", KT_UNIT_LENGTH, kt_scene_range(0, 20, 0, 0), &eye->site_distance, e) ||
            kt_yml_key_quantity(y, st, ws, "radius", KT_UNIT_LENGTH, kt_scene_range(0.1, 10, 0, 0), &eye->site_radius, e))
            return e->code;
    }
    return KT_OK;
}

static const char *const EYE_KEYS[] = {
    "anterior_radius", "anterior_radius_steep", "anterior_radius_flat", "steep_axis",
    "posterior_radius", "posterior_radius_steep", "posterior_radius_flat", "posterior_steep_axis",
    "central_thickness", "peripheral_thickness", "white_to_white",
    "limbus_width", "sclera_thickness", "globe_radius", "extent", "optical_zone", "mesh_size",
    "incision_rings", "fibres", "anterior_departure", "posterior_departure", NULL};
static const char *const FIBRE_KEYS[] = {"limbal_band", "limbal_density", NULL};

/* Geometric consistency between fields; messages point at the field that breaks it. */
static int check_eye(kt_yml *y, const yaml_node_t *n, const kt_eye *eye, kt_err *e)
{
    /* Geometry of lib/model/eye_geom.h: the cornea ends at rho = wtw/2 on the globe sphere, the
     * limbus is the band out to wtw/2 + limbus_width. Rings and the optical zone must stay
     * limbus_width/2 inside the corneal edge (in clear cornea, as LRIs are placed). */
    double clear = eye->wtw - eye->limbus_width;
    double r_ant = fmin(eye->r_ant_steep, eye->r_ant_flat);
    double r_limbus = 0.5 * eye->wtw + eye->limbus_width;
    yaml_node_t *at;
    if (eye->wtw >= 2 * r_ant) {
        at = kt_yml_get(y, n, "white_to_white");
        return kt_yml_fail(y, at ? at : n, e, "eye.white_to_white: expected less than twice the steep anterior radius (%g mm), got %g mm",
                           2 * r_ant, eye->wtw);
    }
    if (eye->limbus_width >= 0.5 * eye->wtw) {
        at = kt_yml_get(y, n, "limbus_width");
        return kt_yml_fail(y, at ? at : n, e, "eye.limbus_width: expected less than half of white_to_white (%g mm), got %g mm",
                           0.5 * eye->wtw, eye->limbus_width);
    }
    if (eye->globe_radius <= r_limbus) {
        at = kt_yml_get(y, n, "globe_radius");
        return kt_yml_fail(y, at ? at : n, e, "eye.globe_radius: expected more than the limbus's outer radius white_to_white/2 + limbus_width (%g mm), got %g mm",
                           r_limbus, eye->globe_radius);
    }
    double polar = asin(r_limbus / eye->globe_radius) * 180 / KT_PI;
    if (eye->extent <= polar) {
        at = kt_yml_get(y, n, "extent");
        return kt_yml_fail(y, at ? at : n, e, "eye.extent: expected more than the polar angle of the limbus's outer edge (%.1f deg), got %g deg",
                           polar, eye->extent);
    }
    if (eye->optical_zone > clear) {
        at = kt_yml_get(y, n, "optical_zone");
        return kt_yml_fail(y, at ? at : n, e, "eye.optical_zone: expected a diameter inside the clear cornea (<= white_to_white - limbus_width = %g mm), got %g mm",
                           clear, eye->optical_zone);
    }
    double vmin = kt_eye_wtw_v_min(eye);
    if (eye->wtw_v < vmin) {
        at = kt_yml_get(y, n, "white_to_white");
        if (at && kt_yml_get(y, at, "vertical")) at = kt_yml_get(y, at, "vertical");
        return kt_yml_fail(y, at ? at : n, e, "eye.white_to_white.vertical: expected at least %g mm (the horizontal %g mm "
                           "less 1.6 x (white_to_white - limbus_width - optical_zone) / 2: the oval warp's room between "
                           "the optical zone and the outermost ring), got %g mm", vmin, eye->wtw, eye->wtw_v);
    }
    yaml_node_t *rings = kt_yml_get(y, n, "incision_rings");
    double t_max = fmax(eye->t_central, eye->t_peripheral);
    for (int i = 0; i < eye->nring; i++) {
        const kt_ring *r = &eye->ring[i];
        yaml_node_t *item = kt_yml_seq_item(y, rings, i);
        yaml_node_t *d = kt_yml_get(y, item, "diameter");
        if (r->diameter <= eye->optical_zone || r->diameter > clear)
            return kt_yml_fail(y, d, e, "eye.incision_rings[%d].diameter: expected a diameter in (%g, %g] mm (outside the optical zone, inside white_to_white - limbus_width), got %g mm",
                               i, eye->optical_zone, clear, r->diameter);
        if (r->depth_fraction == 0 && r->depth >= t_max)
            return kt_yml_fail(y, kt_yml_get(y, item, "depth"), e, "eye.incision_rings[%d].depth: expected less than the corneal thickness (%g mm), got %g mm",
                               i, t_max, r->depth);
    }
    return KT_OK;
}

/* The posterior surface: posterior_radius (of revolution) or the steep/flat pair with
 * posterior_steep_axis (toric); r_post is the pair's mean curvature's radius. */
static int parse_posterior(kt_yml *y, const yaml_node_t *n, kt_eye *eye, kt_err *e)
{
    const char *w = "eye";
    kt_yml_bounds radius = kt_scene_range(1, 50, 0, 0);
    yaml_node_t *one = kt_yml_get(y, n, "posterior_radius"), *ps = kt_yml_get(y, n, "posterior_radius_steep"),
                *pf = kt_yml_get(y, n, "posterior_radius_flat");
    if (one && (ps || pf))
        return kt_yml_fail(y, one, e, "eye.posterior_radius: expected either posterior_radius or the steep/flat pair, not both");
    if (!ps != !pf)
        return kt_yml_fail(y, ps ? ps : pf, e, "eye.%s: expected posterior_radius_steep and posterior_radius_flat together",
                           ps ? "posterior_radius_steep" : "posterior_radius_flat");
    double r = eye->r_post;
    if (kt_yml_key_quantity(y, n, w, "posterior_radius", KT_UNIT_LENGTH, radius, &r, e) ||
        kt_yml_key_quantity(y, n, w, "posterior_steep_axis", KT_UNIT_ANGLE, kt_scene_range(0, 180, 0, 0), &eye->post_axis, e))
        return e->code;
    if (one || !ps) eye->r_post = eye->r_post_steep = eye->r_post_flat = r;
    if (!ps) return KT_OK;
    if (kt_yml_key_quantity(y, n, w, "posterior_radius_steep", KT_UNIT_LENGTH, radius, &eye->r_post_steep, e) ||
        kt_yml_key_quantity(y, n, w, "posterior_radius_flat", KT_UNIT_LENGTH, radius, &eye->r_post_flat, e))
        return e->code;
    if (eye->r_post_steep > eye->r_post_flat)
        return kt_yml_fail(y, ps, e, "eye.posterior_radius_steep: expected at most posterior_radius_flat (%g mm), got %g mm",
                           eye->r_post_flat, eye->r_post_steep);
    eye->r_post = 2 / (1 / eye->r_post_steep + 1 / eye->r_post_flat);
    return KT_OK;
}

static const char *const DEP_KEYS[] = {"zernike_order", "radius", "taper", "coefficients", NULL};
static const char *const DEP_ANT_KEYS[] = {"asphericity", "zernike_order", "radius", "taper", "coefficients", NULL};

/* A measured surface's departure (eye_depart.h): the anterior base's asphericity (anterior
 * only), a Zernike expansion of zernike_order over the zone of `radius` about the axis, tapered
 * to 0 at `taper` (at most the corneal edge's radius white_to_white / 2; the posterior's end is
 * checked against the geometry when meshing). */
static int parse_departure(kt_yml *y, const yaml_node_t *n, const char *w, kt_eye *eye, kt_eye_departure *d,
                           kt_err *e)
{
    int ant = d == &eye->dep_ant;
    if (kt_yml_check_map(y, n, w, ant ? DEP_ANT_KEYS : DEP_KEYS, e) ||
        kt_yml_key_number(y, n, w, "asphericity", kt_scene_range(-1, 1, 1, 0), &d->conic, e) ||
        !kt_yml_require(y, n, "zernike_order", w, e) ||
        !kt_yml_require(y, n, "radius", w, e) || !kt_yml_require(y, n, "taper", w, e) ||
        !kt_yml_require(y, n, "coefficients", w, e) ||
        kt_yml_key_int(y, n, w, "zernike_order", 2, KT_ZERN_ORDER_MAX, &d->order, e) ||
        kt_yml_key_quantity(y, n, w, "radius", KT_UNIT_LENGTH, kt_scene_range(0.5, 7, 0, 0), &d->radius, e) ||
        kt_yml_key_quantity(y, n, w, "taper", KT_UNIT_LENGTH, kt_scene_range(0.5, 15, 0, 0), &d->taper, e))
        return e->code;
    if (!(d->taper > d->radius && d->taper <= 0.5 * eye->wtw))
        return kt_yml_fail(y, kt_yml_get(y, n, "taper"), e, "%s.taper: expected more than radius (%g mm) and at most "
                           "the corneal edge's radius white_to_white / 2 (%g mm), got %g mm", w, d->radius,
                           0.5 * eye->wtw, d->taper);
    char what[128];
    int nt = kt_zern_nterms(d->order);
    snprintf(what, sizeof what, "%s.coefficients (zernike_order %d)", w, d->order);
    yaml_node_t *c = kt_yml_get(y, n, "coefficients");
    if (kt_yml_check_seq(y, c, what, nt, nt, e)) return e->code;
    for (int j = 0; j < nt; j++)
        if (kt_yml_quantity(y, kt_yml_seq_item(y, c, j), what, KT_UNIT_LENGTH, kt_scene_range(-1, 1, 0, 0), &d->coef[j],
                            e))
            return e->code;
    return KT_OK;
}

int kt_scene_parse_eye(kt_yml *y, const yaml_node_t *n, kt_eye *eye, kt_err *e)
{
    const char *w = "eye";
    if (kt_yml_check_map(y, n, w, EYE_KEYS, e)) return e->code;
    yaml_node_t *one = kt_yml_get(y, n, "anterior_radius");
    if (one && (kt_yml_get(y, n, "anterior_radius_steep") || kt_yml_get(y, n, "anterior_radius_flat")))
        return kt_yml_fail(y, one, e, "eye.anterior_radius: expected either anterior_radius or the steep/flat pair, not both");
    kt_yml_bounds radius = kt_scene_range(1, 50, 0, 0), thick = kt_scene_range(0.05, 5, 0, 0);
    double r = eye->r_ant_steep;
    if (kt_yml_key_quantity(y, n, w, "anterior_radius", KT_UNIT_LENGTH, radius, &r, e)) return e->code;
    eye->r_ant_steep = eye->r_ant_flat = r;
    if (kt_yml_key_quantity(y, n, w, "anterior_radius_steep", KT_UNIT_LENGTH, radius, &eye->r_ant_steep, e) ||
        kt_yml_key_quantity(y, n, w, "anterior_radius_flat", KT_UNIT_LENGTH, radius, &eye->r_ant_flat, e) ||
        kt_yml_key_quantity(y, n, w, "steep_axis", KT_UNIT_ANGLE, kt_scene_range(0, 180, 0, 0), &eye->steep_axis, e) ||
        kt_yml_key_quantity(y, n, w, "central_thickness", KT_UNIT_LENGTH, thick, &eye->t_central, e) ||
        kt_yml_key_quantity(y, n, w, "peripheral_thickness", KT_UNIT_LENGTH, thick, &eye->t_peripheral, e) ||
        kt_scene_parse_wtw(y, n, w, kt_scene_range(2, 30, 0, 0), kt_scene_range(2, 30, 0, 0), &eye->wtw, &eye->wtw_v, e) ||
        kt_yml_key_quantity(y, n, w, "limbus_width", KT_UNIT_LENGTH, kt_scene_range(0, 10, 1, 0), &eye->limbus_width, e) ||
        kt_yml_key_quantity(y, n, w, "sclera_thickness", KT_UNIT_LENGTH, thick, &eye->sclera_thickness, e) ||
        kt_yml_key_quantity(y, n, w, "globe_radius", KT_UNIT_LENGTH, radius, &eye->globe_radius, e) ||
        kt_yml_key_quantity(y, n, w, "extent", KT_UNIT_ANGLE, kt_scene_range(0, 180, 1, 0), &eye->extent, e) ||
        kt_yml_key_quantity(y, n, w, "optical_zone", KT_UNIT_LENGTH, kt_scene_range(0, 30, 1, 0), &eye->optical_zone, e))
        return e->code;
    if (parse_posterior(y, n, eye, e)) return e->code;
    yaml_node_t *fib = kt_yml_get(y, n, "fibres");
    if (fib && (kt_yml_check_map(y, fib, "eye.fibres", FIBRE_KEYS, e) ||
                kt_yml_key_quantity(y, fib, "eye.fibres", "limbal_band", KT_UNIT_LENGTH,
                                    kt_scene_range(0, 5, 1, 0), &eye->fibre_band, e) ||
                kt_yml_key_number(y, fib, "eye.fibres", "limbal_density", kt_scene_range(1, 5, 0, 0),
                                  &eye->fibre_density, e)))
        return e->code;
    if (eye->r_ant_steep > eye->r_ant_flat)
        return kt_yml_fail(y, kt_yml_get(y, n, "anterior_radius_steep"), e,
                           "eye.anterior_radius_steep: expected at most anterior_radius_flat (%g mm), got %g mm",
                           eye->r_ant_flat, eye->r_ant_steep);
    yaml_node_t *v;
    if ((v = kt_yml_get(y, n, "mesh_size")) && parse_sizes(y, v, eye, e)) return e->code;
    if ((v = kt_yml_get(y, n, "incision_rings")) && parse_rings(y, v, eye, e)) return e->code;
    if ((v = kt_yml_get(y, n, "anterior_departure")) &&
        parse_departure(y, v, "eye.anterior_departure", eye, &eye->dep_ant, e))
        return e->code;
    if ((v = kt_yml_get(y, n, "posterior_departure")) &&
        parse_departure(y, v, "eye.posterior_departure", eye, &eye->dep_post, e))
        return e->code;
    return check_eye(y, n, eye, e);
}

