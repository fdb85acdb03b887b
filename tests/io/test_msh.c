/* test_msh.c: MSH 4.1 round trips (ASCII and binary, P1 and P2, triangles in two groups), a
 * hand-written gmsh-style file (sparse tags, parametric nodes, skipped element types, unnamed
 * groups), and malformed or truncated files.
 *
 * Extra modes for tests/interop.sh:
 *   test_msh --samples DIR     write sample meshes msh-p1.msh, msh-p1-bin.msh, msh-p2.msh, ...
 *   test_msh --counts FILE     read FILE, print counts, groups and geometric checks
 *   test_msh --compare A B     exit 0 when A and B hold the same mesh (groups in any order) */
#define _GNU_SOURCE /* memmem, mkdtemp */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "grid.h"
#include "kt_test.h"
#include "msh.h"

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
static int write_text(const char *path, const char *s, size_t n)
{
    unlink(path);
    FILE *f = fopen(path, "wb");
    if (!f) return -1;
    fwrite(s, 1, n, f);
    return fclose(f);
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

/* Bitwise equality of two meshes; *why names the first difference. */
static int mesh_equal(const kt_mesh *a, const kt_mesh *b, const char **why)
{
    int tv = kt_tet_nv(a->order), fv = kt_tri_nv(a->order);
    *why = "order/counts";
    if (a->order != b->order || a->nn != b->nn || a->ne != b->ne || a->nf != b->nf || a->ng != b->ng)
        return 0;
    *why = "coordinates";
    if (memcmp(a->xyz, b->xyz, sizeof(double) * 3 * (size_t)a->nn)) return 0;
    *why = "tets";
    if (memcmp(a->tet, b->tet, sizeof(int) * (size_t)tv * a->ne)) return 0;
    *why = "tet tags";
    if (memcmp(a->tet_tag, b->tet_tag, sizeof(int) * (size_t)a->ne)) return 0;
    *why = "triangles";
    if (memcmp(a->tri, b->tri, sizeof(int) * (size_t)fv * a->nf)) return 0;
    *why = "triangle tags";
    if (memcmp(a->tri_tag, b->tri_tag, sizeof(int) * (size_t)a->nf)) return 0;
    *why = "groups";
    for (int g = 0; g < a->ng; g++)
        if (a->group[g].dim != b->group[g].dim || a->group[g].tag != b->group[g].tag ||
            strcmp(a->group[g].name, b->group[g].name))
            return 0;
    *why = "";
    return 1;
}

/* The sample mesh: a box with two regions (split at x = lx/2), its six faces, and a group
 * "bottom-too" that repeats the zmin triangles (a triangle in two groups). Coordinates are
 * perturbed by irrational amounts so that printing them exactly matters. */
static int sample_mesh(kt_mesh *m, int nx, int ny, int nz, int order, kt_err *e)
{
    if (kt_grid_box(m, nx, ny, nz, 1.0, 0.8, 1.3, e)) return e->code;
    if (kt_mesh_add_group(m, 3, 2, "right", e) || kt_mesh_add_group(m, 2, 17, "bottom-too", e))
        return e->code;
    for (int i = 0; i < m->ne; i++) {
        double cx = 0;
        for (int j = 0; j < 4; j++) cx += 0.25 * m->xyz[3 * m->tet[4 * i + j]];
        if (cx > 0.5) m->tet_tag[i] = 2;
    }
    const kt_group *zmin = kt_mesh_find_group(m, 2, "zmin");
    int extra = 0;
    for (int i = 0; i < m->nf; i++) extra += m->tri_tag[i] == zmin->tag;
    int nf = m->nf;
    m->tri = realloc(m->tri, sizeof(int) * 3 * (size_t)(nf + extra));
    m->tri_tag = realloc(m->tri_tag, sizeof(int) * (size_t)(nf + extra));
    for (int i = 0; i < nf; i++)
        if (m->tri_tag[i] == zmin->tag) {
            memcpy(m->tri + 3 * m->nf, m->tri + 3 * i, 3 * sizeof(int));
            m->tri_tag[m->nf++] = 17;
        }
    for (int i = 0; i < 3 * m->nn; i++) m->xyz[i] += 1e-3 * sin(1.0 + i) / 3.0;
    if (order == 2 && kt_mesh_elevate(m, e)) return e->code;
    return KT_OK;
}

static void round_trip(const char *label, const kt_mesh *m)
{
    for (int bin = 0; bin <= 1; bin++) {
        kt_err e = {0};
        char name[64], name2[64];
        snprintf(name, sizeof name, "%s-%s.msh", label, bin ? "bin" : "ascii");
        snprintf(name2, sizeof name2, "%s-%s-again.msh", label, bin ? "bin" : "ascii");
        CHECK(kt_msh_write(tmp(name), m, bin, &e) == KT_OK, "%s: write: %s", name, e.msg);
        kt_mesh r;
        CHECK(kt_msh_read(tmp(name), &r, &e) == KT_OK, "%s: read: %s", name, e.msg);
        if (e.code) continue;
        const char *why;
        CHECK(mesh_equal(m, &r, &why), "%s: round trip differs in %s", name, why);
        CHECK(kt_mesh_check(&r, name, &e) == KT_OK, "%s: %s", name, e.msg);
        /* Writing what was read gives the same bytes. */
        CHECK(kt_msh_write(tmp(name2), &r, bin, &e) == KT_OK, "%s", e.msg);
        size_t n1, n2;
        char *a = read_all(tmp(name), &n1), *b = read_all(tmp(name2), &n2);
        CHECK(a && b && n1 == n2 && memcmp(a, b, n1) == 0, "%s: rewrite differs (%zu vs %zu bytes)", name, n1, n2);
        printf("%s: %zu bytes, nn %d ne %d nf %d\n", name, n1, m->nn, m->ne, m->nf);
        free(a);
        free(b);
        kt_mesh_free(&r);
    }
}

/* A file in gmsh's own style: sparse node tags in two blocks (one parametric), element tags
 * out of order, line and point elements, a surface in two physical groups, an unnamed physical
 * volume, a surface without physical group, unknown sections. */
static const char *gmsh_style =
    "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n"
    "$Comments\nwritten by hand $Nodes\n$EndComments\n"
    "$PhysicalNames\n4\n1 3 \"edge\"\n2 1 \"anterior\"\n2 2 \"incision\"\n3 5 \"cornea\"\n$EndPhysicalNames\n"
    "$Entities\n1 1 3 2\n"
    "1 0 0 0 0\n"
    "3 0 0 0 1 0 0 1 3 2 1 -2\n"
    "5 0 0 0 1 1 1 2 1 2 0\n"
    "6 0 0 0 1 1 0 1 1 0\n"
    "7 0 0 0 1 1 1 0 0\n"
    "1 0 0 0 1 1 1 1 100 0\n"
    "2 0 0 0 1 1 1 1 5 0\n"
    "$EndEntities\n"
    "$Nodes\n2 5 10 50\n"
    "3 1 0 2\n40\n10\n0 0 1\n0 0 0\n"
    "2 5 1 3\n30\n20\n50\n0 1 0 0.5 0.5\n1 0 0 0.25 0.75\n1 1 1 0 0\n"
    "$EndNodes\n"
    "$Elements\n7 8 1 12\n"
    "1 3 1 2\n1 10 20\n2 20 30\n"
    "0 1 15 1\n5 10\n"
    "2 6 2 1\n9 10 20 30\n"
    "2 5 2 1\n11 20 30 40\n"
    "2 7 2 1\n12 10 30 40\n"
    "3 1 4 1\n7 10 20 30 40\n"
    "3 2 4 1\n3 20 30 40 50\n"
    "$EndElements\n"
    "$NodeData\n1\n\"u\"\n0\n3\n0\n1\n1\n10 0.5\n$EndNodeData\n";

static void test_gmsh_style(void)
{
    kt_err e = {0};
    kt_mesh m;
    write_text(tmp("style.msh"), gmsh_style, strlen(gmsh_style));
    CHECK(kt_msh_read(tmp("style.msh"), &m, &e) == KT_OK, "%s", e.msg);
    if (e.code) return;
    static const double xyz[15] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 1};
    static const int tet[8] = {1, 2, 3, 4, 0, 1, 2, 3}, tet_tag[2] = {5, 100};
    static const int tri[9] = {0, 1, 2, 1, 2, 3, 1, 2, 3}, tri_tag[3] = {1, 1, 2};
    CHECK(m.order == 1 && m.nn == 5 && m.ne == 2 && m.nf == 3 && m.ng == 4,
          "order %d nn %d ne %d nf %d ng %d", m.order, m.nn, m.ne, m.nf, m.ng);
    if (m.nn != 5 || m.ne != 2 || m.nf != 3 || m.ng != 4) return;
    CHECK(memcmp(m.xyz, xyz, sizeof xyz) == 0, "coordinates compacted in tag order");
    CHECK(memcmp(m.tet, tet, sizeof tet) == 0 && memcmp(m.tet_tag, tet_tag, sizeof tet_tag) == 0,
          "tets in element-tag order with their regions");
    CHECK(memcmp(m.tri, tri, sizeof tri) == 0 && memcmp(m.tri_tag, tri_tag, sizeof tri_tag) == 0,
          "triangle of two groups listed twice");
    const kt_group *g = kt_mesh_find_tag(&m, 3, 100);
    CHECK(g && g->name[0] == '\0', "unnamed physical volume 100 kept");
    g = kt_mesh_find_group(&m, 2, "incision");
    CHECK(g && g->tag == 2, "group incision");
    CHECK(!kt_mesh_find_group(&m, 1, "edge"), "dimension-1 names dropped");
    CHECK(kt_mesh_check(&m, "style", &e) == KT_OK, "%s", e.msg);
    /* Written back and read again: the same mesh. */
    kt_mesh r;
    const char *why = "read";
    CHECK(kt_msh_write(tmp("style-out.msh"), &m, 1, &e) == KT_OK &&
          kt_msh_read(tmp("style-out.msh"), &r, &e) == KT_OK && mesh_equal(&m, &r, &why),
          "style rewrite: %s %s", why, e.msg);
    if (!e.code) kt_mesh_free(&r);
    kt_mesh_free(&m);
}

