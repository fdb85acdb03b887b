/* test_scene.c: scene files load with units converted; bad scenes are rejected with the
 * position and the expectation; materials and Dirichlet data land on a mesh's groups. */
#define _POSIX_C_SOURCE 200809L
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "bind.h"
#include "grid.h"
#include "kt_test.h"
#include "scene.h"
#include "yml.h"

#define MMHG 133.322387415e-6 /* MPa per mmHg (conventional millimetre of mercury) */

static char dir[64];

static void write_file(const char *path, const char *text)
{
    FILE *f = fopen(path, "w");
    if (!f) {
        perror(path);
        exit(1);
    }
    fputs(text, f);
    fclose(f);
}

/* Units: each conversion against its definition. */
static void test_units(void)
{
    struct { const char *text; int dim; double want; } ok[] = {
        {"7.8 mm", KT_UNIT_LENGTH, 7.8},       {"540 um", KT_UNIT_LENGTH, 0.54},
        {"540um", KT_UNIT_LENGTH, 0.54},       {"1.2 cm", KT_UNIT_LENGTH, 12.0},
        {"0.024 m", KT_UNIT_LENGTH, 24.0},     {"-3e-1 mm", KT_UNIT_LENGTH, -0.3},
        {"0.3 MPa", KT_UNIT_PRESSURE, 0.3},    {"300 kPa", KT_UNIT_PRESSURE, 0.3},
        {"2000 Pa", KT_UNIT_PRESSURE, 0.002},  {"15 mmHg", KT_UNIT_PRESSURE, 15 * MMHG},
        {"0.001 GPa", KT_UNIT_PRESSURE, 1.0},  {"90 deg", KT_UNIT_ANGLE, 90.0},
        {"3.14159265358979 rad", KT_UNIT_ANGLE, 180.0}, {"2 mN", KT_UNIT_FORCE, 0.002},
        {"1.5 D", KT_UNIT_POWER, 1.5},         {"0.49", KT_UNIT_NONE, 0.49},
    };
    for (size_t i = 0; i < sizeof ok / sizeof ok[0]; i++) {
        double v = NAN;
        CHECK(kt_yml_parse_quantity(ok[i].text, ok[i].dim, &v) == 0, "'%s' rejected", ok[i].text);
        CHECK_NEAR(v, ok[i].want, 1e-12, ok[i].text);
    }
    /* 15 mmHg is the 0.0020 MPa the scene documentation quotes. */
    CHECK_NEAR(15 * MMHG, 0.0020, 0.001, "15 mmHg in MPa");
    const char *bad[] = {"7.8", "7.8 mmHg", "mm", "7.8 mmm", "nan mm", "1e999 mm", "15 deg"};
    int dims[] = {KT_UNIT_LENGTH, KT_UNIT_LENGTH, KT_UNIT_LENGTH, KT_UNIT_LENGTH, KT_UNIT_LENGTH,
                  KT_UNIT_LENGTH, KT_UNIT_PRESSURE};
    for (int i = 0; i < 7; i++) {
        double v;
        CHECK(kt_yml_parse_quantity(bad[i], dims[i], &v) != 0, "'%s' accepted", bad[i]);
    }
}

