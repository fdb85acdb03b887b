/* test_refgeom.c: the stress-free reference geometry (lib/fem/refgeom.h).
 *
 * Every check of the inverse is made with an independent forward solve (kt_fem_solve, a fresh
 * CHOLMOD factorization, not refgeom's preconditioned CG): loading the stress-free mesh must give
 * back the measured shape.
 *  - P1 eye (coarse, 1.5 D with-the-rule toric): X0 + u(X0) reproduces the measured coordinates
 *    within the tolerance (0.03 um) plus the forward solve's round-off, and the toric fit of the
 *    loaded anterior surface gives K = 337.5/R of the scene's radii within 0.02 D, axis within
 *    1 deg; the naive model (measured shape taken as stress-free) is off by more than 1 D.
 *  - A run that may not converge (2 solves) fails with KT_ERUN and leaves the mesh unchanged.
 *  - P2 box under an end pressure with a prescribed (non-zero) support displacement, through
 *    mesh-prep (kt_prep_run): the written, renumbered mesh loaded by a forward solve lands on
 *    the scene's grid; its summary reports the iteration.
 *  - No loads: nothing to do; loads.reference and reference_tolerance parse, bad ones are
 *    rejected with file:line:col. */
#define _POSIX_C_SOURCE 200809L
#include <cholmod.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "curv.h"
#include "bind.h"
#include "kt_test.h"
#include "msh.h"
#include "build.h"
#include "meshprep_run.h"
#include "refgeom.h"
#include "scene.h"

static char dir[64];

static void write_file(const char *name, const char *text, char *path)
{
    snprintf(path, 256, "%s/%s", dir, name);
    FILE *f = fopen(path, "w");
    if (f) {
        fputs(text, f);
        fclose(f);
    }
}

/* u under the scene's loads on m, by a plain direct solve. */
static int forward(const kt_scene *s, const kt_mesh *m, double *u, kt_err *e)
{
    size_t n = 3 * (size_t)m->nn;
    kt_fem_problem fp;
    double *f = calloc(n, sizeof(double));
    int rc = !f || kt_fem_bind(s, m, &fp, e);
    if (!rc) {
        rc = kt_fem_problem_loads(&fp, m, 1.0, f, e);
        cholmod_common c;
        cholmod_start(&c);
        if (!rc) rc = kt_fem_solve(m, &fp.mats, fp.fixed, fp.g, f, u, &c, e);
        cholmod_finish(&c);
        kt_fem_problem_free(&fp);
    }
    free(f);
    return rc;
}

/* Largest |X + u - Xm| over all nodes (or the listed ones), mm. */
static double shape_error(const kt_mesh *m, const double *u, const double *Xm, const int *nodes, int cnt)
{
    double emax = 0;
    int n = nodes ? cnt : m->nn;
    for (int k = 0; k < n; k++) {
        int v = nodes ? nodes[k] : k;
        double d2 = 0;
        for (int c = 0; c < 3; c++) {
            double d = m->xyz[3 * v + c] + u[3 * v + c] - Xm[3 * v + c];
            d2 += d * d;
        }
        emax = fmax(emax, sqrt(d2));
    }
    return emax;
}

/* Keratometry of the anterior surface at X + u (toric fit, 3 mm zone). */
static int kerato(const kt_mesh *m, const double *u, kt_kerato *k, kt_err *e)
{
    const kt_group *g = kt_mesh_find_group(m, 2, "anterior");
    int *nodes = NULL, cnt = 0;
    if (!g || kt_mesh_group_nodes(m, g, &nodes, &cnt, e)) return 1;
    double *p = malloc(sizeof(double) * 3 * (size_t)cnt);
    for (int i = 0; i < cnt; i++)
        for (int c = 0; c < 3; c++) p[3 * i + c] = m->xyz[3 * nodes[i] + c] + u[3 * nodes[i] + c];
    kt_fit fit;
    int rc = kt_curv_fit(p, cnt, KT_FIT_TORIC, 6, 3.0, 0, 0, &fit, NULL, 0, e);
    if (!rc) kt_curv_simk(&fit, k);
    free(p);
    free(nodes);
    return rc;
}

