/* msh_read.c: gmsh MSH 4.1 reader (ASCII and binary).
 *
 * The reader loads the whole file, then walks it with a cursor that reads either ASCII tokens
 * or native binary values (size_t as 8 bytes, int as 4, byte-swapped when the endianness check
 * says so). Errors name file:line:col (ASCII) or file: byte N (binary). */
#include "msh.h"

#include "cursor.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

/* ------------------------------------------------------------------------------------------ */
/* Element types: node counts per gmsh type, measured with gmshModelMeshGetElementProperties   */
/* (gmsh 4.8.4); needed to skip blocks of types we do not keep in binary files.                */

static int type_nodes(int type)
{
    static const short nv[] = {
        0,  2,  3,  4,  4,  8,  6,  5,  3,  6,  9,  10, 27, 18, 14, 1,  8,  20, 15, 13,
        9,  10, 12, 15, 15, 21, 4,  5,  6,  20, 35, 56, 22, 28, 0,  0,  16, 25, 36, 12,
        16, 20, 28, 36, 45, 55, 66, 49, 64, 81, 100, 121, 18, 21, 24, 27, 30, 24, 28, 32,
        36, 40, 7,  8,  9,  10, 11};
    if (type > 0 && type < (int)(sizeof nv / sizeof nv[0])) return nv[type];
    static const short hi[][2] = {
        {71, 84},   {72, 120},  {73, 165},  {74, 220},  {75, 286}, {79, 34},   {80, 40},
        {81, 46},   {82, 52},   {83, 58},   {84, 1},    {85, 1},   {86, 1},    {87, 1},
        {88, 1},    {89, 1},    {92, 64},   {93, 125},  {94, 216}, {95, 343},  {96, 512},
        {97, 729},  {98, 1000}, {99, 32},   {100, 44},  {101, 56}, {102, 68},  {103, 80},
        {104, 92},  {105, 104}, {118, 30},  {119, 55},  {120, 91}, {121, 140}, {122, 204},
        {123, 285}, {124, 385}, {125, 21},  {126, 29},  {127, 37}, {128, 45},  {129, 53},
        {130, 61},  {131, 69},  {132, 1},   {137, 16}};
    for (size_t i = 0; i < sizeof hi / sizeof hi[0]; i++)
        if (hi[i][0] == type) return hi[i][1];
    return 0;
}

enum { K_TET4, K_TET10, K_TRI3, K_TRI6, K_N };
static const int kind_type[K_N] = {4, 11, 2, 9};
static const int kind_nv[K_N] = {4, 10, 3, 6};
static const int kind_dim[K_N] = {3, 3, 2, 2};

static int type_kind(int type)
{
    for (int k = 0; k < K_N; k++)
        if (kind_type[k] == type) return k;
    return -1;
}

/* ------------------------------------------------------------------------------------------ */
/* Tokens and values on the shared cursor (core/cursor.h).                                      */

typedef kt_cursor rd;

/* After a section header line, binary data starts right after its newline. */
static int end_header_line(rd *r)
{
    if (r->p < r->n && r->b[r->p] == '\r') r->p++;
    r->at = r->p;
    if (r->p >= r->n || r->b[r->p] != '\n') return kt_cursor_fail(r, "expected end of line");
    r->p++;
    return KT_OK;
}

/* Skip an unknown section: continue after the line "$End<name>". */
static int skip_section(rd *r, const char *name)
{
    char end[80];
    snprintf(end, sizeof end, "$End%s", name);
    size_t k = strlen(end);
    for (size_t q = r->p; q + k <= r->n; q++) {
        if (r->b[q] == '$' && (q == 0 || r->b[q - 1] == '\n') && memcmp(r->b + q, end, k) == 0 &&
            (q + k == r->n || kt_cursor_is_ws(r->b[q + k]))) {
            r->p = q + k;
            return KT_OK;
        }
    }
    r->at = r->n;
    return kt_cursor_fail(r, "expected %s", end);
}

/* ------------------------------------------------------------------------------------------ */
/* What the reader gathers before it builds the mesh.                                          */

typedef struct ents {       /* dim-2 or dim-3 entities and their physical tags (CSR) */
    int n, *tag, *ptr, *phys;
    int nphys;
} ents;

typedef struct elist {      /* raw elements of one kind, in file order */
    size_t n, cap;
    size_t *etag;           /* element tag */
    int *ent;               /* entity tag */
    int *node;              /* nv node numbers (compacted) */
} elist;

