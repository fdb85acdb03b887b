/* scene.c: load and validate a scene YAML file (see man/man5/keratome-scene.5). */
#include "scene.h"
#include "units.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "eye.h"
#include "scene_int.h"
#include "yml.h"


static const char *const TOP_KEYS[] = {"name", "description", "model", "order", "ordering", "eye",
                                       "box", "surface", "image", "materials", "loads",
                                       "fixation", "uncertainty", "wound", NULL};
static const char *const MODELS[] = {"eye", "box", "surface", "image", NULL};
static const char *const ORDERINGS[] = {"amd", "metis", "constrained", "natural", "metis-last", NULL};
static const char *const FACES[] = {"xmin", "xmax", "ymin", "ymax", "zmin", "zmax", "none", NULL};
static const char *const AXES[] = {"x", "y", "z", NULL};

/* Surface groups each model writes (the eye adds its incision rings, CGAL models 'below'). */
const char *const kt_scene_eye_surfaces[] = {"anterior", "inner", "fixed", "outer", NULL};
static const char *const BOX_SURFACES[] = {"xmin", "xmax", "ymin", "ymax", "zmin", "zmax", "fixed", NULL};
static const char *const CGAL_SURFACES[] = {"boundary", NULL};
static const char *const EYE_REGIONS[] = {"cornea", "limbus", "sclera", NULL};
static const char *const BODY_REGIONS[] = {"body", NULL};

static void scene_defaults(kt_scene *s)
{
    memset(s, 0, sizeof *s);
    s->model = KT_MODEL_EYE;
    s->order = 1;
    kt_scene_eye_defaults(&s->eye);
    s->box.fixed_face = 4; /* zmin */
    s->cgal.unit = 1.0;
    s->ordering_centre = NAN;
    s->ordering_sector = NAN;
    s->ordering_halo = -1; /* default set once the model is known */
    s->reference = -1; /* set by model_defaults: eye prestressed, others loaded */
    s->reference_tol = 3e-5;            /* mm (0.03 um): K within about 0.01 D at 3 mm */
    kt_scene_unc_defaults(&s->unc);
    kt_scene_wound_defaults(&s->wound);
}

int kt_scene_in_list(const char *const *list, const char *s)
{
    for (int i = 0; list && list[i]; i++)
        if (strcmp(list[i], s) == 0) return 1;
    return 0;
}

/* A group name usable in MSH physical names and shell commands. */
static int valid_name(const char *s)
{
    for (; *s; s++)
        if (!((*s >= 'a' && *s <= 'z') || (*s >= 'A' && *s <= 'Z') || (*s >= '0' && *s <= '9') ||
              *s == '-' || *s == '_' || *s == '.'))
            return 0;
    return 1;
}

int kt_scene_name_field(kt_yml *y, const yaml_node_t *n, const char *what, char *buf, kt_err *e)
{
    if (kt_yml_string(y, n, what, buf, KT_NAME_MAX, e)) return e->code;
    if (!valid_name(buf))
        return kt_yml_fail(y, n, e, "%s: expected a name of letters, digits, '-', '_' or '.', got '%s'",
                           what, buf);
    return KT_OK;
}

kt_yml_bounds kt_scene_range(double lo, double hi, int lo_open, int hi_open)
{
    kt_yml_bounds b = {lo, hi, lo_open, hi_open};
    return b;
}

/* The plausible ranges of the scene's physical values (keratome-scene(5), LIMITS), in the
 * internal units mm and MPa. */
#define KT_SCENE_MODULUS kt_scene_range(1e-6, 1e3, 0, 0)   /* 1 Pa to 1 GPa: gels to bone */
#define KT_SCENE_LENGTH kt_scene_range(0, 1e6, 1, 0)       /* sizes: within the mesh's extent */
#define KT_SCENE_COORD kt_scene_range(-1e6, 1e6, 0, 0)     /* positions: KT_MESH_MAX_COORD */
#define KT_SCENE_DISPLACEMENT kt_scene_range(-1e3, 1e3, 0, 0)
/* An intraocular pressure, 1 to 100 mmHg (physiological 10-21 mmHg; acute glaucoma reaches
 * 60-80); any other model's pressure at most 1 GPa either way. */
#define KT_SCENE_IOP kt_scene_range(1 * KT_MMHG_MPA, 100 * KT_MMHG_MPA, 0, 0)
#define KT_SCENE_PRESSURE kt_scene_range(-1e3, 1e3, 0, 0)

/* ---- box and CGAL models ---------------------------------------------------------------- */

