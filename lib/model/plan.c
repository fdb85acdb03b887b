/* plan.c: load and validate an incision plan (man/man5/keratome-plan.5). */
#include "plan.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "eye_geom.h"
#include "plan_tunnel.h"
#include "scene_int.h"
#include "yml.h"

/* Defaults, documented in keratome-plan(5). */
#define DEFAULT_DEGREES_PER_STEP 5.0 /* deg: the default progression */
#define DEFAULT_SNAP_FRACTION 0.25   /* of the shortest edge at a node */
#define DEFAULT_MIN_QUALITY 0.05     /* mean ratio */
#define RING_MATCH 0.005             /* mm: a position diameter names a ring within this */

static const char *const TOP_KEYS[] = {"name", "description", "scene", "incisions", "progression",
                                       "deform", "planar_cut", "snap", "target", "tunnels", NULL};
static const char *const INC_KEYS[] = {"meridian", "arc", "depth", "depth_fraction", "position",
                                       "paired", "arc_opposite", "direction", "progression", NULL};
static const char *const POS_KEYS[] = {"diameter", "surface", NULL};
static const char *const PROG_KEYS[] = {"degrees_per_step", "nodes_per_step", NULL};
static const char *const DEF_KEYS[] = {"surface", "region", "displacement", "force", "components",
                                       "steps", "nodes_per_step", "max_nodes", "order", NULL};
static const char *const PLANAR_KEYS[] = {"point", "normal", "advance", "length", "nodes_per_step",
                                          "pull_force", "pull_surface", NULL};
static const char *const SNAP_KEYS[] = {"fraction", "min_quality", NULL};
static const char *const TARGET_KEYS[] = {"magnitude", "axis", NULL};
static const char *const DIRECTIONS[] = {"cw", "ccw", "centre-out", "center-out", NULL};

static kt_mark mark_of(const yaml_node_t *n)
{
    kt_mark m = {0, 0};
    if (n) {
        m.line = kt_yml_line(n);
        m.col = kt_yml_col(n);
    }
    return m;
}

void kt_plan_where(const kt_plan *p, kt_mark at, char *buf, size_t size)
{
    const char *name = strcmp(p->path, "-") ? p->path : "<stdin>";
    if (at.line > 0) snprintf(buf, size, "%s:%d:%d", name, at.line, at.col);
    else snprintf(buf, size, "%s", name);
}

/* At most one of two keys; returns the one present (or NULL). */
static yaml_node_t *one_of(kt_yml *y, const yaml_node_t *map, const char *what, const char *a,
                           const char *b, int required, kt_err *e)
{
    yaml_node_t *na = kt_yml_get(y, map, a), *nb = kt_yml_get(y, map, b);
    if (na && nb) {
        kt_yml_fail(y, nb, e, "%s: expected either '%s' or '%s', not both", what, a, b);
        return NULL;
    }
    if (!na && !nb && required) {
        kt_yml_fail(y, map, e, "%s: expected '%s' or '%s'", what, a, b);
        return NULL;
    }
    return na ? na : nb;
}

/* A vector of three quantities (dim KT_UNIT_NONE: plain numbers). */
static int vec3(kt_yml *y, const yaml_node_t *n, const char *what, int dim, double lim, double *v,
                kt_err *e)
{
    if (kt_yml_check_seq(y, n, what, 3, 3, e)) return e->code;
    for (int k = 0; k < 3; k++) {
        char w[96];
        snprintf(w, sizeof w, "%s[%d]", what, k);
        if (kt_yml_quantity(y, kt_yml_seq_item(y, n, k), w, dim, kt_scene_range(-lim, lim, 0, 0), &v[k], e)) return e->code;
    }
    return KT_OK;
}

static int unit_vec3(kt_yml *y, const yaml_node_t *n, const char *what, double *v, kt_err *e)
{
    if (vec3(y, n, what, KT_UNIT_NONE, 1e6, v, e)) return e->code;
    double len = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (!(len > 0) || !isfinite(len))
        return kt_yml_fail(y, n, e, "%s: expected a nonzero direction", what);
    for (int k = 0; k < 3; k++) v[k] /= len;
    return KT_OK;
}

