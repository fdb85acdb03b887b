/* test_bind.c: a box scene bound to its grid mesh: materials by region (named, then
 * 'default'), Dirichlet mask and values from the fixations, pressures by surface tag with
 * their resultant against the closed form p * area, and the input errors a binding reports. */
#define _POSIX_C_SOURCE 200809L
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "bind.h"
#include "grid.h"
#include "kt_test.h"
#include "scene.h"

static char dir[64];

static void write_scene(const char *name, const char *text, char *path)
{
    snprintf(path, 128, "%s/%s", dir, name);
    FILE *f = fopen(path, "w");
    if (!f) {
        perror(path);
        exit(1);
    }
    fputs(text, f);
    fclose(f);
}

/* Load a scene and the grid it describes. */
static int load(const char *name, const char *text, kt_scene *s, kt_mesh *m, char *path)
{
    kt_err e = {0};
    write_scene(name, text, path);
    CHECK(kt_scene_load(path, s, &e) == 0, "%s: %s", name, e.msg);
    if (e.code) return e.code;
    CHECK(kt_grid_box(m, s->box.n[0], s->box.n[1], s->box.n[2], s->box.len[0], s->box.len[1], s->box.len[2], &e) == 0,
          "%s", e.msg);
    return e.code;
}

static const char *BOX =
    "model: box\n"
    "box: {nodes: [4, 3, 5], size: [3 mm, 2 mm, 6 mm], fixed: none}\n"
    "materials:\n"
    "  default: {E: 2 kPa, nu: 0.3}\n"
    "  body: {E: 1.5 MPa, nu: 0.45}\n"
    "loads:\n"
    "  pressure:\n"
    "    - {surface: xmax, value: 15 mmHg}\n"
    "    - {surface: ymin, value: 2 kPa}\n"
    "    - {surface: xmax, value: -500 Pa}\n"
    "fixation:\n"
    "  - {surface: zmin, components: xyz, value: [0 mm, 0 mm, 0 mm]}\n"
    "  - {surface: zmax, components: y, value: [0 mm, 30 um, 0 mm]}\n";