static const char *const BOX_KEYS[] = {"nodes", "size", "fixed", NULL};

static int parse_box(kt_yml *y, const yaml_node_t *n, kt_box *box, kt_err *e)
{
    if (kt_yml_check_map(y, n, "box", BOX_KEYS, e)) return e->code;
    yaml_node_t *nodes = kt_yml_require(y, n, "nodes", "box", e);
    if (!nodes || kt_yml_check_seq(y, nodes, "box.nodes", 3, 3, e)) return e->code;
    for (int i = 0; i < 3; i++) {
        char f[32];
        snprintf(f, sizeof f, "box.nodes[%d]", i);
        if (kt_yml_int(y, kt_yml_seq_item(y, nodes, i), f, 2, 100000, &box->n[i], e)) return e->code;
    }
    if ((double)box->n[0] * box->n[1] * box->n[2] > 2e7)
        return kt_yml_fail(y, nodes, e, "box.nodes: expected at most 2e7 nodes in all");
    for (int i = 0; i < 3; i++) box->len[i] = box->n[i] - 1.0; /* 1 mm spacing by default */
    yaml_node_t *size = kt_yml_get(y, n, "size");
    if (size) {
        if (kt_yml_check_seq(y, size, "box.size", 3, 3, e)) return e->code;
        for (int i = 0; i < 3; i++) {
            char f[32];
            snprintf(f, sizeof f, "box.size[%d]", i);
            if (kt_yml_quantity(y, kt_yml_seq_item(y, size, i), f, KT_UNIT_LENGTH, KT_SCENE_LENGTH,
                                &box->len[i], e))
                return e->code;
        }
    }
    int face = box->fixed_face;
    if (kt_yml_key_choice(y, n, "box", "fixed", FACES, &face, e)) return e->code;
    box->fixed_face = face == 6 ? -1 : face;
    return KT_OK;
}

static const char *const CGAL_KEYS[] = {"file", "unit", "facet_size", "facet_distance",
                                        "cell_size", "target_nodes", NULL};

static int parse_cgal(kt_yml *y, const yaml_node_t *n, const char *what, const char *dir,
                      kt_cgal *g, kt_err *e)
{
    if (kt_yml_check_map(y, n, what, CGAL_KEYS, e)) return e->code;
    yaml_node_t *file = kt_yml_require(y, n, "file", what, e);
    char f[64], rel[1024];
    snprintf(f, sizeof f, "%s.file", what);
    if (!file || kt_yml_string(y, file, f, rel, sizeof rel, e)) return e->code;
    int len = rel[0] == '/' ? snprintf(g->path, sizeof g->path, "%s", rel)
                            : snprintf(g->path, sizeof g->path, "%s/%s", dir, rel);
    if (len >= (int)sizeof g->path) return kt_yml_fail(y, file, e, "%s: expected a shorter path", f);
    FILE *probe = fopen(g->path, "rb");
    if (!probe) return kt_yml_fail(y, file, e, "%s: expected an existing, readable file, '%s' cannot be opened", f, g->path);
    fclose(probe);
    if (kt_yml_key_quantity(y, n, what, "unit", KT_UNIT_LENGTH, kt_scene_range(1e-6, 1e6, 0, 0), &g->unit, e) ||
        kt_yml_key_quantity(y, n, what, "facet_size", KT_UNIT_LENGTH, KT_SCENE_LENGTH, &g->facet_size, e) ||
        kt_yml_key_quantity(y, n, what, "facet_distance", KT_UNIT_LENGTH, KT_SCENE_LENGTH, &g->facet_distance, e) ||
        kt_yml_key_quantity(y, n, what, "cell_size", KT_UNIT_LENGTH, KT_SCENE_LENGTH, &g->cell_size, e) ||
        kt_yml_key_int(y, n, what, "target_nodes", 0, 10000000, &g->target_nodes, e))
        return e->code;
    const char *need[] = {"facet_size", "facet_distance", "cell_size"};
    for (int i = 0; i < 3; i++)
        if (!kt_yml_require(y, n, need[i], what, e)) return e->code;
    return KT_OK;
}

/* ---- ordering, materials, loads, fixation ------------------------------------------------ */

static const char *const ORDERING_KEYS[] = {"method", "last", "halo", "centre", "sector", NULL};

