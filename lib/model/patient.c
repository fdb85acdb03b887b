/* patient.c: load and validate a patient file (man/man5/keratome-patient.5). Every default is
 * documented there with its source; every check runs before any meshing. */
#include "patient.h"
#include "units.h"

#include <ctype.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "clearance.h"
#include "eye.h"
#include "scene_int.h" /* the eye defaults of keratome-scene(5) */
#include "yml.h"

/* The patient file's range of a pachymetry, mm (central_thickness, thickness_at_zone, and every
 * cell of a Pentacam pachymetry map). */
#define PACHY_LO 0.3
#define PACHY_HI 1.2

static const char *const TOP_KEYS[] = {"name", "id", "date_of_birth", "surgeon", "description", "eye", "age", "iop",
                                       "cornea", "main_incision", "side_port", "target", "constraints", NULL};
static const char *const CORNEA_KEYS[] = {"keratometry", "pentacam", "posterior", "central_thickness",
                                          "thickness_at_zone", "white_to_white", NULL};
static const char *const K_KEYS[] = {"k_steep", "k_flat", "steep_axis", NULL};
static const char *const PENTA_KEYS[] = {"front", "back", "pachymetry", NULL};
static const char *const MAIN_KEYS[] = {"meridian", "width", "kind", "sia", NULL};
static const char *const SIA_KEYS[] = {"magnitude", "axis", NULL};
static const char *const SIDE_KEYS[] = {"meridian", "width", NULL};
static const char *const TARGET_KEYS[] = {"astigmatism", "residual", NULL};
static const char *const CONS_KEYS[] = {"incisions", "max_arc", "zone", "depth", "clearance", NULL};
static const char *const EYES[] = {"OD", "OS", NULL};
static const char *const KINDS[] = {"clear_corneal", "limbal", NULL};
static const char *const TARGETS[] = {"total_corneal", "keratometric", NULL};
static const char *const ARCS[] = {"either", "single", "paired", NULL};

/* The optical zone a patient's arcs must stay outside, and the band left between the zone and
 * the corneal edge: keratome-scene(5) defaults (eye.optical_zone, eye.limbus_width). */
#define PATIENT_OPTICAL_ZONE 7.0
#define PATIENT_LIMBUS 1.0

double kt_patient_k(double r) { return KT_N_KERATO / r; }
double kt_patient_post_k(double r) { return -KT_PATIENT_N_POST / r; }
void kt_patient_default_posterior(const kt_toric *ant, kt_toric *post)
{
    double c = kt_patient_k(ant->r_steep) - kt_patient_k(ant->r_flat), a = fmod(ant->axis, 180), cyl;
    if (a < 0) a += 180;
    if (a >= 60 && a <= 120) cyl = KT_PATIENT_POST_WTR_SLOPE * c + KT_PATIENT_POST_WTR_D;
    else if (a <= 30 || a >= 150) cyl = KT_PATIENT_POST_ATR_D;
    else cyl = KT_PATIENT_POST_OBL_SLOPE * c + KT_PATIENT_POST_OBL_D;
    double kp = kt_patient_post_k(KT_PATIENT_POST_RADIUS);
    post->r_steep = -KT_PATIENT_N_POST / (kp - cyl / 2);
    post->r_flat = -KT_PATIENT_N_POST / (kp + cyl / 2);
    post->axis = KT_PATIENT_POST_AXIS;
    post->conic = NAN;
    post->source = KT_SOURCE_DEFAULT;
}

double kt_patient_age_factor(double age)
{
    return 1 + KT_UQ_AGE_SLOPE_VALUE * (age - KT_UQ_AGE_PIVOT) / 10; /* scene.h: one copy */
}

static const struct { const char *name; double od, os; } SITES[] = {
    {"temporal", 180, 0},         {"nasal", 0, 180},          {"superior", 90, 90},
    {"inferior", 270, 270},       {"superotemporal", 135, 45}, {"superonasal", 45, 135},
    {"inferotemporal", 225, 315}, {"inferonasal", 315, 225}};