typedef struct nodemap {    /* node tag -> compacted number */
    size_t lo, span;
    int *dense;             /* span entries (-1: none), when tags are dense enough */
    size_t *sorted;         /* otherwise sorted tags; number = position */
    int n;
} nodemap;

typedef struct msh_rd {
    rd r;
    kt_mesh *m;
    ents ent[2];            /* [0] surfaces, [1] volumes */
    elist el[K_N];
    nodemap map;
    int have_nodes, have_elements, have_format, have_entities;
} msh_rd;

static void msh_rd_free(msh_rd *s)
{
    for (int d = 0; d < 2; d++) {
        free(s->ent[d].tag);
        free(s->ent[d].ptr);
        free(s->ent[d].phys);
    }
    for (int k = 0; k < K_N; k++) {
        free(s->el[k].etag);
        free(s->el[k].ent);
        free(s->el[k].node);
    }
    free(s->map.dense);
    free(s->map.sorted);
}

/* ------------------------------------------------------------------------------------------ */

static int read_format(msh_rd *s)
{
    rd *r = &s->r;
    const char *v;
    size_t len;
    if (kt_cursor_token(r, &v, &len, "MSH version")) return r->e->code;
    if (len != 3 || memcmp(v, "4.1", 3) != 0)
        return kt_cursor_fail(r, "expected MSH version 4.1, found '%.*s' (convert with: gmsh FILE -save "
                          "-format msh41 -o OUT.msh)", (int)(len > 20 ? 20 : len), v);
    long long ft, ds;
    if (kt_cursor_ll(r, 0, 1, &ft, "file-type (0 ASCII, 1 binary)")) return r->e->code;
    if (kt_cursor_ll(r, 8, 8, &ds, "data-size 8")) return r->e->code;
    if (ft == 1) {
        if (end_header_line(r)) return r->e->code;
        r->bin = 1;
        int32_t one;
        if (kt_cursor_bytes(r, &one, 4, "endianness check integer 1")) return r->e->code;
        if (one == 0x01000000) r->swap = 1;
        else if (one != 1) return kt_cursor_fail(r, "expected endianness check integer 1, found %d", (int)one);
        r->bin = 0;
    }
    if (kt_cursor_expect(r, "$EndMeshFormat")) return r->e->code;
    r->bin = (int)ft; /* remembered as "file is binary"; sections switch it on and off */
    s->have_format = 1;
    return KT_OK;
}

/* A group for (dim, tag) unless one exists; physical names are read before entities. */
static int ensure_group(msh_rd *s, int dim, int tag, const char *name)
{
    if (kt_mesh_find_tag(s->m, dim, tag)) return KT_OK;
    return kt_mesh_add_group(s->m, dim, tag, name, s->r.e);
}

static int read_physical_names(msh_rd *s)
{
    rd *r = &s->r;
    long long n;
    if (kt_cursor_ll(r, 0, INT_MAX, &n, "number of physical names")) return r->e->code;
    for (long long i = 0; i < n; i++) {
        long long dim, tag;
        if (kt_cursor_ll(r, 0, 3, &dim, "physical dimension (0-3)")) return r->e->code;
        if (kt_cursor_ll(r, INT_MIN, INT_MAX, &tag, "physical tag")) return r->e->code;
        while (r->p < r->n && (r->b[r->p] == ' ' || r->b[r->p] == '\t')) r->p++;
        r->at = r->p;
        if (r->p >= r->n || r->b[r->p] != '"') return kt_cursor_fail(r, "expected a quoted physical name");
        size_t q = r->p + 1;
        while (q < r->n && r->b[q] != '"' && r->b[q] != '\n') q++;
        if (q >= r->n || r->b[q] != '"') return kt_cursor_fail(r, "expected a closing '\"' on this line");
        size_t len = q - r->p - 1;
        const char *name = (const char *)r->b + r->p + 1;
        r->p = q + 1;
        if (dim < 2) continue;
        if (len >= KT_NAME_MAX)
            return kt_cursor_fail(r, "physical name longer than %d characters", KT_NAME_MAX - 1);
        char buf[KT_NAME_MAX];
        memcpy(buf, name, len);
        buf[len] = '\0';
        const kt_group *g = kt_mesh_find_tag(s->m, (int)dim, (int)tag);
        if (g && g->name[0]) return kt_cursor_fail(r, "physical group (%lld, %lld) named twice", dim, tag);
        if (g) strcpy(s->m->group[g - s->m->group].name, buf); /* $Entities came first */
        else if (kt_mesh_add_group(s->m, (int)dim, (int)tag, buf, r->e)) return r->e->code;
    }
    return kt_cursor_expect(r, "$EndPhysicalNames");
}