static int parse_ordering(kt_yml *y, const yaml_node_t *n, kt_scene *s, kt_err *e)
{
    if (kt_yml_check_map(y, n, "ordering", ORDERING_KEYS, e)) return e->code;
    int m = s->ordering - 1;
    if (kt_yml_key_choice(y, n, "ordering", "method", ORDERINGS, &m, e)) return e->code;
    s->ordering = m + 1;
    if (kt_yml_key_int(y, n, "ordering", "halo", 0, 3, &s->ordering_halo, e)) return e->code;
    yaml_node_t *centre = kt_yml_get(y, n, "centre");
    if (centre && s->model != KT_MODEL_EYE)
        return kt_yml_fail(y, centre, e, "ordering.centre: expected only on the eye model");
    if (kt_yml_key_quantity(y, n, "ordering", "centre", KT_UNIT_ANGLE, kt_scene_range(0, 360, 0, 1),
                            &s->ordering_centre, e))
        return e->code;
    yaml_node_t *sector = kt_yml_get(y, n, "sector");
    if (sector && s->model != KT_MODEL_EYE)
        return kt_yml_fail(y, sector, e, "ordering.sector: expected only on the eye model");
    if (kt_yml_key_quantity(y, n, "ordering", "sector", KT_UNIT_ANGLE, kt_scene_range(0, 90, 1, 0),
                            &s->ordering_sector, e))
        return e->code;
    yaml_node_t *last = kt_yml_get(y, n, "last");
    return last ? kt_scene_name_field(y, last, "ordering.last", s->ordering_set, e) : KT_OK;
}

static const char *const MAT_KEYS[] = {"model", "E", "nu", "E_inplane", "E_inplane_2",
                                       "G_transverse", "G_transverse_profile", NULL};
static const char *const MAT_MODELS[] = {"isotropic", "fibre", NULL};

static kt_region_mat *find_mat(kt_scene *s, const char *region)
{
    for (int i = 0; i < s->nmat; i++)
        if (strcmp(s->mat[i].region, region) == 0) return &s->mat[i];
    return NULL;
}

static int add_mat(kt_scene *s, const char *region, double E, double nu)
{
    if (s->nmat >= KT_SCENE_MAX) return -1;
    kt_region_mat *r = &s->mat[s->nmat++];
    snprintf(r->region, sizeof r->region, "%s", region);
    r->E = E;
    r->nu = nu;
    return 0;
}

/* Region names a model's mesh can hold; image labels are "label-N". */
static int known_region(const kt_scene *s, const char *name)
{
    if (strcmp(name, "default") == 0) return 1;
    if (s->model == KT_MODEL_EYE) return kt_scene_in_list(EYE_REGIONS, name);
    if (s->model == KT_MODEL_IMAGE) {
        int v;
        return strncmp(name, "label-", 6) == 0 && kt_parse_int(name + 6, &v) == 0 && v > 0;
    }
    return kt_scene_in_list(BODY_REGIONS, name);
}

double kt_gt_profile(const kt_region_mat *r, double s)
{
    const double *g = r->gt_profile;
    if (!(g[0] > 0 && g[1] > 0 && g[2] > 0) || isnan(s)) return r->Gt;
    double h = 3 / (1 / g[0] + 1 / g[1] + 1 / g[2]);
    return r->Gt * g[s < 1.0 / 3 ? 0 : s < 2.0 / 3 ? 1 : 2] / h;
}

/* G_transverse_profile: off (the default), on (the Petsche 2012 thirds) or a list of three
 * moduli, anterior / middle / posterior third. */
static int parse_gt_profile(kt_yml *y, const yaml_node_t *n, const char *what, kt_region_mat *r,
                            kt_err *e)
{
    if (!n) return KT_OK;
    char key[128];
    snprintf(key, sizeof key, "%s.G_transverse_profile", what);
    if (n->type == YAML_SCALAR_NODE) {
        const char *v = (const char *)n->data.scalar.value;
        int on = strcmp(v, "on") == 0;
        if (!on && strcmp(v, "off") != 0)
            return kt_yml_fail(y, n, e, "%s: expected off, on or a list of three moduli "
                               "(anterior, middle, posterior third), got '%s'", key, v);
        static const double P[3] = KT_GT_PROFILE_PETSCHE;
        for (int k = 0; k < 3; k++) r->gt_profile[k] = on ? P[k] : 0;
        return KT_OK;
    }
    if (kt_yml_check_seq(y, n, key, 3, 3, e)) return e->code;
    for (int k = 0; k < 3; k++)
        if (kt_yml_quantity(y, kt_yml_seq_item(y, n, k), key, KT_UNIT_PRESSURE, KT_SCENE_MODULUS,
                            &r->gt_profile[k], e))
            return e->code;
    return KT_OK;
}