double kt_patient_site(int eye, const char *name)
{
    for (size_t i = 0; i < sizeof SITES / sizeof SITES[0]; i++)
        if (strcmp(SITES[i].name, name) == 0) return eye == KT_EYE_OS ? SITES[i].os : SITES[i].od;
    return NAN;
}

static kt_yml_bounds range(double lo, double hi, int lo_open, int hi_open)
{
    kt_yml_bounds b = {lo, hi, lo_open, hi_open};
    return b;
}

static void defaults(kt_patient *p)
{
    memset(p, 0, sizeof *p);
    p->iop = KT_PATIENT_IOP_MMHG * KT_MMHG_MPA;
    p->ant.conic = p->post.conic = NAN;
    /* the posterior of an anterior without cylinder until the anterior is known (parse) */
    kt_toric no_cyl = {KT_PATIENT_POST_RADIUS, KT_PATIENT_POST_RADIUS, 0, NAN, KT_SOURCE_DEFAULT};
    kt_patient_default_posterior(&no_cyl, &p->post);
    p->t_central = 0.54; /* Doughty & Zaman 2000 */
    p->t_zone = NAN;
    p->wtw = 11.7;       /* Rufer et al. 2005 */
    p->wtw_v = 11.7 - KT_EYE_WTW_DIFF; /* keratome-patient(5), white_to_white */
    p->main_simulate = 1;
    p->target_residual = 0.5; /* Villegas et al. 2014 */
    p->max_arc = 90;
    p->zone = NAN;            /* 10.5 mm (Nichamin 2006), inside the corneal edge: check() */
    p->clearance = KT_CLEARANCE_DEG;
    p->depth_fraction = KT_PATIENT_DEPTH_MAX;
}

/* An angle of an axis: [0, 180], 180 taken as 0. */
static int axis_field(kt_yml *y, const yaml_node_t *map, const char *what, const char *key, double *v,
                      kt_err *e)
{
    if (kt_yml_key_quantity(y, map, what, key, KT_UNIT_ANGLE, range(0, 180, 0, 0), v, e)) return e->code;
    if (*v >= 180) *v = 0;
    return KT_OK;
}

/* keratometry {k_steep, k_flat, steep_axis}: sign -1 for the posterior surface (negative
 * powers, steep = larger magnitude), +1 for the anterior (keratometric index). */
static int parse_k(kt_yml *y, const yaml_node_t *n, const char *what, int sign, kt_toric *t, kt_err *e)
{
    if (kt_yml_check_map(y, n, what, K_KEYS, e)) return e->code;
    for (int i = 0; K_KEYS[i]; i++)
        if (!kt_yml_require(y, n, K_KEYS[i], what, e)) return e->code;
    kt_yml_bounds b = sign > 0 ? range(KT_PATIENT_K_MIN, KT_PATIENT_K_MAX, 0, 0) : range(-15, -2, 0, 0);
    double ks, kf;
    if (kt_yml_key_quantity(y, n, what, "k_steep", KT_UNIT_POWER, b, &ks, e) ||
        kt_yml_key_quantity(y, n, what, "k_flat", KT_UNIT_POWER, b, &kf, e) ||
        axis_field(y, n, what, "steep_axis", &t->axis, e))
        return e->code;
    if (fabs(kf) > fabs(ks))
        return kt_yml_fail(y, kt_yml_get(y, n, "k_flat"), e,
                           "%s.k_flat: expected at most k_steep in magnitude (%g D), got %g D", what, ks, kf);
    t->r_steep = sign > 0 ? KT_N_KERATO / ks : -KT_PATIENT_N_POST / ks;
    t->r_flat = sign > 0 ? KT_N_KERATO / kf : -KT_PATIENT_N_POST / kf;
    t->conic = NAN;
    t->source = KT_SOURCE_KERATOMETRY;
    return KT_OK;
}