static void test_eye_plan(void)
{
    kt_scene s;
    kt_err e = {0};
    CHECK(kt_scene_load("plans/eye.yaml", &s, &e) == 0, "%s", e.msg);
    if (e.code) return;
    CHECK(s.model == KT_MODEL_EYE && s.order == 2, "model %d order %d", s.model, s.order);
    /* 1.5 D with-the-rule about K 43.27 D: K = 337.5 / R. */
    CHECK_NEAR(337.5 / s.eye.r_ant_steep - 337.5 / s.eye.r_ant_flat, 1.5, 2e-3, "cylinder, D");
    CHECK_NEAR(0.5 * (337.5 / s.eye.r_ant_steep + 337.5 / s.eye.r_ant_flat), 337.5 / 7.8, 1e-3, "mean K");
    CHECK_NEAR(s.eye.steep_axis, 90, 0, "steep axis");
    CHECK_NEAR(s.eye.t_central, 0.540, 1e-15, "540 um in mm");
    CHECK_NEAR(s.eye.t_peripheral, 0.670, 1e-15, "670 um in mm");
    CHECK_NEAR(s.eye.wtw, 11.7, 0, "white to white");
    CHECK_NEAR(s.eye.wtw_v, 10.6, 0, "vertical white to white: a horizontally oval cornea");
    CHECK(s.eye.nring == 1 && strcmp(s.eye.ring[0].name, "incision-ring-1") == 0, "ring name");
    CHECK_NEAR(s.eye.ring[0].diameter, 10.5, 0, "ring diameter");
    CHECK_NEAR(s.eye.ring[0].depth_fraction, 0.9, 0, "ring depth fraction");
    CHECK(s.eye.ring[0].diameter <= s.eye.wtw - s.eye.limbus_width, "ring inside the clear cornea");
    CHECK(s.ordering == KT_ORDERING_CONSTRAINED && s.ordering_set[0] == 0, "ordering %d", s.ordering);
    CHECK_NEAR(s.ordering_centre, s.eye.steep_axis, 0, "sweep from the steep meridian");
    CHECK(s.ordering_halo == 2, "halo %d", s.ordering_halo);
    CHECK_NEAR(s.ordering_sector, 50, 0, "sector about the steep meridian");
    CHECK(s.npressure == 1 && strcmp(s.pressure[0].surface, "inner") == 0, "pressure surface");
    CHECK_NEAR(s.pressure[0].p, 15 * MMHG, 1e-12, "IOP in MPa");
    CHECK(s.nmat == 3, "materials %d", s.nmat);
    for (int i = 0; i < s.nmat; i++) CHECK_NEAR(s.mat[i].nu, 0.49, 0, s.mat[i].region);
    CHECK(strcmp(s.mat[0].region, "cornea") == 0, "first region %s", s.mat[0].region);
    CHECK(s.mat[0].fibre && s.mat[1].fibre && !s.mat[2].fibre, "cornea and limbus fibre, sclera isotropic");
    CHECK_NEAR(s.mat[0].E1, 2.0, 0, "cornea E_inplane, MPa");
    CHECK_NEAR(s.mat[0].E2, 2.0, 0, "cornea E_inplane_2 = E_inplane");
    CHECK_NEAR(s.mat[0].Gt, 0.0095, 1e-15, "cornea G_transverse 9.5 kPa in MPa");
    CHECK_NEAR(s.eye.fibre_band, 1.5, 0, "limbal band, mm");
    CHECK_NEAR(s.eye.fibre_density, 1.91, 0, "limbal density");
    CHECK_NEAR(s.eye.h_floor, 0.042, 1e-15, "incision floor 42 um in mm");
    CHECK_NEAR(s.eye.floor_sector, 50, 0, "floor refined in the ordering's sector");
    CHECK(s.reference == KT_REFERENCE_PRESTRESSED, "reference %d", s.reference);
    CHECK(s.nfix == 1 && s.fix[0].mask == 7 && strcmp(s.fix[0].surface, "fixed") == 0, "fixation");
}

static void test_beam_plans(void)
{
    int h[] = {4, 16, 1024};
    for (int i = 0; i < 3; i++) {
        char path[64];
        snprintf(path, sizeof path, "plans/bench/beam-%d.yaml", h[i]);
        kt_scene s;
        kt_err e = {0};
        CHECK(kt_scene_load(path, &s, &e) == 0, "%s", e.msg);
        if (e.code) continue;
        CHECK(s.model == KT_MODEL_BOX, "%s model", path);
        CHECK(s.box.n[0] == 5 && s.box.n[1] == 5 && s.box.n[2] == h[i], "%s nodes", path);
        /* 1 mm spacing: (n - 1) mm per side. */
        CHECK_NEAR(s.box.len[0], 4, 0, path);
        CHECK_NEAR(s.box.len[2], h[i] - 1, 0, path);
        CHECK(s.box.fixed_face == 4 && strcmp(s.ordering_set, "zmax") == 0, "%s fixed/last", path);
        CHECK(s.nmat == 1 && strcmp(s.mat[0].region, "body") == 0, "%s material", path);
        CHECK(s.npressure == 0 && s.nfix == 1, "%s loads", path);
    }
    kt_scene s;
    kt_err e = {0};
    CHECK(kt_scene_load("plans/bench/brick-20.yaml", &s, &e) == 0, "%s", e.msg);
    /* The paper's largest brick: 18,081 nodes. */
    CHECK(s.box.n[0] * s.box.n[1] * s.box.n[2] == 18081, "brick-20 nodes");
}

