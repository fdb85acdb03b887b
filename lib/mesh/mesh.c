/* mesh.c: tetrahedral mesh container, groups, checks, renumbering and order elevation. */
#include "mesh.h"
#include "topology.h"

#include <stdlib.h>
#include <string.h>

int kt_tet_nv(int order) { return order == 2 ? 10 : 4; }
int kt_tri_nv(int order) { return order == 2 ? 6 : 3; }

void kt_mesh_free(kt_mesh *m)
{
    if (!m) return;
    free(m->xyz);
    free(m->tet);
    free(m->tet_tag);
    free(m->tri);
    free(m->tri_tag);
    free(m->group);
    memset(m, 0, sizeof *m);
}

static void *dup_array(const void *src, size_t n, size_t size, kt_err *e)
{
    void *d = kt_calloc(n, size, e);
    if (d && n) memcpy(d, src, n * size);
    return d;
}

int kt_mesh_copy(kt_mesh *dst, const kt_mesh *src, kt_err *e)
{
    memset(dst, 0, sizeof *dst);
    *dst = *src;
    int tv = kt_tet_nv(src->order), fv = kt_tri_nv(src->order);
    dst->xyz = dup_array(src->xyz, 3 * (size_t)src->nn, sizeof(double), e);
    dst->tet = dup_array(src->tet, (size_t)tv * src->ne, sizeof(int), e);
    dst->tet_tag = dup_array(src->tet_tag, src->ne, sizeof(int), e);
    dst->tri = dup_array(src->tri, (size_t)fv * src->nf, sizeof(int), e);
    dst->tri_tag = dup_array(src->tri_tag, src->nf, sizeof(int), e);
    dst->group = dup_array(src->group, src->ng, sizeof(kt_group), e);
    if (e->code) {
        kt_mesh_free(dst);
        return e->code;
    }
    return KT_OK;
}

int kt_mesh_add_group(kt_mesh *m, int dim, int tag, const char *name, kt_err *e)
{
    if (kt_mesh_find_tag(m, dim, tag))
        return kt_fail(e, KT_EINPUT, "group tag %d of dimension %d used twice", tag, dim);
    if (strlen(name) >= KT_NAME_MAX)
        return kt_fail(e, KT_EINPUT, "group name '%s' longer than %d characters", name,
                       KT_NAME_MAX - 1);
    kt_group *g = kt_realloc(m->group, (size_t)m->ng + 1, sizeof *g, e);
    if (!g) return e->code;
    m->group = g;
    g[m->ng].dim = dim;
    g[m->ng].tag = tag;
    strcpy(g[m->ng].name, name);
    m->ng++;
    return KT_OK;
}

const kt_group *kt_mesh_find_group(const kt_mesh *m, int dim, const char *name)
{
    for (int i = 0; i < m->ng; i++)
        if (m->group[i].dim == dim && strcmp(m->group[i].name, name) == 0) return &m->group[i];
    return NULL;
}

const kt_group *kt_mesh_find_tag(const kt_mesh *m, int dim, int tag)
{
    for (int i = 0; i < m->ng; i++)
        if (m->group[i].dim == dim && m->group[i].tag == tag) return &m->group[i];
    return NULL;
}

static int cmp_int(const void *a, const void *b)
{
    int x = *(const int *)a, y = *(const int *)b;
    return (x > y) - (x < y);
}

int kt_mesh_group_nodes(const kt_mesh *m, const kt_group *g, int **nodes, int *count, kt_err *e)
{
    int nv = g->dim == 3 ? kt_tet_nv(m->order) : kt_tri_nv(m->order);
    int nel = g->dim == 3 ? m->ne : m->nf;
    const int *conn = g->dim == 3 ? m->tet : m->tri;
    const int *tag = g->dim == 3 ? m->tet_tag : m->tri_tag;
    size_t k = 0;
    for (int i = 0; i < nel; i++) k += (tag[i] == g->tag) ? (size_t)nv : 0;
    int *v = kt_calloc(k, sizeof(int), e);
    if (!v) return e->code;
    k = 0;
    for (int i = 0; i < nel; i++)
        if (tag[i] == g->tag)
            for (int j = 0; j < nv; j++) v[k++] = conn[(size_t)i * nv + j];
    qsort(v, k, sizeof(int), cmp_int);
    size_t u = 0;
    for (size_t i = 0; i < k; i++)
        if (u == 0 || v[i] != v[u - 1]) v[u++] = v[i];
    *nodes = v;
    *count = (int)u;
    return KT_OK;
}

