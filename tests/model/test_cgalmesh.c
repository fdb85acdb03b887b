/* test_cgalmesh.c: CGAL Mesh_3 on real inputs (the Stanford bunny surface, a labelled CT liver)
 * checked against independent readings of the same files: enclosed volume by the divergence
 * theorem on the OFF triangles, labelled volume by counting voxels. Skips in a build without
 * CGAL. */
#define _GNU_SOURCE
#include "cgalmesh.h"
#include "kt_test.h"

#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define BUNNY "share/data/bunny00.off"
#define LIVER "share/data/liver.inr.gz"

/* Bunny sizes (file units; the surface spans about 1 x 1 x 0.8): about 20,000 nodes, close to
 * the paper's 20,133-node bunny. */
#define BUNNY_H 0.0205
#define BUNNY_FD 0.0015

/* ---------- independent readers ---------- */

/* Volume enclosed by an OFF triangle surface: sum of a . (b x c) / 6 over its triangles. */
static double off_volume(const char *path, int *ntri)
{
    FILE *f = fopen(path, "r");
    char magic[8] = "";
    int nv = 0, nf = 0, ne = 0;
    double vol = 0;
    *ntri = 0;
    if (!f) return 0;
    if (fscanf(f, "%7s %d %d %d", magic, &nv, &nf, &ne) != 4 || strcmp(magic, "OFF") || nv <= 0) {
        fclose(f);
        return 0;
    }
    double *x = calloc(3 * (size_t)nv, sizeof *x);
    for (int i = 0; x && i < 3 * nv; i++)
        if (fscanf(f, "%lf", &x[i]) != 1) nf = 0;
    for (int i = 0; x && i < nf; i++) {
        int k, a, b, c;
        if (fscanf(f, "%d %d %d %d", &k, &a, &b, &c) != 4 || k != 3) break;
        const double *p = x + 3 * a, *q = x + 3 * b, *r = x + 3 * c;
        vol += (p[0] * (q[1] * r[2] - q[2] * r[1]) - p[1] * (q[0] * r[2] - q[2] * r[0]) +
                p[2] * (q[0] * r[1] - q[1] * r[0])) / 6;
        (*ntri)++;
    }
    free(x);
    fclose(f);
    return vol;
}

/* Voxel counts per label of an 8-bit INR image, read through gzip; 0 on success. */
static int inr_histogram(const char *path, long count[256], double voxel[3])
{
    char cmd[512], hdr[257], *all = NULL;
    snprintf(cmd, sizeof cmd, "gzip -dc '%s'", path);
    FILE *f = popen(cmd, "r");
    if (!f) return 1;
    size_t len = 0;
    long dim[3] = {0, 0, 0};
    int ok = 0;
    /* The header is a multiple of 256 bytes ending with "##}\n". */
    while (fread(hdr, 1, 256, f) == 256) {
        hdr[256] = 0;
        char *grown = realloc(all, len + 257);
        if (!grown) break;
        all = grown;
        memcpy(all + len, hdr, 257);
        len += 256;
        if (strstr(all, "##}")) {
            ok = 1;
            break;
        }
    }
    if (ok) {
        const char *key[6] = {"XDIM=", "YDIM=", "ZDIM=", "VX=", "VY=", "VZ="};
        for (int i = 0; i < 6; i++) {
            const char *s = strstr(all, key[i]);
            if (!s) ok = 0;
            else if (i < 3) dim[i] = atol(s + strlen(key[i]));
            else voxel[i - 3] = atof(s + strlen(key[i]));
        }
        ok = ok && strstr(all, "PIXSIZE=8 bits") && strstr(all, "TYPE=unsigned fixed");
    }
    free(all);
    memset(count, 0, 256 * sizeof count[0]);
    long n = ok ? dim[0] * dim[1] * dim[2] : 0, got = 0;
    unsigned char buf[65536];
    size_t r;
    while (n && (r = fread(buf, 1, sizeof buf, f)) > 0)
        for (size_t i = 0; i < r && got < n; i++, got++) count[buf[i]]++;
    pclose(f);
    return !(ok && got == n);
}

/* ---------- mesh measurements ---------- */