/* A fibre region: E_inplane (both in-plane directions unless E_inplane_2 gives the second),
 * G_transverse, nu; a field left out keeps the region's default (an eye region's, else none). */
static int parse_fibre_mat(kt_yml *y, const yaml_node_t *v, const char *what, kt_region_mat *r,
                           kt_err *e)
{
    if (kt_yml_get(y, v, "E"))
        return kt_yml_fail(y, kt_yml_get(y, v, "E"), e, "%s.E: expected E_inplane for model fibre", what);
    if (!r->E1 && (!kt_yml_get(y, v, "E_inplane") || !kt_yml_get(y, v, "G_transverse") ||
                   !kt_yml_get(y, v, "nu")))
        return kt_yml_fail(y, v, e, "%s: expected E_inplane, G_transverse and nu (no default for this region)", what);
    double E1 = r->E1;
    if (kt_yml_key_quantity(y, v, what, "E_inplane", KT_UNIT_PRESSURE, KT_SCENE_MODULUS, &E1, e))
        return e->code;
    if (kt_yml_get(y, v, "E_inplane")) r->E2 = E1; /* transversely isotropic unless E_inplane_2 */
    r->E1 = E1;
    if (kt_yml_key_quantity(y, v, what, "E_inplane_2", KT_UNIT_PRESSURE, KT_SCENE_MODULUS, &r->E2, e) ||
        kt_yml_key_quantity(y, v, what, "G_transverse", KT_UNIT_PRESSURE, KT_SCENE_MODULUS, &r->Gt, e) ||
        kt_yml_key_number(y, v, what, "nu", kt_scene_range(-1, 0.5, 1, 1), &r->nu, e))
        return e->code;
    return parse_gt_profile(y, kt_yml_get(y, v, "G_transverse_profile"), what, r, e);
}

static int parse_materials(kt_yml *y, const yaml_node_t *n, kt_scene *s, kt_err *e)
{
    if (kt_yml_check_map(y, n, "materials", NULL, e)) return e->code;
    for (int i = 0; i < kt_yml_map_len(n); i++) {
        yaml_node_t *kn, *v;
        const char *region = kt_yml_map_key(y, n, i, &kn, &v);
        char what[96];
        snprintf(what, sizeof what, "materials.%s", region);
        if (!known_region(s, region))
            return kt_yml_fail(y, kn, e, "materials: expected a region of the %s model or 'default', got '%s'",
                               MODELS[s->model - 1], region);
        if (kt_yml_check_map(y, v, what, MAT_KEYS, e)) return e->code;
        kt_region_mat *r = find_mat(s, region);
        if (!r) {
            if (strlen(region) >= KT_NAME_MAX || add_mat(s, region, 0, 0))
                return kt_yml_fail(y, kn, e, "materials: expected at most %d regions with names under %d characters",
                                   KT_SCENE_MAX, KT_NAME_MAX);
            r = find_mat(s, region);
        }
        /* model: as given; else fibre when a fibre field is given, isotropic when E is, else
         * the region's default */
        if (kt_yml_get(y, v, "E_inplane") || kt_yml_get(y, v, "E_inplane_2") || kt_yml_get(y, v, "G_transverse"))
            r->fibre = 1;
        else if (kt_yml_get(y, v, "E"))
            r->fibre = 0;
        if (kt_yml_key_choice(y, v, what, "model", MAT_MODELS, &r->fibre, e)) return e->code;
        if (r->fibre && s->model != KT_MODEL_EYE)
            return kt_yml_fail(y, kt_yml_get(y, v, "model"), e,
                               "%s.model: expected isotropic (fibre frames exist on the eye only)", what);
        if (r->fibre) {
            if (parse_fibre_mat(y, v, what, r, e)) return e->code;
            continue;
        }
        if (kt_yml_get(y, v, "E_inplane") || kt_yml_get(y, v, "E_inplane_2") || kt_yml_get(y, v, "G_transverse"))
            return kt_yml_fail(y, v, e, "%s: expected 'model: fibre' with E_inplane, E_inplane_2, G_transverse", what);
        yaml_node_t *E = kt_yml_get(y, v, "E"), *nu = kt_yml_get(y, v, "nu");
        if ((!r->E && !E) || (!r->nu && !nu))
            return kt_yml_fail(y, v, e, "%s: expected both 'E' and 'nu' (no default for this region)", what);
        if (kt_yml_key_quantity(y, v, what, "E", KT_UNIT_PRESSURE, KT_SCENE_MODULUS, &r->E, e) ||
            kt_yml_key_number(y, v, what, "nu", kt_scene_range(-1, 0.5, 1, 1), &r->nu, e))
            return e->code;
    }
    return KT_OK;
}