static const char *EYE =
    "name: eye-refgeom\n"
    "model: eye\n"
    "order: 1\n"
    "eye:\n"
    "  anterior_radius_steep: 7.667 mm\n"
    "  anterior_radius_flat: 7.938 mm\n"
    "  steep_axis: 90 deg\n"
    "  mesh_size: {optical_zone: 0.216 mm, incision: 0.3 mm, cornea: 0.216 mm, sclera: 2.5 mm}\n"
    "materials:\n" /* the stress-free iteration is isotropic only */
    "  cornea: {E: 0.3 MPa, nu: 0.49}\n"
    "  limbus: {E: 1.0 MPa, nu: 0.49}\n"
    "loads:\n"
    "  pressure: {surface: inner, value: 15 mmHg}\n"
    "  reference: loaded\n";

static void test_eye(void)
{
    char path[256];
    write_file("eye.yaml", EYE, path);
    kt_scene *s = calloc(1, sizeof *s);
    kt_err e = {0};
    kt_mesh m = {0};
    CHECK(kt_scene_load(path, s, &e) == 0, "%s", e.msg);
    CHECK(s->reference == KT_REFERENCE_LOADED && fabs(s->reference_tol - 3e-5) < 1e-15, "defaults");
    if (e.code || kt_build_mesh(s, 1, 1, &m, &e)) {
        CHECK(0, "eye build: %s", e.msg);
        free(s);
        return;
    }
    size_t n = 3 * (size_t)m.nn;
    double *Xm = malloc(n * sizeof(double)), *u = calloc(n, sizeof(double));
    memcpy(Xm, m.xyz, n * sizeof(double));
    const kt_group *ga = kt_mesh_find_group(&m, 2, "anterior");
    int *ant = NULL, nant = 0;
    kt_mesh_group_nodes(&m, ga, &ant, &nant, &e);
    double k_steep = 337.5 / 7.667, k_flat = 337.5 / 7.938;

    /* The naive model: the measured shape loaded again. */
    kt_kerato k;
    CHECK(forward(s, &m, u, &e) == 0 && kerato(&m, u, &k, &e) == 0, "naive: %s", e.msg);
    double naive = shape_error(&m, u, Xm, ant, nant);
    CHECK(naive > 0.05 && fabs(k.k_mean - 0.5 * (k_steep + k_flat)) > 1.0,
          "the measured shape taken as stress-free is far off: %.1f um, mean K %.2f D", 1000 * naive, k.k_mean);

    /* Too few solves: a loud failure, the mesh untouched. */
    kt_refgeom_opts o;
    kt_refgeom_stats st;
    kt_refgeom_opts_default(s, &o);
    o.quiet = 1;
    o.maxit = 2;
    kt_err e2 = {0};
    CHECK(kt_refgeom_unload(s, &m, &o, &st, &e2) == KT_ERUN && strstr(e2.msg, "did not converge"),
          "2 solves: %s", e2.msg);
    CHECK(memcmp(m.xyz, Xm, n * sizeof(double)) == 0, "mesh unchanged after a failure");

    /* The real thing. */
    kt_refgeom_opts_default(s, &o);
    o.quiet = 1;
    CHECK(kt_refgeom_unload(s, &m, &o, &st, &e) == 0, "unload: %s", e.msg);
    CHECK(st.residual <= o.tol && st.iters > 1 && st.shift > 0.05, "stats: %d solves, %.3g um, shift %.1f um",
          st.iters, 1000 * st.residual, 1000 * st.shift);
    CHECK(st.initial > 10 * o.tol && st.initial > 10 * st.residual,
          "initial shape error recorded and reduced: %.3g um -> %.3g um", 1000 * st.initial,
          1000 * st.residual);
    memset(u, 0, n * sizeof(double));
    CHECK(forward(s, &m, u, &e) == 0, "forward: %s", e.msg);
    double err_all = shape_error(&m, u, Xm, NULL, 0), err_ant = shape_error(&m, u, Xm, ant, nant);
    /* 0.03 um plus the forward solve's round-off against refgeom's CG (1e-11 relative) */
    CHECK(err_all <= o.tol + 1e-6, "loaded stress-free mesh vs measured: %.4g um everywhere", 1000 * err_all);
    CHECK(err_ant <= o.tol + 1e-6, "anterior surface: %.4g um", 1000 * err_ant);
    CHECK(kerato(&m, u, &k, &e) == 0, "fit: %s", e.msg);
    CHECK(fabs(k.k_steep - k_steep) <= 0.02, "K steep %.4f D vs %.4f D", k.k_steep, k_steep);
    CHECK(fabs(k.k_flat - k_flat) <= 0.02, "K flat %.4f D vs %.4f D", k.k_flat, k_flat);
    CHECK(fabs(k.axis_steep - 90) <= 1, "steep axis %.2f deg", k.axis_steep);
    /* Fixed nodes keep their place. */
    kt_fem_problem fp;
    CHECK(kt_fem_bind(s, &m, &fp, &e) == 0, "%s", e.msg);
    double fixmove = 0;
    for (size_t i = 0; fp.fixed && i < n; i++)
        if (fp.fixed[i]) fixmove = fmax(fixmove, fabs(m.xyz[i] - Xm[i]));
    CHECK(fixmove == 0, "fixed nodes moved %.3g mm", fixmove);
    kt_fem_problem_free(&fp);
    free(ant);
    free(Xm);
    free(u);
    kt_mesh_free(&m);
    free(s);
}

