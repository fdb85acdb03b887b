/* vtk_write.c: legacy VTK (4.2-compatible, "Version 3.0" header) writer for UNSTRUCTURED_GRID
 * and POLYDATA with POINT_DATA / CELL_DATA. BINARY files are big-endian. */
#include "vtk.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "g17.h"
#include "vtk_int.h"

/* ------------------------------------------------------------------------------------------ */
/* Writer                                                                                      */

typedef struct vw {
    FILE *f;
    int bin, swap;
    size_t len;                 /* bytes waiting in buf */
    char buf[1 << 16];
} vw;

/* The data blocks go through buf (one fwrite per 64 KiB, not one stdio call per value); every
 * block ends with end_block, which flushes it before the next keyword line is printed to f. */
static void vw_flush(vw *w)
{
    if (w->len) fwrite(w->buf, 1, w->len, w->f);
    w->len = 0;
}

static void vw_room(vw *w, size_t n)
{
    if (w->len + n >= sizeof w->buf) vw_flush(w); /* >=: end_block's newline always fits */
}

static void put_be(vw *w, const void *src, size_t size)
{
    vw_room(w, size);
    const unsigned char *s = src;
    char *b = w->buf + w->len;
    for (size_t i = 0; i < size; i++) b[i] = (char)(w->swap ? s[size - 1 - i] : s[i]);
    w->len += size;
}

/* One ASCII value and its separator: a newline after every per_line-th value, else a blank. */
static void put_text_double(vw *w, double v, size_t i, int per_line)
{
    vw_room(w, KT_G17_MAX + 1);
    w->len += (size_t)kt_g17(v, w->buf + w->len);
    w->buf[w->len++] = (i + 1) % (size_t)per_line == 0 ? '\n' : ' ';
}

static void put_text_int(vw *w, int v, size_t i, int per_line)
{
    vw_room(w, 13);
    w->len += (size_t)kt_itoa(v, w->buf + w->len);
    w->buf[w->len++] = (i + 1) % (size_t)per_line == 0 ? '\n' : ' ';
}

/* n doubles, per_line to a line in ASCII ("%.17g": kt_g17 prints the same text). */
static void put_doubles(vw *w, const double *v, size_t n, int per_line)
{
    for (size_t i = 0; i < n; i++) {
        if (w->bin) put_be(w, &v[i], 8);
        else put_text_double(w, v[i], i, per_line);
    }
}

static void put_ints(vw *w, const int *v, size_t n, int per_line)
{
    for (size_t i = 0; i < n; i++) {
        if (w->bin) {
            int32_t x = v[i];
            put_be(w, &x, 4);
        } else {
            put_text_int(w, v[i], i, per_line);
        }
    }
}

/* The end of a data block: its bytes go out before the next keyword line is printed. */
static void end_block(vw *w)
{
    if (w->bin) w->buf[w->len++] = '\n';
    vw_flush(w);
}

static void write_header(vw *w, const char *title, const char *dataset, int nn, const double *xyz)
{
    fprintf(w->f, "# vtk DataFile Version 3.0\n%s\n%s\nDATASET %s\nPOINTS %d double\n", title,
            w->bin ? "BINARY" : "ASCII", dataset, nn);
    put_doubles(w, xyz, 3 * (size_t)nn, 3);
    end_block(w);
}

static int check_fields(const kt_vtk_field *f, int nf, int reserve_region, kt_err *e)
{
    for (int i = 0; i < nf; i++) {
        const char *n = f[i].name;
        if (!n[0] || strpbrk(n, " \t\r\n"))
            return kt_fail(e, KT_EINPUT, "VTK field name '%s': expected a non-empty name without blanks", n);
        if (f[i].ncomp < 1 || f[i].ncomp > KT_VTK_MAXCOMP)
            return kt_fail(e, KT_EINPUT, "VTK field '%s': expected 1 to %d components, got %d", n,
                           KT_VTK_MAXCOMP, f[i].ncomp);
        if (reserve_region && f[i].on_cells && strcmp(n, "region") == 0)
            return kt_fail(e, KT_EINPUT, "VTK field 'region' on cells is written from the mesh's tags");
        for (int j = 0; j < i; j++)
            if (f[j].on_cells == f[i].on_cells && strcmp(f[j].name, n) == 0)
                return kt_fail(e, KT_EINPUT, "VTK field '%s' given twice", n);
    }
    return KT_OK;
}