/* A scene that must fail: KT_EINPUT, "file:line:col:" and the expectation in the message. */
static void reject(const char *name, const char *text, int line, int col, const char *expect)
{
    char path[128], pos[200];
    snprintf(path, sizeof path, "%s/%s.yaml", dir, name);
    write_file(path, text);
    kt_scene s;
    kt_err e = {0};
    int rc = kt_scene_load(path, &s, &e);
    snprintf(pos, sizeof pos, "%s:%d:%d: ", path, line, col);
    CHECK(rc == KT_EINPUT, "%s: rc %d", name, rc);
    CHECK(strncmp(e.msg, pos, strlen(pos)) == 0, "%s: message '%s' does not start with '%s'", name, e.msg, pos);
    CHECK(strstr(e.msg, expect) != NULL, "%s: message '%s' lacks '%s'", name, e.msg, expect);
    CHECK(strchr(e.msg, '\n') == NULL, "%s: message has more than one line", name);
}

static void test_bad_scenes(void)
{
    reject("malformed", "model: eye\neye:\n  extent: [90 deg\n", 4, 1, "expected well-formed YAML");
    reject("colon", "name: a: b\n", 1, 8, "expected well-formed YAML");
    reject("two-docs", "model: eye\n---\nmodel: box\n", 2, 1, "expected a single YAML document");
    reject("empty", "", 1, 1, "expected a YAML mapping");
    reject("toplist", "- eye\n", 1, 1, "expected a mapping");
    reject("unknown-top", "model: eye\nmodle: box\n", 2, 1, "unknown key 'modle'");
    reject("unknown-eye", "eye:\n  central_thicknes: 0.5 mm\n", 2, 3, "unknown key 'central_thicknes'");
    reject("duplicate", "eye:\n  extent: 90 deg\n  extent: 80 deg\n", 3, 3, "duplicate key 'extent' (first given at line 2)");
    reject("model", "model: lens\n", 1, 8, "expected one of: eye, box, surface, image");
    reject("order", "order: two\n", 1, 8, "expected an integer");
    reject("order3", "order: 3\n", 1, 8, "expected an integer in [1, 2]");
    reject("no-unit", "eye:\n  central_thickness: 0.54\n", 2, 22, "without a unit");
    reject("bad-unit", "eye:\n  central_thickness: 0.54 mmm\n", 2, 22, "unknown unit 'mmm'");
    reject("wrong-dim", "eye:\n  central_thickness: 15 mmHg\n", 2, 22, "expected a length (mm, um, cm, m), got a pressure");
    reject("negative", "eye:\n  central_thickness: -0.5 mm\n", 2, 22, "expected a length in [0.05, 5] mm");
    reject("type", "eye: 7.8 mm\n", 1, 6, "eye: expected a mapping");
    reject("nu", "materials:\n  cornea: {E: 0.3 MPa, nu: 0.5}\n", 2, 28, "materials.cornea.nu: expected a number in (-1, 0.5)");
    reject("gt", "materials:\n  cornea: {model: fibre, G_transverse: 47}\n", 2, 40, "expected a pressure with a unit");
    reject("fibre_e", "materials:\n  cornea: {model: fibre, E: 2 MPa}\n", 2, 29, "materials.cornea.E: expected E_inplane for model fibre");
    reject("density", "eye:\n  fibres: {limbal_density: 0.5}\n", 2, 28, "eye.fibres.limbal_density: expected a number");
    reject("box_fibre", "model: box\nbox: {nodes: [2, 2, 2], size: [1 mm, 1 mm, 1 mm]}\nmaterials:\n  body: {model: fibre, E_inplane: 2 MPa, G_transverse: 47 kPa, nu: 0.49}\n", 4, 17, "expected isotropic");
    reject("E", "materials:\n  cornea: {E: 0.3, nu: 0.49}\n", 2, 15, "expected a pressure with a unit");
    reject("region", "materials:\n  lens: {E: 1 MPa, nu: 0.4}\n", 2, 3, "expected a region of the eye model");
    reject("oz", "eye:\n  optical_zone: 11.5 mm\n", 2, 17, "eye.optical_zone: expected a diameter inside the clear cornea");
    reject("ring-out", "eye:\n  incision_rings:\n    - {name: r1, diameter: 11.5 mm, depth: 500 um}\n", 3, 28,
           "expected a diameter in (7, 10.7] mm");
    reject("ring-in", "eye:\n  incision_rings:\n    - {name: r1, diameter: 6 mm, depth: 500 um}\n", 3, 28,
           "outside the optical zone");
    reject("ring-frac", "eye:\n  incision_rings:\n    - diameter: 10 mm\n      depth_fraction: 1.2\n", 4, 23,
           "depth_fraction: expected a number in (0, 1)");
    reject("ring-both", "eye:\n  incision_rings:\n    - {diameter: 10 mm, depth: 500 um, depth_fraction: 0.5}\n", 3, 32,
           "exactly one of 'depth' or 'depth_fraction'");
    reject("ring-name", "eye:\n  incision_rings:\n    - {name: inner, diameter: 10 mm, depth: 500 um}\n", 3, 7,
           "'inner' is a surface of the eye");
    reject("missing-file", "model: surface\nsurface:\n  file: no-such.off\n  facet_size: 1 mm\n", 3, 9,
           "expected an existing, readable file");
    reject("box-nodes", "model: box\nbox:\n  nodes: [5, 5]\n", 3, 10, "box.nodes: expected 3 items, found 2");
    reject("box-missing", "model: box\n", 1, 1, "expected key 'box'");
    reject("other-block", "model: eye\nbox:\n  nodes: [2, 2, 2]\n", 3, 3, "expected only the block of model 'eye'");
    reject("fix-surface", "fixation:\n  - {surface: bottom}\n", 2, 15, "expected a surface of the eye model, got 'bottom'");
    reject("components", "fixation:\n  - {surface: fixed, components: xq}\n", 2, 34, "distinct letters from 'xyz'");
    reject("fix-value", "fixation:\n  - {surface: fixed, value: [0 mm, 0 mm]}\n", 2, 29, "expected 3 items");
    reject("pressure", "loads:\n  pressure: {surface: inner}\n", 2, 13, "expected key 'value'");
    reject("last", "ordering: {method: constrained, last: nowhere}\n", 1, 39, "ordering.last: expected a surface");
    reject("method", "ordering: {method: rcm}\n", 1, 20, "expected one of: amd, metis, constrained, natural");
    reject("centre-box", "model: box\nbox: {nodes: [2, 2, 2]}\nordering: {centre: 0 deg}\n", 3, 20,
           "ordering.centre: expected only on the eye model");
    reject("centre-range", "ordering: {centre: 360 deg}\n", 1, 20, "expected an angle in [0, 360) deg");
    reject("halo", "ordering: {halo: 4}\n", 1, 18, "ordering.halo: expected an integer in [0, 3]");
    reject("below-eye", "fixation:\n  - below: {axis: y, value: 0 mm}\n", 2, 12, "expected only on box");
    reject("extent", "eye:\n  extent: 20 deg\n", 2, 11, "eye.extent: expected more than the polar angle");
    reject("wtw-vertical", "eye:\n  white_to_white: {horizontal: 11.7 mm, vertical: 11.8 mm}\n", 2, 51,
           "eye.white_to_white.vertical: expected at most the horizontal diameter (11.7 mm)");
    reject("wtw-flat", "eye:\n  white_to_white: {horizontal: 11.7 mm, vertical: 8.5 mm}\n", 2, 51,
           "eye.white_to_white.vertical: expected at least 8.74 mm");
    reject("wtw-key", "eye:\n  white_to_white: {horizontal: 11.7 mm, vertikal: 10 mm}\n", 2, 41, "unknown key 'vertikal'");
    reject("wtw-unit", "eye:\n  white_to_white: {vertical: 10.6}\n", 2, 30, "without a unit");
    reject("floor-bound", "eye:\n  mesh_size: {incision_floor: 4 um}\n", 2, 31,
           "eye.mesh_size.incision_floor: expected a length in [0.005, 1] mm");
    reject("floor-coarse", "eye:\n  mesh_size: {incision: 0.1 mm, incision_floor: 0.15 mm}\n", 2, 49,
           "eye.mesh_size.incision_floor: expected at most mesh_size.incision (0.1 mm)");
    reject("grading-low", "eye:\n  mesh_size: {floor_grading: 0.05}\n", 2, 30,
           "eye.mesh_size.floor_grading: expected a number in [0.1, 2]");
    reject("grading-high", "eye:\n  mesh_size: {floor_grading: 2.5}\n", 2, 30,
           "eye.mesh_size.floor_grading: expected a number in [0.1, 2]");
    reject("grading-unit", "eye:\n  mesh_size: {floor_grading: 1 mm}\n", 2, 30,
           "eye.mesh_size.floor_grading: expected a number");
}