/* A binary file from a big-endian machine, built byte by byte: the reader must swap. */
typedef struct buf {
    unsigned char b[1024];
    size_t n;
} buf;

static void be(buf *o, const void *v, int size)
{
    for (int i = size - 1; i >= 0; i--) o->b[o->n++] = ((const unsigned char *)v)[i]; /* host is little-endian */
}
static void be32(buf *o, int32_t v) { be(o, &v, 4); }
static void be64(buf *o, uint64_t v) { be(o, &v, 8); }
static void bed(buf *o, double v) { be(o, &v, 8); }
static void txt(buf *o, const char *s)
{
    memcpy(o->b + o->n, s, strlen(s));
    o->n += strlen(s);
}

static void test_big_endian(void)
{
    const uint16_t one = 1;
    if (*(const unsigned char *)&one != 1) return; /* the builder assumes a little-endian host */
    static const double c[4][3] = {{0, 0, 1.25}, {0, 1, 0}, {1, 0, 0}, {0.1, 0.2, 0.3}};
    buf o = {.n = 0};
    txt(&o, "$MeshFormat\n4.1 1 8\n");
    be32(&o, 1);
    txt(&o, "\n$EndMeshFormat\n$PhysicalNames\n1\n3 9 \"vol\"\n$EndPhysicalNames\n$Entities\n");
    be64(&o, 0), be64(&o, 0), be64(&o, 0), be64(&o, 1);
    be32(&o, 1);
    for (int k = 0; k < 6; k++) bed(&o, k < 3 ? 0.0 : 1.25);
    be64(&o, 1), be32(&o, 9), be64(&o, 0);
    txt(&o, "\n$EndEntities\n$Nodes\n");
    be64(&o, 1), be64(&o, 4), be64(&o, 1), be64(&o, 4);
    be32(&o, 3), be32(&o, 1), be32(&o, 0), be64(&o, 4);
    for (int i = 0; i < 4; i++) be64(&o, (uint64_t)(4 - i)); /* tags 4 3 2 1 */
    for (int i = 0; i < 4; i++)
        for (int k = 0; k < 3; k++) bed(&o, c[i][k]);
    txt(&o, "\n$EndNodes\n$Elements\n");
    be64(&o, 1), be64(&o, 1), be64(&o, 1), be64(&o, 1);
    be32(&o, 3), be32(&o, 1), be32(&o, 4), be64(&o, 1);
    be64(&o, 1), be64(&o, 4), be64(&o, 3), be64(&o, 2), be64(&o, 1); /* tet (4 3 2 1) */
    txt(&o, "\n$EndElements\n");
    write_text(tmp("big-endian.msh"), (const char *)o.b, o.n);
    kt_err e = {0};
    kt_mesh m;
    CHECK(kt_msh_read(tmp("big-endian.msh"), &m, &e) == KT_OK, "big-endian: %s", e.msg);
    if (e.code) return;
    /* Node i is tag i+1, written at position 3 - i. */
    int xyz_ok = m.nn == 4;
    for (int i = 0; xyz_ok && i < 4; i++) xyz_ok = memcmp(m.xyz + 3 * i, c[3 - i], sizeof c[0]) == 0;
    CHECK(xyz_ok, "big-endian coordinates");
    CHECK(m.ne == 1 && m.tet[0] == 3 && m.tet[1] == 2 && m.tet[2] == 1 && m.tet[3] == 0 && m.tet_tag[0] == 9,
          "big-endian tetrahedron");
    CHECK(m.ng == 1 && strcmp(m.group[0].name, "vol") == 0, "big-endian group");
    kt_mesh_free(&m);
}