static int parse_progression(kt_yml *y, const yaml_node_t *n, const char *what, kt_progression *pr,
                             kt_err *e)
{
    if (kt_yml_check_map(y, n, what, PROG_KEYS, e)) return e->code;
    yaml_node_t *v = one_of(y, n, what, "degrees_per_step", "nodes_per_step", 1, e);
    if (!v) return e->code;
    pr->degrees_per_step = 0;
    pr->nodes_per_step = 0;
    if (kt_yml_key_quantity(y, n, what, "degrees_per_step", KT_UNIT_ANGLE,
                            (kt_yml_bounds){0, 360, 1, 0}, &pr->degrees_per_step, e) ||
        kt_yml_key_int(y, n, what, "nodes_per_step", 1, 100000000, &pr->nodes_per_step, e))
        return e->code;
    pr->at = mark_of(v);
    return KT_OK;
}

/* ---- scene ---- */

static int parse_scene_key(kt_yml *y, const yaml_node_t *root, kt_plan *p, kt_err *e)
{
    yaml_node_t *n = kt_yml_require(y, root, "scene", "the plan", e);
    char rel[1024], dir[1024];
    if (!n || kt_yml_string(y, n, "scene", rel, sizeof rel, e)) return e->code;
    kt_path_dir(p->path, dir, sizeof dir);
    int len = rel[0] == '/' ? snprintf(p->scene_path, sizeof p->scene_path, "%s", rel)
                            : snprintf(p->scene_path, sizeof p->scene_path, "%s/%s", dir, rel);
    if (len >= (int)sizeof p->scene_path) return kt_yml_fail(y, n, e, "scene: path too long");
    FILE *f = fopen(p->scene_path, "r");
    if (!f)
        return kt_yml_fail(y, n, e, "scene: expected an existing scene file, cannot open %s: %s",
                           p->scene_path, strerror(errno));
    fclose(f);
    return kt_scene_load(p->scene_path, &p->scene, e);
}

/* ---- incisions ---- */

/* The ring of the scene named s, or at diameter D (name NULL); -1 if none. */
static int find_ring(const kt_eye *eye, const char *name, double D)
{
    for (int i = 0; i < eye->nring; i++) {
        if (name && strcmp(eye->ring[i].name, name) == 0) return i;
        if (!name && fabs(eye->ring[i].diameter - D) <= RING_MATCH) return i;
    }
    return -1;
}

static void ring_names(const kt_eye *eye, char *buf, size_t size)
{
    buf[0] = '\0';
    for (int i = 0; i < eye->nring; i++) {
        size_t l = strlen(buf);
        snprintf(buf + l, size - l, "%s%s (%g mm)", i ? ", " : "", eye->ring[i].name,
                 eye->ring[i].diameter);
    }
    if (!buf[0]) snprintf(buf, size, "none");
}

/* The ring of incision inc: the one its surface names (by_surface), else the one at its
 * diameter, if any (inc->surface, inc->diameter set). 1 with msg ".surface: ..." or
 * ".diameter: ..." (after the position's name) when it names none or cuts the optical zone. */
static int resolve_ring(const kt_eye *eye, kt_incision *inc, int by_surface, char *msg, size_t size)
{
    if (by_surface) {
        int r = find_ring(eye, inc->surface, 0);
        if (r < 0) {
            char names[600];
            ring_names(eye, names, sizeof names);
            snprintf(msg, size, ".surface: expected an incision ring of the scene (%s), found '%s'", names, inc->surface);
            return 1;
        }
        inc->diameter = eye->ring[r].diameter;
        return 0;
    }
    if (!(inc->diameter > eye->optical_zone)) { /* a cut across the visual axis zone */
        snprintf(msg, size, ".diameter: expected a diameter outside the eye's optical zone (> eye.optical_zone = %g mm; "
                 "limbal relaxing incisions lie in the peripheral cornea), found %g mm", eye->optical_zone, inc->diameter);
        return 1;
    }
    int r = find_ring(eye, NULL, inc->diameter);
    if (r >= 0) snprintf(inc->surface, sizeof inc->surface, "%s", eye->ring[r].name);
    return 0;
}