/* eye.white_to_white: a length is the horizontal diameter, the vertical one 1.1 mm less (the
 * population means, keratome-scene(5)); {horizontal, vertical}, either alone; written back. */
static void test_wtw(void)
{
    struct { const char *text; double h, v; } ok[] = {
        {"model: eye\n", 11.7, 10.6},
        {"eye:\n  white_to_white: 12.1 mm\n", 12.1, 12.1 - 1.1},
        {"eye:\n  white_to_white: {horizontal: 11.5 mm, vertical: 10.2 mm}\n", 11.5, 10.2},
        {"eye:\n  white_to_white: {horizontal: 11.2 mm}\n", 11.2, 11.2 - 1.1},
        {"eye:\n  white_to_white: {vertical: 10.9 mm}\n", 11.7, 10.9},
        {"eye:\n  white_to_white: {horizontal: 11.7 mm, vertical: 11.7 mm}\n", 11.7, 11.7},
    };
    for (size_t i = 0; i < sizeof ok / sizeof ok[0]; i++) {
        char path[128];
        snprintf(path, sizeof path, "%s/wtw-%zu.yaml", dir, i);
        write_file(path, ok[i].text);
        kt_scene s;
        kt_err e = {0};
        CHECK(kt_scene_load(path, &s, &e) == 0, "%s", e.msg);
        CHECK_NEAR(s.eye.wtw, ok[i].h, 0, "horizontal white-to-white");
        CHECK_NEAR(s.eye.wtw_v, ok[i].v, 0, "vertical white-to-white");
    }
}

