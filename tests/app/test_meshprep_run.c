/* test_meshprep_run.c: element quality against analytic tets, 'below' groups, the box build
 * with its fixed face, and the ordering set. */
#define _POSIX_C_SOURCE 200809L
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "grid.h"
#include "kt_test.h"
#include "bind.h"
#include "build.h"
#include "orderset.h"
#include "quality.h"


/* A one-tet mesh on the given vertices. */
static void one_tet(kt_mesh *m, const double x[12])
{
    memset(m, 0, sizeof *m);
    m->order = 1;
    m->nn = 4;
    m->ne = 1;
    m->xyz = malloc(sizeof(double) * 12);
    memcpy(m->xyz, x, sizeof(double) * 12);
    m->tet = malloc(sizeof(int) * 4);
    for (int i = 0; i < 4; i++) m->tet[i] = i;
    m->tet_tag = calloc(1, sizeof(int));
}

static void test_quality(void)
{
    kt_mesh m;
    kt_quality q;
    /* Regular tet: every dihedral angle acos(1/3) = 70.53 deg, radius ratio 1. */
    double reg[12] = {1, 1, 1, 1, -1, -1, -1, 1, -1, -1, -1, 1};
    one_tet(&m, reg);
    kt_mesh_quality(&m, &q);
    double dih = acos(1.0 / 3.0) * 180 / KT_PI;
    CHECK_NEAR(q.dihedral_min, dih, 1e-12, "regular min dihedral");
    CHECK_NEAR(q.dihedral_max, dih, 1e-12, "regular max dihedral");
    CHECK_NEAR(q.ratio_min, 1.0, 1e-12, "regular radius ratio");
    kt_mesh_free(&m);
    /* Corner tet (0, e1, e2, e3): dihedrals 90 (three) and acos(1/sqrt3) = 54.74 deg (three);
     * r_in = 1 / (3 + sqrt 3), r_circ = sqrt(3)/2. */
    double corner[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
    one_tet(&m, corner);
    kt_mesh_quality(&m, &q);
    CHECK_NEAR(q.dihedral_min, acos(1 / sqrt(3.0)) * 180 / KT_PI, 1e-12, "corner min dihedral");
    CHECK_NEAR(q.dihedral_max, 90, 1e-12, "corner max dihedral");
    CHECK_NEAR(q.ratio_min, 3 * (1 / (3 + sqrt(3.0))) / (sqrt(3.0) / 2), 1e-12, "corner radius ratio");
    kt_mesh_free(&m);
    /* A flat sliver: four points near a square, dihedrals near 0 and 180. */
    double sliver[12] = {0, 0, 0, 1, 1, 0, 1, 0, 0.01, 0, 1, 0.01};
    one_tet(&m, sliver);
    kt_mesh_quality(&m, &q);
    CHECK(q.dihedral_min < 2 && q.dihedral_max > 178 && q.ratio_min < 0.05, "sliver %g %g %g",
          q.dihedral_min, q.dihedral_max, q.ratio_min);
    kt_mesh_free(&m);
}

/* Area of a group's triangles and the sign of their normals along an axis. */
static void group_area(const kt_mesh *m, const kt_group *g, int axis, double *area, double *signed_area)
{
    *area = *signed_area = 0;
    int nv = kt_tri_nv(m->order);
    for (int i = 0; i < m->nf; i++) {
        if (m->tri_tag[i] != g->tag) continue;
        const int *t = m->tri + nv * i;
        const double *a = m->xyz + 3 * t[0], *b = m->xyz + 3 * t[1], *c = m->xyz + 3 * t[2];
        double u[3], v[3], n[3];
        for (int k = 0; k < 3; k++) u[k] = b[k] - a[k], v[k] = c[k] - a[k];
        n[0] = u[1] * v[2] - u[2] * v[1];
        n[1] = u[2] * v[0] - u[0] * v[2];
        n[2] = u[0] * v[1] - u[1] * v[0];
        *area += 0.5 * sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        *signed_area += 0.5 * n[axis];
    }
}

static void test_below(void)
{
    kt_mesh m;
    kt_err e = {0};
    kt_grid_box(&m, 4, 5, 6, 3, 4, 5, &e);
    int nf0 = m.nf;
    /* Faces with every vertex at y <= 0.5: only the ymin face (3 x 5 mm), outward = -y. */
    CHECK(kt_build_below_group(&m, "feet", 1, 0.5, &e) == 0, "%s", e.msg);
    const kt_group *g = kt_mesh_find_group(&m, 2, "feet");
    CHECK(g && m.nf == nf0 + 2 * 3 * 5, "feet: %d new triangles", m.nf - nf0);
    double area, sa;
    if (g) {
        group_area(&m, g, 1, &area, &sa);
        CHECK_NEAR(area, 15, 1e-12, "feet area");
        CHECK_NEAR(sa, -15, 1e-12, "feet face outwards (-y)");
    }
    CHECK(kt_mesh_check(&m, "below", &e) == 0, "%s", e.msg);
    kt_err e2 = {0};
    CHECK(kt_build_below_group(&m, "nothing", 2, -1, &e2) == KT_EINPUT, "empty group accepted");
    kt_err e3 = {0};
    CHECK(kt_build_below_group(&m, "feet", 2, 1, &e3) == KT_EINPUT, "duplicate name accepted");
    kt_mesh_free(&m);
}

static void write_file(const char *path, const char *text)
{
    FILE *f = fopen(path, "w");
    if (f) {
        fputs(text, f);
        fclose(f);
    }
}

static void test_box_build(const char *dir)
{
    char path[128];
    snprintf(path, sizeof path, "%s/b.yaml", dir);
    write_file(path, "model: box\norder: 2\nbox: {nodes: [3, 3, 5], size: [1 mm, 1 mm, 2 mm], fixed: xmax}\n"
                     "ordering: {last: zmin, halo: 0}\nmaterials: {body: {E: 1 MPa, nu: 0.3}}\n");
    kt_scene s;
    kt_err e = {0};
    CHECK(kt_scene_load(path, &s, &e) == 0, "%s", e.msg);
    kt_mesh m;
    CHECK(kt_build_mesh(&s, s.order, 1, &m, &e) == 0, "%s", e.msg);
    if (e.code) return;
    /* P2 nodes: 45 vertices plus one per edge of the P1 grid (counted on a fresh copy). */
    kt_mesh p1;
    kt_grid_box(&p1, 3, 3, 5, 1, 1, 2, &e);
    int edges = 0;
    for (int a = 0; a < p1.nn; a++)
        for (int b = a + 1; b < p1.nn; b++) {
            int shared = 0;
            for (int t = 0; t < p1.ne && !shared; t++) {
                int ha = 0, hb = 0;
                for (int k = 0; k < 4; k++) ha |= p1.tet[4 * t + k] == a, hb |= p1.tet[4 * t + k] == b;
                shared = ha && hb;
            }
            edges += shared;
        }
    CHECK(m.order == 2 && m.nn == 45 + edges, "P2 nodes %d, want %d", m.nn, 45 + edges);
    kt_mesh_free(&p1);
    const kt_group *fixed = kt_mesh_find_group(&m, 2, "fixed");
    CHECK(fixed && !kt_mesh_find_group(&m, 2, "xmax"), "xmax renamed to fixed");
    double area, sa;
    if (fixed) {
        group_area(&m, fixed, 0, &area, &sa);
        CHECK_NEAR(area, 2.0, 1e-12, "fixed face area");
    }
    kt_fem_problem fp;
    CHECK(kt_fem_bind(&s, &m, &fp, &e) == 0, "%s", e.msg);
    const unsigned char *fx = fp.fixed;
    int bad = 0, cnt = 0;
    for (int i = 0; i < m.nn; i++) {
        cnt += fx[3 * i];
        bad += fx[3 * i] != (fabs(m.xyz[3 * i] - 1.0) < 1e-12);
    }
    CHECK(bad == 0 && cnt > 0, "fixed nodes are those at x = 1 (%d wrong of %d)", bad, cnt);
    kt_fem_problem_free(&fp);
    int *set = NULL, nset = 0;
    char label[160];
    CHECK(kt_orderset_nodes(&s, &m, &set, &nset, label, &e) == 0 && nset == 25, "zmin set %d nodes (P2: 5x5)", nset);
    CHECK(strstr(label, "zmin") != NULL, "label %s", label);
    free(set);
    /* One halo layer: the nodes of the tets touching zmin, i.e. every node with z <= 0.5. */
    s.ordering_halo = 1;
    CHECK(kt_orderset_nodes(&s, &m, &set, &nset, label, &e) == 0, "%s", e.msg);
    int low = 0, inlow = 0;
    for (int i = 0; i < m.nn; i++) low += m.xyz[3 * i + 2] <= 0.5 + 1e-12;
    for (int k = 0; k < nset; k++) inlow += m.xyz[3 * set[k] + 2] <= 0.5 + 1e-12;
    CHECK(nset == low && inlow == nset, "halo set %d nodes, %d with z <= 0.5", nset, low);
    free(set);
    kt_mesh_free(&m);
}

int main(void)
{
    char dir[] = "/tmp/kt-prep-XXXXXX";
    if (!mkdtemp(dir)) return 1;
    test_quality();
    test_below();
    test_box_build(dir);
    char cmd[64];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    if (system(cmd) != 0) fprintf(stderr, "could not remove %s\n", dir);
    return kt_test_done("test_meshprep_run");
}