/* The depth of inc from its length (by_fraction 0) or its fraction of the local thickness:
 * within the tissue and the ring. 1 with msg ".depth: ..." otherwise. */
static int resolve_depth(const kt_eye *eye, kt_incision *inc, int by_fraction, char *msg, size_t size)
{
    double t = kt_eye_thickness(eye, 0.5 * inc->diameter);
    if (!(t > 0)) {
        snprintf(msg, size, ".depth: no corneal thickness at %g mm from the axis", 0.5 * inc->diameter);
        return 1;
    }
    if (!by_fraction && inc->depth >= t) {
        snprintf(msg, size, ".depth: expected less than the local thickness (%.3f mm at diameter %g mm), found %.3f mm",
                 t, inc->diameter, inc->depth);
        return 1;
    }
    if (by_fraction) inc->depth = inc->depth_fraction * t;
    int r = inc->surface[0] ? find_ring(eye, inc->surface, 0) : -1;
    if (r >= 0) {
        const kt_ring *ring = &eye->ring[r];
        double rd = ring->depth_fraction > 0 ? ring->depth_fraction * t : ring->depth;
        if (inc->depth > rd + 1e-6) {
            snprintf(msg, size, ".depth: expected at most the depth of incision-ready surface '%s' (%.3f mm), found %.3f mm",
                     ring->name, rd, inc->depth);
            return 1;
        }
    }
    return 0;
}

static int parse_position(kt_yml *y, const yaml_node_t *n, const char *what, const kt_eye *eye,
                          kt_incision *inc, kt_err *e)
{
    if (kt_yml_check_map(y, n, what, POS_KEYS, e)) return e->code;
    yaml_node_t *v = one_of(y, n, what, "diameter", "surface", 1, e);
    if (!v) return e->code;
    inc->at_position = mark_of(v);
    int by_surface = kt_yml_get(y, n, "surface") != NULL;
    if (by_surface) {
        if (kt_yml_key_string(y, n, what, "surface", inc->surface, sizeof inc->surface, e)) return e->code;
    } else {
        double rmax = eye->wtw + 2 * eye->limbus_width;
        if (kt_yml_key_quantity(y, n, what, "diameter", KT_UNIT_LENGTH, (kt_yml_bounds){0, rmax, 1, 1}, &inc->diameter, e))
            return e->code;
    }
    char msg[800];
    if (resolve_ring(eye, inc, by_surface, msg, sizeof msg)) return kt_yml_fail(y, v, e, "%s%s", what, msg);
    return KT_OK;
}

/* Depth from a length or a fraction of the local thickness; within the tissue and the ring. */
static int parse_depth(kt_yml *y, const yaml_node_t *n, const char *what, const kt_eye *eye,
                       kt_incision *inc, kt_err *e)
{
    char w[96];
    snprintf(w, sizeof w, "%s.depth", what);
    yaml_node_t *v = one_of(y, n, w, "depth", "depth_fraction", 1, e);
    if (!v) return e->code;
    inc->at_depth = mark_of(v);
    int by_fraction = kt_yml_get(y, n, "depth") == NULL;
    if (!by_fraction && kt_yml_key_quantity(y, n, what, "depth", KT_UNIT_LENGTH, kt_scene_range(0, 5, 1, 0), &inc->depth, e))
        return e->code;
    if (by_fraction && kt_yml_key_number(y, n, what, "depth_fraction", (kt_yml_bounds){0, 1, 1, 1}, &inc->depth_fraction, e))
        return e->code;
    char msg[400];
    if (resolve_depth(eye, inc, by_fraction, msg, sizeof msg)) return kt_yml_fail(y, v, e, "%s%s", what, msg);
    return KT_OK;
}

