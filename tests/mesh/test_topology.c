/* test_topology.c: the tet face and edge tables against geometry (outward normals, P2
 * midpoints made by kt_mesh_elevate), node -> tet adjacency against a brute-force scan, and
 * the sorted face table against the box's known boundary. */
#include <stdlib.h>
#include <string.h>

#include "grid.h"
#include "kt_test.h"
#include "mesh.h"
#include "predicates.h"
#include "topology.h"

static const double *X(const kt_mesh *m, int v) { return m->xyz + 3 * (size_t)v; }

/* Every face of every (positive) tet: the opposite vertex lies on the inner side of the face's
 * right-hand normal, decided exactly; the face does not hold its opposite vertex. */
static void test_face_orientation(void)
{
    kt_mesh m;
    kt_err e = {0};
    CHECK(kt_grid_box(&m, 3, 4, 3, 2.0, 3.0, 1.5, &e) == 0, "%s", e.msg);
    if (e.code) return;
    int bad_sign = 0, bad_opp = 0, neg = 0;
    for (int t = 0; t < m.ne; t++) {
        const int *v = m.tet + 4 * (size_t)t;
        if (kt_pred_orient3d(X(&m, v[0]), X(&m, v[1]), X(&m, v[2]), X(&m, v[3])) != 1) neg++;
        for (int f = 0; f < 4; f++) {
            const int *fv = kt_tet_face[f];
            bad_opp += fv[0] == f || fv[1] == f || fv[2] == f;
            /* outward normal: the opposite vertex is on the negative side */
            if (kt_pred_orient3d(X(&m, v[fv[0]]), X(&m, v[fv[1]]), X(&m, v[fv[2]]), X(&m, v[f])) != -1)
                bad_sign++;
        }
    }
    CHECK(neg == 0, "%d box tets not positive", neg);
    CHECK(bad_opp == 0, "%d faces hold their opposite vertex", bad_opp);
    CHECK(bad_sign == 0, "%d of %d face normals point inward", bad_sign, 4 * m.ne);
    /* the reference tet, with the normal computed in doubles: n . (centroid_f - x_f) > 0 */
    double P[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    CHECK(kt_tet_volume(P[0], P[1], P[2], P[3]) > 0, "reference tet positive");
    for (int f = 0; f < 4; f++) {
        const double *a = P[kt_tet_face[f][0]], *b = P[kt_tet_face[f][1]], *c = P[kt_tet_face[f][2]];
        double u[3], w[3], n[3], d = 0;
        for (int i = 0; i < 3; i++) u[i] = b[i] - a[i], w[i] = c[i] - a[i];
        n[0] = u[1] * w[2] - u[2] * w[1];
        n[1] = u[2] * w[0] - u[0] * w[2];
        n[2] = u[0] * w[1] - u[1] * w[0];
        for (int i = 0; i < 3; i++) d += n[i] * ((a[i] + b[i] + c[i]) / 3 - P[f][i]);
        CHECK(d > 0, "face %d of the reference tet: n . outward = %g", f, d);
    }
    /* the six edges are the six distinct vertex pairs */
    int seen[4][4] = {{0}};
    for (int k = 0; k < 6; k++) {
        int a = kt_tet_edge[k][0], b = kt_tet_edge[k][1];
        if (a != b) seen[a < b ? a : b][a < b ? b : a]++;
    }
    int pairs = 0;
    for (int a = 0; a < 4; a++)
        for (int b = a + 1; b < 4; b++) pairs += seen[a][b] == 1;
    CHECK(pairs == 6, "tet edges cover %d of the 6 vertex pairs once", pairs);
    kt_mesh_free(&m);
}

/* kt_mesh_elevate puts the P2 node of tet edge k at local 4 + k, at the midpoint of the corners
 * kt_tet_edge[k]; triangles likewise with kt_tri_edge. */
static void test_edges_vs_elevate(void)
{
    kt_mesh m;
    kt_err e = {0};
    CHECK(kt_grid_box(&m, 3, 3, 4, 1.0, 2.0, 3.0, &e) == 0, "%s", e.msg);
    CHECK(kt_mesh_elevate(&m, &e) == 0 && m.order == 2, "%s", e.msg);
    if (e.code) return;
    int bad = 0, checked = 0;
    for (int t = 0; t < m.ne; t++) {
        const int *v = m.tet + 10 * (size_t)t;
        for (int k = 0; k < 6; k++) {
            const double *a = X(&m, v[kt_tet_edge[k][0]]), *b = X(&m, v[kt_tet_edge[k][1]]);
            const double *mid = X(&m, v[4 + k]);
            for (int i = 0; i < 3; i++) bad += fabs(mid[i] - 0.5 * (a[i] + b[i])) > 1e-14;
            checked++;
        }
    }
    CHECK(bad == 0 && checked == 6 * m.ne, "%d tet mid-edge coordinates off the midpoint", bad);
    int tbad = 0;
    for (int f = 0; f < m.nf; f++) {
        const int *v = m.tri + 6 * (size_t)f;
        for (int k = 0; k < 3; k++) {
            const double *a = X(&m, v[kt_tri_edge[k][0]]), *b = X(&m, v[kt_tri_edge[k][1]]);
            const double *mid = X(&m, v[3 + k]);
            for (int i = 0; i < 3; i++) tbad += fabs(mid[i] - 0.5 * (a[i] + b[i])) > 1e-14;
        }
    }
    CHECK(m.nf > 0 && tbad == 0, "%d triangle mid-edge coordinates off the midpoint", tbad);
    kt_mesh_free(&m);
}

/* Node -> tets against a scan of every tet, for order 1 and order 2. */
static void check_node_tets(const kt_mesh *m, const char *what)
{
    int *Ep = NULL, *Ei = NULL;
    kt_err e = {0};
    CHECK(kt_mesh_node_tets(m, &Ep, &Ei, &e) == 0, "%s: %s", what, e.msg);
    if (e.code) return;
    int nv = kt_tet_nv(m->order), bad = 0, total = 0;
    for (int v = 0; v < m->nn; v++) {
        int k = Ep[v];
        for (int t = 0; t < m->ne; t++) {
            int has = 0;
            for (int a = 0; a < nv; a++) has |= m->tet[(size_t)t * nv + a] == v;
            if (!has) continue;
            total++;
            if (k >= Ep[v + 1] || Ei[k] != t) bad++;
            else k++;
        }
        if (k != Ep[v + 1]) bad++;
    }
    CHECK(Ep[0] == 0 && bad == 0 && Ep[m->nn] == total, "%s: %d mismatches, %d entries (want %d)", what, bad,
          Ep[m->nn], total);
    free(Ep);
    free(Ei);
}

static void test_node_tets(void)
{
    kt_mesh m;
    kt_err e = {0};
    CHECK(kt_grid_box(&m, 4, 3, 5, 3.0, 2.0, 4.0, &e) == 0, "%s", e.msg);
    if (e.code) return;
    check_node_tets(&m, "order 1");
    /* node 0, the box's corner, is on the main diagonal of cell (0,0,0): in its six tets,
     * which the grid numbers first */
    int *Ep, *Ei;
    if (kt_mesh_node_tets(&m, &Ep, &Ei, &e) == 0) {
        int ok = 1;
        for (int k = Ep[0]; k < Ep[1]; k++) ok &= Ei[k] < 6;
        CHECK(ok && Ep[1] - Ep[0] == 6, "node 0 in %d tets (want the 6 of cell 0, all around its diagonal)", Ep[1] - Ep[0]);
        free(Ep);
        free(Ei);
    }
    CHECK(kt_mesh_elevate(&m, &e) == 0, "%s", e.msg);
    check_node_tets(&m, "order 2");
    kt_mesh_free(&m);
    /* a broken tet holding node 1 twice lists that tet once; node 3 is in no tet */
    int tet[8] = {0, 1, 1, 2, 2, 1, 0, 4};
    double xyz[15] = {0};
    kt_mesh b = {.order = 1, .nn = 5, .xyz = xyz, .ne = 2, .tet = tet};
    int *Bp, *Bi;
    CHECK(kt_mesh_node_tets(&b, &Bp, &Bi, &e) == 0, "%s", e.msg);
    if (!e.code) {
        int want_p[6] = {0, 2, 4, 6, 6, 7}, want_i[7] = {0, 1, 0, 1, 0, 1, 1};
        CHECK(memcmp(Bp, want_p, sizeof want_p) == 0 && memcmp(Bi, want_i, sizeof want_i) == 0,
              "repeated node: Ep %d %d %d %d %d %d", Bp[0], Bp[1], Bp[2], Bp[3], Bp[4], Bp[5]);
        free(Bp);
        free(Bi);
    }
}

/* The sorted face table of a box: interior faces twice, boundary faces once; the boundary is
 * the box's 4 (ab + bc + ca) triangles, which are exactly the grid's surface triangles. */
static void test_tet_faces(void)
{
    int nx = 4, ny = 3, nz = 5;
    kt_mesh m;
    kt_err e = {0};
    CHECK(kt_grid_box(&m, nx, ny, nz, 3.0, 2.0, 4.0, &e) == 0, "%s", e.msg);
    if (e.code) return;
    kt_face *f = NULL;
    CHECK(kt_mesh_tet_faces(&m, &f, &e) == 0, "%s", e.msg);
    if (e.code) return;
    int nf = 4 * m.ne, once = 0, twice = 0, more = 0, unsorted = 0, badid = 0;
    for (int i = 0; i < nf;) {
        int j = i + 1;
        while (j < nf && kt_face_cmp_v(&f[i], &f[j]) == 0) j++;
        if (j - i == 1) once++;
        else if (j - i == 2) twice++;
        else more++;
        i = j;
    }
    for (int i = 0; i + 1 < nf; i++) unsorted += kt_face_cmp(&f[i], &f[i + 1]) >= 0;
    for (int i = 0; i < nf; i++) {
        int t = f[i].id / 4, j = f[i].id % 4, v[3];
        for (int k = 0; k < 3; k++) v[k] = m.tet[4 * (size_t)t + kt_tet_face[j][k]];
        kt_sort3(v);
        badid += memcmp(v, f[i].v, sizeof v) != 0 || !(f[i].v[0] < f[i].v[1] && f[i].v[1] < f[i].v[2]);
    }
    int a = nx - 1, b = ny - 1, c = nz - 1;
    int nbound = 4 * (a * b + b * c + c * a);
    CHECK(more == 0 && once == nbound, "boundary faces %d (want %d), faces in 3+ tets %d", once, nbound, more);
    CHECK(2 * twice + once == nf, "interior %d, boundary %d, total %d", twice, once, nf);
    /* interior faces by Euler on the cells: 6 tets a cell, 6 inner faces a cell, plus the
     * faces between cells: 2 triangles per shared cell face */
    int inner = 6 * a * b * c + 2 * ((a - 1) * b * c + a * (b - 1) * c + a * b * (c - 1));
    CHECK(twice == inner, "interior faces %d, want %d", twice, inner);
    CHECK(unsorted == 0 && badid == 0, "%d out of order, %d ids that do not give the face back", unsorted, badid);
    CHECK(m.nf == nbound, "the grid's surface triangles %d, boundary faces %d", m.nf, nbound);
    /* every surface triangle of the grid is a face of exactly one tet, found by kt_face_find */
    int notfound = 0, notonce = 0;
    for (int i = 0; i < m.nf; i++) {
        int v[3] = {m.tri[3 * i + 2], m.tri[3 * i], m.tri[3 * i + 1]};
        int k = kt_face_find(f, nf, v);
        if (k < 0) {
            notfound++;
            continue;
        }
        if ((k > 0 && kt_face_cmp_v(&f[k - 1], &f[k]) == 0) || (k + 1 < nf && kt_face_cmp_v(&f[k + 1], &f[k]) == 0))
            notonce++;
    }
    CHECK(notfound == 0 && notonce == 0, "surface triangles: %d not found, %d not a boundary face", notfound, notonce);
    /* kt_face_find returns the first of a pair, and -1 for a triple that is no face */
    int firsts = 0;
    for (int i = 0; i + 1 < nf; i++)
        if (kt_face_cmp_v(&f[i], &f[i + 1]) == 0) {
            int v[3] = {f[i].v[1], f[i].v[2], f[i].v[0]};
            firsts += kt_face_find(f, nf, v) == i;
        }
    CHECK(firsts == inner, "kt_face_find found the first of %d pairs of %d", firsts, inner);
    int none[3] = {0, m.nn - 1, m.nn / 2}, low[3] = {-3, -2, -1}, high[3] = {m.nn, m.nn + 1, m.nn + 2};
    CHECK(kt_face_find(f, nf, none) == -1, "corner-to-corner triple is no face");
    CHECK(kt_face_find(f, nf, low) == -1 && kt_face_find(f, nf, high) == -1, "out-of-range triples");
    CHECK(kt_face_find(f, 0, f[0].v) == -1, "empty table");
    free(f);
    kt_mesh_free(&m);
}

static void test_sort3(void)
{
    int p[6][3] = {{1, 2, 3}, {1, 3, 2}, {2, 1, 3}, {2, 3, 1}, {3, 1, 2}, {3, 2, 1}}, ok = 0;
    for (int i = 0; i < 6; i++) {
        kt_sort3(p[i]);
        ok += p[i][0] == 1 && p[i][1] == 2 && p[i][2] == 3;
    }
    int d[3] = {5, 2, 5};
    kt_sort3(d);
    CHECK(ok == 6 && d[0] == 2 && d[1] == 5 && d[2] == 5, "kt_sort3: %d of 6 permutations", ok);
}

int main(void)
{
    test_face_orientation();
    test_edges_vs_elevate();
    test_node_tets();
    test_tet_faces();
    test_sort3();
    return kt_test_done("test_topology");
}
