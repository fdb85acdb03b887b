/* test_vtk.c: legacy VTK write/read-back (ASCII and big-endian binary, P1 and P2 tets,
 * POLYDATA), the gmsh -> VTK quadratic-tet node order checked geometrically, hand-written
 * files from other writers' habits, and malformed or truncated files.
 *
 * Extra mode for tests/interop.sh:
 *   test_vtk --samples DIR   write vtk-p1.vtk, vtk-p1-bin.vtk, vtk-p2.vtk, vtk-p2-bin.vtk,
 *                            surf.vtk, surf-bin.vtk with analytic fields (see sample_fields),
 *                            and the same tet meshes as vtk-p1.msh, vtk-p2.msh */
#define _GNU_SOURCE /* mkdtemp */
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "grid.h"
#include "kt_test.h"
#include "msh.h"
#include "vtk.h"

static char tmpdir[64];

static const char *tmp(const char *name)
{
    static char buf[8][256];
    static int k;
    k = (k + 1) % 8;
    snprintf(buf[k], sizeof buf[k], "%s/%s", tmpdir, name);
    return buf[k];
}

/* A fresh file each time: truncating one in place makes ext4 flush it on close. */
static void write_text(const char *path, const char *s, size_t n)
{
    unlink(path);
    FILE *f = fopen(path, "wb");
    if (!f) return;
    fwrite(s, 1, n, f);
    fclose(f);
}

static char *read_all(const char *path, size_t *n)
{
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    fseek(f, 0, SEEK_END);
    long len = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *b = malloc((size_t)len + 1);
    *n = fread(b, 1, (size_t)len, f);
    b[*n] = '\0';
    fclose(f);
    return b;
}

/* Box with regions 1 (centroid x < 0.5) and 2, coordinates perturbed by irrational amounts. */
static int box(kt_mesh *m, int n, int order, kt_err *e)
{
    if (kt_grid_box(m, n, n, n + 1, 1.0, 0.8, 1.3, e) || kt_mesh_add_group(m, 3, 2, "right", e))
        return e->code;
    for (int i = 0; i < m->ne; i++) {
        double cx = 0;
        for (int j = 0; j < 4; j++) cx += 0.25 * m->xyz[3 * m->tet[4 * i + j]];
        if (cx > 0.5) m->tet_tag[i] = 2;
    }
    for (int i = 0; i < 3 * m->nn; i++) m->xyz[i] += 1e-3 * sin(1.0 + i) / 3.0;
    return order == 2 ? kt_mesh_elevate(m, e) : KT_OK;
}

/* The analytic sample fields (tests/interop.sh recomputes them):
 * displacement = (1e-3 sin 3x, x y z, z^2/4 - y), origin = node number + 1,
 * on cells: volume (double), parity = i % 3 (int), and sym6 (6 components, written as a FIELD
 * array): component k of cell i = i % 7 + k / 8. */
typedef struct fields {
    double *disp, *origin, *vol, *parity, *sym6;
    kt_vtk_field f[5];
} fields;