static int parse_incision(kt_yml *y, const yaml_node_t *n, int i, kt_plan *p, kt_err *e)
{
    char what[64];
    snprintf(what, sizeof what, "incisions[%d]", i);
    kt_incision *inc = &p->inc[i];
    memset(inc, 0, sizeof *inc);
    inc->at = mark_of(n);
    inc->prog = p->prog;
    if (kt_yml_check_map(y, n, what, INC_KEYS, e)) return e->code;
    const char *need[] = {"meridian", "arc", "position"};
    for (int k = 0; k < 3; k++)
        if (!kt_yml_require(y, n, need[k], what, e)) return e->code;
    if (kt_yml_key_quantity(y, n, what, "meridian", KT_UNIT_ANGLE, (kt_yml_bounds){0, 360, 0, 1},
                            &inc->meridian, e) ||
        kt_yml_key_quantity(y, n, what, "arc", KT_UNIT_ANGLE, (kt_yml_bounds){0, 360, 1, 0},
                            &inc->arc, e))
        return e->code;
    char w[96];
    snprintf(w, sizeof w, "%s.position", what);
    if (parse_position(y, kt_yml_get(y, n, "position"), w, &p->scene.eye, inc, e) ||
        parse_depth(y, n, what, &p->scene.eye, inc, e))
        return e->code;
    int dir = 0;
    if (kt_yml_key_bool(y, n, what, "paired", &inc->paired, e) ||
        kt_yml_key_choice(y, n, what, "direction", DIRECTIONS, &dir, e))
        return e->code;
    inc->direction = dir == 0 ? KT_BLADE_CW : dir == 1 ? KT_BLADE_CCW : KT_BLADE_CENTRE_OUT;
    if (inc->paired && inc->arc > 180.0)
        return kt_yml_fail(y, kt_yml_get(y, n, "arc"), e, "%s.arc: expected at most 180 deg for a "
                           "paired incision (the two arcs would overlap), found %g deg", what, inc->arc);
    yaml_node_t *ao = kt_yml_get(y, n, "arc_opposite");
    if (ao && !inc->paired)
        return kt_yml_fail(y, ao, e, "%s.arc_opposite: expected only with paired: true", what);
    if (ao && kt_yml_key_quantity(y, n, what, "arc_opposite", KT_UNIT_ANGLE, (kt_yml_bounds){0, 180, 1, 0},
                                  &inc->arc_opposite, e))
        return e->code;
    yaml_node_t *pr = kt_yml_get(y, n, "progression");
    snprintf(w, sizeof w, "%s.progression", what);
    if (pr && parse_progression(y, pr, w, &inc->prog, e)) return e->code;
    return KT_OK;
}

/* The arcs' steps must stay within KT_PLAN_MAX_STEPS: checked before any mesh is read, at the
 * degrees_per_step that sets them (1e-9 deg would otherwise ask for billions of steps). */
static int check_arc_steps(const kt_plan *p, kt_err *e)
{
    double total = kt_plan_tunnel_steps(p); /* the tunnels come first */
    for (int i = 0; i < p->ninc; i++) {
        const kt_incision *inc = &p->inc[i];
        if (!(inc->prog.degrees_per_step > 0)) continue;
        total += ceil(inc->arc / inc->prog.degrees_per_step - 1e-9);
        if (total > KT_PLAN_MAX_STEPS) {
            char at[1100];
            kt_plan_where(p, inc->prog.at.line ? inc->prog.at : inc->at, at, sizeof at);
            return kt_fail(e, KT_EINPUT, "%s: progression.degrees_per_step: expected at most %d "
                           "steps in the plan, incisions[%d] (arc %g deg at %g deg per step) "
                           "brings them to %.0f", at, KT_PLAN_MAX_STEPS, i, inc->arc,
                           inc->prog.degrees_per_step, total);
        }
    }
    return KT_OK;
}

