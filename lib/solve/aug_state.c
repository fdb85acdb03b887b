/* aug_state.c: the stream's state (aug_stream): the cut mesh as the edits go, its node->tet
 * adjacency (for element-local stiffness columns), the parents of new nodes, the constraints
 * and forces the edits set, and the loads on the current mesh from the fem layer. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "aug_impl.h"
#include "apply.h"

/* Grow an array from oldn to newn items, filling the new ones with byte. */
static int grow_array(void *pp, size_t oldn, size_t newn, size_t sz, int byte, kt_err *e)
{
    void **p = pp;
    void *q = kt_realloc(*p, newn, sz, e);
    if (!q) return e->code;
    memset((char *)q + oldn * sz, byte, (newn - oldn) * sz);
    *p = q;
    return KT_OK;
}

static int grow(aug_stream *s, int nn, kt_err *e)
{
    if (nn <= s->cap_nn) return KT_OK;
    size_t o = (size_t)s->cap_nn, n = (size_t)(nn > 2 * s->cap_nn ? nn : 2 * s->cap_nn);
    size_t od = 3 * o, nd = 3 * n;
    if (grow_array(&s->adj, o, n, sizeof(int *), 0, e) ||
        grow_array(&s->adj_n, o, n, sizeof(int), 0, e) ||
        grow_array(&s->adj_cap, o, n, sizeof(int), 0, e) ||
        grow_array(&s->origin, o, n, sizeof(int), 0xff, e) ||
        grow_array(&s->parent, o, n, sizeof(int), 0xff, e) ||
        grow_array(&s->nmark, o, n, sizeof(int), 0, e) ||
        grow_array(&s->cons, od, nd, 1, 0, e) || grow_array(&s->fixed0, od, nd, 1, 0, e) ||
        grow_array(&s->g, od, nd, sizeof(double), 0, e) ||
        grow_array(&s->force, od, nd, sizeof(double), 0, e) ||
        grow_array(&s->f, od, nd, sizeof(double), 0, e))
        return e->code;
    s->cap_nn = (int)n;
    return KT_OK;
}

static int adj_add(aug_stream *s, int node, int tet, kt_err *e)
{
    if (s->adj_n[node] == s->adj_cap[node]) {
        int c = s->adj_cap[node] ? 2 * s->adj_cap[node] : 8;
        int *p = kt_realloc(s->adj[node], (size_t)c, sizeof(int), e);
        if (!p) return e->code;
        s->adj[node] = p;
        s->adj_cap[node] = c;
    }
    s->adj[node][s->adj_n[node]++] = tet;
    return KT_OK;
}

static void adj_remove(aug_stream *s, int node, int tet)
{
    for (int k = 0; k < s->adj_n[node]; k++)
        if (s->adj[node][k] == tet) {
            s->adj[node][k] = s->adj[node][--s->adj_n[node]];
            return;
        }
}

static int build_adjacency(aug_stream *s, kt_err *e)
{
    int nv = kt_tet_nv(s->mesh.order);
    for (int t = 0; t < s->mesh.ne; t++)
        for (int l = 0; l < nv; l++)
            if (adj_add(s, s->mesh.tet[(size_t)t * nv + l], t, e)) return e->code;
    for (int a = 0; a < s->mesh.nn; a++)
        if (s->adj_n[a] == 0)
            return kt_fail(e, KT_EINPUT, "node %d belongs to no tet (its stiffness would be zero)",
                           a + 1);
    return KT_OK;
}

int kt_aug_stream_loads(aug_stream *s, kt_err *e)
{
    size_t n = 3 * (size_t)s->mesh.nn;
    memset(s->f, 0, n * sizeof(double));
    for (int k = 0; k < s->npress; k++)
        if (kt_fem_pressure(&s->mesh, s->press[k].tag, s->press[k].p, s->f, e)) return e->code;
    if (kt_fem_release_loads(&s->mesh, &s->mats, s->f, e)) return e->code;
    for (size_t i = 0; i < n; i++) {
        s->f[i] += s->force[i];
        if (!isfinite(s->f[i]))
            return kt_fail(e, KT_EINPUT, "step %d: the load on node %zu sums to a value that is "
                           "not finite (an edits force or a pressure too large)", s->step, i / 3 + 1);
    }
    return KT_OK;
}

int kt_aug_stream_init(aug_stream *s, const kt_aug_problem *p, kt_err *e)
{
    if (kt_mesh_copy(&s->mesh, p->mesh, e)) return e->code;
    s->mats.nmat = p->mats->nmat;
    s->mats.mat = kt_calloc((size_t)p->mats->nmat, sizeof(kt_material), e);
    s->press = kt_calloc((size_t)(p->npress ? p->npress : 1), sizeof(kt_aug_pressure), e);
    s->fix = kt_calloc((size_t)(p->nfix ? p->nfix : 1), sizeof(kt_aug_fixsurf), e);
    if (e->code) return e->code;
    memcpy(s->mats.mat, p->mats->mat, (size_t)p->mats->nmat * sizeof(kt_material));
    s->mats.td = p->mats->td; /* per-tet data: shared, owned by the caller */
    s->mats.wound = p->mats->wound; /* the healed wound's bridge: likewise */
    s->npress = p->npress;
    if (p->npress) memcpy(s->press, p->press, (size_t)p->npress * sizeof(kt_aug_pressure));
    s->nfix = p->nfix;
    if (p->nfix) memcpy(s->fix, p->fix, (size_t)p->nfix * sizeof(kt_aug_fixsurf));
    int nn = s->mesh.nn;
    s->nn0 = nn;
    if (grow(s, nn, e) || build_adjacency(s, e)) return e->code;
    for (int a = 0; a < nn; a++) s->origin[a] = a;
    for (int i = 0; i < 3 * nn; i++)
        if (p->fixed && p->fixed[i]) {
            s->cons[i] = s->fixed0[i] = 1;
            s->g[i] = p->g ? p->g[i] : 0.0;
        }
    return kt_aug_stream_loads(s, e);
}