/* A file path relative to the patient's folder; it must be readable. */
static int path_field(kt_yml *y, const yaml_node_t *map, const char *what, const char *key, const char *dir,
                      char *out, size_t size, kt_err *e)
{
    yaml_node_t *n = kt_yml_get(y, map, key);
    if (!n) return KT_OK;
    char f[96], rel[1024];
    snprintf(f, sizeof f, "%s.%s", what, key);
    if (kt_yml_string(y, n, f, rel, sizeof rel, e)) return e->code;
    int len = rel[0] == '/' ? snprintf(out, size, "%s", rel) : snprintf(out, size, "%s/%s", dir, rel);
    if (len >= (int)size) return kt_yml_fail(y, n, e, "%s: expected a shorter path", f);
    FILE *probe = fopen(out, "rb");
    if (!probe) return kt_yml_fail(y, n, e, "%s: expected an existing, readable file, '%s' cannot be opened", f, out);
    fclose(probe);
    return KT_OK;
}

static int parse_cornea(kt_yml *y, const yaml_node_t *n, kt_patient *p, kt_err *e)
{
    const char *w = "cornea";
    if (kt_yml_check_map(y, n, w, CORNEA_KEYS, e)) return e->code;
    yaml_node_t *k = kt_yml_get(y, n, "keratometry"), *pc = kt_yml_get(y, n, "pentacam");
    if (!k == !pc)
        return kt_yml_fail(y, k ? k : n, e, "cornea: expected exactly one of 'keratometry' or 'pentacam'");
    if (k && parse_k(y, k, "cornea.keratometry", 1, &p->ant, e)) return e->code;
    if (pc) {
        const char *wp = "cornea.pentacam";
        if (kt_yml_check_map(y, pc, wp, PENTA_KEYS, e) || !kt_yml_require(y, pc, "front", wp, e) ||
            path_field(y, pc, wp, "front", p->dir, p->pentacam_front, sizeof p->pentacam_front, e) ||
            path_field(y, pc, wp, "back", p->dir, p->pentacam_back, sizeof p->pentacam_back, e) ||
            path_field(y, pc, wp, "pachymetry", p->dir, p->pentacam_pachy, sizeof p->pentacam_pachy, e))
            return e->code;
        p->ant.source = KT_SOURCE_PENTACAM;
    }
    yaml_node_t *post = kt_yml_get(y, n, "posterior");
    if (post && p->pentacam_back[0])
        return kt_yml_fail(y, post, e, "cornea.posterior: expected either it or cornea.pentacam.back, not both");
    if (post && parse_k(y, post, "cornea.posterior", -1, &p->post, e)) return e->code;
    if (p->pentacam_back[0]) p->post.source = KT_SOURCE_PENTACAM;
    if (!post && k) kt_patient_default_posterior(&p->ant, &p->post); /* follows the anterior */
    yaml_node_t *tc = kt_yml_get(y, n, "central_thickness");
    if (tc && p->pentacam_pachy[0])
        return kt_yml_fail(y, tc, e, "cornea.central_thickness: expected either it or cornea.pentacam.pachymetry, not both");
    kt_yml_bounds thick = range(PACHY_LO, PACHY_HI, 0, 0);
    if (kt_yml_key_quantity(y, n, w, "central_thickness", KT_UNIT_LENGTH, thick, &p->t_central, e) ||
        kt_yml_key_quantity(y, n, w, "thickness_at_zone", KT_UNIT_LENGTH, thick, &p->t_zone, e) ||
        kt_scene_parse_wtw(y, n, w, range(9, 14, 0, 0), range(8, 14, 0, 0), &p->wtw, &p->wtw_v, e))
        return e->code;
    return KT_OK;
}

/* A site: a name (temporal, nasal, ...) or an angle in [0, 360) deg. */
static int site_field(kt_yml *y, const yaml_node_t *m, const char *what, int eye, double *v, kt_err *e)
{
    char text[64], expl[160];
    if (kt_yml_string(y, m, what, text, sizeof text, e)) return e->code;
    *v = kt_patient_site(eye, text);
    snprintf(expl, sizeof expl, "%s (a site: temporal, nasal, superior, inferior, superotemporal, ...; or an angle)", what);
    if (isnan(*v) && kt_yml_quantity(y, m, expl, KT_UNIT_ANGLE, range(0, 360, 0, 1), v, e)) return e->code;
    return KT_OK;
}