/* One attribute: VECTORS for 3 components, SCALARS (LOOKUP_TABLE default) for 1, 2 or 4, and
 * a FIELD of one array for more (SCALARS allow at most 4). */
static int put_field(vw *w, const kt_vtk_field *f, size_t count, kt_err *e)
{
    const char *type = f->is_int ? "int" : "double";
    if (f->ncomp == 3) fprintf(w->f, "VECTORS %s %s\n", f->name, type);
    else if (f->ncomp > 4)
        fprintf(w->f, "FIELD %s 1\n%s %d %zu %s\n", f->name, f->name, f->ncomp, count, type);
    else fprintf(w->f, "SCALARS %s %s %d\nLOOKUP_TABLE default\n", f->name, type, f->ncomp);
    size_t n = count * (size_t)f->ncomp;
    if (!f->is_int) {
        put_doubles(w, f->v, n, f->ncomp);
    } else {
        for (size_t i = 0; i < n; i++) {
            double x = f->v[i];
            if (!(x >= INT_MIN && x <= INT_MAX) || x != floor(x)) {
                vw_flush(w);
                return kt_fail(e, KT_EINPUT, "VTK int field '%s': value %g at %zu is not an int",
                               f->name, x, i);
            }
            int k = (int)x;
            if (w->bin) put_be(w, &(int32_t){k}, 4);
            else put_text_int(w, k, i, f->ncomp);
        }
    }
    end_block(w);
    return KT_OK;
}

static int put_fields(vw *w, const kt_vtk_field *f, int nf, int on_cells, size_t count, kt_err *e)
{
    for (int i = 0; i < nf; i++)
        if (f[i].on_cells == on_cells && put_field(w, &f[i], count, e)) return e->code;
    return KT_OK;
}

static int count_fields(const kt_vtk_field *f, int nf, int on_cells)
{
    int k = 0;
    for (int i = 0; i < nf; i++) k += f[i].on_cells == on_cells;
    return k;
}

static int write_tets(vw *w, const kt_mesh *m, const kt_vtk_field *f, int nf, kt_err *e)
{
    int nv = kt_tet_nv(m->order);
    char title[64];
    snprintf(title, sizeof title, "keratome tetrahedra order %d", m->order);
    write_header(w, title, "UNSTRUCTURED_GRID", m->nn, m->xyz);
    fprintf(w->f, "CELLS %d %zu\n", m->ne, (size_t)m->ne * (size_t)(nv + 1));
    for (int i = 0; i < m->ne; i++) {
        int row[11];
        row[0] = nv;
        for (int j = 0; j < nv; j++)
            row[1 + j] = m->tet[(size_t)nv * i + (nv == 10 ? gmsh_to_vtk_tet10[j] : j)];
        put_ints(w, row, (size_t)nv + 1, nv + 1);
    }
    end_block(w);
    fprintf(w->f, "CELL_TYPES %d\n", m->ne);
    int type = m->order == 2 ? VTK_QUADRATIC_TETRA : VTK_TETRA;
    for (int i = 0; i < m->ne; i++) put_ints(w, &type, 1, 1);
    end_block(w);
    fprintf(w->f, "CELL_DATA %d\nSCALARS region int 1\nLOOKUP_TABLE default\n", m->ne);
    put_ints(w, m->tet_tag, (size_t)m->ne, 1);
    end_block(w);
    if (put_fields(w, f, nf, 1, (size_t)m->ne, e)) return e->code;
    if (count_fields(f, nf, 0)) {
        fprintf(w->f, "POINT_DATA %d\n", m->nn);
        if (put_fields(w, f, nf, 0, (size_t)m->nn, e)) return e->code;
    }
    return KT_OK;
}