static void sample_fields(fields *F, const kt_mesh *m)
{
    F->disp = malloc(sizeof(double) * 3 * (size_t)m->nn);
    F->origin = malloc(sizeof(double) * (size_t)m->nn);
    F->vol = malloc(sizeof(double) * (size_t)m->ne);
    F->parity = malloc(sizeof(double) * (size_t)m->ne);
    F->sym6 = malloc(sizeof(double) * 6 * (size_t)m->ne);
    for (int i = 0; i < m->nn; i++) {
        const double *x = m->xyz + 3 * i;
        F->disp[3 * i] = 1e-3 * sin(3 * x[0]);
        F->disp[3 * i + 1] = x[0] * x[1] * x[2];
        F->disp[3 * i + 2] = 0.25 * x[2] * x[2] - x[1];
        F->origin[i] = i + 1;
    }
    int nv = kt_tet_nv(m->order);
    for (int i = 0; i < m->ne; i++) {
        const int *t = m->tet + (size_t)nv * i;
        F->vol[i] = kt_tet_volume(m->xyz + 3 * t[0], m->xyz + 3 * t[1], m->xyz + 3 * t[2], m->xyz + 3 * t[3]);
        F->parity[i] = i % 3;
        for (int k = 0; k < 6; k++) F->sym6[6 * i + k] = i % 7 + k / 8.0;
    }
    F->f[0] = (kt_vtk_field){"displacement", 3, 0, 0, F->disp};
    F->f[1] = (kt_vtk_field){"origin", 1, 0, 1, F->origin};
    F->f[2] = (kt_vtk_field){"volume", 1, 1, 0, F->vol};
    F->f[3] = (kt_vtk_field){"parity", 1, 1, 1, F->parity};
    F->f[4] = (kt_vtk_field){"sym6", 6, 1, 0, F->sym6};
}

static void free_fields(fields *F)
{
    free(F->disp);
    free(F->origin);
    free(F->vol);
    free(F->parity);
    free(F->sym6);
}

static int same_field(const kt_vtk *v, const kt_vtk_field *want, int count)
{
    const kt_vtk_field *f = kt_vtk_find(v, want->name, want->on_cells);
    return f && f->ncomp == want->ncomp && f->is_int == want->is_int &&
           memcmp(f->v, want->v, sizeof(double) * (size_t)count * want->ncomp) == 0;
}

/* VTK_QUADRATIC_TETRA: node 4+k is the midpoint of edge k = 01 12 20 03 13 23. */
static double vtk_midedge_dev(const kt_vtk *v)
{
    static const int ed[6][2] = {{0, 1}, {1, 2}, {2, 0}, {0, 3}, {1, 3}, {2, 3}};
    double dev = 0;
    for (int c = 0; c < v->ncell; c++) {
        const int *t = v->conn + v->cell_ptr[c];
        for (int k = 0; k < 6; k++)
            for (int d = 0; d < 3; d++) {
                double mid = 0.5 * (v->xyz[3 * t[ed[k][0]] + d] + v->xyz[3 * t[ed[k][1]] + d]);
                dev = fmax(dev, fabs(mid - v->xyz[3 * t[4 + k] + d]));
            }
    }
    return dev;
}

static void tets_round_trip(int order)
{
    kt_err e = {0};
    kt_mesh m;
    CHECK(box(&m, 4, order, &e) == KT_OK, "%s", e.msg);
    fields F;
    sample_fields(&F, &m);
    int nv = kt_tet_nv(order);
    for (int bin = 0; bin <= 1; bin++) {
        char name[64];
        snprintf(name, sizeof name, "tets-p%d-%s.vtk", order, bin ? "bin" : "ascii");
        CHECK(kt_vtk_write_tets(tmp(name), &m, F.f, 5, bin, &e) == KT_OK, "%s: %s", name, e.msg);
        kt_vtk v;
        CHECK(kt_vtk_read(tmp(name), &v, &e) == KT_OK, "%s: read: %s", name, e.msg);
        if (e.code) continue;
        struct stat st;
        stat(tmp(name), &st);
        printf("%s: %lld bytes, nn %d ne %d\n", name, (long long)st.st_size, m.nn, m.ne);
        CHECK(!v.is_polydata && v.nn == m.nn && v.ncell == m.ne, "%s: counts %d %d", name, v.nn, v.ncell);
        if (v.nn != m.nn || v.ncell != m.ne) continue;
        CHECK(memcmp(v.xyz, m.xyz, sizeof(double) * 3 * (size_t)m.nn) == 0, "%s: points exact", name);
        int types = 1, ptr = 1, vert = 1;
        for (int c = 0; c < v.ncell; c++) {
            types &= v.cell_type[c] == (order == 2 ? 24 : 10);
            ptr &= v.cell_ptr[c + 1] - v.cell_ptr[c] == nv;
            for (int j = 0; j < 4; j++) vert &= v.conn[v.cell_ptr[c] + j] == m.tet[(size_t)nv * c + j];
        }
        CHECK(types && ptr && vert, "%s: cell types %d, sizes %d, vertices %d", name, types, ptr, vert);
        if (order == 2) CHECK(vtk_midedge_dev(&v) < 1e-15, "%s: quadratic tet mid-edge nodes off by %g", name, vtk_midedge_dev(&v));
        const kt_vtk_field *reg = kt_vtk_find(&v, "region", 1);
        int reg_ok = reg && reg->is_int && reg->ncomp == 1;
        for (int c = 0; reg_ok && c < m.ne; c++) reg_ok = reg->v[c] == m.tet_tag[c];
        CHECK(reg_ok, "%s: CELL_DATA region equals tet_tag", name);
        for (int k = 0; k < 5; k++)
            CHECK(same_field(&v, &F.f[k], F.f[k].on_cells ? m.ne : m.nn), "%s: field %s", name, F.f[k].name);
        CHECK(kt_vtk_find(&v, "stress", 0) == NULL, "%s: missing field is NULL", name);
        CHECK(kt_vtk_find(&v, "displacement", 1) == NULL, "%s: point field not found on cells", name);
        kt_vtk_free(&v);
    }
    free_fields(&F);
    kt_mesh_free(&m);
}

