/* vtk_read.c: legacy VTK reader (ASCII and BINARY, big-endian) for UNSTRUCTURED_GRID and
 * POLYDATA with POINT_DATA / CELL_DATA, on the shared cursor (core/cursor.h). */
#include "vtk.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "cursor.h"
#include "vtk_int.h"

/* ------------------------------------------------------------------------------------------ */
/* Reader                                                                                      */

typedef kt_cursor vr;


#define TOKMAX 300
/* The tokens of one keyword line (at most max); leaves p after its newline, where binary data
 * starts. */
static int line_tokens(vr *r, char tok[][TOKMAX], int max, int *count)
{
    while (r->p < r->n && kt_cursor_is_ws(r->b[r->p])) r->p++;
    r->at = r->p;
    *count = 0;
    if (r->p >= r->n) return KT_OK;
    for (;;) {
        while (r->p < r->n && (r->b[r->p] == ' ' || r->b[r->p] == '\t' || r->b[r->p] == '\r')) r->p++;
        if (r->p >= r->n) return KT_OK;
        if (r->b[r->p] == '\n') {
            r->p++;
            return KT_OK;
        }
        size_t q = r->p;
        while (q < r->n && !kt_cursor_is_ws(r->b[q])) q++;
        if (*count >= max || q - r->p >= TOKMAX) {
            r->at = r->p;
            return kt_cursor_fail(r, "expected at most %d words of less than %d characters on this line",
                           max, TOKMAX);
        }
        memcpy(tok[*count], r->b + r->p, q - r->p);
        tok[*count][q - r->p] = '\0';
        (*count)++;
        r->p = q;
    }
}

/* Data types of the legacy format that the reader accepts. */
typedef struct vtype {
    const char *name;
    int size, is_int, is_signed, is_float;
} vtype;

static const vtype vtypes[] = {
    {"double", 8, 0, 1, 1},       {"float", 4, 0, 1, 1},         {"int", 4, 1, 1, 0},
    {"unsigned_int", 4, 1, 0, 0}, {"short", 2, 1, 1, 0},         {"unsigned_short", 2, 1, 0, 0},
    {"char", 1, 1, 1, 0},         {"unsigned_char", 1, 1, 0, 0}, {"vtktypeint64", 8, 1, 1, 0},
    {"vtktypeuint64", 8, 1, 0, 0}, {"vtktypeint32", 4, 1, 1, 0},
};

static const vtype *find_type(vr *r, const char *name)
{
    for (size_t i = 0; i < sizeof vtypes / sizeof vtypes[0]; i++)
        if (strcasecmp(vtypes[i].name, name) == 0) return &vtypes[i];
    kt_cursor_fail(r, "expected a data type (double, float, int, ...), found '%s'", name);
    return NULL;
}

static double decode_be(const vtype *t, const unsigned char *s, int swap)
{
    unsigned char b[8];
    for (int i = 0; i < t->size; i++) b[i] = swap ? s[t->size - 1 - i] : s[i];
    if (t->is_float) {
        if (t->size == 8) {
            double d;
            memcpy(&d, b, 8);
            return d;
        }
        float f;
        memcpy(&f, b, 4);
        return f;
    }
    switch (t->size) {
    case 1: return t->is_signed ? (double)(int8_t)b[0] : (double)b[0];
    case 2: { uint16_t u; memcpy(&u, b, 2); return t->is_signed ? (double)(int16_t)u : (double)u; }
    case 4: { uint32_t u; memcpy(&u, b, 4); return t->is_signed ? (double)(int32_t)u : (double)u; }
    default: { uint64_t u; memcpy(&u, b, 8); return t->is_signed ? (double)(int64_t)u : (double)u; }
    }
}