/* Triangles as POLYDATA POLYGONS, or (grid) as an UNSTRUCTURED_GRID of VTK_TRIANGLE cells. */
static int write_poly(vw *w, int nn, const double *xyz, int ntri, const int *tri,
                      const kt_vtk_field *f, int nf, int grid, kt_err *e)
{
    write_header(w, "keratome triangles", grid ? "UNSTRUCTURED_GRID" : "POLYDATA", nn, xyz);
    fprintf(w->f, "%s %d %zu\n", grid ? "CELLS" : "POLYGONS", ntri, 4 * (size_t)ntri);
    for (int i = 0; i < ntri; i++) {
        int row[4] = {3, tri[3 * (size_t)i], tri[3 * (size_t)i + 1], tri[3 * (size_t)i + 2]};
        put_ints(w, row, 4, 4);
    }
    end_block(w);
    if (grid) {
        int type = VTK_TRIANGLE;
        fprintf(w->f, "CELL_TYPES %d\n", ntri);
        for (int i = 0; i < ntri; i++) put_ints(w, &type, 1, 1);
        end_block(w);
    }
    if (count_fields(f, nf, 1)) {
        fprintf(w->f, "CELL_DATA %d\n", ntri);
        if (put_fields(w, f, nf, 1, (size_t)ntri, e)) return e->code;
    }
    if (count_fields(f, nf, 0)) {
        fprintf(w->f, "POINT_DATA %d\n", nn);
        if (put_fields(w, f, nf, 0, (size_t)nn, e)) return e->code;
    }
    return KT_OK;
}

static int check_nodes(const int *el, size_t n, int nn, const char *what, kt_err *e)
{
    for (size_t i = 0; i < n; i++)
        if (el[i] < 0 || el[i] >= nn)
            return kt_fail(e, KT_EINPUT, "VTK output: %s %zu refers to node %d of %d", what,
                           i, el[i], nn);
    return KT_OK;
}

int kt_vtk_write_tets(const char *path, const kt_mesh *m, const kt_vtk_field *f, int nf,
                      int binary, kt_err *e)
{
    if (m->order != 1 && m->order != 2)
        return kt_fail(e, KT_EINPUT, "VTK output: mesh order %d, expected 1 or 2", m->order);
    if (check_fields(f, nf, 1, e) ||
        check_nodes(m->tet, (size_t)m->ne * kt_tet_nv(m->order), m->nn, "tet node entry", e))
        return e->code;
    kt_out o;
    if (kt_out_open(&o, path, e)) return e->code;
    vw w;
    w.f = o.f, w.bin = binary, w.swap = host_is_little(), w.len = 0;
    if (write_tets(&w, m, f, nf, e)) {
        kt_out_abort(&o);
        return e->code;
    }
    return kt_out_commit(&o, e);
}

static int write_triangles(const char *path, int nn, const double *xyz, int ntri, const int *tri,
                           const kt_vtk_field *f, int nf, int binary, int grid, kt_err *e)
{
    if (check_fields(f, nf, 0, e) || check_nodes(tri, 3 * (size_t)ntri, nn, "triangle node entry", e))
        return e->code;
    kt_out o;
    if (kt_out_open(&o, path, e)) return e->code;
    vw w;
    w.f = o.f, w.bin = binary, w.swap = host_is_little(), w.len = 0;
    if (write_poly(&w, nn, xyz, ntri, tri, f, nf, grid, e)) {
        kt_out_abort(&o);
        return e->code;
    }
    return kt_out_commit(&o, e);
}


int kt_vtk_write_polydata(const char *path, int nn, const double *xyz, int ntri, const int *tri,
                          const kt_vtk_field *f, int nf, int binary, kt_err *e)
{
    return write_triangles(path, nn, xyz, ntri, tri, f, nf, binary, 0, e);
}

int kt_vtk_write_tri_grid(const char *path, int nn, const double *xyz, int ntri, const int *tri,
                          const kt_vtk_field *f, int nf, int binary, kt_err *e)
{
    return write_triangles(path, nn, xyz, ntri, tri, f, nf, binary, 1, e);
}
