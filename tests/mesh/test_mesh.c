/* test_mesh.c: box grids, order elevation, renumbering and the structural check. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "grid.h"
#include "kt_test.h"

static double total_volume(const kt_mesh *m)
{
    int nv = kt_tet_nv(m->order);
    double v = 0;
    for (int i = 0; i < m->ne; i++) {
        const int *t = m->tet + (size_t)nv * i;
        v += kt_tet_volume(m->xyz + 3 * t[0], m->xyz + 3 * t[1], m->xyz + 3 * t[2], m->xyz + 3 * t[3]);
    }
    return v;
}

/* The content hash: a copy hashes alike, one changed coordinate or tet node does not, -0 and +0
 * are one value, and the FNV-1a constants give the published value for an empty input. */
static void test_hash(void)
{
    kt_err e = {0};
    kt_mesh a, b;
    CHECK(kt_grid_box(&a, 3, 3, 3, 1.0, 1.0, 1.0, &e) == 0 && kt_mesh_copy(&b, &a, &e) == 0, "%s", e.msg);
    uint64_t h = kt_mesh_hash(&a);
    CHECK(kt_mesh_hash(&b) == h, "a copy hashes alike");
    b.xyz[7] += 1e-12;
    CHECK(kt_mesh_hash(&b) != h, "a coordinate moved by 1e-12 mm changes the hash");
    b.xyz[7] = a.xyz[7];
    int i0 = -1;
    for (int i = 0; i < 3 * b.nn && i0 < 0; i++)
        if (b.xyz[i] == 0) i0 = i;
    b.xyz[i0] = -0.0;
    CHECK(i0 >= 0 && kt_mesh_hash(&b) == h, "-0 hashes as +0");
    int t = b.tet[0];
    b.tet[0] = b.tet[1], b.tet[1] = t;
    CHECK(kt_mesh_hash(&b) != h, "two nodes of a tet swapped change the hash");
    kt_mesh empty = {0};
    empty.order = 0;
    /* order, nn, ne all 0: FNV-1a of 12 zero bytes, computed by hand from the definition */
    uint64_t want = 14695981039346656037ull;
    for (int k = 0; k < 12; k++) want *= 1099511628211ull;
    CHECK(kt_mesh_hash(&empty) == want, "empty mesh: %016llx", (unsigned long long)kt_mesh_hash(&empty));
    kt_mesh_free(&a);
    kt_mesh_free(&b);
}

int main(void)
{
    test_hash();
    kt_err e = {0};
    kt_mesh m;
    CHECK(kt_grid_box(&m, 5, 5, 9, 1.0, 1.0, 2.0, &e) == 0, "%s", e.msg);
    CHECK(m.nn == 225 && m.ne == 6 * 4 * 4 * 8, "nn %d ne %d", m.nn, m.ne);
    CHECK_NEAR(total_volume(&m), 2.0, 1e-12, "box volume");
    CHECK(kt_mesh_check(&m, "box", &e) == 0, "%s", e.msg);

    /* Boundary triangles: every face of the box is covered, area 2*(1*1) + 4*(1*2) = 10. */
    double area = 0;
    for (int i = 0; i < m.nf; i++) {
        const double *a = m.xyz + 3 * m.tri[3 * i], *b = m.xyz + 3 * m.tri[3 * i + 1],
                     *c = m.xyz + 3 * m.tri[3 * i + 2];
        double u[3], v[3], n[3];
        for (int k = 0; k < 3; k++) u[k] = b[k] - a[k], v[k] = c[k] - a[k];
        n[0] = u[1] * v[2] - u[2] * v[1];
        n[1] = u[2] * v[0] - u[0] * v[2];
        n[2] = u[0] * v[1] - u[1] * v[0];
        area += 0.5 * sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    }
    CHECK_NEAR(area, 10.0, 1e-12, "box surface area");

    const kt_group *g = kt_mesh_find_group(&m, 2, "zmin");
    int *nodes = NULL, cnt = 0;
    CHECK(g && kt_mesh_group_nodes(&m, g, &nodes, &cnt, &e) == 0, "zmin group");
    CHECK(cnt == 25, "zmin has %d nodes", cnt);
    free(nodes);

    /* Reverse the numbering: volume and check survive, coordinates follow. */
    int *perm = malloc(sizeof(int) * m.nn);
    for (int i = 0; i < m.nn; i++) perm[i] = m.nn - 1 - i;
    double x0[3];
    memcpy(x0, m.xyz, sizeof x0);
    CHECK(kt_mesh_permute(&m, perm, &e) == 0, "%s", e.msg);
    CHECK(memcmp(m.xyz + 3 * (m.nn - 1), x0, sizeof x0) == 0, "permuted coordinates");
    CHECK_NEAR(total_volume(&m), 2.0, 1e-12, "permuted volume");
    free(perm);

    /* Elevation: edges of a 4x4x8-cell Kuhn grid; mid-nodes halfway. */
    int nn1 = m.nn;
    CHECK(kt_mesh_elevate(&m, &e) == 0, "%s", e.msg);
    CHECK(m.order == 2 && m.nn > nn1, "order %d nn %d", m.order, m.nn);
    int bad = 0;
    static const int EDGE[6][2] = {{0, 1}, {1, 2}, {2, 0}, {3, 0}, {3, 2}, {3, 1}};
    for (int i = 0; i < m.ne; i++)
        for (int j = 0; j < 6; j++) {
            const int *t = m.tet + 10 * i;
            for (int c = 0; c < 3; c++) {
                double mid = 0.5 * (m.xyz[3 * t[EDGE[j][0]] + c] + m.xyz[3 * t[EDGE[j][1]] + c]);
                if (fabs(mid - m.xyz[3 * t[4 + j] + c]) > 1e-14) bad++;
            }
        }
    CHECK(bad == 0, "%d misplaced mid-edge nodes", bad);
    CHECK(kt_mesh_check(&m, "p2 box", &e) == 0, "%s", e.msg);

    /* An inverted tet is reported, naming it. */
    int s = m.tet[10 * 7 + 1];
    m.tet[10 * 7 + 1] = m.tet[10 * 7 + 2];
    m.tet[10 * 7 + 2] = s;
    kt_err e2 = {0};
    CHECK(kt_mesh_check(&m, "box", &e2) == KT_ERUN && strstr(e2.msg, "tet 8 is inverted"), "%s", e2.msg);
    kt_mesh_free(&m);
    return kt_test_done("test_mesh");
}