static void poly_round_trip(void)
{
    kt_err e = {0};
    kt_mesh m;
    box(&m, 3, 1, &e);
    double *h = malloc(sizeof(double) * (size_t)m.nn), *side = malloc(sizeof(double) * (size_t)m.nf);
    for (int i = 0; i < m.nn; i++) h[i] = m.xyz[3 * i + 2];
    for (int i = 0; i < m.nf; i++) side[i] = m.tri_tag[i];
    kt_vtk_field f[2] = {{"height", 1, 0, 0, h}, {"side", 1, 1, 1, side}};
    for (int bin = 0; bin <= 1; bin++) {
        const char *p = tmp(bin ? "surf-bin.vtk" : "surf.vtk");
        CHECK(kt_vtk_write_polydata(p, m.nn, m.xyz, m.nf, m.tri, f, 2, bin, &e) == KT_OK, "%s", e.msg);
        kt_vtk v;
        CHECK(kt_vtk_read(p, &v, &e) == KT_OK, "%s", e.msg);
        if (e.code) continue;
        CHECK(v.is_polydata && v.nn == m.nn && v.ncell == m.nf, "polydata counts");
        int ok = v.ncell == m.nf;
        for (int c = 0; ok && c < v.ncell; c++)
            ok = v.cell_type[c] == 5 && v.cell_ptr[c] == 3 * c &&
                 memcmp(v.conn + 3 * c, m.tri + 3 * c, 3 * sizeof(int)) == 0;
        CHECK(ok, "polydata %s: triangles", bin ? "binary" : "ASCII");
        CHECK(same_field(&v, &f[0], m.nn) && same_field(&v, &f[1], m.nf), "polydata fields");
        CHECK(kt_vtk_find(&v, "region", 1) == NULL, "polydata has no region");
        kt_vtk_free(&v);
    }
    free(h);
    free(side);
    kt_mesh_free(&m);
}

/* Written by hand in the styles of other writers: float points, a quad and a triangle, SCALARS
 * without LOOKUP_TABLE, FIELD arrays, METADATA, lower-case keywords, dataset FIELD data. */