/* side_port {meridian, width}: a paracentesis, for the arcs' clearance only (not cut). */
static int parse_side(kt_yml *y, const yaml_node_t *n, kt_patient *p, kt_err *e)
{
    const char *w = "side_port";
    yaml_node_t *m;
    if (kt_yml_check_map(y, n, w, SIDE_KEYS, e) || !(m = kt_yml_require(y, n, "meridian", w, e)) ||
        !kt_yml_require(y, n, "width", w, e) || site_field(y, m, "side_port.meridian", p->eye, &p->side_meridian, e) ||
        kt_yml_key_quantity(y, n, w, "width", KT_UNIT_LENGTH, range(0.3, 3, 0, 0), &p->side_width, e))
        return e->code;
    p->side_present = 1;
    return KT_OK;
}

static int parse_main(kt_yml *y, const yaml_node_t *n, kt_patient *p, kt_err *e)
{
    const char *w = "main_incision";
    if (kt_yml_check_map(y, n, w, MAIN_KEYS, e)) return e->code;
    yaml_node_t *m = kt_yml_require(y, n, "meridian", w, e);
    if (!m || !kt_yml_require(y, n, "width", w, e)) return e->code;
    if (site_field(y, m, "main_incision.meridian", p->eye, &p->main_meridian, e)) return e->code;
    if (kt_yml_key_quantity(y, n, w, "width", KT_UNIT_LENGTH, range(1, 6, 0, 0), &p->main_width, e) ||
        kt_yml_key_choice(y, n, w, "kind", KINDS, &p->main_kind, e))
        return e->code;
    yaml_node_t *sia = kt_yml_get(y, n, "sia");
    if (sia && sia->type == YAML_SCALAR_NODE) {
        static const char *const SIM[] = {"simulate", NULL};
        int idx;
        if (kt_yml_choice(y, sia, "main_incision.sia (or a mapping {magnitude, axis})", SIM, &idx, e))
            return e->code;
    } else if (sia) {
        const char *ws = "main_incision.sia";
        if (kt_yml_check_map(y, sia, ws, SIA_KEYS, e) || !kt_yml_require(y, sia, "magnitude", ws, e) ||
            !kt_yml_require(y, sia, "axis", ws, e) ||
            kt_yml_key_quantity(y, sia, ws, "magnitude", KT_UNIT_POWER, range(0, KT_PATIENT_SIA_MAX, 0, 0), &p->main_sia, e) ||
            axis_field(y, sia, ws, "axis", &p->main_sia_axis, e))
            return e->code;
        p->main_simulate = 0;
    }
    p->main_present = 1;
    return KT_OK;
}

/* constraints.depth: "90 %" of the pachymetry at the zone, or a length ("600 um"). */
static int parse_depth(kt_yml *y, const yaml_node_t *n, kt_patient *p, kt_err *e)
{
    const char *what = "constraints.depth";
    char text[64];
    if (kt_yml_string(y, n, what, text, sizeof text, e)) return e->code;
    size_t len = strlen(text);
    while (len && isspace((unsigned char)text[len - 1])) len--;
    if (len && text[len - 1] == '%') {
        text[len - 1] = '\0';
        double v;
        if (kt_parse_double(text, &v) != 0) {
            char *end;
            v = strtod(text, &end);
            while (*end && isspace((unsigned char)*end)) end++;
            if (end == text || *end) return kt_yml_fail(y, n, e, "%s: expected a percentage like '90 %%'", what);
        }
        if (!(v > 0 && v <= 100 * KT_PATIENT_DEPTH_MAX))
            return kt_yml_fail(y, n, e, "%s: expected a percentage of the pachymetry in (0, %g] %%, got %g %%", what,
                               100 * KT_PATIENT_DEPTH_MAX, v);
        p->depth_fraction = v / 100, p->depth = 0;
        return KT_OK;
    }
    if (kt_yml_quantity(y, n, "constraints.depth (a percentage like '90 %' or a length)", KT_UNIT_LENGTH,
                        KT_YML_POSITIVE, &p->depth, e))
        return e->code;
    p->depth_fraction = 0;
    return KT_OK;
}