double kt_tet_volume(const double *a, const double *b, const double *c, const double *d)
{
    double u[3], v[3], w[3];
    for (int i = 0; i < 3; i++) {
        u[i] = b[i] - a[i];
        v[i] = c[i] - a[i];
        w[i] = d[i] - a[i];
    }
    return (u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) +
            u[2] * (v[0] * w[1] - v[1] * w[0])) / 6.0;
}

int kt_mesh_check(const kt_mesh *m, const char *what, kt_err *e)
{
    if (m->order != 1 && m->order != 2)
        return kt_fail(e, KT_EINPUT, "%s: element order %d (expected 1 or 2)", what, m->order);
    int tv = kt_tet_nv(m->order), fv = kt_tri_nv(m->order);
    for (int i = 0; i < m->ne; i++) {
        const int *t = m->tet + (size_t)i * tv;
        for (int j = 0; j < tv; j++)
            if (t[j] < 0 || t[j] >= m->nn)
                return kt_fail(e, KT_EINPUT, "%s: tet %d names node %d (mesh has %d nodes)", what,
                               i + 1, t[j] + 1, m->nn);
        if (!kt_mesh_find_tag(m, 3, m->tet_tag[i]))
            return kt_fail(e, KT_EINPUT, "%s: tet %d has region tag %d with no group", what,
                           i + 1, m->tet_tag[i]);
        double v = kt_tet_volume(m->xyz + 3 * t[0], m->xyz + 3 * t[1], m->xyz + 3 * t[2],
                                 m->xyz + 3 * t[3]);
        if (!(v > 0))
            return kt_fail(e, KT_ERUN, "%s: tet %d is %s (volume %.3g mm^3)", what, i + 1,
                           v < 0 ? "inverted" : "degenerate", v);
    }
    for (int i = 0; i < m->nf; i++) {
        for (int j = 0; j < fv; j++) {
            int n = m->tri[(size_t)i * fv + j];
            if (n < 0 || n >= m->nn)
                return kt_fail(e, KT_EINPUT, "%s: triangle %d names node %d (mesh has %d nodes)",
                               what, i + 1, n + 1, m->nn);
        }
        if (!kt_mesh_find_tag(m, 2, m->tri_tag[i]))
            return kt_fail(e, KT_EINPUT, "%s: triangle %d has surface tag %d with no group",
                           what, i + 1, m->tri_tag[i]);
    }
    return KT_OK;
}

int kt_mesh_permute(kt_mesh *m, const int *perm, kt_err *e)
{
    int *inv = kt_calloc(m->nn, sizeof(int), e);
    double *xyz = kt_calloc(3 * (size_t)m->nn, sizeof(double), e);
    if (!inv || !xyz) {
        free(inv);
        free(xyz);
        return e->code;
    }
    for (int i = 0; i < m->nn; i++) inv[i] = -1;
    for (int i = 0; i < m->nn; i++) {
        int p = perm[i];
        if (p < 0 || p >= m->nn || inv[p] >= 0) {
            free(inv);
            free(xyz);
            return kt_fail(e, KT_ERUN, "node permutation is not a permutation (entry %d)", i);
        }
        inv[p] = i;
        memcpy(xyz + 3 * (size_t)i, m->xyz + 3 * (size_t)p, 3 * sizeof(double));
    }
    size_t nt = (size_t)m->ne * kt_tet_nv(m->order), nf = (size_t)m->nf * kt_tri_nv(m->order);
    for (size_t k = 0; k < nt; k++) m->tet[k] = inv[m->tet[k]];
    for (size_t k = 0; k < nf; k++) m->tri[k] = inv[m->tri[k]];
    free(m->xyz);
    m->xyz = xyz;
    free(inv);
    return KT_OK;
}

/* An edge as the pair (lo, hi) packed in one 64-bit key. */
static long long edge_key(int a, int b)
{
    return a < b ? ((long long)a << 32) | (unsigned)b : ((long long)b << 32) | (unsigned)a;
}

static int cmp_ll(const void *a, const void *b)
{
    long long x = *(const long long *)a, y = *(const long long *)b;
    return (x > y) - (x < y);
}