/* P2 box 1 x 1 x 2 mm: zmin pushed down 0.01 mm, 0.05 MPa on zmax (E 1 MPa): ~5% strain. */
static const char *BOX =
    "model: box\n"
    "order: 2\n"
    "box: {nodes: [3, 3, 5], size: [1 mm, 1 mm, 2 mm], fixed: zmin}\n"
    "materials:\n"
    "  body: {E: 1 MPa, nu: 0.45}\n"
    "loads:\n"
    "  pressure: {surface: zmax, value: 0.05 MPa}\n"
    "  reference_tolerance: 0.001 um\n"
    "fixation:\n"
    "  - {surface: fixed, components: xyz, value: [0 mm, 0 mm, -0.01 mm]}\n";

static void test_box_prep(void)
{
    char path[256], out[256], sum[256];
    write_file("box.yaml", BOX, path);
    snprintf(out, sizeof out, "%s/box.msh", dir);
    snprintf(sum, sizeof sum, "%s/summary.txt", dir);
    kt_prep_opts o = {0};
    o.scene = path;
    o.out = out;
    o.quiet = 1;
    kt_err e = {0};
    FILE *f = fopen(sum, "w");
    CHECK(f && kt_prep_run(&o, f, &e) == 0, "mesh-prep: %s", e.msg);
    if (f) fclose(f);
    char text[8192] = "";
    f = fopen(sum, "r");
    if (f) {
        size_t len = fread(text, 1, sizeof text - 1, f);
        text[len] = '\0';
        fclose(f);
    }
    CHECK(strstr(text, "reference    stress-free shape") && strstr(text, "residual max |X0 + u(X0) - X_measured|"),
          "summary reports the reference geometry:\n%s", text);
    kt_scene *s = calloc(1, sizeof *s);
    kt_mesh m = {0};
    CHECK(kt_scene_load(path, s, &e) == 0 && kt_msh_read(out, &m, &e) == 0, "%s", e.msg);
    if (e.code) {
        free(s);
        return;
    }
    CHECK(m.order == 2 && fabs(s->reference_tol - 1e-6) < 1e-18, "P2 mesh, tolerance read in um");
    double *u = calloc(3 * (size_t)m.nn, sizeof(double));
    CHECK(forward(s, &m, u, &e) == 0, "forward: %s", e.msg);
    /* Loaded, every node (mid-edge ones too) sits on the scene's grid of half spacings
     * (0.25 mm in x, y, 0.25 mm in z): the measured shape. */
    double err = 0, moved = 0;
    for (int v = 0; v < m.nn; v++)
        for (int c = 0; c < 3; c++) {
            double x = m.xyz[3 * v + c] + u[3 * v + c];
            err = fmax(err, fabs(x - 0.25 * round(x / 0.25)));
            moved = fmax(moved, fabs(m.xyz[3 * v + c] - 0.25 * round(m.xyz[3 * v + c] / 0.25)));
        }
    CHECK(err <= 1e-6 + 1e-9, "loaded P2 box off the grid by %.3g um", 1000 * err);
    CHECK(moved > 0.005, "the stress-free box differs from the grid (%.3g mm)", moved);
    free(u);
    kt_mesh_free(&m);
    free(s);
}