static double mesh_volume(const kt_mesh *m, int tag, int *nonpositive)
{
    double v = 0;
    *nonpositive = 0;
    for (int i = 0; i < m->ne; i++) {
        if (tag && m->tet_tag[i] != tag) continue;
        const int *t = m->tet + 4 * (size_t)i;
        double vi = kt_tet_volume(m->xyz + 3 * t[0], m->xyz + 3 * t[1], m->xyz + 3 * t[2],
                                  m->xyz + 3 * t[3]);
        *nonpositive += !(vi > 0);
        v += vi;
    }
    return v;
}

static double dihedral(const double *a, const double *b, const double *c, const double *d)
{
    double u[3], v[3], w[3], n1[3], n2[3];
    for (int i = 0; i < 3; i++) {
        u[i] = b[i] - a[i];
        v[i] = c[i] - a[i];
        w[i] = d[i] - a[i];
    }
    n1[0] = u[1] * v[2] - u[2] * v[1], n1[1] = u[2] * v[0] - u[0] * v[2];
    n1[2] = u[0] * v[1] - u[1] * v[0];
    n2[0] = u[1] * w[2] - u[2] * w[1], n2[1] = u[2] * w[0] - u[0] * w[2];
    n2[2] = u[0] * w[1] - u[1] * w[0];
    double dot = n1[0] * n2[0] + n1[1] * n2[1] + n1[2] * n2[2];
    double nn = sqrt((n1[0] * n1[0] + n1[1] * n1[1] + n1[2] * n1[2]) *
                     (n2[0] * n2[0] + n2[1] * n2[1] + n2[2] * n2[2]));
    return acos(fmax(-1, fmin(1, dot / nn))) * 180 / M_PI;
}

/* Smallest dihedral angle (degrees) over all tets: the angle at edge ab between faces abc, abd. */
static double min_dihedral(const kt_mesh *m)
{
    static const int E[6][4] = {{0, 1, 2, 3}, {0, 2, 1, 3}, {0, 3, 1, 2},
                                {1, 2, 0, 3}, {1, 3, 0, 2}, {2, 3, 0, 1}};
    double mn = 180;
    for (int t = 0; t < m->ne; t++)
        for (int k = 0; k < 6; k++) {
            const int *q = m->tet + 4 * (size_t)t;
            double a = dihedral(m->xyz + 3 * q[E[k][0]], m->xyz + 3 * q[E[k][1]],
                                m->xyz + 3 * q[E[k][2]], m->xyz + 3 * q[E[k][3]]);
            mn = fmin(mn, a);
        }
    return mn;
}

/* A tet face as its sorted node triple and the tet's region tag. */
typedef struct face {
    int v[3], tag;
} face;

static int cmp_face(const void *x, const void *y)
{
    const face *a = x, *b = y;
    for (int i = 0; i < 3; i++)
        if (a->v[i] != b->v[i]) return (a->v[i] > b->v[i]) - (a->v[i] < b->v[i]);
    return 0;
}

static void sort3(int *v)
{
    for (int i = 0; i < 2; i++)
        for (int j = 0; j < 2 - i; j++)
            if (v[j] > v[j + 1]) {
                int t = v[j];
                v[j] = v[j + 1];
                v[j + 1] = t;
            }
}

/* Boundary check: every triangle must be a face of one tet, or of two tets of different
 * regions, and every such tet face must be listed (the boundary is complete). *outer_vol is the
 * volume the outer triangles (faces of one tet) enclose as oriented (divergence theorem).
 * Returns the number of triangles failing. */
static int check_boundary_faces(const kt_mesh *m, int *listed_ok, int *expected,
                                double *outer_vol)
{
    size_t nface = 4 * (size_t)m->ne;
    face *f = calloc(nface, sizeof *f);
    if (!f) return -1;
    for (int t = 0; t < m->ne; t++)
        for (int k = 0; k < 4; k++) {
            face *g = &f[4 * (size_t)t + k];
            for (int j = 0, n = 0; j < 4; j++)
                if (j != k) g->v[n++] = m->tet[4 * (size_t)t + j];
            sort3(g->v);
            g->tag = m->tet_tag[t];
        }
    qsort(f, nface, sizeof *f, cmp_face);
    *expected = 0;
    for (size_t i = 0; i < nface;) {
        size_t j = i + 1;
        while (j < nface && cmp_face(&f[i], &f[j]) == 0) j++;
        *expected += (j - i == 1) || (j - i == 2 && f[i].tag != f[i + 1].tag);
        i = j;
    }
    int bad = 0;
    *listed_ok = 0;
    *outer_vol = 0;
    for (int i = 0; i < m->nf; i++) {
        face key;
        memcpy(key.v, m->tri + 3 * (size_t)i, sizeof key.v);
        sort3(key.v);
        face *hit = bsearch(&key, f, nface, sizeof *f, cmp_face);
        if (!hit) {
            bad++;
            continue;
        }
        while (hit > f && cmp_face(hit - 1, &key) == 0) hit--;
        int mult = 1;
        while (hit + mult < f + nface && cmp_face(hit + mult, &key) == 0) mult++;
        int good = mult == 1 || (mult == 2 && hit[0].tag != hit[1].tag);
        bad += !good;
        *listed_ok += good;
        const double *x = m->xyz, o[3] = {0, 0, 0};
        const int *t = m->tri + 3 * (size_t)i;
        if (mult == 1) *outer_vol += kt_tet_volume(o, x + 3 * t[0], x + 3 * t[1], x + 3 * t[2]);
    }
    free(f);
    return bad;
}