/* eye.mesh_size.incision_floor in mm; the floor is refined in the ordering's sector. */
static void test_floor(void)
{
    char path[128];
    snprintf(path, sizeof path, "%s/floor.yaml", dir);
    write_file(path, "eye:\n  mesh_size: {incision: 0.2 mm, incision_floor: 30 um}\n"
                     "ordering: {centre: 20 deg, sector: 40 deg}\n");
    kt_scene s;
    kt_err e = {0};
    CHECK(kt_scene_load(path, &s, &e) == 0, "%s", e.msg);
    if (e.code) return;
    CHECK_NEAR(s.eye.h_floor, 0.03, 1e-15, "30 um in mm");
    CHECK_NEAR(s.eye.floor_centre, 20, 0, "floor centre = ordering.centre");
    CHECK_NEAR(s.eye.floor_sector, 40, 0, "floor sector = ordering.sector");
    CHECK(s.eye.floor_grading == 0.5, "built-in floor grading 0.5 mm per mm (%g)", s.eye.floor_grading);
    write_file(path, "eye:\n  mesh_size: {incision: 0.2 mm, incision_floor: 30 um, floor_grading: 1.25}\n");
    CHECK(kt_scene_load(path, &s, &e) == 0, "%s", e.msg);
    CHECK(s.eye.floor_grading == 1.25, "floor_grading read (%g)", s.eye.floor_grading);
    write_file(path, "eye:\n  mesh_size: {incision: 0.2 mm}\n");
    CHECK(kt_scene_load(path, &s, &e) == 0, "%s", e.msg);
    CHECK(s.eye.h_floor == 0, "built-in: no floor refinement (%g mm)", s.eye.h_floor);
}