/* Literature defaults of the eye's tissues; sources in keratome-scene(5). */
static void eye_material_defaults(kt_scene *s)
{
    /* Lamellar stroma, moduli for a wound that opens over a day (keratome-scene(5), "Rate:
     * which moduli a slowly opening wound sees"; docs/moduli.md): in-plane 2.0 MPa, the
     * slowest measured value (vibrational OCT, Silver 2018), not extrapolated; transverse shear
     * 9.5 kPa = (94 kPa in vivo at 10 kHz by OCE - the membrane prestress 14.4 kPa) times
     * (f_w / 10 kHz)^0.0948, f_w = 1 / (2 pi 1 day), the exponent of the loss ratio 0.15 of
     * stroma in torsion (Hatami-Marbini 2014); nu 0.49 nearly incompressible (Pitre 2020). The
     * limbus region: the same lamellae, fully circumferential (kt_physics). */
    for (int k = 0; k < 2; k++) {
        add_mat(s, k ? "limbus" : "cornea", 0, 0.49);
        kt_region_mat *r = find_mat(s, k ? "limbus" : "cornea");
        r->fibre = 1;
        r->E1 = r->E2 = 2.0;
        r->Gt = 0.0095;
    }
    add_mat(s, "sclera", 3.0, 0.49);
}

static const char *const PRESSURE_KEYS[] = {"surface", "value", NULL};
static const char *const LOAD_KEYS[] = {"pressure", "reference", "reference_tolerance", NULL};
static const char *const REFERENCES[] = {"loaded", "unloaded", "prestressed", NULL};

static int parse_pressure(kt_yml *y, const yaml_node_t *n, const char *what, int eye,
                          kt_pressure *p, kt_err *e)
{
    if (kt_yml_check_map(y, n, what, PRESSURE_KEYS, e)) return e->code;
    char f[96];
    snprintf(f, sizeof f, "%s.surface", what);
    yaml_node_t *surf = kt_yml_require(y, n, "surface", what, e);
    if (!surf || kt_scene_name_field(y, surf, f, p->surface, e)) return e->code;
    if (!kt_yml_require(y, n, "value", what, e)) return e->code;
    return kt_yml_key_quantity(y, n, what, "value", KT_UNIT_PRESSURE,
                               eye ? KT_SCENE_IOP : KT_SCENE_PRESSURE, &p->p, e);
}

static int parse_loads(kt_yml *y, const yaml_node_t *n, kt_scene *s, kt_err *e)
{
    if (kt_yml_check_map(y, n, "loads", LOAD_KEYS, e)) return e->code;
    /* What the geometry is: the measured shape under these loads (default), or stress-free. */
    if (kt_yml_key_choice(y, n, "loads", "reference", REFERENCES, &s->reference, e) ||
        kt_yml_key_quantity(y, n, "loads", "reference_tolerance", KT_UNIT_LENGTH,
                            kt_scene_range(1e-9, 0.01, 0, 0), &s->reference_tol, e))
        return e->code;
    s->npressure = 0;
    yaml_node_t *p = kt_yml_get(y, n, "pressure");
    if (!p) return KT_OK;
    if (p->type == YAML_MAPPING_NODE) {
        s->npressure = 1;
        return parse_pressure(y, p, "loads.pressure", s->model == KT_MODEL_EYE, &s->pressure[0], e);
    }
    if (kt_yml_check_seq(y, p, "loads.pressure", 0, KT_SCENE_MAX, e)) return e->code;
    for (int i = 0; i < kt_yml_seq_len(p); i++) {
        char what[48];
        snprintf(what, sizeof what, "loads.pressure[%d]", i);
        if (parse_pressure(y, kt_yml_seq_item(y, p, i), what, s->model == KT_MODEL_EYE, &s->pressure[i], e))
            return e->code;
        s->npressure = i + 1;
    }
    return KT_OK;
}

static const char *const FIX_KEYS[] = {"surface", "below", "components", "value", NULL};
static const char *const BELOW_KEYS[] = {"axis", "value", NULL};