/* Read text as a file; expect KT_EINPUT with a message starting "path" and holding `want`. */
static void expect_error(const char *label, const char *text, size_t n, const char *want)
{
    kt_err e = {0};
    kt_mesh m;
    const char *p = tmp("bad.msh");
    write_text(p, text, n);
    int rc = kt_msh_read(p, &m, &e);
    CHECK(rc == KT_EINPUT, "%s: code %d (%s)", label, rc, e.msg);
    CHECK(strncmp(e.msg, p, strlen(p)) == 0 && strstr(e.msg, want), "%s: message '%s' lacks '%s'",
          label, e.msg, want);
    CHECK(m.nn == 0 && m.xyz == NULL && m.group == NULL, "%s: mesh left empty", label);
    if (rc == KT_OK) kt_mesh_free(&m);
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

/* line:col of the first occurrence of `what` in s. */
static void where(const char *s, const char *what, char *buf, size_t n)
{
    const char *at = strstr(s, what);
    int line = 1, col = 1;
    for (const char *c = s; c < at; c++) {
        if (*c == '\n') line++, col = 1;
        else col++;
    }
    snprintf(buf, n, ":%d:%d: ", line, col);
}

static void test_malformed(void)
{
    char loc[32];
    char *t = replace(gmsh_style, "0 1 0 0.5 0.5", "0 1 zz 0.5 0.5");
    where(t, "zz", loc, sizeof loc);
    expect_error("bad coordinate", t, strlen(t), loc);
    expect_error("bad coordinate text", t, strlen(t), "expected node coordinate (a number), found 'zz'");
    free(t);
    t = replace(gmsh_style, "3 20 30 40 50", "3 20 30 99 50");
    expect_error("unknown node", t, strlen(t), "node tag 99 is not in $Nodes");
    free(t);
    t = replace(gmsh_style, "4.1 0 8", "2.2 0 8");
    expect_error("old version", t, strlen(t), "expected MSH version 4.1");
    free(t);
    t = replace(gmsh_style, "$Nodes\n2 5 10 50", "$Nodes\n2 999999999999 10 50");
    expect_error("huge count", t, strlen(t), "more than the rest of the file");
    free(t);
    char *t1 = replace(gmsh_style, "1 0 0 0 1 1 1 1 100 0", "1 0 0 0 1 1 1 0 0");
    t = replace(t1, "2 0 0 0 1 1 1 1 5 0", "2 0 0 0 1 1 1 0 0");
    free(t1);
    expect_error("no physical volume", t, strlen(t), "tetrahedra in a physical volume group, found none");
    free(t);
    t = replace(gmsh_style, "$EndNodes", "$EndNodez");
    where(t, "$EndNodez", loc, sizeof loc);
    expect_error("section end", t, strlen(t), loc);
    free(t);
    t = replace(gmsh_style, "3 2 4 1\n3 20 30 40 50", "3 2 4 1\n7 20 30 40 50");
    expect_error("duplicate element tag", t, strlen(t), "element tag 7 appears twice");
    free(t);
    t = replace(gmsh_style, "3 2 4 1\n3 20 30 40 50", "3 4 4 1\n3 20 30 40 50");
    where(t, "3 4 4 1", loc, sizeof loc);
    expect_error("undeclared entity", t, strlen(t), loc);
    expect_error("undeclared entity text", t, strlen(t), "element block on entity (3, 4), which $Entities does not declare");
    free(t);
    t = replace(gmsh_style, "2 6 2 1\n9 10 20 30", "2 6 9 1\n9 10 20 30 10 20 30");
    expect_error("mixed orders", t, strlen(t), "expected 3-node triangles to match 4-node tetrahedra");
    free(t);

    kt_err e = {0};
    kt_mesh m;
    CHECK(kt_msh_read(tmp("missing.msh"), &m, &e) == KT_EINPUT && strstr(e.msg, "cannot open"),
          "missing file: %s", e.msg);
}

/* Every proper prefix of a valid file is a clean KT_EINPUT. */
static void test_truncated(const kt_mesh *m, int bin)
{
    kt_err e = {0};
    const char *p = tmp("whole.msh");
    CHECK(kt_msh_write(p, m, bin, &e) == KT_OK, "%s", e.msg);
    size_t n;
    char *all = read_all(p, &n);
    int bad = 0, eof_msgs = 0;
    for (size_t len = 0; len + 1 < n; len++) {
        kt_err e2 = {0};
        kt_mesh r;
        write_text(tmp("cut.msh"), all, len);
        int rc = kt_msh_read(tmp("cut.msh"), &r, &e2);
        if (rc != KT_EINPUT || strncmp(e2.msg, tmp("cut.msh"), strlen(tmp("cut.msh")))) {
            if (bad++ < 3) fprintf(stderr, "prefix %zu: code %d '%s'\n", len, rc, e2.msg);
            if (rc == KT_OK) kt_mesh_free(&r);
        }
        eof_msgs += strstr(e2.msg, "unexpected end of file") != NULL;
    }
    CHECK(bad == 0, "%s: %d of %zu prefixes not a clean KT_EINPUT", bin ? "binary" : "ASCII", bad, n - 1);
    CHECK(eof_msgs > (int)n / 4, "%s: %d prefixes said 'unexpected end of file'", bin ? "binary" : "ASCII", eof_msgs);
    /* A specific cut inside the binary node coordinates names the byte offset at the end. */
    if (bin) {
        char *at = memmem(all, n, "$EndNodes", 9);
        size_t cut = (size_t)(at - all) - 5;
        write_text(tmp("cut.msh"), all, cut);
        kt_mesh r;
        kt_err e3 = {0};
        kt_msh_read(tmp("cut.msh"), &r, &e3);
        CHECK(strstr(e3.msg, "unexpected end of file: expected node coordinate"), "binary cut: %s", e3.msg);
        /* A corrupt endianness word names its byte offset (after "$MeshFormat\n4.1 1 8\n"). */
        all[20] = 7;
        write_text(tmp("cut.msh"), all, n);
        e3 = (kt_err){0};
        kt_msh_read(tmp("cut.msh"), &r, &e3);
        CHECK(strstr(e3.msg, "byte 20: expected endianness check integer 1"), "endianness: %s", e3.msg);
    }
    free(all);
}

static void test_writer_errors(void)
{
    kt_err e = {0};
    kt_mesh m;
    sample_mesh(&m, 2, 2, 2, 1, &e);
    CHECK(kt_msh_write("/nonexistent-dir/x.msh", &m, 0, &e) == KT_EINPUT, "bad dir: %s", e.msg);
    e = (kt_err){0};
    m.tet_tag[1] = 42;
    CHECK(kt_msh_write(tmp("unknown-tag.msh"), &m, 0, &e) == KT_EINPUT && strstr(e.msg, "region tag 42"),
          "unknown tag: %s", e.msg);
    struct stat st;
    CHECK(stat(tmp("unknown-tag.msh"), &st) != 0, "no partial output file");
    kt_mesh_free(&m);
}

static int samples(const char *dir)
{
    kt_err e = {0};
    char p[512];
    for (int order = 1; order <= 2; order++)
        for (int bin = 0; bin <= 1; bin++) {
            kt_mesh m;
            if (sample_mesh(&m, 4, 3, 5, order, &e)) break;
            snprintf(p, sizeof p, "%s/msh-p%d%s.msh", dir, order, bin ? "-bin" : "");
            kt_msh_write(p, &m, bin, &e);
            kt_mesh_free(&m);
        }
    if (e.code) fprintf(stderr, "%s\n", e.msg);
    return e.code;
}

/* Counts and geometric checks of a mesh file, one "key value" per line. */
static int counts(const char *path)
{
    kt_err e = {0};
    kt_mesh m;
    if (kt_msh_read(path, &m, &e)) {
        fprintf(stderr, "%s\n", e.msg);
        return e.code;
    }
    printf("order %d\nnodes %d\ntets %d\ntriangles %d\ngroups %d\n", m.order, m.nn, m.ne, m.nf, m.ng);
    for (int g = 0; g < m.ng; g++) {
        int n = 0, cnt = m.group[g].dim == 3 ? m.ne : m.nf;
        const int *tag = m.group[g].dim == 3 ? m.tet_tag : m.tri_tag;
        for (int i = 0; i < cnt; i++) n += tag[i] == m.group[g].tag;
        printf("group %d %d %s %d\n", m.group[g].dim, m.group[g].tag,
               m.group[g].name[0] ? m.group[g].name : "-", n);
    }
    double vol = 0, dev = 0;
    for (int i = 0; i < m.ne; i++) {
        const int *t = m.tet + (size_t)kt_tet_nv(m.order) * i;
        vol += kt_tet_volume(m.xyz + 3 * t[0], m.xyz + 3 * t[1], m.xyz + 3 * t[2], m.xyz + 3 * t[3]);
        /* gmsh edge order 01 12 20 30 32 31 */
        static const int ed[6][2] = {{0, 1}, {1, 2}, {2, 0}, {3, 0}, {3, 2}, {3, 1}};
        for (int k = 0; m.order == 2 && k < 6; k++)
            for (int c = 0; c < 3; c++) {
                double mid = 0.5 * (m.xyz[3 * t[ed[k][0]] + c] + m.xyz[3 * t[ed[k][1]] + c]);
                dev = fmax(dev, fabs(mid - m.xyz[3 * t[4 + k] + c]));
            }
    }
    printf("volume %.15g\nmidedge_maxdev %.3g\n", vol, dev);
    printf("check %s\n", kt_mesh_check(&m, path, &e) == KT_OK ? "ok" : e.msg);
    kt_mesh_free(&m);
    return 0;
}

static int group_sets_equal(const kt_mesh *a, const kt_mesh *b)
{
    if (a->ng != b->ng) return 0;
    for (int g = 0; g < a->ng; g++) {
        const kt_group *h = kt_mesh_find_tag(b, a->group[g].dim, a->group[g].tag);
        if (!h || strcmp(h->name, a->group[g].name)) return 0;
    }
    return 1;
}

static int compare(const char *pa, const char *pb)
{
    kt_err e = {0};
    kt_mesh a, b;
    if (kt_msh_read(pa, &a, &e) || kt_msh_read(pb, &b, &e)) {
        fprintf(stderr, "%s\n", e.msg);
        return 2;
    }
    const char *why = "";
    int tv = kt_tet_nv(a.order), fv = kt_tri_nv(a.order), same = 1;
    double dx = 0;
    if (a.order != b.order || a.nn != b.nn || a.ne != b.ne || a.nf != b.nf) same = 0, why = "counts";
    if (same) {
        for (int i = 0; i < 3 * a.nn; i++) dx = fmax(dx, fabs(a.xyz[i] - b.xyz[i]));
        if (dx > 1e-14) same = 0, why = "coordinates";
        else if (memcmp(a.tet, b.tet, sizeof(int) * (size_t)tv * a.ne) ||
                 memcmp(a.tet_tag, b.tet_tag, sizeof(int) * (size_t)a.ne))
            same = 0, why = "tets";
        else if (memcmp(a.tri, b.tri, sizeof(int) * (size_t)fv * a.nf) ||
                 memcmp(a.tri_tag, b.tri_tag, sizeof(int) * (size_t)a.nf))
            same = 0, why = "triangles";
        else if (!group_sets_equal(&a, &b))
            same = 0, why = "groups";
    }
    if (same) printf("same (max coordinate difference %.3g)\n", dx);
    else printf("differ in %s\n", why);
    kt_mesh_free(&a);
    kt_mesh_free(&b);
    return same ? 0 : 1;
}

int main(int argc, char **argv)
{
    if (argc == 3 && strcmp(argv[1], "--samples") == 0) return samples(argv[2]);
    if (argc == 3 && strcmp(argv[1], "--counts") == 0) return counts(argv[2]);
    if (argc == 4 && strcmp(argv[1], "--compare") == 0) return compare(argv[2], argv[3]);
    strcpy(tmpdir, "/tmp/kt-test-msh-XXXXXX");
    if (!mkdtemp(tmpdir)) return 1;

    kt_err e = {0};
    kt_mesh p1, p2, small;
    CHECK(sample_mesh(&p1, 4, 3, 5, 1, &e) == KT_OK, "%s", e.msg);
    CHECK(sample_mesh(&p2, 4, 3, 5, 2, &e) == KT_OK, "%s", e.msg);
    CHECK(sample_mesh(&small, 2, 2, 2, 1, &e) == KT_OK, "%s", e.msg);
    if (e.code) return kt_test_done("test_msh");
    CHECK(p1.nf > 0 && kt_mesh_find_group(&p1, 2, "bottom-too") && p1.tri_tag[p1.nf - 1] == 17,
          "sample has triangles in two groups");
    round_trip("p1", &p1);
    round_trip("p2", &p2);
    test_gmsh_style();
    test_big_endian();
    test_malformed();
    test_truncated(&small, 0);
    test_truncated(&small, 1);
    test_writer_errors();
    kt_mesh_free(&p1);
    kt_mesh_free(&p2);
    kt_mesh_free(&small);

    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf %s", tmpdir);
    if (system(cmd) != 0) fprintf(stderr, "could not remove %s\n", tmpdir);
    return kt_test_done("test_msh");
}
