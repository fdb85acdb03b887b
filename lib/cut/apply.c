/* apply.c: apply the node duplications of a step to a mesh, all-or-nothing, and report the nodes
 * whose stiffness columns changed. */
#include "apply.h"

#include <stdlib.h>
#include <string.h>

/* Scratch copies of the elements a step changes, so a bad edit leaves the mesh untouched. */
typedef struct scratch {
    int ntet, *tet_id, *tet_nodes;   /* sorted tet numbers and their node lists (nv each) */
    int ntri, *tri_id, *tri_nodes;   /* candidate triangles and their node lists (fv each) */
} scratch;

static void scratch_free(scratch *s)
{
    free(s->tet_id);
    free(s->tet_nodes);
    free(s->tri_id);
    free(s->tri_nodes);
}

static int cmp_int(const void *a, const void *b)
{
    int x = *(const int *)a, y = *(const int *)b;
    return (x > y) - (x < y);
}

/* Sort and drop repeats; returns the new length. */
static int unique(int *v, int n)
{
    if (n == 0) return 0;
    qsort(v, (size_t)n, sizeof(int), cmp_int);
    int k = 1;
    for (int i = 1; i < n; i++)
        if (v[i] != v[k - 1]) v[k++] = v[i];
    return k;
}

static int count_dups(const kt_step *s, int *nel)
{
    int nd = 0;
    *nel = 0;
    for (int i = 0; i < s->n; i++)
        if (s->edit[i].kind == KT_EDIT_DUP) {
            nd++;
            *nel += s->edit[i].nel;
        }
    return nd;
}

/* Copy every tet a dup lists, and every triangle holding a node a dup names. */
static int make_scratch(const kt_mesh *m, const kt_step *s, int nel, int nn_end, scratch *sc,
                        kt_err *e)
{
    int nv = kt_tet_nv(m->order), fv = kt_tri_nv(m->order);
    sc->tet_id = kt_calloc((size_t)nel, sizeof(int), e);
    unsigned char *mark = kt_calloc((size_t)nn_end, 1, e);
    if (e->code) {
        free(mark);
        return e->code;
    }
    int k = 0;
    for (int i = 0; i < s->n; i++) {
        const kt_edit *ed = &s->edit[i];
        if (ed->kind != KT_EDIT_DUP) continue;
        for (int j = 0; j < ed->nel; j++) {
            if (ed->el[j] < 0 || ed->el[j] >= m->ne) {
                free(mark);
                return kt_fail(e, KT_EINPUT, "step %d: dup of node %d names tet %d (expected 1..%d)",
                               s->index, ed->node + 1, ed->el[j] + 1, m->ne);
            }
            sc->tet_id[k++] = ed->el[j];
        }
        if (ed->node >= 0 && ed->node < nn_end) mark[ed->node] = 1;
    }
    sc->ntet = unique(sc->tet_id, k);
    sc->tet_nodes = kt_calloc((size_t)sc->ntet * nv, sizeof(int), e);
    int nt = 0;
    for (int t = 0; t < m->nf; t++)
        for (int a = 0; a < fv; a++)
            if (mark[m->tri[(size_t)t * fv + a]]) {
                nt++;
                break;
            }
    sc->tri_id = kt_calloc((size_t)nt, sizeof(int), e);
    sc->tri_nodes = kt_calloc((size_t)nt * fv, sizeof(int), e);
    if (e->code) {
        free(mark);
        return e->code;
    }
    for (int i = 0; i < sc->ntet; i++)
        memcpy(sc->tet_nodes + (size_t)i * nv, m->tet + (size_t)sc->tet_id[i] * nv,
               sizeof(int) * nv);
    for (int t = 0; t < m->nf && sc->ntri < nt; t++)
        for (int a = 0; a < fv; a++)
            if (mark[m->tri[(size_t)t * fv + a]]) {
                sc->tri_id[sc->ntri] = t;
                memcpy(sc->tri_nodes + (size_t)sc->ntri * fv, m->tri + (size_t)t * fv,
                       sizeof(int) * fv);
                sc->ntri++;
                break;
            }
    free(mark);
    return KT_OK;
}

static int find_slot(const int *ids, int n, int id)
{
    const int *p = bsearch(&id, ids, (size_t)n, sizeof(int), cmp_int);
    return p ? (int)(p - ids) : -1;
}

static int has_node(const int *v, int n, int x)
{
    for (int i = 0; i < n; i++)
        if (v[i] == x) return 1;
    return 0;
}

/* A triangle lies on a face of a tet when all its nodes are nodes of the tet. */
static int on_tet(const int *tri, int fv, const int *tet, int nv)
{
    for (int a = 0; a < fv; a++)
        if (!has_node(tet, nv, tri[a])) return 0;
    return 1;
}