/* One entity record; physical tags of surfaces and volumes are kept. */
static int read_entity(msh_rd *s, int dim)
{
    rd *r = &s->r;
    int tag;
    double x;
    size_t np, nb;
    if (kt_cursor_int(r, &tag, "entity tag")) return r->e->code;
    for (int k = 0; k < (dim == 0 ? 3 : 6); k++)
        if (kt_cursor_double(r, &x, dim == 0 ? "point coordinate" : "bounding box coordinate"))
            return r->e->code;
    if (kt_cursor_size(r, &np, "number of physical tags")) return r->e->code;
    if (kt_cursor_fits(r, np, r->bin ? 4 : 2, "number of physical tags")) return r->e->code;
    ents *E = dim >= 2 ? &s->ent[dim - 2] : NULL;
    if (E) {
        int *t = kt_realloc(E->tag, (size_t)E->n + 1, sizeof *t, r->e);
        if (!t) return r->e->code;
        E->tag = t;
        int *pp = kt_realloc(E->ptr, (size_t)E->n + 2, sizeof *pp, r->e);
        if (!pp) return r->e->code;
        E->ptr = pp;
        int *ph = kt_realloc(E->phys, (size_t)E->nphys + np, sizeof *ph, r->e);
        if (!ph) return r->e->code;
        E->phys = ph;
        for (int i = 0; i < E->n; i++)
            if (E->tag[i] == tag) return kt_cursor_fail(r, "entity (%d, %d) defined twice", dim, tag);
        if (E->n == 0) E->ptr[0] = 0;
        E->tag[E->n] = tag;
    }
    for (size_t i = 0; i < np; i++) {
        int ph;
        if (kt_cursor_int(r, &ph, "physical tag")) return r->e->code;
        if (!E) continue;
        E->phys[E->nphys++] = ph;
        if (ensure_group(s, dim, ph, "")) return r->e->code;
    }
    if (E) E->ptr[++E->n] = E->nphys;
    if (dim == 0) return KT_OK;
    if (kt_cursor_size(r, &nb, "number of bounding entities")) return r->e->code;
    if (kt_cursor_fits(r, nb, r->bin ? 4 : 2, "number of bounding entities")) return r->e->code;
    for (size_t i = 0; i < nb; i++)
        if (kt_cursor_int(r, &tag, "bounding entity tag")) return r->e->code;
    return KT_OK;
}

static int read_entities(msh_rd *s)
{
    rd *r = &s->r;
    size_t cnt[4];
    static const char *what[4] = {"number of points", "number of curves", "number of surfaces",
                                  "number of volumes"};
    for (int d = 0; d < 4; d++)
        if (kt_cursor_size(r, &cnt[d], what[d]) || kt_cursor_fits(r, cnt[d], r->bin ? 32 : 8, what[d]))
            return r->e->code;
    for (int d = 0; d < 4; d++)
        for (size_t i = 0; i < cnt[d]; i++)
            if (read_entity(s, d)) return r->e->code;
    s->have_entities = 1;
    return KT_OK;
}

/* ------------------------------------------------------------------------------------------ */
/* Nodes: gathered in file order, then compacted in tag order.                                 */

typedef struct tagpos {
    size_t tag;
    size_t pos;
} tagpos;

static int cmp_tagpos(const void *a, const void *b)
{
    const tagpos *x = a, *y = b;
    if (x->tag != y->tag) return x->tag < y->tag ? -1 : 1;
    return x->pos < y->pos ? -1 : (x->pos > y->pos);
}