void kt_aug_stream_free(aug_stream *s)
{
    for (int a = 0; a < s->cap_nn; a++) free(s->adj[a]);
    free(s->adj);
    free(s->adj_n);
    free(s->adj_cap);
    free(s->origin);
    free(s->parent);
    free(s->nmark);
    free(s->cons);
    free(s->fixed0);
    free(s->g);
    free(s->force);
    free(s->f);
    free(s->press);
    free(s->fix);
    free(s->mats.mat);
    kt_mesh_free(&s->mesh);
    memset(s, 0, sizeof *s);
}

/* ----------------------------------------------------------------- the edits */

static int append_int(int **v, int *n, int *cap, int x, kt_err *e)
{
    if (*n == *cap) {
        int c = *cap ? 2 * *cap : 16;
        int *p = kt_realloc(*v, (size_t)c, sizeof(int), e);
        if (!p) return e->code;
        *v = p;
        *cap = c;
    }
    (*v)[(*n)++] = x;
    return KT_OK;
}

/* Move the tets of each dup in the adjacency; a node left with no tet is bad input. */
static int update_adjacency(aug_stream *s, const kt_step *st, kt_err *e)
{
    for (int i = 0; i < st->n; i++) {
        const kt_edit *ed = &st->edit[i];
        if (ed->kind != KT_EDIT_DUP) continue;
        s->origin[ed->new_node] = s->origin[ed->node];
        s->parent[ed->new_node] = ed->node;
        for (int j = 0; j < ed->nel; j++) {
            adj_remove(s, ed->node, ed->el[j]);
            if (adj_add(s, ed->new_node, ed->el[j], e)) return e->code;
        }
    }
    for (int i = 0; i < st->n; i++) {
        const kt_edit *ed = &st->edit[i];
        if (ed->kind == KT_EDIT_DUP && s->adj_n[ed->node] == 0)
            return kt_fail(e, KT_EINPUT, "step %d: dup of node %d moves every tet of it, leaving a "
                           "node in no element", st->index, ed->node + 1);
    }
    return KT_OK;
}

/* Fixations: a node created on a fixation surface is fixed like the surface. */
static int auto_fixes(aug_stream *s, int nn_old, kt_step *fixes, kt_err *e)
{
    int fv = kt_tri_nv(s->mesh.order);
    for (int t = 0; t < s->mesh.nf; t++)
        for (int k = 0; k < s->nfix; k++) {
            if (s->mesh.tri_tag[t] != s->fix[k].tag) continue;
            const int *tri = s->mesh.tri + (size_t)t * fv;
            for (int l = 0; l < fv; l++)
                if (tri[l] >= nn_old) {
                    kt_edit ed = {.kind = KT_EDIT_FIX, .node = tri[l], .mask = s->fix[k].mask};
                    memcpy(ed.v, s->fix[k].v, sizeof ed.v);
                    if (kt_step_add(fixes, &ed, e)) return e->code;
                }
        }
    return KT_OK;
}

/* One fix edit: constraints new to this step go to newc; values are recorded. */
static int apply_fix(aug_stream *s, const kt_edit *ed, int **newc, int *nc, int *ccap, kt_err *e)
{
    for (int c = 0; c < 3; c++) {
        if (!(ed->mask & (1u << c))) continue;
        int j = 3 * ed->node + c;
        if (!s->cons[j]) {
            s->cons[j] = 1;
            if (append_int(newc, nc, ccap, j, e)) return e->code;
        }
        s->g[j] = ed->v[c];
    }
    return KT_OK;
}

static int check_node(const aug_stream *s, const kt_step *st, const kt_edit *ed, kt_err *e)
{
    if (ed->node < 0 || ed->node >= s->mesh.nn)
        return kt_fail(e, KT_EINPUT, "step %d: %s names node %d (expected 1..%d)", st->index,
                       ed->kind == KT_EDIT_FIX ? "fix" : "force", ed->node + 1, s->mesh.nn);
    return KT_OK;
}

int kt_aug_stream_apply(aug_stream *s, const kt_step *st, int **newc, int *nc, kt_err *e)
{
    *newc = NULL;
    *nc = 0;
    int ccap = 0, ndup = 0, nn_old = s->mesh.nn, *touched = NULL, nt = 0;
    kt_step fixes = {0};
    s->step = st->index;
    for (int i = 0; i < st->n; i++) ndup += st->edit[i].kind == KT_EDIT_DUP;
    if (ndup && (kt_cut_apply(&s->mesh, st, &touched, &nt, e) || grow(s, s->mesh.nn, e) ||
                 update_adjacency(s, st, e) || auto_fixes(s, nn_old, &fixes, e)))
        goto done;
    for (int i = 0; i < st->n; i++)
        if (st->edit[i].kind == KT_EDIT_FIX || st->edit[i].kind == KT_EDIT_FORCE)
            if (check_node(s, st, &st->edit[i], e)) goto done;
    for (int i = 0; i < fixes.n; i++)
        if (apply_fix(s, &fixes.edit[i], newc, nc, &ccap, e)) goto done;
    for (int i = 0; i < st->n; i++) {
        const kt_edit *ed = &st->edit[i];
        if (ed->kind == KT_EDIT_FIX && apply_fix(s, ed, newc, nc, &ccap, e)) goto done;
        if (ed->kind == KT_EDIT_FORCE)
            memcpy(s->force + 3 * (size_t)ed->node, ed->v, sizeof ed->v);
    }
done:
    free(touched);
    kt_step_free(&fixes);
    return e->code;
}