static void test_box(void)
{
    kt_scene s;
    kt_mesh m;
    char path[128];
    if (load("box.yaml", BOX, &s, &m, path)) return;
    kt_fem_problem p;
    kt_err e = {0};
    CHECK(kt_fem_bind(&s, &m, &p, &e) == 0, "%s", e.msg);
    if (e.code) return;
    CHECK(p.nn == m.nn && p.nn == 60, "nn %d", p.nn);
    /* a named region wins over 'default' */
    const kt_group *body = kt_mesh_find_group(&m, 3, "body");
    CHECK(body && p.mats.nmat > body->tag, "nmat %d", p.mats.nmat);
    if (body && p.mats.nmat > body->tag) {
        CHECK_NEAR(p.mats.mat[body->tag].E, 1.5, 1e-15, "body E, MPa");
        CHECK_NEAR(p.mats.mat[body->tag].nu, 0.45, 1e-15, "body nu");
    }
    /* fixation: zmin all three, zmax y only with 0.030 mm */
    int bad = 0, nfixed = 0;
    for (int i = 0; i < m.nn; i++) {
        double z = m.xyz[3 * i + 2];
        int bottom = z == 0, top = z == 6;
        for (int c = 0; c < 3; c++) {
            int want = bottom || (top && c == 1);
            double gv = top && c == 1 && !bottom ? 0.030 : 0.0;
            nfixed += p.fixed[3 * i + c];
            bad += p.fixed[3 * i + c] != want;
            bad += fabs(p.g[3 * i + c] - gv) > 1e-15;
        }
    }
    CHECK(bad == 0 && nfixed == 12 * 3 + 12, "fixed DOFs %d, %d wrong", nfixed, bad);
    const kt_group *zmin = kt_mesh_find_group(&m, 2, "zmin"), *zmax = kt_mesh_find_group(&m, 2, "zmax");
    CHECK(p.nfix == 2 && zmin && zmax && p.fix[0].tag == zmin->tag && p.fix[0].mask == 7u &&
          p.fix[1].tag == zmax->tag && p.fix[1].mask == 2u && fabs(p.fix[1].v[1] - 0.030) < 1e-15,
          "fixation surfaces by tag");
    /* pressures by tag, in order, in MPa */
    const kt_group *xmax = kt_mesh_find_group(&m, 2, "xmax"), *ymin = kt_mesh_find_group(&m, 2, "ymin");
    CHECK(p.npress == 3 && xmax && ymin && p.press[0].tag == xmax->tag && p.press[1].tag == ymin->tag &&
          p.press[2].tag == xmax->tag, "pressure tags");
    CHECK_NEAR(p.press[0].p, 15 * 133.322387415e-6, 1e-12, "15 mmHg in MPa");
    CHECK_NEAR(p.press[1].p, 0.002, 1e-15, "2 kPa in MPa");
    CHECK_NEAR(p.press[2].p, -0.0005, 1e-15, "-500 Pa in MPa");

    /* loads = the sum of one kt_fem_pressure call per entry, scaled */
    size_t n = 3 * (size_t)m.nn;
    double *f = calloc(n, sizeof(double)), *ref = calloc(n, sizeof(double));
    if (!f || !ref) exit(1);
    double scale = 0.7;
    for (size_t i = 0; i < n; i++) f[i] = 99; /* overwritten, not added to */
    CHECK(kt_fem_problem_loads(&p, &m, scale, f, &e) == 0, "%s", e.msg);
    for (int i = 0; i < 3; i++) CHECK(kt_fem_pressure(&m, p.press[i].tag, scale * p.press[i].p, ref, &e) == 0, "%s", e.msg);
    double diff = 0, mag = 0;
    for (size_t i = 0; i < n; i++) diff = fmax(diff, fabs(f[i] - ref[i])), mag = fmax(mag, fabs(ref[i]));
    CHECK(mag > 0 && diff <= 1e-15 * mag, "loads differ from the sum of pressures by %.3g (max %.3g)", diff, mag);
    /* resultant: a pressure pushes into the solid, so on xmax (area 2 x 6) the force is -x,
     * on ymin (area 3 x 6) it is +y */
    double F[3] = {0, 0, 0};
    for (int i = 0; i < m.nn; i++)
        for (int c = 0; c < 3; c++) F[c] += f[3 * i + c];
    double px = 15 * 133.322387415e-6 - 0.0005;
    CHECK_NEAR(F[0], -scale * px * 12, 1e-12, "resultant x, N");
    CHECK_NEAR(F[1], scale * 0.002 * 18, 1e-12, "resultant y, N");
    CHECK_NEAR(F[2], 0, 1e-12, "resultant z, N");
    free(f);
    free(ref);
    kt_fem_problem_free(&p);
    CHECK(p.fixed == NULL && p.g == NULL && p.mats.mat == NULL, "free clears the struct");
    kt_mesh_free(&m);
}

/* 'default' alone covers the region; a region the scene does not name and no 'default' is an
 * input error naming the scene file and the region. */