/* Materials by region tag and Dirichlet data on the box's groups. */
static void test_on_mesh(void)
{
    char path[128];
    snprintf(path, sizeof path, "%s/box.yaml", dir);
    write_file(path, "model: box\nbox: {nodes: [3, 4, 5], fixed: none}\n"
                     "materials: {default: {E: 2 kPa, nu: 0.3}}\n"
                     "fixation:\n  - {surface: zmin, components: xz, value: [0.1 mm, 0 mm, -200 um]}\n");
    kt_scene s;
    kt_err e = {0};
    CHECK(kt_scene_load(path, &s, &e) == 0, "%s", e.msg);
    kt_mesh m;
    CHECK(kt_grid_box(&m, s.box.n[0], s.box.n[1], s.box.n[2], s.box.len[0], s.box.len[1], s.box.len[2], &e) == 0, "%s", e.msg);
    kt_fem_problem fp;
    CHECK(kt_fem_bind(&s, &m, &fp, &e) == 0, "%s", e.msg);
    CHECK(fp.mats.nmat == 2 && fp.mats.mat, "nmat %d", fp.mats.nmat);
    if (fp.mats.mat) CHECK_NEAR(fp.mats.mat[1].E, 0.002, 1e-15, "body E from default, MPa");
    CHECK(fp.nfix == 1 && fp.fix[0].mask == 5u, "fixation surfaces %d", fp.nfix);
    const unsigned char *fixed = fp.fixed;
    const double *g = fp.g;
    int nfixed = 0, bad = 0;
    for (int i = 0; i < m.nn; i++) {
        int on_zmin = m.xyz[3 * i + 2] == 0;
        for (int c = 0; c < 3; c++) {
            nfixed += fixed[3 * i + c];
            int want = on_zmin && c != 1;
            if (fixed[3 * i + c] != want) bad++;
        }
        if (on_zmin && (g[3 * i] != 0.1 || g[3 * i + 2] != -0.2)) bad++;
    }
    CHECK(nfixed == 2 * 3 * 4 && bad == 0, "fixed %d, %d wrong", nfixed, bad);
    kt_fem_problem_free(&fp);
    /* A scene naming a surface the mesh lacks is an input error. */
    s.fix[0].surface[0] = 'q';
    kt_err e2 = {0};
    CHECK(kt_fem_bind(&s, &m, &fp, &e2) == KT_EINPUT && strstr(e2.msg, "qmin"), "%s", e2.msg);
    CHECK(fp.fixed == NULL && fp.mats.mat == NULL, "a failed binding holds nothing");
    kt_mesh_free(&m);
}

/* The wound: section: defaults (immediate, k = 0), units, the k of the age and time rule. */
static void test_wound(void)
{
    char path[128];
    kt_scene s;
    kt_err e = {0};
    snprintf(path, sizeof path, "%s/wound0.yaml", dir);
    write_file(path, "model: box\nbox: {nodes: [2, 2, 2], size: [1 mm, 1 mm, 1 mm]}\n");
    CHECK(kt_scene_load(path, &s, &e) == KT_OK, "%s", e.msg);
    CHECK(s.wound.state == KT_WOUND_IMMEDIATE && kt_scene_wound_k(&s) == 0 &&
              s.wound.bridge_stiffness == KT_WOUND_K_DEFAULT && kt_scene_wound_age(&s) == 60,
          "default wound: immediate, k 0");
    snprintf(path, sizeof path, "%s/wound1.yaml", dir);
    write_file(path, "model: box\nbox: {nodes: [2, 2, 2], size: [1 mm, 1 mm, 1 mm]}\n"
                     "wound: {state: healed, bridge_stiffness: 300 kPa/mm, age_rate: 0.5 %/y, age: 80,\n"
                     "        months: 61 d, heal_time: 4 wk}\n");
    CHECK(kt_scene_load(path, &s, &e) == KT_OK, "%s", e.msg);
    double months = 61 * 12 / 365.25, tau = 28 * 12 / 365.25;
    CHECK_NEAR(s.wound.bridge_stiffness, 0.3, 1e-15, "300 kPa/mm");
    CHECK_NEAR(s.wound.age_rate, 0.005, 1e-15, "0.5 %/y");
    CHECK_NEAR(s.wound.months, months, 1e-14, "61 d in months");
    CHECK_NEAR(kt_scene_wound_k(&s), 0.3 * exp(-0.005 * 20) * (1 - exp(-months / tau)), 1e-14,
               "k = k_ref exp(-rate (age - 60)) (1 - exp(-months / heal_time))");
    s.wound.age = NAN;
    s.unc.age = 45; /* the age_slope age (lri-plan's patient) when wound.age is not given */
    s.wound.months = NAN;
    CHECK_NEAR(kt_scene_wound_k(&s), 0.3 * exp(0.005 * 15), 1e-14, "k follows the age_slope age");
    reject("wound_unit", "model: eye\nwound:\n  bridge_stiffness: 1 MPa\n", 3, 21, "expected a stiffness per area");
    reject("wound_state", "model: eye\nwound:\n  state: open\n", 3, 10, "expected one of: immediate, healed");
}

int main(void)
{
    snprintf(dir, sizeof dir, "/tmp/kt-scene-XXXXXX");
    if (!mkdtemp(dir)) {
        perror("mkdtemp");
        return 1;
    }
    test_units();
    test_eye_plan();
    test_beam_plans();
    test_bad_scenes();
    test_floor();
    test_wtw();
    test_on_mesh();
    test_wound();
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    if (system(cmd) != 0) fprintf(stderr, "could not remove %s\n", dir);
    return kt_test_done("test_scene");
}