static int all_nodes_used(const kt_mesh *m)
{
    char *used = calloc((size_t)m->nn, 1);
    int n = 0;
    if (!used) return 0;
    for (size_t k = 0; k < 4 * (size_t)m->ne; k++) used[m->tet[k]] = 1;
    for (int i = 0; i < m->nn; i++) n += used[i];
    free(used);
    return n == m->nn;
}

/* ---------- tests ---------- */

static void write_file(const char *path, const char *text)
{
    FILE *f = fopen(path, "w");
    if (f) {
        fputs(text, f);
        fclose(f);
    }
}

/* Bad inputs are KT_EINPUT errors naming the file. */
static void test_errors(const char *dir)
{
    char open_off[512], crossed[512];
    snprintf(open_off, sizeof open_off, "%s/open.off", dir);
    snprintf(crossed, sizeof crossed, "%s/crossed.off", dir);
    /* A tetrahedron with one face missing: manifold, but with a hole. */
    write_file(open_off, "OFF\n4 3 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n");
    /* Two closed tetrahedra passing through each other. */
    write_file(crossed, "OFF\n8 8 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n"
                        "0.2 0.2 0.2\n1.2 0.2 0.2\n0.2 1.2 0.2\n0.2 0.2 1.2\n"
                        "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n"
                        "3 4 6 5\n3 4 5 7\n3 4 7 6\n3 5 6 7\n");
    kt_mesh m;
    kt_err e = {0};
    int rc = kt_cgal_mesh_surface(open_off, 0.1, 0.01, 0.1, &m, &e);
    CHECK(rc == KT_EINPUT && strstr(e.msg, "not closed") && strstr(e.msg, open_off), "%d %s", rc,
          e.msg);
    kt_err e2 = {0};
    rc = kt_cgal_mesh_surface(crossed, 0.1, 0.01, 0.1, &m, &e2);
    CHECK(rc == KT_EINPUT && strstr(e2.msg, "intersects itself"), "%d %s", rc, e2.msg);
    kt_err e3 = {0};
    rc = kt_cgal_mesh_surface(BUNNY, 0.1, -1, 0.1, &m, &e3);
    CHECK(rc == KT_EINPUT && strstr(e3.msg, "positive"), "%d %s", rc, e3.msg);
    kt_err e4 = {0};
    rc = kt_cgal_mesh_image("/nonexistent/x.inr", 1, 1, 1, &m, &e4);
    CHECK(rc == KT_EINPUT && strstr(e4.msg, "/nonexistent/x.inr"), "%d %s", rc, e4.msg);
    kt_err e5 = {0};
    rc = kt_cgal_mesh_image(open_off, 1, 1, 1, &m, &e5);
    CHECK(rc == KT_EINPUT, "%d %s", rc, e5.msg);
    CHECK(m.nn == 0 && m.ne == 0 && m.xyz == NULL, "a failed call leaves an empty mesh");
    unlink(open_off);
    unlink(crossed);
}