static void test_default_and_missing_region(void)
{
    kt_scene s;
    kt_mesh m;
    char path[128];
    if (load("default.yaml",
             "model: box\nbox: {nodes: [2, 2, 2], fixed: zmin}\nmaterials: {default: {E: 2 kPa, nu: 0.3}}\n", &s, &m,
             path))
        return;
    kt_fem_problem p;
    kt_err e = {0};
    /* the grid names the fixed face zmin; the scene calls it 'fixed' as mesh-prep renames it */
    for (int i = 0; i < m.ng; i++)
        if (m.group[i].dim == 2 && strcmp(m.group[i].name, "zmin") == 0) strcpy(m.group[i].name, "fixed");
    CHECK(kt_fem_bind(&s, &m, &p, &e) == 0, "%s", e.msg);
    if (!e.code) {
        CHECK(p.mats.nmat == 2 && fabs(p.mats.mat[1].E - 0.002) < 1e-15 && p.mats.mat[1].nu == 0.3, "default material");
        int nf = 0;
        for (int i = 0; i < 3 * m.nn; i++) nf += p.fixed[i];
        CHECK(nf == 12, "default fixation of the fixed face: %d DOFs", nf);
        kt_fem_problem_free(&p);
    }
    /* a second region, 'lens', with no entry and no default */
    CHECK(kt_mesh_add_group(&m, 3, 2, "lens", &e) == 0, "%s", e.msg);
    m.tet_tag[0] = 2;
    strcpy(s.mat[0].region, "body");
    kt_err e2 = {0};
    CHECK(kt_fem_bind(&s, &m, &p, &e2) == KT_EINPUT, "rc %d", e2.code);
    CHECK(strncmp(e2.msg, path, strlen(path)) == 0 && strstr(e2.msg, "region 'lens'"), "'%s'", e2.msg);
    CHECK(p.fixed == NULL && p.g == NULL && p.mats.mat == NULL, "a failed binding holds nothing");
    kt_mesh_free(&m);
}

/* A pressure or fixation surface the mesh lacks: KT_EINPUT naming the file and the entry. */
static void test_missing_surface(void)
{
    kt_scene s;
    kt_mesh m;
    char path[128];
    if (load("missing.yaml", BOX, &s, &m, path)) return;
    kt_fem_problem p;
    /* the mesh loses its ymin group name: the second pressure cannot be bound */
    for (int i = 0; i < m.ng; i++)
        if (m.group[i].dim == 2 && strcmp(m.group[i].name, "ymin") == 0) strcpy(m.group[i].name, "side");
    kt_err e = {0};
    CHECK(kt_fem_bind(&s, &m, &p, &e) == KT_EINPUT, "rc %d", e.code);
    CHECK(strncmp(e.msg, path, strlen(path)) == 0 && strstr(e.msg, "loads.pressure[1]") && strstr(e.msg, "'ymin'"),
          "'%s'", e.msg);
    CHECK(p.fixed == NULL && p.g == NULL && p.mats.mat == NULL && p.npress == 0, "a failed binding holds nothing");
    /* a fixation surface */
    for (int i = 0; i < m.ng; i++)
        if (m.group[i].dim == 2 && strcmp(m.group[i].name, "zmax") == 0) strcpy(m.group[i].name, "top");
    kt_err e2 = {0};
    CHECK(kt_fem_bind(&s, &m, &p, &e2) == KT_EINPUT, "rc %d", e2.code);
    CHECK(strncmp(e2.msg, path, strlen(path)) == 0 && strstr(e2.msg, "fixation[1]") && strstr(e2.msg, "'zmax'"),
          "'%s'", e2.msg);
    CHECK(p.fixed == NULL && p.g == NULL && p.mats.mat == NULL, "a failed binding holds nothing");
    /* kt_fem_dirichlet alone reports the same */
    unsigned char *fixed = calloc(3 * (size_t)m.nn, 1);
    kt_err e3 = {0};
    CHECK(fixed && kt_fem_dirichlet(&s, &m, fixed, NULL, NULL, &e3) == KT_EINPUT && strstr(e3.msg, "'zmax'"), "'%s'",
          e3.msg);
    free(fixed);
    kt_mesh_free(&m);
}

int main(void)
{
    snprintf(dir, sizeof dir, "/tmp/kt-bind-XXXXXX");
    if (!mkdtemp(dir)) {
        perror("mkdtemp");
        return 1;
    }
    test_box();
    test_default_and_missing_region();
    test_missing_surface();
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    if (system(cmd) != 0) fprintf(stderr, "could not remove %s\n", dir);
    return kt_test_done("test_bind");
}