static int build_nodes(msh_rd *s, tagpos *tp, const double *xyz, size_t nn)
{
    rd *r = &s->r;
    kt_mesh *m = s->m;
    qsort(tp, nn, sizeof *tp, cmp_tagpos);
    for (size_t i = 1; i < nn; i++)
        if (tp[i].tag == tp[i - 1].tag)
            return kt_fail(r->e, KT_EINPUT, "%s: $Nodes: node tag %zu appears twice", r->path, tp[i].tag);
    m->nn = (int)nn;
    m->xyz = kt_calloc(3 * nn, sizeof(double), r->e);
    if (!m->xyz) return r->e->code;
    for (size_t i = 0; i < nn; i++) memcpy(m->xyz + 3 * i, xyz + 3 * tp[i].pos, 3 * sizeof(double));
    nodemap *M = &s->map;
    M->n = (int)nn;
    M->lo = nn ? tp[0].tag : 0;
    M->span = nn ? tp[nn - 1].tag - M->lo + 1 : 0;
    if (M->span <= 4 * nn + 1024) {
        M->dense = kt_calloc(M->span, sizeof(int), r->e);
        if (!M->dense) return r->e->code;
        for (size_t i = 0; i < M->span; i++) M->dense[i] = -1;
        for (size_t i = 0; i < nn; i++) M->dense[tp[i].tag - M->lo] = (int)i;
    } else {
        M->sorted = kt_calloc(nn, sizeof(size_t), r->e);
        if (!M->sorted) return r->e->code;
        for (size_t i = 0; i < nn; i++) M->sorted[i] = tp[i].tag;
    }
    return KT_OK;
}

static int node_number(const nodemap *M, size_t tag)
{
    if (M->dense) return (tag < M->lo || tag - M->lo >= M->span) ? -1 : M->dense[tag - M->lo];
    size_t lo = 0, hi = (size_t)M->n;
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        if (M->sorted[mid] < tag) lo = mid + 1;
        else hi = mid;
    }
    return (lo < (size_t)M->n && M->sorted[lo] == tag) ? (int)lo : -1;
}

static int read_nodes(msh_rd *s)
{
    rd *r = &s->r;
    if (s->have_nodes) return kt_cursor_fail(r, "expected one $Nodes section, found a second");
    s->have_nodes = 1;
    size_t nblk, nn, mintag, maxtag;
    if (kt_cursor_size(r, &nblk, "number of node blocks") || kt_cursor_size(r, &nn, "number of nodes") ||
        kt_cursor_size(r, &mintag, "minimum node tag") || kt_cursor_size(r, &maxtag, "maximum node tag"))
        return r->e->code;
    if (kt_cursor_fits(r, nblk, r->bin ? 20 : 8, "number of node blocks") ||
        kt_cursor_fits(r, nn, r->bin ? 32 : 8, "number of nodes"))
        return r->e->code;
    if (nn > KT_MESH_MAX_NODES)
        return kt_cursor_fail(r, "expected at most %d nodes, found %zu", KT_MESH_MAX_NODES, nn);
    tagpos *tp = kt_calloc(nn, sizeof *tp, r->e);
    double *xyz = kt_calloc(3 * nn, sizeof *xyz, r->e);
    size_t k = 0;
    for (size_t b = 0; b < nblk && !r->e->code; b++) {
        int edim, etag, param;
        size_t cnt;
        if (kt_cursor_int(r, &edim, "entity dimension") || kt_cursor_int(r, &etag, "entity tag") ||
            kt_cursor_int(r, &param, "parametric flag (0 or 1)") ||
            kt_cursor_size(r, &cnt, "number of nodes in block"))
            break;
        if (edim < 0 || edim > 3) { kt_cursor_fail(r, "expected entity dimension 0-3, found %d", edim); break; }
        if (param != 0 && param != 1) { kt_cursor_fail(r, "expected parametric flag 0 or 1, found %d", param); break; }
        if (cnt > nn - k) { kt_cursor_fail(r, "node block of %zu nodes exceeds the %zu nodes declared", cnt, nn); break; }
        for (size_t i = 0; i < cnt; i++) {
            if (kt_cursor_size(r, &tp[k + i].tag, "node tag")) break;
            if (tp[k + i].tag == 0) { kt_cursor_fail(r, "expected a node tag >= 1, found 0"); break; }
            tp[k + i].pos = k + i;
        }
        int extra = param ? (edim < 3 ? edim : 3) : 0;
        for (size_t i = 0; i < cnt && !r->e->code; i++) {
            for (int c = 0; c < 3; c++) {
                double *x = &xyz[3 * (k + i) + c];
                if (kt_cursor_double(r, x, "node coordinate")) break;
                if (!(fabs(*x) <= KT_MESH_MAX_COORD)) {
                    kt_cursor_fail(r, "expected a node coordinate within +-%g mm, found %g",
                                   KT_MESH_MAX_COORD, *x);
                    break;
                }
            }
            double uvw;
            for (int c = 0; c < extra && !r->e->code; c++) kt_cursor_double(r, &uvw, "parametric coordinate");
        }
        k += cnt;
    }
    if (!r->e->code && k != nn) kt_cursor_fail(r, "node blocks hold %zu nodes, header declared %zu", k, nn);
    if (!r->e->code) build_nodes(s, tp, xyz, nn);
    free(tp);
    free(xyz);
    return r->e->code;
}