/* count values of type t: raw big-endian after the keyword line, or whitespace-separated. */
static int read_values(vr *r, const vtype *t, size_t count, double *out, const char *what)
{
    if (r->bin) {
        r->at = r->p;
        if (count > (r->n - r->p) / (size_t)t->size) {
            r->at = r->n;
            return kt_cursor_fail(r, "expected %zu binary %s values for %s", count, t->name, what);
        }
        int swap = host_is_little();
        if (t->is_float && t->size == 8) { /* the common case, a word at a time */
            const unsigned char *s = r->b + r->p;
            for (size_t i = 0; i < count; i++) {
                uint64_t u;
                memcpy(&u, s + 8 * i, 8);
                if (swap) u = __builtin_bswap64(u);
                memcpy(&out[i], &u, 8);
            }
        }
        for (size_t i = 0; i < count; i++) {
            if (!(t->is_float && t->size == 8)) out[i] = decode_be(t, r->b + r->p + i * t->size, swap);
            if (!isfinite(out[i])) {
                r->at = r->p + i * t->size;
                return kt_cursor_fail(r, "expected a finite number for %s, found %g", what, out[i]);
            }
        }
        r->p += count * (size_t)t->size;
        return KT_OK;
    }
    for (size_t i = 0; i < count; i++) {
        while (r->p < r->n && kt_cursor_is_ws(r->b[r->p])) r->p++;
        r->at = r->p;
        if (r->p >= r->n) return kt_cursor_fail(r, "expected %zu values for %s, found %zu", count, what, i);
        char *end;
        errno = 0;
        out[i] = strtod((const char *)r->b + r->p, &end);
        size_t q = (size_t)((const unsigned char *)end - r->b);
        if (q == r->p || (q < r->n && !kt_cursor_is_ws(r->b[q])))
            return kt_cursor_fail(r, "expected a number for %s", what);
        if (!isfinite(out[i]))
            return kt_cursor_fail(r, "expected a finite number for %s, found %g", what, out[i]);
        if (t->is_int && out[i] != floor(out[i]))
            return kt_cursor_fail(r, "expected an integer for %s", what);
        r->p = q;
    }
    return KT_OK;
}

/* Integer count or size from a keyword line. */
static int parse_count(vr *r, const char *s, size_t *v, const char *what)
{
    char *end;
    errno = 0;
    long long x = strtoll(s, &end, 10);
    if (end == s || *end || errno == ERANGE || x < 0 || x > INT_MAX)
        return kt_cursor_fail(r, "expected %s (a count), found '%s'", what, s);
    *v = (size_t)x;
    return KT_OK;
}

typedef struct cells {      /* one cell section: n cells, conn with leading counts */
    size_t n, size;
    int *raw;
} cells;

typedef struct vtk_rd {
    vr r;
    kt_vtk *v;
    int dataset;            /* 0 none, 1 unstructured grid, 2 polydata */
    int have_points;
    cells ug, poly[4];      /* UNSTRUCTURED_GRID CELLS; POLYDATA verts, lines, polys, strips */
    int *types;
    size_t ntypes;
    int have_types;
    int assoc;              /* -1 none, 0 POINT_DATA, 1 CELL_DATA */
    size_t assoc_n;
} vtk_rd;

static int read_ints(vtk_rd *s, size_t count, int **out, const char *what)
{
    vr *r = &s->r;
    static const vtype i32 = {"int", 4, 1, 1, 0};
    if (kt_cursor_fits(r, count, r->bin ? 4 : 1, what)) return r->e->code;
    double *tmp = kt_calloc(count, sizeof *tmp, r->e);
    *out = kt_calloc(count, sizeof **out, r->e);
    if (!tmp || !*out) {
        free(tmp);
        return r->e->code;
    }
    if (read_values(r, &i32, count, tmp, what) == KT_OK)
        for (size_t i = 0; i < count; i++) {
            if (tmp[i] < INT_MIN || tmp[i] > INT_MAX) {
                kt_cursor_fail(r, "%s value %g out of range", what, tmp[i]);
                break;
            }
            (*out)[i] = (int)tmp[i];
        }
    free(tmp);
    return r->e->code;
}