static int parse_incisions(kt_yml *y, const yaml_node_t *n, kt_plan *p, kt_err *e)
{
    if (kt_yml_check_seq(y, n, "incisions", 1, KT_PLAN_MAX, e)) return e->code;
    if (p->scene.model != KT_MODEL_EYE)
        return kt_yml_fail(y, n, e, "incisions: expected an eye scene, %s is not one", p->scene_path);
    p->ninc = kt_yml_seq_len(n);
    for (int i = 0; i < p->ninc; i++)
        if (parse_incision(y, kt_yml_seq_item(y, n, i), i, p, e)) return e->code;
    return check_arc_steps(p, e);
}

/* ---- deformation ---- */

static int parse_components(kt_yml *y, const yaml_node_t *map, const char *what, unsigned *mask,
                            kt_err *e)
{
    char s[8] = "xyz";
    if (kt_yml_key_string(y, map, what, "components", s, sizeof s, e)) return e->code;
    *mask = 0;
    for (const char *c = s; *c; c++) {
        unsigned bit = *c == 'x' ? 1u : *c == 'y' ? 2u : *c == 'z' ? 4u : 0u;
        if (!bit || (*mask & bit))
            return kt_yml_fail(y, kt_yml_get(y, map, "components"), e,
                               "%s.components: expected distinct letters of 'xyz', found '%s'", what, s);
        *mask |= bit;
    }
    return KT_OK;
}

static int parse_deform(kt_yml *y, const yaml_node_t *n, int i, kt_deform *d, kt_err *e)
{
    char what[64];
    snprintf(what, sizeof what, "deform[%d]", i);
    memset(d, 0, sizeof *d);
    d->at = mark_of(n);
    if (kt_yml_check_map(y, n, what, DEF_KEYS, e)) return e->code;
    yaml_node_t *set = one_of(y, n, what, "surface", "region", 1, e);
    if (!set) return e->code;
    d->at_set = mark_of(set);
    d->set_dim = kt_yml_get(y, n, "surface") ? 2 : 3;
    if (kt_yml_string(y, set, what, d->set, sizeof d->set, e)) return e->code;
    yaml_node_t *val = one_of(y, n, what, "displacement", "force", 1, e);
    if (!val) return e->code;
    char w[96];
    if (kt_yml_get(y, n, "displacement")) {
        d->kind = KT_DEFORM_FIX;
        snprintf(w, sizeof w, "%s.displacement", what);
        if (vec3(y, val, w, KT_UNIT_LENGTH, 1e3, d->v, e) || parse_components(y, n, what, &d->mask, e))
            return e->code;
    } else {
        d->kind = KT_DEFORM_FORCE;
        snprintf(w, sizeof w, "%s.force", what);
        if (vec3(y, val, w, KT_UNIT_FORCE, 10, d->v, e)) return e->code;
        if (kt_yml_get(y, n, "components"))
            return kt_yml_fail(y, kt_yml_get(y, n, "components"), e,
                               "%s.components: expected only with a displacement", what);
    }
    if (kt_yml_get(y, n, "steps") && kt_yml_get(y, n, "nodes_per_step")) {
        one_of(y, n, what, "steps", "nodes_per_step", 0, e);
        return e->code;
    }
    d->steps = 1;
    if (kt_yml_key_int(y, n, what, "steps", 1, KT_PLAN_MAX_STEPS, &d->steps, e) ||
        kt_yml_key_int(y, n, what, "nodes_per_step", 1, 100000000, &d->nodes_per_step, e) ||
        kt_yml_key_int(y, n, what, "max_nodes", 1, 100000000, &d->max_nodes, e))
        return e->code;
    yaml_node_t *o = kt_yml_get(y, n, "order");
    snprintf(w, sizeof w, "%s.order", what);
    if (o && vec3(y, o, w, KT_UNIT_NONE, 1e6, d->order, e)) return e->code;
    return KT_OK;
}