static int parse_components(kt_yml *y, const yaml_node_t *n, const char *what, unsigned *mask, kt_err *e)
{
    char c[8];
    if (kt_yml_string(y, n, what, c, sizeof c, e)) return e->code;
    *mask = 0;
    for (const char *p = c; *p; p++) {
        unsigned bit = *p == 'x' ? 1u : *p == 'y' ? 2u : *p == 'z' ? 4u : 0u;
        if (!bit || (*mask & bit))
            return kt_yml_fail(y, n, e, "%s: expected distinct letters from 'xyz', got '%s'", what, c);
        *mask |= bit;
    }
    return KT_OK;
}

static int parse_below(kt_yml *y, const yaml_node_t *n, const char *what, kt_fixation *f, kt_err *e)
{
    if (kt_yml_check_map(y, n, what, BELOW_KEYS, e)) return e->code;
    if (!kt_yml_require(y, n, "axis", what, e) || !kt_yml_require(y, n, "value", what, e))
        return e->code;
    if (kt_yml_key_choice(y, n, what, "axis", AXES, &f->below_axis, e)) return e->code;
    return kt_yml_key_quantity(y, n, what, "value", KT_UNIT_LENGTH, KT_SCENE_COORD, &f->below_value, e);
}

static int parse_fix(kt_yml *y, const yaml_node_t *n, const char *what, kt_fixation *f, kt_err *e)
{
    if (kt_yml_check_map(y, n, what, FIX_KEYS, e)) return e->code;
    memset(f, 0, sizeof *f);
    f->mask = 7;
    f->below_axis = -1;
    char fld[96];
    yaml_node_t *surf = kt_yml_get(y, n, "surface"), *below = kt_yml_get(y, n, "below"), *v;
    if (!surf && !below) return kt_yml_fail(y, n, e, "%s: expected key 'surface' or 'below'", what);
    snprintf(f->surface, sizeof f->surface, "fixed");
    snprintf(fld, sizeof fld, "%s.surface", what);
    if (surf && kt_scene_name_field(y, surf, fld, f->surface, e)) return e->code;
    snprintf(fld, sizeof fld, "%s.below", what);
    if (below && parse_below(y, below, fld, f, e)) return e->code;
    snprintf(fld, sizeof fld, "%s.components", what);
    if ((v = kt_yml_get(y, n, "components")) && parse_components(y, v, fld, &f->mask, e)) return e->code;
    if ((v = kt_yml_get(y, n, "value"))) {
        snprintf(fld, sizeof fld, "%s.value", what);
        if (kt_yml_check_seq(y, v, fld, 3, 3, e)) return e->code;
        for (int c = 0; c < 3; c++) {
            snprintf(fld, sizeof fld, "%s.value[%d]", what, c);
            if (kt_yml_quantity(y, kt_yml_seq_item(y, v, c), fld, KT_UNIT_LENGTH, KT_SCENE_DISPLACEMENT, &f->value[c], e))
                return e->code;
        }
    }
    return KT_OK;
}

static int parse_fixation(kt_yml *y, const yaml_node_t *n, kt_scene *s, kt_err *e)
{
    if (kt_yml_check_seq(y, n, "fixation", 0, KT_SCENE_MAX, e)) return e->code;
    s->nfix = 0;
    for (int i = 0; i < kt_yml_seq_len(n); i++) {
        char what[48];
        snprintf(what, sizeof what, "fixation[%d]", i);
        if (parse_fix(y, kt_yml_seq_item(y, n, i), what, &s->fix[i], e)) return e->code;
        s->nfix = i + 1;
    }
    return KT_OK;
}

/* ---- names and model defaults ------------------------------------------------------------ */

/* Is name a surface group the model's mesh will have? */
static int known_surface(const kt_scene *s, const char *name)
{
    if (s->model == KT_MODEL_EYE) {
        for (int i = 0; i < s->eye.nring; i++)
            if (strcmp(s->eye.ring[i].name, name) == 0) return 1;
        return kt_scene_in_list(kt_scene_eye_surfaces, name) && (strcmp(name, "fixed") || s->eye.extent < 180);
    }
    for (int i = 0; i < s->nfix; i++)
        if (s->fix[i].below_axis >= 0 && strcmp(s->fix[i].surface, name) == 0) return 1;
    if (s->model == KT_MODEL_BOX) {
        /* The fixed face is renamed "fixed" and no longer has its own name. */
        int face = s->box.fixed_face;
        if (!strcmp(name, "fixed")) return face >= 0;
        return kt_scene_in_list(BOX_SURFACES, name) && !(face >= 0 && !strcmp(name, FACES[face]));
    }
    return kt_scene_in_list(CGAL_SURFACES, name);
}