static void test_no_loads(void)
{
    char path[256];
    write_file("beam.yaml", "model: box\nbox: {nodes: [2, 2, 3]}\n", path);
    kt_scene *s = calloc(1, sizeof *s);
    kt_err e = {0};
    kt_mesh m = {0};
    CHECK(kt_scene_load(path, s, &e) == 0 && kt_build_mesh(s, 1, 1, &m, &e) == 0, "%s", e.msg);
    double x0 = m.nn ? m.xyz[3 * (m.nn - 1)] : 0;
    kt_refgeom_opts o;
    kt_refgeom_stats st;
    kt_refgeom_opts_default(s, &o);
    CHECK(kt_refgeom_unload(s, &m, &o, &st, &e) == 0 && st.iters == 0 && m.xyz[3 * (m.nn - 1)] == x0,
          "no loads: %d solves", st.iters);
    kt_mesh_free(&m);
    free(s);
}

static void reject(const char *loads, int line, int col, const char *what)
{
    char text[512], path[256];
    snprintf(text, sizeof text, "model: eye\nloads:\n%s", loads);
    write_file("bad.yaml", text, path);
    kt_scene *s = calloc(1, sizeof *s);
    kt_err e = {0};
    char where[300];
    snprintf(where, sizeof where, "%s:%d:%d:", path, line, col);
    CHECK(kt_scene_load(path, s, &e) == KT_EINPUT && strstr(e.msg, where) && strstr(e.msg, what),
          "expected '%s ... %s', got '%s'", where, what, e.msg);
    free(s);
}

static void test_parse(void)
{
    char path[256];
    write_file("unl.yaml", "model: eye\nloads:\n  reference: unloaded\n  pressure: {surface: inner, value: 2 kPa}\n",
               path);
    kt_scene *s = calloc(1, sizeof *s);
    kt_err e = {0};
    CHECK(kt_scene_load(path, s, &e) == 0 && s->reference == KT_REFERENCE_UNLOADED && s->npressure == 1,
          "unloaded: %s", e.msg);
    free(s);
    reject("  reference: sideways\n", 3, 14, "expected one of");
    reject("  reference_tolerance: 5\n", 3, 24, "reference_tolerance");
    reject("  reference_tolerance: 0 um\n", 3, 24, "reference_tolerance");
}

int main(void)
{
    snprintf(dir, sizeof dir, "/tmp/kt_refgeom_XXXXXX");
    if (!mkdtemp(dir)) {
        perror("mkdtemp");
        return 1;
    }
    test_parse();
    test_no_loads();
    test_box_prep();
    test_eye();
    const char *names[] = {"eye.yaml", "box.yaml", "box.msh", "summary.txt", "beam.yaml", "bad.yaml", "unl.yaml"};
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) {
        char p[256];
        snprintf(p, sizeof p, "%s/%s", dir, names[i]);
        unlink(p);
    }
    rmdir(dir);
    return kt_test_done("test_refgeom");
}