static int parse_rest(kt_yml *y, const yaml_node_t *root, kt_patient *p, kt_err *e)
{
    yaml_node_t *n;
    if ((n = kt_yml_get(y, root, "main_incision")) && parse_main(y, n, p, e)) return e->code;
    if ((n = kt_yml_get(y, root, "side_port")) && parse_side(y, n, p, e)) return e->code;
    if ((n = kt_yml_get(y, root, "target"))) {
        if (kt_yml_check_map(y, n, "target", TARGET_KEYS, e) ||
            kt_yml_key_choice(y, n, "target", "astigmatism", TARGETS, &p->target_kind, e) ||
            kt_yml_key_quantity(y, n, "target", "residual", KT_UNIT_POWER, range(0, 3, 0, 0), &p->target_residual, e))
            return e->code;
    }
    if ((n = kt_yml_get(y, root, "constraints"))) {
        const char *w = "constraints";
        if (kt_yml_check_map(y, n, w, CONS_KEYS, e) || kt_yml_key_choice(y, n, w, "incisions", ARCS, &p->arcs, e) ||
            kt_yml_key_quantity(y, n, w, "max_arc", KT_UNIT_ANGLE, range(10, 120, 0, 0), &p->max_arc, e) ||
            kt_yml_key_quantity(y, n, w, "zone", KT_UNIT_LENGTH, KT_YML_POSITIVE, &p->zone, e) ||
            kt_yml_key_quantity(y, n, w, "clearance", KT_UNIT_ANGLE, range(0, 90, 0, 0), &p->clearance, e))
            return e->code;
        yaml_node_t *d = kt_yml_get(y, n, "depth");
        if (d && parse_depth(y, d, p, e)) return e->code;
    }
    return KT_OK;
}

/* The default eye with the patient's cornea, thickness and white-to-white. */
static void model_eye(const kt_patient *p, kt_eye *eye)
{
    kt_scene_eye_defaults(eye);
    eye->r_ant_steep = p->ant.source == KT_SOURCE_KERATOMETRY ? p->ant.r_steep : eye->r_ant_steep;
    eye->r_ant_flat = p->ant.source == KT_SOURCE_KERATOMETRY ? p->ant.r_flat : eye->r_ant_flat;
    eye->r_post = 2 / (1 / p->post.r_steep + 1 / p->post.r_flat);
    eye->t_central = p->t_central;
    eye->wtw = p->wtw;
    eye->wtw_v = p->wtw_v;
}

double kt_patient_model_zone_thickness(const kt_patient *p)
{
    kt_eye eye;
    model_eye(p, &eye);
    return kt_eye_thickness(&eye, p->zone / 2);
}

double kt_patient_zone_chord(const kt_patient *p, double centre, double arc)
{
    kt_eye eye;
    model_eye(p, &eye);
    return kt_eye_arc_chord(&eye, p->zone, centre - arc / 2, centre + arc / 2);
}

/* Consistency: the zone between the optical zone and the corneal edge, the depth within the
 * pachymetry at the zone. */