/* The node of item i's key in a sequence of mappings, for messages (NULL-safe). */
static yaml_node_t *item_key(kt_yml *y, yaml_node_t *root, const char *block, const char *sub,
                             int i, const char *key)
{
    yaml_node_t *b = kt_yml_get(y, root, block);
    if (sub) b = kt_yml_get(y, b, sub);
    yaml_node_t *item = b && b->type == YAML_SEQUENCE_NODE ? kt_yml_seq_item(y, b, i) : b;
    yaml_node_t *v = kt_yml_get(y, item, key);
    return v ? v : item;
}

static int check_names(kt_yml *y, yaml_node_t *root, kt_scene *s, kt_err *e)
{
    const char *model = MODELS[s->model - 1];
    for (int i = 0; i < s->npressure; i++)
        if (!known_surface(s, s->pressure[i].surface))
            return kt_yml_fail(y, item_key(y, root, "loads", "pressure", i, "surface"), e,
                               "loads.pressure: expected a surface of the %s model, got '%s'", model,
                               s->pressure[i].surface);
    for (int i = 0; i < s->nfix; i++) {
        const kt_fixation *f = &s->fix[i];
        if (f->below_axis >= 0 && s->model == KT_MODEL_EYE)
            return kt_yml_fail(y, item_key(y, root, "fixation", NULL, i, "below"), e,
                               "fixation[%d].below: expected only on box, surface and image models", i);
        if (f->below_axis < 0 && !known_surface(s, f->surface))
            return kt_yml_fail(y, item_key(y, root, "fixation", NULL, i, "surface"), e,
                               "fixation[%d].surface: expected a surface of the %s model, got '%s'", i,
                               model, f->surface);
    }
    if (s->ordering_set[0] && !known_surface(s, s->ordering_set))
        return kt_yml_fail(y, item_key(y, root, "ordering", NULL, 0, "last"), e,
                           "ordering.last: expected a surface of the %s model, got '%s'", model,
                           s->ordering_set);
    return KT_OK;
}

/* Defaults that depend on the model, for blocks the file leaves out. */
static void model_defaults(yaml_node_t *materials, yaml_node_t *loads, yaml_node_t *fixation,
                           kt_scene *s)
{
    int eye = s->model == KT_MODEL_EYE;
    if (!materials && eye) eye_material_defaults(s);
    if (s->reference < 0) s->reference = eye ? KT_REFERENCE_PRESTRESSED : KT_REFERENCE_LOADED;
    if (!loads && eye) {
        /* Mean intraocular pressure 15 mmHg (Klein et al. 1992), on the inner surface. */
        s->npressure = 1;
        snprintf(s->pressure[0].surface, KT_NAME_MAX, "inner");
        s->pressure[0].p = 15 * KT_MMHG_MPA;
    }
    int has_fixed = eye ? s->eye.extent < 180 : s->model == KT_MODEL_BOX && s->box.fixed_face >= 0;
    if (!fixation && has_fixed) {
        s->nfix = 1;
        memset(&s->fix[0], 0, sizeof s->fix[0]);
        snprintf(s->fix[0].surface, KT_NAME_MAX, "fixed");
        s->fix[0].mask = 7;
        s->fix[0].below_axis = -1;
    }
    if (!s->ordering) s->ordering = eye && s->eye.nring ? KT_ORDERING_CONSTRAINED : KT_ORDERING_METIS;
    /* LRI arcs are centred on the steep meridian: sweep the rings from there by default. */
    if (isnan(s->ordering_centre) && eye) s->ordering_centre = s->eye.steep_axis;
    /* 50 deg: a pair of arcs of up to 90 deg about the centre, with 5 deg to spare each side. */
    if (isnan(s->ordering_sector) && eye) s->ordering_sector = 50;
    /* The incision floor is refined where the arcs are cut: the ordering's sector. */
    if (eye) s->eye.floor_centre = s->ordering_centre, s->eye.floor_sector = s->ordering_sector;
    /* One layer: the nodes whose stiffness columns change when the set is cut; the eye takes a
     * second, the rows of those columns, so augsolve's closure solves stay inside the set
     * (measured on plans/eye.yaml: closures of 12-14k DOFs with one layer, 5k with two). */
    if (s->ordering_halo < 0) s->ordering_halo = eye ? 2 : 1;
}