static int kw_points(vtk_rd *s, char tok[][TOKMAX], int nt)
{
    vr *r = &s->r;
    size_t n;
    if (nt != 3) return kt_cursor_fail(r, "expected POINTS n type");
    if (s->have_points) return kt_cursor_fail(r, "expected one POINTS section");
    if (parse_count(r, tok[1], &n, "number of points")) return r->e->code;
    const vtype *t = find_type(r, tok[2]);
    if (!t || kt_cursor_fits(r, 3 * n, r->bin ? (size_t)t->size : 1, "POINTS")) return r->e->code;
    s->v->xyz = kt_calloc(3 * n, sizeof(double), r->e);
    if (!s->v->xyz) return r->e->code;
    s->v->nn = (int)n;
    s->have_points = 1;
    return read_values(r, t, 3 * n, s->v->xyz, "POINTS");
}

/* CELLS (unstructured grid) or a POLYDATA cell section: n cells in size integers. */
static int kw_cells(vtk_rd *s, cells *c, char tok[][TOKMAX], int nt)
{
    vr *r = &s->r;
    if (nt != 3) return kt_cursor_fail(r, "expected %s n size", tok[0]);
    if (c->raw) return kt_cursor_fail(r, "expected one %s section", tok[0]);
    if (parse_count(r, tok[1], &c->n, "number of cells") || parse_count(r, tok[2], &c->size, "size"))
        return r->e->code;
    if (read_ints(s, c->size, &c->raw, tok[0])) return r->e->code;
    size_t q = 0;
    for (size_t i = 0; i < c->n; i++) {
        if (q >= c->size || c->raw[q] < 0 || (size_t)c->raw[q] > c->size - q - 1)
            return kt_cursor_fail(r, "%s: cell %zu does not fit in the %zu integers declared", tok[0], i, c->size);
        q += (size_t)c->raw[q] + 1;
    }
    if (q != c->size) return kt_cursor_fail(r, "%s: %zu cells use %zu of the %zu integers declared", tok[0], c->n, q, c->size);
    return KT_OK;
}

static int kw_cell_types(vtk_rd *s, char tok[][TOKMAX], int nt)
{
    vr *r = &s->r;
    if (nt != 2) return kt_cursor_fail(r, "expected CELL_TYPES n");
    if (s->have_types) return kt_cursor_fail(r, "expected one CELL_TYPES section");
    if (parse_count(r, tok[1], &s->ntypes, "number of cell types")) return r->e->code;
    s->have_types = 1;
    return read_ints(s, s->ntypes, &s->types, "CELL_TYPES");
}

static size_t cell_count(const vtk_rd *s)
{
    if (s->dataset == 1) return s->ug.n;
    size_t n = 0;
    for (int k = 0; k < 4; k++) n += s->poly[k].n;
    return n;
}

static int kw_assoc(vtk_rd *s, char tok[][TOKMAX], int nt, int on_cells)
{
    vr *r = &s->r;
    size_t n;
    if (nt != 2 || parse_count(r, tok[1], &n, "number of values")) return kt_cursor_fail(r, "expected %s n", tok[0]);
    size_t want = on_cells ? cell_count(s) : (size_t)s->v->nn;
    if (!on_cells && !s->have_points) return kt_cursor_fail(r, "expected POINTS before POINT_DATA");
    if (n != want)
        return kt_cursor_fail(r, "%s %zu does not match the %zu %s", tok[0], n, want, on_cells ? "cells" : "points");
    s->assoc = on_cells;
    s->assoc_n = n;
    return KT_OK;
}

/* Add a field and read its values. */
static int add_field(vtk_rd *s, const char *name, const vtype *t, int ncomp)
{
    vr *r = &s->r;
    kt_vtk *v = s->v;
    if (s->assoc < 0) return kt_cursor_fail(r, "expected POINT_DATA or CELL_DATA before field '%s'", name);
    if (strlen(name) >= KT_NAME_MAX)
        return kt_cursor_fail(r, "field name longer than %d characters", KT_NAME_MAX - 1);
    size_t count = s->assoc_n * (size_t)ncomp;
    if (kt_cursor_fits(r, count, r->bin ? (size_t)t->size : 1, name)) return r->e->code;
    kt_vtk_field *f = kt_realloc(v->field, (size_t)v->nfield + 1, sizeof *f, r->e);
    if (!f) return r->e->code;
    v->field = f;
    f += v->nfield;
    memset(f, 0, sizeof *f);
    strcpy(f->name, name);
    f->ncomp = ncomp;
    f->on_cells = s->assoc;
    f->is_int = t->is_int;
    f->v = kt_calloc(count, sizeof(double), r->e);
    if (!f->v) return r->e->code;
    v->nfield++;
    return read_values(r, t, count, f->v, name);
}

