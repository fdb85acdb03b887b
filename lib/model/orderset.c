/* orderset.c: the node set a scene's constrained ordering puts last, and its ranks. */
#include "orderset.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>


/* ---- the ordering set ------------------------------------------------------------------------ */

static int cmp_int(const void *a, const void *b)
{
    int x = *(const int *)a, y = *(const int *)b;
    return (x > y) - (x < y);
}

/* Append group g's nodes to *v (size *n), then the caller sorts and dedups. */
static int append_group(const kt_mesh *m, const kt_group *g, int **v, int *n, kt_err *e)
{
    int *nodes = NULL, cnt = 0;
    if (kt_mesh_group_nodes(m, g, &nodes, &cnt, e)) return e->code;
    int *w = kt_realloc(*v, (size_t)*n + cnt, sizeof(int), e);
    if (!w) {
        free(nodes);
        return e->code;
    }
    memcpy(w + *n, nodes, sizeof(int) * (size_t)cnt);
    *v = w;
    *n += cnt;
    free(nodes);
    return KT_OK;
}

/* Grow the sorted set by 'layers' layers of tet neighbours; the result stays sorted. */
static int grow(const kt_mesh *m, int layers, int **nodes, int *count, kt_err *e)
{
    if (layers <= 0) return KT_OK;
    unsigned char *in = kt_calloc((size_t)m->nn, 1, e), *add = kt_calloc((size_t)m->nn, 1, e);
    if (!in || !add) {
        free(in);
        free(add);
        return e->code;
    }
    int nv = kt_tet_nv(m->order);
    for (int k = 0; k < *count; k++) in[(*nodes)[k]] = 1;
    for (int l = 0; l < layers; l++) {
        for (int t = 0; t < m->ne; t++) {
            const int *q = m->tet + (size_t)t * nv;
            int touch = 0;
            for (int j = 0; j < nv; j++) touch |= in[q[j]];
            for (int j = 0; j < nv && touch; j++) add[q[j]] = 1;
        }
        memcpy(in, add, (size_t)m->nn);
    }
    int n = 0;
    for (int v = 0; v < m->nn; v++) n += in[v];
    int *v2 = kt_realloc(*nodes, (size_t)n, sizeof(int), e);
    if (v2) {
        *nodes = v2;
        *count = 0;
        for (int v = 0; v < m->nn; v++)
            if (in[v]) v2[(*count)++] = v;
    }
    free(in);
    free(add);
    return e->code;
}

/* The named surfaces' nodes, sorted and unique. */
static int surfaces_nodes(const kt_scene *s, const kt_mesh *m, int **nodes, int *count, char *label, kt_err *e)
{
    if (s->ordering_set[0]) {
        const kt_group *g = kt_mesh_find_group(m, 2, s->ordering_set);
        if (!g)
            return kt_fail(e, KT_EINPUT, "%s: ordering.last: expected surface '%s' in the mesh", s->path,
                           s->ordering_set);
        snprintf(label, 96, "surface '%s' (ordering.last)", s->ordering_set);
        return kt_mesh_group_nodes(m, g, nodes, count, e);
    }
    int len = snprintf(label, 96, "incision rings");
    for (int i = 0; i < s->eye.nring; i++) {
        const kt_group *g = kt_mesh_find_group(m, 2, s->eye.ring[i].name);
        if (!g) return kt_fail(e, KT_ERUN, "eye mesh lacks incision surface '%s'", s->eye.ring[i].name);
        if (len < 80) len += snprintf(label + len, 96 - len, "%s%s", i ? "," : " ", g->name);
        if (append_group(m, g, nodes, count, e)) return e->code;
    }
    qsort(*nodes, (size_t)*count, sizeof(int), cmp_int);
    int u = 0;
    for (int i = 0; i < *count; i++)
        if (u == 0 || (*nodes)[i] != (*nodes)[u - 1]) (*nodes)[u++] = (*nodes)[i];
    *count = u;
    return KT_OK;
}

static double meridian_distance(const kt_mesh *m, int v, double centre);

/* Eye: keep only the nodes within ordering.sector of the centre meridian or its opposite (a
 * smaller set last means a smaller dense root block of L; the cut arcs lie inside it). */
static int keep_sector(const kt_scene *s, const kt_mesh *m, int *nodes, int *count)
{
    if (s->model != KT_MODEL_EYE || isnan(s->ordering_centre) || isnan(s->ordering_sector)) return 0;
    int u = 0;
    for (int k = 0; k < *count; k++)
        if (meridian_distance(m, nodes[k], s->ordering_centre) <= s->ordering_sector) nodes[u++] = nodes[k];
    *count = u;
    return 0;
}

int kt_orderset_nodes(const kt_scene *s, const kt_mesh *m, int **nodes, int *count, char *label, kt_err *e)
{
    *nodes = NULL;
    *count = 0;
    if (!s->ordering_set[0] && (s->model != KT_MODEL_EYE || s->eye.nring == 0)) {
        snprintf(label, 160, "all nodes (the scene names no incision surface)");
        return KT_OK;
    }
    char what[96];
    if (surfaces_nodes(s, m, nodes, count, what, e) || keep_sector(s, m, *nodes, count) ||
        grow(m, s->ordering_halo, nodes, count, e)) {
        free(*nodes);
        *nodes = NULL;
        *count = 0;
        return e->code;
    }
    int len = snprintf(label, 160, "%s", what);
    if (len < 160 && s->model == KT_MODEL_EYE && !isnan(s->ordering_centre) && !isnan(s->ordering_sector))
        len += snprintf(label + len, 160 - len, " within %g deg of meridian %g and its opposite",
                        s->ordering_sector, s->ordering_centre);
    if (len < 160 && s->ordering_halo)
        snprintf(label + len, 160 - len, " and %d layer%s of tet neighbours (ordering.halo)",
                 s->ordering_halo, s->ordering_halo > 1 ? "s" : "");
    return KT_OK;
}

/* Angular distance (deg, 0-90) of node v from the meridian line through centre. */
static double meridian_distance(const kt_mesh *m, int v, double centre)
{
    double t = atan2(m->xyz[3 * (size_t)v + 1], m->xyz[3 * (size_t)v]) * 180 / KT_PI;
    double d = fmod(fabs(t - centre), 180.0);
    return fmin(d, 180.0 - d);
}

int kt_orderset_ranks(const kt_scene *s, const kt_mesh *m, const int *nodes, int count, int **rank,
                      kt_err *e)
{
    *rank = NULL;
    if (s->model != KT_MODEL_EYE || isnan(s->ordering_centre) || count == 0) return KT_OK;
    *rank = kt_calloc((size_t)count, sizeof(int), e);
    if (!*rank) return e->code;
    for (int k = 0; k < count; k++)
        (*rank)[k] = (int)lround(2 * (90 - meridian_distance(m, nodes[k], s->ordering_centre)));
    return KT_OK;
}

/* The set's nodes within 30 deg of the centre meridian (what a paired 60-degree LRI cuts). */
int kt_orderset_sector(const kt_scene *s, const kt_mesh *m, const int *set, int nset, int **out,
                        int *count, kt_err *e)
{
    *out = NULL;
    *count = 0;
    if (s->model != KT_MODEL_EYE || isnan(s->ordering_centre) || nset == 0) return KT_OK;
    *out = kt_calloc((size_t)nset, sizeof(int), e);
    if (!*out) return e->code;
    for (int k = 0; k < nset; k++)
        if (meridian_distance(m, set[k], s->ordering_centre) <= 30) (*out)[(*count)++] = set[k];
    return KT_OK;
}