/* A unit cube as ASCII STL (12 triangles, outward): tests the STL path and repeatability. */
static void test_stl_cube(const char *dir)
{
    static const int q[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    char path[512];
    snprintf(path, sizeof path, "%s/cube.stl", dir);
    FILE *f = fopen(path, "w");
    if (!f) return;
    fprintf(f, "solid cube\n");
    for (int k = 0; k < 6; k++)
        for (int h = 0; h < 2; h++) {
            int c[3] = {q[k][0], q[k][1 + h], q[k][2 + h]};
            fprintf(f, "facet normal 0 0 0\nouter loop\n");
            for (int j = 0; j < 3; j++)
                fprintf(f, "vertex %d %d %d\n", c[j] & 1, (c[j] >> 1) & 1, (c[j] >> 2) & 1);
            fprintf(f, "endloop\nendfacet\n");
        }
    fprintf(f, "endsolid cube\n");
    fclose(f);
    kt_mesh a, b;
    kt_err e = {0};
    int rc = kt_cgal_mesh_surface(path, 0.2, 0.01, 0.2, &a, &e);
    CHECK(rc == 0, "cube: %s", e.msg);
    if (rc == 0) {
        int bad;
        double v = mesh_volume(&a, 0, &bad);
        /* Unprotected edges are approximated by facets within facet_distance: a little less. */
        CHECK(bad == 0 && v < 1 && v > 0.95, "cube volume %g, %d bad tets", v, bad);
        kt_err e2 = {0};
        rc = kt_cgal_mesh_surface(path, 0.2, 0.01, 0.2, &b, &e2);
        int same = rc == 0 && a.nn == b.nn && a.ne == b.ne && a.nf == b.nf &&
                   !memcmp(a.xyz, b.xyz, 3 * sizeof(double) * (size_t)a.nn) &&
                   !memcmp(a.tet, b.tet, 4 * sizeof(int) * (size_t)a.ne);
        CHECK(same, "meshing the cube twice gave different meshes (%d/%d nodes)", a.nn, b.nn);
        printf("cube (STL): %d nodes, %d tets, volume %.4f, repeatable %s\n", a.nn, a.ne, v,
               same ? "yes" : "NO");
        kt_mesh_free(&b);
    }
    kt_mesh_free(&a);
    unlink(path);
}

static void test_bunny(void)
{
    int ntri;
    double v_surf = off_volume(BUNNY, &ntri);
    CHECK(ntri == 75408 && v_surf > 0, "bunny OFF read independently: %d triangles", ntri);
    kt_mesh m;
    kt_err e = {0};
    double t0 = kt_now();
    int rc = kt_cgal_mesh_surface(BUNNY, BUNNY_H, BUNNY_FD, BUNNY_H, &m, &e);
    double t = kt_now() - t0;
    CHECK(rc == 0, "bunny: %s", e.msg);
    if (rc) return;
    kt_err ec = {0};
    CHECK(kt_mesh_check(&m, "bunny", &ec) == 0, "%s", ec.msg);
    const kt_group *body = kt_mesh_find_group(&m, 3, "body");
    const kt_group *bnd = kt_mesh_find_group(&m, 2, "boundary");
    CHECK(body && body->tag == 1 && bnd && bnd->tag == 1, "groups body/boundary with tag 1");
    CHECK(m.nn > 15000 && m.nn < 25000, "about 20,000 nodes: %d", m.nn);
    CHECK(all_nodes_used(&m), "every node belongs to a tet");
    int bad;
    double v = mesh_volume(&m, 0, &bad);
    CHECK(bad == 0, "%d tets with volume <= 0", bad);
    CHECK(fabs(v - v_surf) <= 0.02 * v_surf, "tet volume %.6f vs %.6f enclosed by the OFF surface",
          v, v_surf);
    int listed_ok, expected;
    double v_out;
    int fails = check_boundary_faces(&m, &listed_ok, &expected, &v_out);
    CHECK(fabs(v_out - v) <= 1e-9 * v, "boundary triangles enclose %.12g, tets %.12g (outward?)",
          v_out, v);
    CHECK(fails == 0 && listed_ok == m.nf && expected == m.nf,
          "%d boundary triangles: %d not a face of exactly one tet; %d open tet faces", m.nf,
          fails, expected);
    double dmin = min_dihedral(&m);
    CHECK(dmin > 5, "min dihedral angle %.2f deg", dmin);
    printf("bunny: h %g, %d nodes, %d tets, %d boundary triangles, %.1f s; volume %.6f vs "
           "surface %.6f (%+.2f%%); min dihedral %.2f deg\n",
           BUNNY_H, m.nn, m.ne, m.nf, t, v, v_surf, 100 * (v - v_surf) / v_surf, dmin);
    kt_mesh_free(&m);
}

static void test_liver(void)
{
    long count[256];
    double vx[3] = {0, 0, 0};
    CHECK(inr_histogram(LIVER, count, vx) == 0, "liver INR read independently");
    double voxel = vx[0] * vx[1] * vx[2];
    kt_mesh m;
    kt_err e = {0};
    double t0 = kt_now();
    int rc = kt_cgal_mesh_image(LIVER, 6, 2, 8, &m, &e);
    double t = kt_now() - t0;
    CHECK(rc == 0, "liver: %s", e.msg);
    if (rc) return;
    kt_err ec = {0};
    CHECK(kt_mesh_check(&m, "liver", &ec) == 0, "%s", ec.msg);
    const kt_group *bnd = kt_mesh_find_group(&m, 2, "boundary");
    CHECK(bnd && bnd->tag == 1, "boundary group with tag 1");
    int bad;
    double vall = mesh_volume(&m, 0, &bad);
    CHECK(bad == 0, "%d tets with volume <= 0", bad);
    long nlab = 0;
    for (int l = 1; l < 256; l++) nlab += count[l];
    printf("liver: %d nodes, %d tets, %d boundary triangles, %.1f s; min dihedral %.2f deg\n",
           m.nn, m.ne, m.nf, t, min_dihedral(&m));
    printf("liver: all labels: mesh %.0f mm^3, voxels %.0f mm^3 %+.2f%%\n", vall, nlab * voxel,
           100 * (vall - nlab * voxel) / (nlab * voxel));
    CHECK_NEAR(vall, nlab * voxel, 0.03, "volume of all labels");
    /* Each region is a label of the image; the large ones must come back within 3%. */
    for (int g = 0; g < m.ng; g++) {
        if (m.group[g].dim != 3) continue;
        int l = m.group[g].tag;
        char name[KT_NAME_MAX];
        snprintf(name, sizeof name, "label-%d", l);
        CHECK(l > 0 && l < 256 && count[l] > 0 && !strcmp(name, m.group[g].name),
              "region %s (tag %d) is a label of the image", m.group[g].name, l);
        if (l <= 0 || l >= 256) continue;
        double vl = mesh_volume(&m, l, &bad), vv = count[l] * voxel;
        printf("liver: label %d: mesh %.0f mm^3, voxels %.0f mm^3 (%ld) %+.2f%%\n", l, vl, vv,
               count[l], 100 * (vl - vv) / vv);
        if (count[l] > 100000) CHECK_NEAR(vl, vv, 0.03, name);
    }
    /* Every label larger than a few mesh cells (8 mm: about 500 voxels) is present. */
    for (int l = 1; l < 256; l++) {
        char name[KT_NAME_MAX];
        snprintf(name, sizeof name, "label-%d", l);
        if (count[l] > 1000)
            CHECK(kt_mesh_find_group(&m, 3, name) != NULL, "%s (%ld voxels) missing", name,
                  count[l]);
    }
    int listed_ok, expected;
    double v_out;
    int fails = check_boundary_faces(&m, &listed_ok, &expected, &v_out);
    CHECK(fails == 0 && listed_ok == m.nf && expected == m.nf,
          "%d boundary triangles: %d not on the region boundary; %d expected", m.nf, fails,
          expected);
    CHECK_NEAR(v_out, vall, 1e-9, "outer boundary triangles enclose all tets, outward");
    kt_mesh_free(&m);
}

int main(void)
{
    kt_mesh m;
    kt_err e = {0};
    kt_cgal_mesh_surface("/nonexistent/probe.off", 1, 1, 1, &m, &e);
    if (strstr(e.msg, "no CGAL")) {
        printf("test_cgal: CGAL is absent in this build (KT_WITH_CGAL=OFF); skipping\n");
        return kt_test_done("test_cgalmesh");
    }
    CHECK(e.code == KT_EINPUT && strstr(e.msg, "/nonexistent/probe.off"), "%s", e.msg);
    char dir[] = "/tmp/kt_test_cgal_XXXXXX";
    if (!mkdtemp(dir)) {
        CHECK(0, "mkdtemp failed");
        return kt_test_done("test_cgalmesh");
    }
    test_errors(dir);
    test_stl_cube(dir);
    if (access(BUNNY, R_OK) == 0 && access(LIVER, R_OK) == 0) {
        test_bunny();
        test_liver();
    } else {
        CHECK(0, "%s or %s missing: run scripts/setup.sh", BUNNY, LIVER);
    }
    rmdir(dir);
    return kt_test_done("test_cgalmesh");
}