static int parse_deforms(kt_yml *y, const yaml_node_t *n, kt_plan *p, kt_err *e)
{
    if (kt_yml_check_seq(y, n, "deform", 1, KT_PLAN_MAX, e)) return e->code;
    p->ndeform = kt_yml_seq_len(n);
    for (int i = 0; i < p->ndeform; i++)
        if (parse_deform(y, kt_yml_seq_item(y, n, i), i, &p->deform[i], e)) return e->code;
    return KT_OK;
}

/* ---- planar cut ---- */

static int parse_planar(kt_yml *y, const yaml_node_t *n, kt_plan *p, kt_err *e)
{
    kt_planar *pl = &p->planar;
    const char *what = "planar_cut";
    pl->set = 1;
    pl->at = mark_of(n);
    if (kt_yml_check_map(y, n, what, PLANAR_KEYS, e)) return e->code;
    yaml_node_t *pt = kt_yml_require(y, n, "point", what, e);
    yaml_node_t *nm = pt ? kt_yml_require(y, n, "normal", what, e) : NULL;
    yaml_node_t *ad = nm ? kt_yml_require(y, n, "advance", what, e) : NULL;
    if (!ad) return e->code;
    if (vec3(y, pt, "planar_cut.point", KT_UNIT_LENGTH, 1e6, pl->point, e) ||
        unit_vec3(y, nm, "planar_cut.normal", pl->normal, e) ||
        unit_vec3(y, ad, "planar_cut.advance", pl->advance, e))
        return e->code;
    /* the blade moves in the plane: drop the advance's normal component */
    double dn = 0, len = 0;
    for (int k = 0; k < 3; k++) dn += pl->advance[k] * pl->normal[k];
    for (int k = 0; k < 3; k++) {
        pl->advance[k] -= dn * pl->normal[k];
        len += pl->advance[k] * pl->advance[k];
    }
    if (sqrt(len) < 1e-6)
        return kt_yml_fail(y, ad, e, "planar_cut.advance: expected a direction in the plane, not "
                           "along its normal");
    for (int k = 0; k < 3; k++) pl->advance[k] /= sqrt(len);
    pl->nodes_per_step = p->prog.nodes_per_step;
    if (kt_yml_key_quantity(y, n, what, "length", KT_UNIT_LENGTH, kt_scene_range(0, 1e6, 1, 0), &pl->length, e) ||
        kt_yml_key_int(y, n, what, "nodes_per_step", 1, 100000000, &pl->nodes_per_step, e) ||
        kt_yml_key_quantity(y, n, what, "pull_force", KT_UNIT_FORCE, kt_scene_range(0, 10, 0, 0), &pl->pull_force, e) ||
        kt_yml_key_string(y, n, what, "pull_surface", pl->pull_surface, sizeof pl->pull_surface, e))
        return e->code;
    pl->at_pull = mark_of(kt_yml_get(y, n, "pull_surface"));
    if (pl->nodes_per_step <= 0)
        return kt_yml_fail(y, n, e, "planar_cut: expected 'nodes_per_step' (here or in progression)");
    return KT_OK;
}

/* ---- the plan ---- */

static int parse_snap(kt_yml *y, const yaml_node_t *n, kt_snap *s, kt_err *e)
{
    if (kt_yml_check_map(y, n, "snap", SNAP_KEYS, e)) return e->code;
    if (kt_yml_key_number(y, n, "snap", "fraction", (kt_yml_bounds){0, 0.5, 0, 0}, &s->fraction, e) ||
        kt_yml_key_number(y, n, "snap", "min_quality", (kt_yml_bounds){0, 1, 0, 1}, &s->min_quality, e))
        return e->code;
    return KT_OK;
}