static int kw_scalars(vtk_rd *s, char tok[][TOKMAX], int nt)
{
    vr *r = &s->r;
    size_t nc = 1;
    if (nt < 3 || nt > 4) return kt_cursor_fail(r, "expected SCALARS name type [ncomp]");
    if (nt == 4 && (parse_count(r, tok[3], &nc, "number of components") || nc < 1 || nc > 4))
        return kt_cursor_fail(r, "expected 1 to 4 components, found '%s'", tok[3]);
    const vtype *t = find_type(r, tok[2]);
    if (!t) return r->e->code;
    /* LOOKUP_TABLE is optional: look for it literally, since binary data may follow. */
    static const char lt[] = "LOOKUP_TABLE";
    size_t q = r->p;
    if (!r->bin)
        while (q < r->n && kt_cursor_is_ws(r->b[q])) q++;
    if (r->n - q > sizeof lt && memcmp(r->b + q, lt, sizeof lt - 1) == 0 && kt_cursor_is_ws(r->b[q + sizeof lt - 1])) {
        char t2[2][TOKMAX];
        int n2;
        r->p = q;
        if (line_tokens(r, t2, 2, &n2)) return r->e->code;
    }
    return add_field(s, tok[1], t, (int)nc);
}

static int kw_field(vtk_rd *s, char tok[][TOKMAX], int nt)
{
    vr *r = &s->r;
    size_t na;
    if (nt != 3 || parse_count(r, tok[2], &na, "number of arrays")) return kt_cursor_fail(r, "expected FIELD name n");
    for (size_t i = 0; i < na; i++) {
        char a[5][TOKMAX];
        int n;
        size_t nc, ntup;
        if (line_tokens(r, a, 5, &n)) return r->e->code;
        if (n != 4) return kt_cursor_fail(r, "expected a FIELD array line: name ncomp ntuples type");
        if (parse_count(r, a[1], &nc, "number of components") ||
            parse_count(r, a[2], &ntup, "number of tuples"))
            return r->e->code;
        if (nc < 1 || nc > 9) return kt_cursor_fail(r, "expected 1 to 9 components, found %zu", nc);
        if (s->assoc >= 0 && ntup != s->assoc_n)
            return kt_cursor_fail(r, "FIELD array '%s' has %zu tuples, expected %zu", a[0], ntup, s->assoc_n);
        const vtype *t = find_type(r, a[3]);
        if (!t) return r->e->code;
        if (s->assoc >= 0) {
            if (add_field(s, a[0], t, (int)nc)) return r->e->code;
            continue;
        }
        /* Dataset-level field data (such as TIME): read and dropped. */
        if (kt_cursor_fits(r, nc * ntup, r->bin ? (size_t)t->size : 1, a[0])) return r->e->code;
        double *tmp = kt_calloc(nc * ntup, sizeof *tmp, r->e);
        if (!tmp) return r->e->code;
        read_values(r, t, nc * ntup, tmp, a[0]);
        free(tmp);
        if (r->e->code) return r->e->code;
    }
    return KT_OK;
}

/* METADATA blocks (newer VTK writers) end at an empty line. */
static int skip_metadata(vr *r)
{
    while (r->p < r->n) {
        size_t q = r->p;
        while (q < r->n && r->b[q] != '\n') q++;
        int blank = 1;
        for (size_t i = r->p; i < q; i++) blank &= kt_cursor_is_ws(r->b[i]);
        r->p = q < r->n ? q + 1 : q;
        if (blank) return KT_OK;
    }
    return KT_OK;
}