static int parse_model(kt_yml *y, yaml_node_t *root, kt_scene *s, kt_err *e)
{
    const char *blocks[] = {"eye", "box", "surface", "image"};
    for (int i = 0; i < 4; i++) {
        yaml_node_t *b = kt_yml_get(y, root, blocks[i]);
        if (b && i != s->model - 1)
            return kt_yml_fail(y, b, e, "%s: expected only the block of model '%s'", blocks[i],
                               MODELS[s->model - 1]);
    }
    yaml_node_t *b = kt_yml_get(y, root, blocks[s->model - 1]);
    switch (s->model) {
    case KT_MODEL_EYE: return b ? kt_scene_parse_eye(y, b, &s->eye, e) : KT_OK;
    case KT_MODEL_BOX:
        if (!b) return kt_yml_fail(y, root, e, "expected key 'box' for model box");
        return parse_box(y, b, &s->box, e);
    default:
        if (!b) return kt_yml_fail(y, root, e, "expected key '%s' for model %s", blocks[s->model - 1], blocks[s->model - 1]);
        return parse_cgal(y, b, blocks[s->model - 1], s->dir, &s->cgal, e);
    }
}

/* The work an eye's mesh sizes ask for, bounded before any meshing (eye_budget.c). A geometry
 * the estimate cannot take is left to the mesher, which names what is wrong with it. */
static int check_budget(kt_yml *y, yaml_node_t *root, const kt_scene *s, kt_err *e)
{
    if (s->model != KT_MODEL_EYE) return KT_OK;
    kt_err ge = {0};
    double tets;
    if (kt_eye_estimate_tets(&s->eye, s->order, &tets, &ge)) return KT_OK;
    if (tets <= KT_EYE_MAX_TETS) return KT_OK;
    yaml_node_t *eye = kt_yml_get(y, root, "eye"), *sizes = eye ? kt_yml_get(y, eye, "mesh_size") : NULL;
    return kt_yml_fail(y, sizes ? sizes : eye ? eye : root, e,
                       "eye.mesh_size: expected sizes that ask for at most %d tets at order %d, these ask "
                       "for about %.3g million (keratome-scene(5), LIMITS)", KT_EYE_MAX_TETS, s->order,
                       tets / 1e6);
}

static int parse_scene(kt_yml *y, yaml_node_t *root, kt_scene *s, kt_err *e)
{
    if (kt_yml_check_map(y, root, "scene", TOP_KEYS, e)) return e->code;
    yaml_node_t *v;
    if ((v = kt_yml_get(y, root, "name")) && kt_scene_name_field(y, v, "name", s->name, e)) return e->code;
    char desc[1024];
    if (kt_yml_key_string(y, root, "", "description", desc, sizeof desc, e)) return e->code;
    int model = s->model - 1;
    if (kt_yml_key_choice(y, root, "", "model", MODELS, &model, e)) return e->code;
    s->model = model + 1;
    if (kt_yml_key_int(y, root, "", "order", 1, 2, &s->order, e)) return e->code;
    if (parse_model(y, root, s, e)) return e->code;
    if ((v = kt_yml_get(y, root, "ordering")) && parse_ordering(y, v, s, e)) return e->code;
    yaml_node_t *mats = kt_yml_get(y, root, "materials"), *loads = kt_yml_get(y, root, "loads"),
                *fix = kt_yml_get(y, root, "fixation");
    if (mats && s->model == KT_MODEL_EYE) eye_material_defaults(s); /* entries override them */
    if (mats && parse_materials(y, mats, s, e)) return e->code;
    if (loads && parse_loads(y, loads, s, e)) return e->code;
    if (fix && parse_fixation(y, fix, s, e)) return e->code;
    if ((v = kt_yml_get(y, root, "uncertainty")) && kt_scene_parse_uncertainty(y, v, &s->unc, e))
        return e->code;
    if ((v = kt_yml_get(y, root, "wound")) && kt_scene_parse_wound(y, v, &s->wound, e)) return e->code;
    model_defaults(mats, loads, fix, s);
    /* After the defaults: the floor refinement's sector is the ordering's. */
    if (check_budget(y, root, s, e)) return e->code;
    return check_names(y, root, s, e);
}

int kt_scene_load(const char *path, kt_scene *s, kt_err *e)
{
    scene_defaults(s);
    if (strlen(path) >= sizeof s->path) return kt_fail(e, KT_EINPUT, "%.200s...: path too long", path);
    strcpy(s->path, path);
    kt_path_dir(path, s->dir, sizeof s->dir);
    kt_path_stem(path, s->name, sizeof s->name);
    kt_yml y;
    if (kt_yml_load(&y, path, e)) return e->code;
    yaml_node_t *root = kt_yml_root(&y, e);
    if (root) parse_scene(&y, root, s, e);
    kt_yml_free(&y);
    return e->code;
}