static int parse_target(kt_yml *y, const yaml_node_t *n, kt_target *t, kt_err *e)
{
    if (kt_yml_check_map(y, n, "target", TARGET_KEYS, e)) return e->code;
    if (!kt_yml_require(y, n, "magnitude", "target", e) || !kt_yml_require(y, n, "axis", "target", e))
        return e->code;
    if (kt_yml_key_quantity(y, n, "target", "magnitude", KT_UNIT_POWER, kt_scene_range(0, 20, 0, 0), &t->magnitude, e) ||
        kt_yml_key_quantity(y, n, "target", "axis", KT_UNIT_ANGLE, (kt_yml_bounds){0, 180, 0, 1},
                            &t->axis, e))
        return e->code;
    t->set = 1;
    return KT_OK;
}

static int parse_plan(kt_yml *y, const yaml_node_t *root, kt_plan *p, kt_err *e)
{
    if (kt_yml_check_map(y, root, "the plan", TOP_KEYS, e)) return e->code;
    yaml_node_t *pr = kt_yml_get(y, root, "progression");
    if (pr && parse_progression(y, pr, "progression", &p->prog, e)) return e->code;
    yaml_node_t *sn = kt_yml_get(y, root, "snap"), *tg = kt_yml_get(y, root, "target");
    if ((sn && parse_snap(y, sn, &p->snap, e)) || (tg && parse_target(y, tg, &p->target, e)))
        return e->code;
    if (parse_scene_key(y, root, p, e)) return e->code;
    yaml_node_t *inc = kt_yml_get(y, root, "incisions"), *def = kt_yml_get(y, root, "deform");
    yaml_node_t *pl = kt_yml_get(y, root, "planar_cut"), *tu = kt_yml_get(y, root, "tunnels");
    if (!inc && !def && !pl && !tu)
        return kt_yml_fail(y, root, e, "the plan: expected 'incisions', 'tunnels', 'planar_cut' or 'deform'");
    if ((def && parse_deforms(y, def, p, e)) || (tu && kt_plan_parse_tunnels(y, tu, p, e)) ||
        (inc && parse_incisions(y, inc, p, e)) || (pl && parse_planar(y, pl, p, e)))
        return e->code;
    return KT_OK;
}

int kt_plan_load(const char *path, kt_plan *p, kt_err *e)
{
    memset(p, 0, sizeof *p);
    if (strlen(path) >= sizeof p->path) return kt_fail(e, KT_EINPUT, "%.200s...: path too long", path);
    snprintf(p->path, sizeof p->path, "%s", path);
    p->prog.degrees_per_step = DEFAULT_DEGREES_PER_STEP;
    p->snap.fraction = DEFAULT_SNAP_FRACTION;
    p->snap.min_quality = DEFAULT_MIN_QUALITY;
    kt_yml y;
    if (kt_yml_load(&y, path, e)) return e->code;
    yaml_node_t *root = kt_yml_root(&y, e);
    if (root) parse_plan(&y, root, p, e);
    kt_yml_free(&y);
    return e->code;
}

/* ---- in memory ---- */

void kt_plan_init(kt_plan *p, const kt_scene *s, const char *name)
{
    memset(p, 0, sizeof *p);
    snprintf(p->path, sizeof p->path, "%s", name);
    snprintf(p->scene_path, sizeof p->scene_path, "%s", s->path);
    p->scene = *s;
    p->prog.degrees_per_step = DEFAULT_DEGREES_PER_STEP;
    p->snap.fraction = DEFAULT_SNAP_FRACTION;
    p->snap.min_quality = DEFAULT_MIN_QUALITY;
}