static int check(kt_yml *y, const yaml_node_t *root, kt_patient *p, kt_err *e)
{
    yaml_node_t *cons = kt_yml_get(y, root, "constraints"), *cornea = kt_yml_get(y, root, "cornea");
    yaml_node_t *zn = kt_yml_get(y, cons, "zone");
    double clear = p->wtw - PATIENT_LIMBUS;
    if (isnan(p->zone)) p->zone = fmin(KT_PATIENT_ZONE, clear); /* not given: the default, or the
                                                                    widest the cornea allows */
    if (p->zone <= PATIENT_OPTICAL_ZONE || p->zone > clear)
        return kt_yml_fail(y, zn ? zn : root, e,
                           "constraints.zone: expected a diameter outside the optical zone (> %g mm) and inside "
                           "white_to_white - limbus (<= %g mm), got %g mm",
                           PATIENT_OPTICAL_ZONE, clear, p->zone);
    kt_eye eye;
    model_eye(p, &eye);
    double vmin = kt_eye_wtw_v_min(&eye);
    if (p->wtw_v < vmin) {
        yaml_node_t *w = kt_yml_get(y, cornea, "white_to_white");
        if (w && kt_yml_get(y, w, "vertical")) w = kt_yml_get(y, w, "vertical");
        return kt_yml_fail(y, w ? w : root, e, "cornea.white_to_white.vertical: expected at least %g mm (the horizontal "
                           "%g mm less what the cornea between the optical zone and the zone's ring can take), got %g mm",
                           vmin, p->wtw, p->wtw_v);
    }
    if (!isnan(p->t_zone) && p->t_zone < p->t_central) {
        yaml_node_t *t = kt_yml_get(y, cornea, "thickness_at_zone");
        return kt_yml_fail(y, t, e, "cornea.thickness_at_zone: expected at least central_thickness (%g um), got %g um",
                           1000 * p->t_central, 1000 * p->t_zone);
    }
    if (p->depth > 0) {
        /* Without a measured pachymetry at the zone, the default eye's profile there. */
        double t = isnan(p->t_zone) ? kt_patient_model_zone_thickness(p) : p->t_zone;
        if (p->depth > KT_PATIENT_DEPTH_MAX * t)
            return kt_yml_fail(y, kt_yml_get(y, cons, "depth"), e,
                               "constraints.depth: expected at most %g%% of the pachymetry at the zone (%g um), got %g um",
                               100 * KT_PATIENT_DEPTH_MAX, 1000 * KT_PATIENT_DEPTH_MAX * t, 1000 * p->depth);
    }
    return KT_OK;
}

static const char *const FIELD_NAMES[KT_PF_N] = {
    "patient", "eye", "age", "cornea", "cornea.keratometry", "cornea.posterior", "cornea.pentacam.front",
    "cornea.pentacam.back", "cornea.pentacam.pachymetry", "cornea.central_thickness", "cornea.thickness_at_zone",
    "cornea.white_to_white", "main_incision", "constraints.zone", "constraints.depth"};

/* The positions of the fields a later refusal may name. */
static void record_marks(kt_yml *y, const yaml_node_t *root, kt_patient *p)
{
    yaml_node_t *c = kt_yml_get(y, root, "cornea"), *pc = kt_yml_get(y, c, "pentacam"),
                *cons = kt_yml_get(y, root, "constraints");
    const yaml_node_t *n[KT_PF_N] = {
        root, kt_yml_get(y, root, "eye"), kt_yml_get(y, root, "age"), c, kt_yml_get(y, c, "keratometry"),
        kt_yml_get(y, c, "posterior"), kt_yml_get(y, pc, "front"), kt_yml_get(y, pc, "back"),
        kt_yml_get(y, pc, "pachymetry"), kt_yml_get(y, c, "central_thickness"), kt_yml_get(y, c, "thickness_at_zone"),
        kt_yml_get(y, c, "white_to_white"), kt_yml_get(y, root, "main_incision"), kt_yml_get(y, cons, "zone"),
        kt_yml_get(y, cons, "depth")};
    for (int i = 0; i < KT_PF_N; i++)
        if (n[i]) p->mark[i][0] = kt_yml_line(n[i]), p->mark[i][1] = kt_yml_col(n[i]);
}

int kt_patient_fail(const kt_patient *p, kt_err *e, int field, int fallback, const char *fmt, ...)
{
    int at = p->mark[field][0] ? field : fallback >= 0 && p->mark[fallback][0] ? fallback : -1;
    char msg[700];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    return kt_fail(e, KT_EINPUT, "%s:%d:%d: %s: %s", p->path, at >= 0 ? p->mark[at][0] : 1, at >= 0 ? p->mark[at][1] : 1,
                   FIELD_NAMES[field], msg);
}

