/* aug_cols.c: columns of the current stiffness K, computed from the element stiffness of the
 * tets around a node and, for a healed wound, the bridge of the cut face pairs it lies on
 * (never by reassembling K). */
#include <stdlib.h>
#include <string.h>

#include "aug_impl.h"
#include "wound.h"

int kt_aug_col_reserve(aug_col *c, int n, kt_err *e)
{
    if (n <= c->cap) return KT_OK;
    int cap = c->cap ? c->cap : 16;
    while (cap < n) cap *= 2;
    int *i = kt_realloc(c->i, (size_t)cap, sizeof(int), e);
    if (!i) return e->code;
    c->i = i;
    double *x = kt_realloc(c->x, (size_t)cap, sizeof(double), e);
    if (!x) return e->code;
    c->x = x;
    c->cap = cap;
    return KT_OK;
}

void kt_aug_col_free(aug_col *c)
{
    free(c->i);
    free(c->x);
    memset(c, 0, sizeof *c);
}

/* Local index of node a in tet t (nv nodes), -1 if absent. */
static int local_of(const int *t, int nv, int a)
{
    for (int k = 0; k < nv; k++)
        if (t[k] == a) return k;
    return -1;
}

/* The cut face pairs node a lies on (by their lower slot, each once) into pairs (capacity
 * 4 adj_n[a]); returns the count. None without a healed wound. */
static int node_pairs(const aug_stream *s, int a, int *pairs)
{
    const kt_wound *w = s->mats.wound;
    if (!kt_wound_on(&s->mats)) return 0;
    int nv = kt_tet_nv(s->mesh.order), np = 0, loc[6];
    for (int k = 0; k < s->adj_n[a]; k++) {
        int t = s->adj[a][k];
        for (int f = 0; f < 4; f++) {
            int sl = 4 * t + f, o = w->mate[sl], fv = kt_wound_face_local(s->mesh.order, f, loc), on = 0;
            for (int i = 0; i < fv; i++) on |= s->mesh.tet[(size_t)t * nv + loc[i]] == a;
            if (o < 0 || !on || !kt_wound_cut(w, &s->mesh, sl)) continue;
            int low = o < sl ? o : sl, q = 0;
            while (q < np && pairs[q] != low) q++;
            if (q == np) pairs[np++] = low;
        }
    }
    return np;
}

/* Mark and list node b (slot nb) unless marked. */
static int slot_add(aug_stream *s, int b, int *nodes, int cap, int nb)
{
    if (s->nmark[b] == s->nstamp) return nb;
    s->nmark[b] = s->nstamp;
    if (nb < cap) nodes[nb] = b;
    return nb + 1;
}

/* The neighbours of a (nodes sharing a tet or one of the cut face pairs[0..np), a first) get
 * slots 0..nb-1 in s->nmark. */
static int neighbour_slots(aug_stream *s, int a, const int *pairs, int np, int *nodes, int cap)
{
    int nv = kt_tet_nv(s->mesh.order), nb = 0, loc[6];
    s->nstamp++;
    for (int k = 0; k < s->adj_n[a]; k++) {
        const int *t = s->mesh.tet + (size_t)s->adj[a][k] * nv;
        for (int l = 0; l < nv; l++) nb = slot_add(s, t[l], nodes, cap, nb);
    }
    for (int q = 0; q < np; q++)
        for (int side = 0; side < 2; side++) {
            int sl = side ? s->mats.wound->mate[pairs[q]] : pairs[q];
            int fv = kt_wound_face_local(s->mesh.order, sl % 4, loc);
            for (int i = 0; i < fv; i++)
                nb = slot_add(s, s->mesh.tet[(size_t)(sl / 4) * nv + loc[i]], nodes, cap, nb);
        }
    return nb;
}

static int slot_of(const int *nodes, int nb, int b)
{
    for (int k = 0; k < nb; k++)
        if (nodes[k] == b) return k;
    return -1;
}

/* Add tet t's contribution to the three columns of node a, accumulated densely by slot. */
static int add_tet(aug_stream *s, int tet, int a, const int *nodes, int nb, double *acc, double *Ke,
                   kt_err *e)
{
    int nv = kt_tet_nv(s->mesh.order), nd = 3 * nv;
    const int *t = s->mesh.tet + (size_t)tet * nv;
    int tag = s->mesh.tet_tag[tet];
    if (tag < 0 || tag >= s->mats.nmat)
        return kt_fail(e, KT_EINPUT, "tet %d has region tag %d without a material", tet + 1, tag);
    if (kt_fem_element(&s->mesh, &s->mats, tet, Ke, e)) return e->code;
    int la = local_of(t, nv, a);
    for (int l = 0; l < nv; l++) {
        int s = slot_of(nodes, nb, t[l]);
        for (int r = 0; r < 3; r++)
            for (int c = 0; c < 3; c++)
                acc[(3 * s + r) * 3 + c] += Ke[(size_t)(3 * l + r) * nd + 3 * la + c];
    }
    return KT_OK;
}

/* The bridge's entries of node a's columns into acc (by slot). */
typedef struct bridge_acc {
    int a, nb;
    const int *nodes;
    double *acc;
} bridge_acc;

static void bridge_put(void *ctx, int v, int w, double x)
{
    bridge_acc *b = ctx;
    if (w / 3 != b->a) return;
    int sl = slot_of(b->nodes, b->nb, v / 3);
    b->acc[(3 * sl + v % 3) * 3 + w % 3] += x;
}

int kt_aug_node_columns(aug_stream *s, int a, aug_col col[3], kt_err *e)
{
    int nodes_small[256];
    int *pairs = kt_calloc(4 * (size_t)s->adj_n[a] + 1, sizeof(int), e);
    if (!pairs) return e->code;
    int np = node_pairs(s, a, pairs);
    int nb = neighbour_slots(s, a, pairs, np, nodes_small, 256);
    int *nodes = nodes_small;
    if (nb > 256) {
        nodes = kt_calloc((size_t)nb, sizeof(int), e);
        if (!nodes) {
            free(pairs);
            return e->code;
        }
        neighbour_slots(s, a, pairs, np, nodes, nb);
    }
    double *acc = kt_calloc((size_t)nb * 9, sizeof(double), e);
    double *Ke = kt_calloc(900, sizeof(double), e);
    for (int k = 0; k < 3 && !e->code; k++) kt_aug_col_reserve(&col[k], 3 * nb, e);
    for (int k = 0; k < s->adj_n[a] && !e->code; k++)
        add_tet(s, s->adj[a][k], a, nodes, nb, acc, Ke, e);
    bridge_acc ba = {a, nb, nodes, acc};
    for (int q = 0; q < np && !e->code; q++)
        kt_wound_pair_put(s->mats.wound, &s->mesh, pairs[q], NULL, 1.0, 1, bridge_put, &ba, e);
    free(pairs);
    if (!e->code)
        for (int c = 0; c < 3; c++) {
            col[c].n = 0;
            for (int s = 0; s < nb; s++)
                for (int r = 0; r < 3; r++) {
                    col[c].i[col[c].n] = 3 * nodes[s] + r;
                    col[c].x[col[c].n++] = acc[(3 * s + r) * 3 + c];
                }
        }
    if (nodes != nodes_small) free(nodes);
    free(acc);
    free(Ke);
    return e->code;
}