/* One dup on the scratch copies: triangles on a face of a moved tet follow it, then the tets. */
static int apply_dup(const kt_mesh *m, const kt_step *s, const kt_edit *ed, int nn_now,
                     scratch *sc, kt_err *e)
{
    int nv = kt_tet_nv(m->order), fv = kt_tri_nv(m->order);
    if (ed->node < 0 || ed->node >= nn_now)
        return kt_fail(e, KT_EINPUT, "step %d: dup names node %d (expected 1..%d)", s->index,
                       ed->node + 1, nn_now);
    if (ed->new_node != nn_now)
        return kt_fail(e, KT_EINPUT, "step %d: dup of node %d creates node %d (expected %d, the "
                       "next free number)", s->index, ed->node + 1, ed->new_node + 1, nn_now + 1);
    if (ed->nel < 1)
        return kt_fail(e, KT_EINPUT, "step %d: dup of node %d moves no tet", s->index,
                       ed->node + 1);
    for (int j = 0; j < ed->nel; j++) {
        int *t = sc->tet_nodes + (size_t)find_slot(sc->tet_id, sc->ntet, ed->el[j]) * nv;
        if (!has_node(t, nv, ed->node))
            return kt_fail(e, KT_EINPUT, "step %d: dup of node %d moves tet %d, which does not "
                           "hold that node", s->index, ed->node + 1, ed->el[j] + 1);
        for (int k = 0; k < sc->ntri; k++) {
            int *tri = sc->tri_nodes + (size_t)k * fv;
            if (has_node(tri, fv, ed->node) && on_tet(tri, fv, t, nv))
                for (int a = 0; a < fv; a++)
                    if (tri[a] == ed->node) tri[a] = ed->new_node;
        }
    }
    for (int j = 0; j < ed->nel; j++) {
        int *t = sc->tet_nodes + (size_t)find_slot(sc->tet_id, sc->ntet, ed->el[j]) * nv;
        for (int a = 0; a < nv; a++)
            if (t[a] == ed->node) t[a] = ed->new_node;
    }
    return KT_OK;
}

/* Copy the scratch elements back and give each new node its original's coordinates. */
static int commit(kt_mesh *m, const kt_step *s, const scratch *sc, int nn_end, kt_err *e)
{
    int nv = kt_tet_nv(m->order), fv = kt_tri_nv(m->order);
    double *xyz = kt_realloc(m->xyz, 3 * (size_t)nn_end, sizeof(double), e);
    if (!xyz) return e->code;
    m->xyz = xyz;
    for (int i = 0; i < s->n; i++) {
        const kt_edit *ed = &s->edit[i];
        if (ed->kind == KT_EDIT_DUP) memcpy(xyz + 3 * (size_t)ed->new_node,
                                            xyz + 3 * (size_t)ed->node, 3 * sizeof(double));
    }
    for (int i = 0; i < sc->ntet; i++)
        memcpy(m->tet + (size_t)sc->tet_id[i] * nv, sc->tet_nodes + (size_t)i * nv,
               sizeof(int) * nv);
    for (int i = 0; i < sc->ntri; i++)
        memcpy(m->tri + (size_t)sc->tri_id[i] * fv, sc->tri_nodes + (size_t)i * fv,
               sizeof(int) * fv);
    m->nn = nn_end;
    return KT_OK;
}

/* Nodes of the moved tets after the step, plus the nodes the dups split. */
static int collect_touched(const kt_mesh *m, const kt_step *s, const scratch *sc, int **touched,
                           int *ntouched, kt_err *e)
{
    int nv = kt_tet_nv(m->order), nd = 0, nel = 0;
    nd = count_dups(s, &nel);
    int cap = sc->ntet * nv + nd;
    int *v = kt_calloc((size_t)cap, sizeof(int), e);
    if (!v) return e->code;
    int k = 0;
    for (int i = 0; i < sc->ntet * nv; i++) v[k++] = sc->tet_nodes[i];
    for (int i = 0; i < s->n; i++)
        if (s->edit[i].kind == KT_EDIT_DUP) v[k++] = s->edit[i].node;
    *ntouched = unique(v, k);
    *touched = v;
    return KT_OK;
}

int kt_cut_apply(kt_mesh *m, const kt_step *s, int **touched, int *ntouched, kt_err *e)
{
    *touched = NULL;
    *ntouched = 0;
    int nel = 0, nd = count_dups(s, &nel);
    if (nd == 0) return KT_OK;
    int nn_end = m->nn + nd;
    scratch sc = {0};
    if (make_scratch(m, s, nel, nn_end, &sc, e) == KT_OK) {
        int nn_now = m->nn;
        for (int i = 0; i < s->n && e->code == KT_OK; i++)
            if (s->edit[i].kind == KT_EDIT_DUP)
                if (apply_dup(m, s, &s->edit[i], nn_now, &sc, e) == KT_OK) nn_now++;
    }
    if (e->code == KT_OK) commit(m, s, &sc, nn_end, e);
    if (e->code == KT_OK) collect_touched(m, s, &sc, touched, ntouched, e);
    scratch_free(&sc);
    return e->code;
}