static int keyword(vtk_rd *s, char tok[][TOKMAX], int nt)
{
    vr *r = &s->r;
    const char *k = tok[0];
    int poly = s->dataset == 2, ug = s->dataset == 1;
    if (strcasecmp(k, "DATASET") == 0) {
        if (s->dataset) return kt_cursor_fail(r, "expected one DATASET line");
        if (nt == 2 && strcasecmp(tok[1], "UNSTRUCTURED_GRID") == 0) s->dataset = 1;
        else if (nt == 2 && strcasecmp(tok[1], "POLYDATA") == 0) s->dataset = 2;
        else return kt_cursor_fail(r, "expected DATASET UNSTRUCTURED_GRID or POLYDATA");
        s->v->is_polydata = s->dataset == 2;
        return KT_OK;
    }
    if (!s->dataset) return kt_cursor_fail(r, "expected DATASET, found '%s'", k);
    if (strcasecmp(k, "POINTS") == 0) return kw_points(s, tok, nt);
    if (ug && strcasecmp(k, "CELLS") == 0) return kw_cells(s, &s->ug, tok, nt);
    if (ug && strcasecmp(k, "CELL_TYPES") == 0) return kw_cell_types(s, tok, nt);
    static const char *pk[4] = {"VERTICES", "LINES", "POLYGONS", "TRIANGLE_STRIPS"};
    for (int i = 0; i < 4; i++)
        if (poly && strcasecmp(k, pk[i]) == 0) return kw_cells(s, &s->poly[i], tok, nt);
    if (strcasecmp(k, "POINT_DATA") == 0) return kw_assoc(s, tok, nt, 0);
    if (strcasecmp(k, "CELL_DATA") == 0) return kw_assoc(s, tok, nt, 1);
    if (strcasecmp(k, "SCALARS") == 0) return kw_scalars(s, tok, nt);
    int nc = strcasecmp(k, "VECTORS") == 0 || strcasecmp(k, "NORMALS") == 0 ? 3
             : strcasecmp(k, "TENSORS") == 0                               ? 9 : 0;
    if (nc) {
        if (nt != 3) return kt_cursor_fail(r, "expected %s name type", k);
        const vtype *t = find_type(r, tok[2]);
        return t ? add_field(s, tok[1], t, nc) : r->e->code;
    }
    if (strcasecmp(k, "FIELD") == 0) return kw_field(s, tok, nt);
    if (strcasecmp(k, "METADATA") == 0) return skip_metadata(r);
    return kt_cursor_fail(r, "unsupported or unknown keyword '%s'", k);
}

static int read_preamble(vtk_rd *s)
{
    vr *r = &s->r;
    static const char magic[] = "# vtk DataFile Version";
    r->at = r->p; /* after a UTF-8 byte-order mark */
    if (r->n - r->p < sizeof magic || memcmp(r->b + r->p, magic, sizeof magic - 1) != 0)
        return kt_cursor_fail(r, "expected '%s x.y' as the first line", magic);
    double ver = atof((const char *)r->b + r->p + sizeof magic - 1);
    if (ver >= 5.0)
        return kt_cursor_fail(r, "legacy VTK version %.1f (OFFSETS/CONNECTIVITY) is not supported; expected "
                          "version 4.2 or older", ver);
    /* Line 2 is a free title. */
    int nl = 0;
    while (r->p < r->n && nl < 2) nl += r->b[r->p++] == '\n';
    char tok[2][TOKMAX];
    int nt;
    if (line_tokens(r, tok, 2, &nt)) return r->e->code;
    if (nt == 1 && strcasecmp(tok[0], "ASCII") == 0) r->bin = 0;
    else if (nt == 1 && strcasecmp(tok[0], "BINARY") == 0) r->bin = 1;
    else return kt_cursor_fail(r, "expected ASCII or BINARY on line 3");
    return KT_OK;
}