int kt_plan_add_incision(kt_plan *p, const kt_incision *in, kt_err *e)
{
    if (p->ninc == KT_PLAN_MAX) return kt_fail(e, KT_EINPUT, "%s: expected at most %d incisions", p->path, KT_PLAN_MAX);
    if (p->scene.model != KT_MODEL_EYE) return kt_fail(e, KT_EINPUT, "%s: incisions: expected an eye scene", p->path);
    kt_incision *inc = &p->inc[p->ninc];
    *inc = *in;
    char msg[800];
    if (!(inc->arc > 0 && inc->arc <= (inc->paired ? 180 : 360)) || !(inc->meridian >= 0 && inc->meridian < 360) ||
        !(inc->arc_opposite >= 0 && inc->arc_opposite <= 180) || !(inc->prog.degrees_per_step > 0 || inc->prog.nodes_per_step > 0))
        return kt_fail(e, KT_EINPUT, "%s: incisions[%d]: expected a meridian in [0, 360) deg, an arc in (0, %d] deg, a "
                       "progression", p->path, p->ninc, inc->paired ? 180 : 360);
    if (resolve_ring(&p->scene.eye, inc, inc->surface[0] != '\0', msg, sizeof msg) ||
        resolve_depth(&p->scene.eye, inc, inc->depth_fraction > 0, msg, sizeof msg))
        return kt_fail(e, KT_EINPUT, "%s: incisions[%d]%s", p->path, p->ninc, msg);
    p->ninc++;
    return check_arc_steps(p, e);
}

int kt_plan_add_tunnel(kt_plan *p, const kt_tunnel *t, kt_err *e)
{
    if (p->ntunnel == KT_PLAN_MAX) return kt_fail(e, KT_EINPUT, "%s: expected at most %d tunnels", p->path, KT_PLAN_MAX);
    kt_tunnel *d = &p->tunnel[p->ntunnel];
    *d = *t;
    const char *field;
    char msg[400];
    if (!(d->steps >= 1 && d->steps <= 100)) return kt_fail(e, KT_EINPUT, "%s: tunnels[%d].steps: expected 1 to 100", p->path, p->ntunnel);
    if (kt_tunnel_derive(&p->scene.eye, d, &field, msg, sizeof msg))
        return kt_fail(e, KT_EINPUT, "%s: tunnels[%d].%s: %s", p->path, p->ntunnel, field, msg);
    p->ntunnel++;
    return KT_OK;
}

/* ---- against the mesh ---- */

static void group_names(const kt_mesh *m, int dim, char *buf, size_t size)
{
    buf[0] = '\0';
    for (int i = 0; i < m->ng; i++) {
        if (m->group[i].dim != dim) continue;
        size_t l = strlen(buf);
        snprintf(buf + l, size - l, "%s%s", l ? ", " : "", m->group[i].name);
    }
    if (!buf[0]) snprintf(buf, size, "none");
}

static int need_group(const kt_plan *p, const kt_mesh *m, const char *mesh_name, int dim,
                      const char *name, kt_mark at, kt_err *e)
{
    if (kt_mesh_find_group(m, dim, name)) return KT_OK;
    char where[1100], names[600];
    kt_plan_where(p, at, where, sizeof where);
    group_names(m, dim, names, sizeof names);
    return kt_fail(e, KT_EINPUT, "%s: expected a %s '%s' in mesh %s (it has: %s)", where,
                   dim == 2 ? "surface" : "region", name, mesh_name, names);
}

int kt_plan_check_mesh(const kt_plan *p, const kt_mesh *m, const char *mesh_name, kt_err *e)
{
    for (int i = 0; i < p->ninc; i++) {
        const kt_incision *inc = &p->inc[i];
        if (need_group(p, m, mesh_name, 2, "anterior", inc->at, e)) return e->code;
        if (inc->surface[0] && need_group(p, m, mesh_name, 2, inc->surface, inc->at_position, e))
            return e->code;
    }
    for (int i = 0; i < p->ntunnel; i++)
        if (need_group(p, m, mesh_name, 2, "anterior", p->tunnel[i].at, e)) return e->code;
    for (int i = 0; i < p->ndeform; i++) {
        const kt_deform *d = &p->deform[i];
        if (need_group(p, m, mesh_name, d->set_dim, d->set, d->at_set, e)) return e->code;
    }
    if (p->planar.set && p->planar.pull_surface[0] &&
        need_group(p, m, mesh_name, 2, p->planar.pull_surface, p->planar.at_pull, e))
        return e->code;
    return KT_OK;
}