/* ------------------------------------------------------------------------------------------ */
/* Elements                                                                                    */

static int elist_grow(elist *L, int nv, size_t add, kt_err *e)
{
    if (L->n + add <= L->cap) return KT_OK;
    size_t cap = L->cap ? L->cap : 64;
    while (cap < L->n + add) cap *= 2;
    size_t *t = kt_realloc(L->etag, cap, sizeof *t, e);
    if (!t) return e->code;
    L->etag = t;
    int *en = kt_realloc(L->ent, cap, sizeof *en, e);
    if (!en) return e->code;
    L->ent = en;
    int *nd = kt_realloc(L->node, cap * (size_t)nv, sizeof *nd, e);
    if (!nd) return e->code;
    L->node = nd;
    L->cap = cap;
    return KT_OK;
}

/* Skip a block of a type we do not keep. */
static int skip_block(rd *r, int type, size_t cnt)
{
    int nv = type_nodes(type);
    if (r->bin) {
        if (nv == 0) return kt_cursor_fail(r, "element type %d: node count unknown, cannot skip a binary block", type);
        size_t bytes = 8 * (size_t)(nv + 1);
        if (cnt > (r->n - r->p) / bytes) {
            r->at = r->n;
            return kt_cursor_fail(r, "expected %zu elements of type %d", cnt, type);
        }
        r->p += cnt * bytes;
        return KT_OK;
    }
    /* ASCII: one element per line (as gmsh writes them). */
    for (size_t i = 0; i <= cnt; i++) {
        while (r->p < r->n && r->b[r->p] != '\n') r->p++;
        if (r->p >= r->n) {
            r->at = r->n;
            return kt_cursor_fail(r, "expected %zu elements of type %d", cnt, type);
        }
        r->p++;
    }
    return KT_OK;
}

static int read_block(msh_rd *s)
{
    rd *r = &s->r;
    int edim, etag, type;
    size_t cnt;
    if (kt_cursor_int(r, &edim, "entity dimension")) return r->e->code;
    size_t header = r->at;
    if (kt_cursor_int(r, &etag, "entity tag") || kt_cursor_int(r, &type, "element type") ||
        kt_cursor_size(r, &cnt, "number of elements in block"))
        return r->e->code;
    int k = type_kind(type);
    if (k < 0) return skip_block(r, type, cnt);
    if (edim != kind_dim[k])
        return kt_cursor_fail(r, "expected entity dimension %d for element type %d, found %d", kind_dim[k], type, edim);
    /* Elements on an undeclared entity would silently lose their groups. */
    const ents *E = &s->ent[kind_dim[k] - 2];
    int declared = 0;
    for (int i = 0; i < E->n && !declared; i++) declared = E->tag[i] == etag;
    if (s->have_entities && !declared) {
        r->at = header;
        return kt_cursor_fail(r, "element block on entity (%d, %d), which $Entities does not declare", edim, etag);
    }
    int nv = kind_nv[k];
    if (kt_cursor_fits(r, cnt, r->bin ? 8 * (size_t)(nv + 1) : 2 * (size_t)(nv + 1), "number of elements"))
        return r->e->code;
    elist *L = &s->el[k];
    if (cnt > (size_t)KT_MESH_MAX_TETS - L->n)
        return kt_cursor_fail(r, "expected at most %d elements of type %d, found %zu more",
                              KT_MESH_MAX_TETS, type, cnt);
    if (elist_grow(L, nv, cnt, r->e)) return r->e->code;
    for (size_t i = 0; i < cnt; i++) {
        size_t t;
        if (kt_cursor_size(r, &L->etag[L->n], "element tag")) return r->e->code;
        L->ent[L->n] = etag;
        int *nd = L->node + (size_t)nv * L->n;
        for (int j = 0; j < nv; j++) {
            if (kt_cursor_size(r, &t, "node tag")) return r->e->code;
            nd[j] = node_number(&s->map, t);
            if (nd[j] < 0) return kt_cursor_fail(r, "node tag %zu is not in $Nodes", t);
        }
        L->n++;
    }
    return KT_OK;
}