static const char *foreign_poly =
    "# vtk DataFile Version 4.2\n"
    "\n"
    "ASCII\n"
    "DATASET POLYDATA\n"
    "FIELD FieldData 1\nTIME 1 1 double\n2.5\n"
    "POINTS 5 float\n0 0 0  1 0 0  1 1 0\n0 1 0  0.5 0.5 1\n"
    "METADATA\nINFORMATION 0\n\n"
    "POLYGONS 2 9\n4 0 1 2 3\n3 0 1 4\n"
    "point_data 5\n"
    "SCALARS temp float\n1.5 2.5 3.5 4.5 5.5\n"
    "FIELD FieldData 2\nid 1 5 int\n7 8 9 10 11\nflow 2 5 double\n0 1 2 3 4 5 6 7 8 9\n"
    "CELL_DATA 2\n"
    "VECTORS n int\n0 0 1\n0 -1 0\n";

static void test_foreign(void)
{
    kt_err e = {0};
    kt_vtk v;
    write_text(tmp("foreign.vtk"), foreign_poly, strlen(foreign_poly));
    CHECK(kt_vtk_read(tmp("foreign.vtk"), &v, &e) == KT_OK, "%s", e.msg);
    if (e.code) return;
    static const int ptr[3] = {0, 4, 7}, conn[7] = {0, 1, 2, 3, 0, 1, 4}, type[2] = {7, 5};
    CHECK(v.is_polydata && v.nn == 5 && v.ncell == 2 && v.nfield == 4, "counts %d %d %d", v.nn, v.ncell, v.nfield);
    if (v.ncell != 2) return;
    CHECK(v.xyz[12] == 0.5 && v.xyz[14] == 1.0, "float points");
    CHECK(!memcmp(v.cell_ptr, ptr, sizeof ptr) && !memcmp(v.conn, conn, sizeof conn) &&
          !memcmp(v.cell_type, type, sizeof type), "polygon and triangle");
    const kt_vtk_field *t = kt_vtk_find(&v, "temp", 0), *id = kt_vtk_find(&v, "id", 0),
                       *fl = kt_vtk_find(&v, "flow", 0), *n = kt_vtk_find(&v, "n", 1);
    CHECK(t && !t->is_int && t->v[4] == 5.5, "SCALARS without LOOKUP_TABLE");
    CHECK(id && id->is_int && id->v[0] == 7 && id->v[4] == 11, "FIELD int array");
    CHECK(fl && fl->ncomp == 2 && fl->v[9] == 9, "FIELD 2-component array");
    CHECK(n && n->is_int && n->ncomp == 3 && n->v[2] == 1 && n->v[4] == -1, "cell VECTORS int");
    CHECK(kt_vtk_find(&v, "TIME", 0) == NULL && kt_vtk_find(&v, "TIME", 1) == NULL, "dataset FIELD dropped");
    kt_vtk_free(&v);
}

static char *replace(const char *s, const char *old, const char *new)
{
    const char *at = strstr(s, old);
    char *out = malloc(strlen(s) + strlen(new) + 1);
    size_t k = (size_t)(at - s);
    memcpy(out, s, k);
    strcpy(out + k, new);
    strcat(out, at + strlen(old));
    return out;
}

static void expect_error(const char *label, const char *text, const char *want)
{
    kt_err e = {0};
    kt_vtk v;
    const char *p = tmp("bad.vtk");
    write_text(p, text, strlen(text));
    int rc = kt_vtk_read(p, &v, &e);
    CHECK(rc == KT_EINPUT, "%s: code %d (%s)", label, rc, e.msg);
    CHECK(strncmp(e.msg, p, strlen(p)) == 0 && strstr(e.msg, want), "%s: message '%s' lacks '%s'", label, e.msg, want);
    CHECK(v.nn == 0 && v.xyz == NULL && v.field == NULL, "%s: result left empty", label);
    if (rc == KT_OK) kt_vtk_free(&v);
}