static int edge_index(const long long *keys, int n, long long k)
{
    const long long *p = bsearch(&k, keys, n, sizeof *keys, cmp_ll);
    return p ? (int)(p - keys) : -1;
}


int kt_mesh_elevate(kt_mesh *m, kt_err *e)
{
    if (m->order != 1) return kt_fail(e, KT_ERUN, "mesh is already of order %d", m->order);
    long long *keys = kt_calloc((size_t)6 * m->ne, sizeof *keys, e);
    if (!keys) return e->code;
    int nk = 0;
    for (int i = 0; i < m->ne; i++)
        for (int j = 0; j < 6; j++)
            keys[nk++] = edge_key(m->tet[4 * i + kt_tet_edge[j][0]], m->tet[4 * i + kt_tet_edge[j][1]]);
    qsort(keys, nk, sizeof *keys, cmp_ll);
    int ned = 0;
    for (int i = 0; i < nk; i++)
        if (ned == 0 || keys[i] != keys[ned - 1]) keys[ned++] = keys[i];
    double *xyz = kt_realloc(m->xyz, (size_t)m->nn + ned, 3 * sizeof(double), e);
    int *tet = kt_calloc((size_t)10 * m->ne, sizeof(int), e);
    int *tri = kt_calloc((size_t)6 * m->nf, sizeof(int), e);
    if (!xyz || !tet || !tri) {
        free(keys);
        free(tet);
        free(tri);
        if (xyz) m->xyz = xyz;
        return e->code;
    }
    m->xyz = xyz;
    for (int k = 0; k < ned; k++) {
        int a = (int)(keys[k] >> 32), b = (int)(keys[k] & 0xffffffff);
        for (int c = 0; c < 3; c++)
            xyz[3 * ((size_t)m->nn + k) + c] = 0.5 * (xyz[3 * (size_t)a + c] + xyz[3 * (size_t)b + c]);
    }
    for (int i = 0; i < m->ne; i++) {
        const int *t = m->tet + 4 * (size_t)i;
        int *q = tet + 10 * (size_t)i;
        memcpy(q, t, 4 * sizeof(int));
        for (int j = 0; j < 6; j++)
            q[4 + j] = m->nn + edge_index(keys, ned, edge_key(t[kt_tet_edge[j][0]], t[kt_tet_edge[j][1]]));
    }
    for (int i = 0; i < m->nf; i++) {
        const int *t = m->tri + 3 * (size_t)i;
        int *q = tri + 6 * (size_t)i;
        memcpy(q, t, 3 * sizeof(int));
        for (int j = 0; j < 3; j++) {
            int k = edge_index(keys, ned, edge_key(t[kt_tri_edge[j][0]], t[kt_tri_edge[j][1]]));
            if (k < 0) {
                free(keys);
                free(tet);
                free(tri);
                return kt_fail(e, KT_ERUN, "triangle %d has an edge that no tet has", i + 1);
            }
            q[3 + j] = m->nn + k;
        }
    }
    free(m->tet);
    free(m->tri);
    m->tet = tet;
    m->tri = tri;
    m->nn += ned;
    m->order = 2;
    free(keys);
    return KT_OK;
}

/* FNV-1a, 64 bits: offset basis 14695981039346656037, prime 1099511628211. */
static uint64_t fnv_bytes(uint64_t h, uint64_t v, int nbytes)
{
    for (int i = 0; i < nbytes; i++) {
        h ^= (v >> (8 * i)) & 0xffu;
        h *= 1099511628211ull;
    }
    return h;
}

uint64_t kt_mesh_hash(const kt_mesh *m)
{
    uint64_t h = 14695981039346656037ull;
    h = fnv_bytes(h, (uint32_t)m->order, 4);
    h = fnv_bytes(h, (uint32_t)m->nn, 4);
    h = fnv_bytes(h, (uint32_t)m->ne, 4);
    for (size_t i = 0; i < 3 * (size_t)m->nn; i++) {
        double x = m->xyz[i] == 0 ? 0.0 : m->xyz[i];
        uint64_t bits;
        memcpy(&bits, &x, sizeof bits);
        h = fnv_bytes(h, bits, 8);
    }
    size_t nt = (size_t)m->ne * (size_t)kt_tet_nv(m->order);
    for (size_t i = 0; i < nt; i++) h = fnv_bytes(h, (uint32_t)m->tet[i], 4);
    return h;
}