int kt_patient_read_map(const kt_patient *p, int field, kt_pentacam_map *m, kt_err *e)
{
    const char *path = field == KT_PF_FRONT ? p->pentacam_front : field == KT_PF_BACK ? p->pentacam_back : p->pentacam_pachy;
    int pachy = field == KT_PF_PACHYMETRY, kind = pachy ? KT_PENTACAM_PACHYMETRY : KT_PENTACAM_ELEVATION;
    char whose[1200];
    snprintf(whose, sizeof whose, " (the patient file's range for a pachymetry, %s:%d:%d)", p->path, p->mark[field][0],
             p->mark[field][1]);
    int rc = pachy ? kt_pentacam_read_range(path, kind, 1000 * PACHY_LO, 1000 * PACHY_HI, whose, m, e)
                   : kt_pentacam_read(path, kind, m, e);
    if (rc) return rc;
    static const char *const EYE[] = {"", "OD", "OS"};
    const char *want = p->eye == KT_EYE_OS ? "OS" : "OD";
    if (m->eye && strcmp(EYE[m->eye], want) != 0)
        rc = kt_fail(e, KT_EINPUT, "%s:%d:%d: expected an export of the patient's eye %s (%s:%d:%d: eye), the export's "
                     "header says %s", path, m->eye_line, m->eye_col, want, p->path, p->mark[KT_PF_EYE][0],
                     p->mark[KT_PF_EYE][1], EYE[m->eye]);
    int want_surface = field == KT_PF_FRONT ? KT_PENTACAM_FRONT : field == KT_PF_BACK ? KT_PENTACAM_BACK : 0;
    static const char *const KIND[] = {"", "an elevation", "a pachymetry"}, *const SURF[] = {"", "front", "back"};
    if (!rc && m->head_kind && (m->head_kind != kind + 1 || (want_surface && m->surface && m->surface != want_surface)))
        rc = kt_fail(e, KT_EINPUT, "%s:%d:%d: expected %s map%s%s (%s:%d:%d: %s), the export's header says %s%s%s", path,
                     m->kind_line, m->kind_col, KIND[kind + 1], want_surface ? " of the " : "", SURF[want_surface],
                     p->path, p->mark[field][0], p->mark[field][1], FIELD_NAMES[field], KIND[m->head_kind],
                     m->surface ? " of the " : "", SURF[m->surface]);
    if (!rc && m->unit[0] && strcmp(m->unit, pachy ? "um" : "mm") != 0)
        rc = kt_fail(e, KT_EINPUT, "%s:%d:%d: expected %s in %s (keratome-patient(5), THE PENTACAM EXPORT), the export's "
                     "header says %s", path, m->unit_line, m->unit_col, pachy ? "a pachymetry" : "elevations",
                     pachy ? "um" : "mm", m->unit);
    if (rc) kt_pentacam_free(m);
    return rc;
}

int kt_patient_check_fit(const kt_patient *p, int post_fit, int pachy_fit, kt_err *e)
{
    double ks = kt_patient_k(p->ant.r_steep), kf = kt_patient_k(p->ant.r_flat);
    if (!(ks >= 20 && ks <= 70 && kf >= 20 && kf <= 70))
        return kt_patient_fail(p, e, KT_PF_FRONT, -1, "the fit of %s gives K %.2f / %.2f D: expected keratometry within "
                               "[20, 70] D (the patient file's range)", p->pentacam_front, ks, kf);
    double ps = kt_patient_post_k(p->post.r_steep), pf = kt_patient_post_k(p->post.r_flat);
    if (post_fit && !(ps >= -15 && ps <= -2 && pf >= -15 && pf <= -2))
        return kt_patient_fail(p, e, KT_PF_BACK, -1, "the fit of %s gives a posterior power %.2f / %.2f D: expected "
                               "within [-15, -2] D (the patient file's range)", p->pentacam_back, ps, pf);
    double ra = 2 / (1 / p->ant.r_steep + 1 / p->ant.r_flat), rp = 2 / (1 / p->post.r_steep + 1 / p->post.r_flat);
    if (post_fit && !(rp < ra))
        return kt_patient_fail(p, e, KT_PF_BACK, -1, "the fit of %s gives a mean radius of %.3f mm, the front map's "
                               "(%s) %.3f mm: expected the back surface more curved than the front (swapped maps?)",
                               p->pentacam_back, rp, p->pentacam_front, ra);
    if (pachy_fit && !(p->t_central >= PACHY_LO && p->t_central <= PACHY_HI))
        return kt_patient_fail(p, e, KT_PF_PACHYMETRY, -1, "the fit of %s gives a central pachymetry of %.0f um: "
                               "expected within [%g, %g] um (the patient file's range)", p->pentacam_pachy,
                               1000 * p->t_central, 1000 * PACHY_LO, 1000 * PACHY_HI);
    return KT_OK;
}