static int read_elements(msh_rd *s)
{
    rd *r = &s->r;
    if (!s->have_nodes) return kt_cursor_fail(r, "expected $Nodes before $Elements");
    if (s->have_elements) return kt_cursor_fail(r, "expected one $Elements section, found a second");
    s->have_elements = 1;
    size_t nblk, ne, lo, hi;
    if (kt_cursor_size(r, &nblk, "number of element blocks") || kt_cursor_size(r, &ne, "number of elements") ||
        kt_cursor_size(r, &lo, "minimum element tag") || kt_cursor_size(r, &hi, "maximum element tag"))
        return r->e->code;
    if (kt_cursor_fits(r, nblk, r->bin ? 20 : 8, "number of element blocks")) return r->e->code;
    for (size_t b = 0; b < nblk; b++)
        if (read_block(s)) return r->e->code;
    return KT_OK;
}

/* ------------------------------------------------------------------------------------------ */
/* From raw element lists to the mesh.                                                         */

static const ents *find_ent_list(const msh_rd *s, int dim) { return &s->ent[dim - 2]; }

/* Physical tags of entity (dim, tag): [*first, *first + *count) of E->phys. */
static void ent_phys(const ents *E, int tag, int *first, int *count)
{
    *first = *count = 0;
    for (int i = 0; i < E->n; i++)
        if (E->tag[i] == tag) {
            *first = E->ptr[i];
            *count = E->ptr[i + 1] - E->ptr[i];
            return;
        }
}

/* Entries of list L that belong to physical groups, in element-tag order: the number of mesh
 * entries it makes (one per physical tag), or -1 after an error. */
static long count_kept(const msh_rd *s, int k)
{
    const elist *L = &s->el[k];
    const ents *E = find_ent_list(s, kind_dim[k]);
    long total = 0;
    int last = INT_MIN, f = 0, c = 0;
    for (size_t i = 0; i < L->n; i++) {
        if (L->ent[i] != last) ent_phys(E, L->ent[i], &f, &c), last = L->ent[i];
        total += c;
    }
    return total;
}

static int emit(msh_rd *s, int k, int **nodes, int **tags, int *count)
{
    rd *r = &s->r;
    const elist *L = &s->el[k];
    const ents *E = find_ent_list(s, kind_dim[k]);
    int nv = kind_nv[k];
    long total = count_kept(s, k);
    if (total > INT_MAX) return kt_fail(r->e, KT_EINPUT, "%s: too many elements", r->path);
    tagpos *ord = kt_calloc(L->n, sizeof *ord, r->e);
    int *phf = kt_calloc(L->n, sizeof *phf, r->e), *phc = kt_calloc(L->n, sizeof *phc, r->e);
    *nodes = kt_calloc((size_t)total * nv, sizeof **nodes, r->e);
    *tags = kt_calloc((size_t)total, sizeof **tags, r->e);
    if (r->e->code) goto done;
    int last = INT_MIN, f = 0, c = 0;
    size_t kept = 0;
    for (size_t i = 0; i < L->n; i++) {
        if (L->ent[i] != last) ent_phys(E, L->ent[i], &f, &c), last = L->ent[i];
        if (!c) continue;
        if (kind_dim[k] == 3 && c > 1) {
            kt_fail(r->e, KT_EINPUT, "%s: volume entity %d is in %d physical volumes; a tetrahedron "
                    "needs exactly one region", r->path, L->ent[i], c);
            goto done;
        }
        ord[kept].tag = L->etag[i];
        ord[kept].pos = i;
        phf[i] = f, phc[i] = c;
        kept++;
    }
    qsort(ord, kept, sizeof *ord, cmp_tagpos);
    int out = 0;
    for (size_t j = 0; j < kept; j++) {
        if (j && ord[j].tag == ord[j - 1].tag) {
            kt_fail(r->e, KT_EINPUT, "%s: $Elements: element tag %zu appears twice", r->path, ord[j].tag);
            goto done;
        }
        size_t i = ord[j].pos;
        for (int p = 0; p < phc[i]; p++, out++) {
            memcpy(*nodes + (size_t)nv * out, L->node + (size_t)nv * i, nv * sizeof(int));
            (*tags)[out] = E->phys[phf[i] + p];
        }
    }
    *count = out;
done:
    free(ord);
    free(phf);
    free(phc);
    return r->e->code;
}