static void test_malformed(void)
{
    char *t;
    char *t1 = replace(foreign_poly, "POLYGONS 2 9", "POLYGONS 2 10");
    t = replace(t1, "3 0 1 4\n", "3 0 1 4 4\n");
    expect_error("cell size", t, "POLYGONS: 2 cells use 9 of the 10 integers declared");
    free(t);
    free(t1);
    t = replace(foreign_poly, "POLYGONS 2 9", "POLYGONS 2 8");
    expect_error("cell overflow", t, "POLYGONS: cell 1 does not fit in the 8 integers declared");
    free(t);
    t = replace(foreign_poly, "0 1 0  0.5", "0 1 0  zz");
    expect_error("bad number", t, ":10:8: expected a number for POINTS");
    free(t);
    t = replace(foreign_poly, "point_data 5", "point_data 6");
    expect_error("count mismatch", t, ":17:1: point_data 6 does not match the 5 points");
    free(t);
    t = replace(foreign_poly, "DATASET POLYDATA", "DATASET STRUCTURED_POINTS");
    expect_error("dataset", t, "expected DATASET UNSTRUCTURED_GRID or POLYDATA");
    free(t);
    t = replace(foreign_poly, "Version 4.2", "Version 5.1");
    expect_error("version 5.1", t, "version 5.1 (OFFSETS/CONNECTIVITY) is not supported");
    free(t);
    t = replace(foreign_poly, "4 0 1 2 3", "4 0 1 2 5");
    expect_error("point range", t, "cell 0 refers to point 5 of 5");
    free(t);
    t = replace(foreign_poly, "SCALARS temp float", "SCALARS temp quaternion");
    expect_error("type", t, "expected a data type (double, float, int, ...), found 'quaternion'");
    free(t);
    expect_error("not vtk", "solid cube\nendsolid\n", ":1:1: expected '# vtk DataFile Version x.y'");
    kt_err e = {0};
    kt_vtk v;
    CHECK(kt_vtk_read(tmp("none.vtk"), &v, &e) == KT_EINPUT && strstr(e.msg, "cannot open"), "%s", e.msg);
}

/* A prefix may read as a valid file only if it stops just before a section keyword or, in
 * ASCII (which has no end marker), inside the last number of a block. */
static int at_section(const char *all, size_t len, int bin)
{
    const char *rest = all + len;
    if (!bin && len > 0 && all[len - 1] != '\n' && all[len - 1] != ' ')
        while (*rest && *rest != '\n' && *rest != ' ') rest++;
    while (*rest == '\n' || *rest == ' ') rest++;
    static const char *kw[] = {"CELLS ",   "CELL_DATA ", "POINT_DATA ", "SCALARS ",
                               "VECTORS ", "FIELD ",     "POLYGONS "};
    if (!*rest) return 1;
    for (size_t i = 0; i < sizeof kw / sizeof kw[0]; i++)
        if (strncmp(rest, kw[i], strlen(kw[i])) == 0) return 1;
    return 0;
}

static void test_truncated(int bin)
{
    kt_err e = {0};
    kt_mesh m;
    box(&m, 2, 1, &e);
    fields F;
    sample_fields(&F, &m);
    const char *p = tmp("whole.vtk");
    kt_vtk_write_tets(p, &m, F.f, 5, bin, &e);
    size_t n = 0;
    char *all = read_all(p, &n);
    /* ASCII cannot detect a cut inside its very last number: stop before the last line. */
    size_t stop = n - 1;
    if (!bin)
        while (stop > 0 && all[stop - 1] != '\n') stop--;
    int bad = 0, ok = 0;
    for (size_t len = 0; len < stop; len++) {
        kt_err e2 = {0};
        kt_vtk v;
        write_text(tmp("cut.vtk"), all, len);
        int rc = kt_vtk_read(tmp("cut.vtk"), &v, &e2);
        int fine = rc == KT_EINPUT ? strncmp(e2.msg, tmp("cut.vtk"), strlen(tmp("cut.vtk"))) == 0
                                   : rc == KT_OK && at_section(all, len, bin);
        if (!fine && bad++ < 3) fprintf(stderr, "prefix %zu: code %d '%s'\n", len, rc, e2.msg);
        if (rc == KT_OK) ok++, kt_vtk_free(&v);
    }
    CHECK(bad == 0, "%s: %d of %zu prefixes not clean", bin ? "binary" : "ASCII", bad, stop);
    printf("%s truncation: %zu prefixes, %d read as shorter well-formed files\n",
           bin ? "binary" : "ASCII", stop, ok);
    free(all);
    free_fields(&F);
    kt_mesh_free(&m);
}