/* Cells into kt_vtk: unstructured cells with their types, or POLYDATA sections in VTK order. */
static int build_cells(vtk_rd *s)
{
    vr *r = &s->r;
    kt_vtk *v = s->v;
    if (!s->have_points) {
        r->at = r->n;
        return kt_cursor_fail(r, "expected POINTS");
    }
    if (s->dataset == 1 && (s->ug.raw != NULL) != s->have_types) {
        r->at = r->n;
        return kt_cursor_fail(r, "expected both CELLS and CELL_TYPES");
    }
    if (s->dataset == 1 && s->ntypes != s->ug.n) {
        r->at = r->n;
        return kt_cursor_fail(r, "CELL_TYPES has %zu entries for %zu cells", s->ntypes, s->ug.n);
    }
    size_t nc = cell_count(s), nconn = 0;
    cells *sec = s->dataset == 1 ? &s->ug : s->poly;
    int nsec = s->dataset == 1 ? 1 : 4;
    for (int k = 0; k < nsec; k++) nconn += sec[k].size - sec[k].n;
    v->ncell = (int)nc;
    v->cell_type = kt_calloc(nc, sizeof(int), r->e);
    v->cell_ptr = kt_calloc(nc + 1, sizeof(int), r->e);
    v->conn = kt_calloc(nconn, sizeof(int), r->e);
    if (r->e->code) return r->e->code;
    size_t c = 0, q = 0;
    for (int k = 0; k < nsec; k++) {
        for (size_t i = 0, at = 0; i < sec[k].n; i++, c++) {
            int nv = sec[k].raw[at];
            v->cell_ptr[c] = (int)q;
            for (int j = 0; j < nv; j++) {
                int id = sec[k].raw[at + 1 + j];
                if (id < 0 || id >= v->nn)
                    return kt_fail(r->e, KT_EINPUT, "%s: cell %zu refers to point %d of %d", r->path, c, id, v->nn);
                v->conn[q++] = id;
            }
            at += (size_t)nv + 1;
            if (s->dataset == 1) v->cell_type[c] = s->types[i];
            else if (k == 0) v->cell_type[c] = nv == 1 ? VTK_VERTEX : VTK_POLY_VERTEX;
            else if (k == 1) v->cell_type[c] = nv == 2 ? VTK_LINE : VTK_POLY_LINE;
            else if (k == 2) v->cell_type[c] = nv == 3 ? VTK_TRIANGLE : VTK_POLYGON;
            else v->cell_type[c] = VTK_TRIANGLE_STRIP;
        }
    }
    v->cell_ptr[nc] = (int)q;
    return KT_OK;
}

int kt_vtk_read(const char *path, kt_vtk *v, kt_err *e)
{
    memset(v, 0, sizeof *v);
    vtk_rd s;
    memset(&s, 0, sizeof s);
    if (kt_cursor_open(&s.r, path, "# vtk DataFile Version", KT_VTK_MAX_BYTES, e)) return e->code;
    s.v = v;
    s.assoc = -1;
    if (read_preamble(&s) == KT_OK) {
        for (;;) {
            char tok[5][TOKMAX];
            int nt;
            if (line_tokens(&s.r, tok, 5, &nt) || nt == 0) break;
            if (keyword(&s, tok, nt)) break;
        }
        if (!e->code && !s.dataset) {
            s.r.at = s.r.n;
            kt_cursor_fail(&s.r, "expected DATASET");
        }
        if (!e->code) build_cells(&s);
    }
    free(s.ug.raw);
    for (int k = 0; k < 4; k++) free(s.poly[k].raw);
    free(s.types);
    kt_cursor_close(&s.r);
    if (e->code) kt_vtk_free(v);
    return e->code;
}

void kt_vtk_free(kt_vtk *v)
{
    if (!v) return;
    free(v->xyz);
    free(v->cell_type);
    free(v->cell_ptr);
    free(v->conn);
    for (int i = 0; i < v->nfield; i++) free(v->field[i].v);
    free(v->field);
    memset(v, 0, sizeof *v);
}

const kt_vtk_field *kt_vtk_find(const kt_vtk *v, const char *name, int on_cells)
{
    for (int i = 0; i < v->nfield; i++)
        if (v->field[i].on_cells == on_cells && strcmp(v->field[i].name, name) == 0) return &v->field[i];
    return NULL;
}