/* date_of_birth: an ISO 8601 calendar date YYYY-MM-DD, a real day of a year 1900-2100. */
static int parse_dob(kt_yml *y, const yaml_node_t *n, kt_patient *p, kt_err *e)
{
    static const int mdays[12] = {31, 29, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
    char t[KT_NAME_MAX];
    if (kt_yml_string(y, n, "date_of_birth", t, sizeof t, e)) return e->code;
    int yr = 0, mo = 0, dy = 0, len = 0;
    int ok = strlen(t) == 10 && sscanf(t, "%4d-%2d-%2d%n", &yr, &mo, &dy, &len) == 3 && len == 10 && t[4] == '-' &&
             t[7] == '-' && isdigit((unsigned char)t[5]) && isdigit((unsigned char)t[8]) && yr >= 1900 && yr <= 2100 &&
             mo >= 1 && mo <= 12 && dy >= 1 && dy <= mdays[mo - 1] &&
             !(mo == 2 && dy == 29 && (yr % 4 || (yr % 100 == 0 && yr % 400)));
    if (!ok) return kt_yml_fail(y, n, e, "date_of_birth: expected a date YYYY-MM-DD (a day of 1900-2100), got '%s'", t);
    memcpy(p->dob, t, 11);
    return KT_OK;
}

/* The optional identification: id, date_of_birth, surgeon (strings; shown on plan.html). */
static int parse_ident(kt_yml *y, const yaml_node_t *root, kt_patient *p, kt_err *e)
{
    yaml_node_t *n = kt_yml_get(y, root, "id");
    if (n && kt_yml_string(y, n, "id", p->id, sizeof p->id, e)) return e->code;
    n = kt_yml_get(y, root, "surgeon");
    if (n && kt_yml_string(y, n, "surgeon", p->surgeon, sizeof p->surgeon, e)) return e->code;
    n = kt_yml_get(y, root, "date_of_birth");
    return n ? parse_dob(y, n, p, e) : KT_OK;
}

static int parse(kt_yml *y, kt_patient *p, kt_err *e)
{
    yaml_node_t *root = kt_yml_root(y, e);
    if (!root || kt_yml_check_map(y, root, "patient", TOP_KEYS, e)) return e->code;
    record_marks(y, root, p);
    yaml_node_t *n = kt_yml_get(y, root, "name");
    if ((n && kt_yml_string(y, n, "name", p->name, sizeof p->name, e)) || parse_ident(y, root, p, e)) return e->code;
    if (!kt_yml_require(y, root, "eye", "patient", e) || !kt_yml_require(y, root, "age", "patient", e) ||
        !kt_yml_require(y, root, "cornea", "patient", e))
        return e->code;
    if (kt_yml_key_choice(y, root, "patient", "eye", EYES, &p->eye, e) ||
        kt_yml_key_quantity(y, root, "patient", "age", KT_UNIT_NONE, range(KT_PATIENT_AGE_MIN, KT_PATIENT_AGE_MAX, 0, 0), &p->age, e) ||
        kt_yml_key_quantity(y, root, "patient", "iop", KT_UNIT_PRESSURE, range(5 * KT_MMHG_MPA, 60 * KT_MMHG_MPA, 0, 0), &p->iop, e) ||
        parse_cornea(y, kt_yml_get(y, root, "cornea"), p, e) || parse_rest(y, root, p, e))
        return e->code;
    return check(y, root, p, e);
}

int kt_patient_load(const char *path, kt_patient *p, kt_err *e)
{
    defaults(p);
    if (strlen(path) >= sizeof p->path) return kt_fail(e, KT_EINPUT, "%.200s...: path too long", path);
    strcpy(p->path, path);
    kt_path_dir(path, p->dir, sizeof p->dir);
    kt_path_stem(path, p->name, sizeof p->name);
    kt_yml y;
    if (kt_yml_load(&y, path, e)) return e->code;
    int rc = parse(&y, p, e);
    kt_yml_free(&y);
    return rc;
}
