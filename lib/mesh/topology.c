/* topology.c: tet face and edge tables, node -> tet adjacency, sorted face tables. */
#include "topology.h"

#include <stdlib.h>
#include <string.h>

const int kt_tet_face[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
const int kt_tet_edge[6][2] = {{0, 1}, {1, 2}, {2, 0}, {3, 0}, {3, 2}, {3, 1}};
const int kt_tri_edge[3][2] = {{0, 1}, {1, 2}, {2, 0}};

void kt_sort3(int *v)
{
    int t;
    if (v[0] > v[1]) t = v[0], v[0] = v[1], v[1] = t;
    if (v[1] > v[2]) t = v[1], v[1] = v[2], v[2] = t;
    if (v[0] > v[1]) t = v[0], v[0] = v[1], v[1] = t;
}

int kt_face_cmp_v(const void *a, const void *b)
{
    const kt_face *x = a, *y = b;
    for (int k = 0; k < 3; k++)
        if (x->v[k] != y->v[k]) return x->v[k] < y->v[k] ? -1 : 1;
    return 0;
}

int kt_face_cmp(const void *a, const void *b)
{
    int c = kt_face_cmp_v(a, b);
    if (c) return c;
    const kt_face *x = a, *y = b;
    return (x->id > y->id) - (x->id < y->id);
}

int kt_face_find(const kt_face *f, int n, const int v[3])
{
    kt_face key = {{v[0], v[1], v[2]}, 0};
    kt_sort3(key.v);
    int lo = 0, hi = n;
    while (lo < hi) {
        int mid = lo + (hi - lo) / 2;
        if (kt_face_cmp_v(&f[mid], &key) < 0) lo = mid + 1;
        else hi = mid;
    }
    return lo < n && kt_face_cmp_v(&f[lo], &key) == 0 ? lo : -1;
}

int kt_mesh_node_tets(const kt_mesh *m, int **Ep, int **Ei, kt_err *e)
{
    int nv = kt_tet_nv(m->order);
    size_t len = (size_t)nv * m->ne;
    int *p = kt_calloc((size_t)m->nn + 1, sizeof(int), e);
    int *t = kt_calloc(len ? len : 1, sizeof(int), e);
    int *next = kt_calloc((size_t)m->nn + 1, sizeof(int), e);
    if (e->code) {
        free(p);
        free(t);
        free(next);
        return e->code;
    }
    for (size_t k = 0; k < len; k++) p[m->tet[k] + 1]++;
    for (int v = 0; v < m->nn; v++) p[v + 1] += p[v];
    memcpy(next, p, sizeof(int) * (size_t)m->nn);
    for (int el = 0; el < m->ne; el++)
        for (int a = 0; a < nv; a++) {
            int v = m->tet[(size_t)el * nv + a];
            /* a node twice in one tet would be a broken element: list the tet once */
            if (next[v] > p[v] && t[next[v] - 1] == el) continue;
            t[next[v]++] = el;
        }
    /* compact away the slots a repeated node left empty */
    int w = 0;
    for (int v = 0; v < m->nn; v++) {
        int start = p[v], end = next[v];
        p[v] = w;
        for (int k = start; k < end; k++) t[w++] = t[k];
    }
    p[m->nn] = w;
    free(next);
    *Ep = p;
    *Ei = t;
    return KT_OK;
}

int kt_mesh_tet_faces(const kt_mesh *m, kt_face **faces, kt_err *e)
{
    int nv = kt_tet_nv(m->order);
    size_t nf = 4 * (size_t)m->ne;
    kt_face *f = kt_calloc(nf ? nf : 1, sizeof *f, e);
    if (!f) return e->code;
    for (int t = 0; t < m->ne; t++)
        for (int j = 0; j < 4; j++) {
            kt_face *q = &f[4 * (size_t)t + j];
            for (int k = 0; k < 3; k++) q->v[k] = m->tet[(size_t)t * nv + kt_tet_face[j][k]];
            kt_sort3(q->v);
            q->id = 4 * t + j;
        }
    qsort(f, nf, sizeof *f, kt_face_cmp);
    *faces = f;
    return KT_OK;
}