static void test_writer_errors(void)
{
    kt_err e = {0};
    kt_mesh m;
    box(&m, 2, 1, &e);
    double *half = calloc((size_t)m.nn, sizeof(double));
    half[3] = 0.5;
    kt_vtk_field bad_name = {"my field", 1, 0, 0, half}, bad_int = {"flag", 1, 0, 1, half};
    CHECK(kt_vtk_write_tets(tmp("a.vtk"), &m, &bad_name, 1, 0, &e) == KT_EINPUT && strstr(e.msg, "without blanks"),
          "blank in name: %s", e.msg);
    e = (kt_err){0};
    CHECK(kt_vtk_write_tets(tmp("b.vtk"), &m, &bad_int, 1, 1, &e) == KT_EINPUT && strstr(e.msg, "not an int"),
          "non-integer int field: %s", e.msg);
    struct stat st;
    CHECK(stat(tmp("a.vtk"), &st) != 0 && stat(tmp("b.vtk"), &st) != 0, "no partial output files");
    e = (kt_err){0};
    CHECK(kt_vtk_write_tets("/nonexistent-dir/c.vtk", &m, NULL, 0, 0, &e) == KT_EINPUT, "bad dir: %s", e.msg);
    free(half);
    kt_mesh_free(&m);
}

static int samples(const char *dir)
{
    kt_err e = {0};
    char p[512];
    for (int order = 1; order <= 2 && !e.code; order++)
        for (int bin = 0; bin <= 1 && !e.code; bin++) {
            kt_mesh m;
            if (box(&m, 4, order, &e)) break;
            fields F;
            sample_fields(&F, &m);
            snprintf(p, sizeof p, "%s/vtk-p%d%s.vtk", dir, order, bin ? "-bin" : "");
            kt_vtk_write_tets(p, &m, F.f, 5, bin, &e);
            snprintf(p, sizeof p, "%s/vtk-p%d.msh", dir, order);
            if (!bin) kt_msh_write(p, &m, 0, &e);
            if (order == 1) {
                double *h = malloc(sizeof(double) * (size_t)m.nn), *side = malloc(sizeof(double) * (size_t)m.nf);
                for (int i = 0; i < m.nn; i++) h[i] = m.xyz[3 * i + 2];
                for (int i = 0; i < m.nf; i++) side[i] = m.tri_tag[i];
                kt_vtk_field f[2] = {{"height", 1, 0, 0, h}, {"side", 1, 1, 1, side}};
                snprintf(p, sizeof p, "%s/surf%s.vtk", dir, bin ? "-bin" : "");
                kt_vtk_write_polydata(p, m.nn, m.xyz, m.nf, m.tri, f, 2, bin, &e);
                free(h);
                free(side);
            }
            free_fields(&F);
            kt_mesh_free(&m);
        }
    if (e.code) fprintf(stderr, "%s\n", e.msg);
    return e.code;
}

int main(int argc, char **argv)
{
    if (argc == 3 && strcmp(argv[1], "--samples") == 0) return samples(argv[2]);
    strcpy(tmpdir, "/tmp/kt-test-vtk-XXXXXX");
    if (!mkdtemp(tmpdir)) return 1;
    tets_round_trip(1);
    tets_round_trip(2);
    poly_round_trip();
    test_foreign();
    test_malformed();
    test_truncated(0);
    test_truncated(1);
    test_writer_errors();
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf %s", tmpdir);
    if (system(cmd) != 0) fprintf(stderr, "could not remove %s\n", tmpdir);
    return kt_test_done("test_vtk");
}