static int build_mesh(msh_rd *s)
{
    rd *r = &s->r;
    kt_mesh *m = s->m;
    long t4 = count_kept(s, K_TET4), t10 = count_kept(s, K_TET10);
    if (t4 && t10)
        return kt_fail(r->e, KT_EINPUT, "%s: expected tetrahedra of one order, found %ld 4-node and "
                       "%ld 10-node tetrahedra", r->path, t4, t10);
    if (!t4 && !t10)
        return kt_fail(r->e, KT_EINPUT, "%s: expected 4- or 10-node tetrahedra in a physical volume "
                       "group, found none", r->path);
    m->order = t10 ? 2 : 1;
    int kt = t10 ? K_TET10 : K_TET4, kf = t10 ? K_TRI6 : K_TRI3, other = t10 ? K_TRI3 : K_TRI6;
    long bad = count_kept(s, other);
    if (bad)
        return kt_fail(r->e, KT_EINPUT, "%s: expected %d-node triangles to match %d-node tetrahedra, "
                       "found %ld %d-node triangles in physical surfaces", r->path, kind_nv[kf],
                       kind_nv[kt], bad, kind_nv[other]);
    if (emit(s, kt, &m->tet, &m->tet_tag, &m->ne)) return r->e->code;
    return emit(s, kf, &m->tri, &m->tri_tag, &m->nf);
}

/* ------------------------------------------------------------------------------------------ */

static int read_sections(msh_rd *s)
{
    rd *r = &s->r;
    int file_bin = 0;
    for (;;) {
        r->bin = 0;
        while (r->p < r->n && kt_cursor_is_ws(r->b[r->p])) r->p++;
        if (r->p >= r->n) break;
        const char *t;
        size_t len;
        if (kt_cursor_token(r, &t, &len, "a section header")) return r->e->code;
        if (t[0] != '$' || len < 2 || len > 60)
            return kt_cursor_fail(r, "expected a section header such as $Nodes, found '%.*s'",
                           (int)(len > 40 ? 40 : len), t);
        char name[64];
        memcpy(name, t + 1, len - 1);
        name[len - 1] = '\0';
        if (!s->have_format && strcmp(name, "MeshFormat") != 0)
            return kt_cursor_fail(r, "expected $MeshFormat first");
        if (strcmp(name, "MeshFormat") == 0) {
            if (s->have_format) return kt_cursor_fail(r, "expected one $MeshFormat section");
            if (read_format(s)) return r->e->code;
            file_bin = r->bin;
            continue;
        }
        if (strcmp(name, "PhysicalNames") == 0) {
            if (read_physical_names(s)) return r->e->code;
            continue;
        }
        if (strcmp(name, "PartitionedEntities") == 0)
            return kt_cursor_fail(r, "partitioned MSH files are not supported (expected $Entities)");
        int (*fn)(msh_rd *) = strcmp(name, "Entities") == 0 ? read_entities
                              : strcmp(name, "Nodes") == 0  ? read_nodes
                              : strcmp(name, "Elements") == 0 ? read_elements
                                                              : NULL;
        if (!fn) {
            if (skip_section(r, name)) return r->e->code;
            continue;
        }
        if (file_bin && end_header_line(r)) return r->e->code;
        r->bin = file_bin;
        if (fn(s)) return r->e->code;
        r->bin = 0;
        char end[72];
        snprintf(end, sizeof end, "$End%s", name);
        if (kt_cursor_expect(r, end)) return r->e->code;
    }
    r->at = r->n;
    if (!s->have_format) return kt_cursor_fail(r, "expected $MeshFormat");
    if (!s->have_nodes) return kt_cursor_fail(r, "expected a $Nodes section");
    if (!s->have_elements) return kt_cursor_fail(r, "expected an $Elements section");
    return KT_OK;
}

int kt_msh_read(const char *path, kt_mesh *m, kt_err *e)
{
    memset(m, 0, sizeof *m);
    msh_rd s;
    memset(&s, 0, sizeof s);
    if (kt_cursor_open(&s.r, path, "$MeshFormat", KT_MSH_MAX_BYTES, e)) return e->code;
    s.m = m;
    if (read_sections(&s) == KT_OK) build_mesh(&s);
    msh_rd_free(&s);
    kt_cursor_close(&s.r);
    if (e->code) kt_mesh_free(m);
    return e->code;
}

