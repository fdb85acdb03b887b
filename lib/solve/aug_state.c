/* aug_state.c: the state the edits change (mesh, node->tet adjacency, loads, constraints and
 * the lifted right-hand side fh), kept up to date incrementally: a step costs in proportion to
 * what it changes, not to the mesh size. */
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

int aug_grow(kt_aug *A, int nn, kt_err *e)
{
    if (nn <= A->cap_nn) return KT_OK;
    size_t o = (size_t)A->cap_nn, n = (size_t)(nn > 2 * A->cap_nn ? nn : 2 * A->cap_nn);
    size_t od = 3 * o, nd = 3 * n;
    if (grow_array(&A->adj, o, n, sizeof(int *), 0, e) || grow_array(&A->adj_n, o, n, sizeof(int), 0, e) ||
        grow_array(&A->adj_cap, o, n, sizeof(int), 0, e) ||
        grow_array(&A->touch_step, o, n, sizeof(int), 0xff, e) ||
        grow_array(&A->origin, o, n, sizeof(int), 0xff, e) ||
        grow_array(&A->nmark, o, n, sizeof(int), 0, e) ||
        grow_array(&A->kids, o, n, sizeof(int *), 0, e) ||
        grow_array(&A->kids_n, o, n, sizeof(int), 0, e) ||
        grow_array(&A->kids_cap, o, n, sizeof(int), 0, e) ||
        grow_array(&A->par, od, nd, sizeof(int), 0xff, e) ||
        grow_array(&A->cons, od, nd, 1, 0, e) || grow_array(&A->g, od, nd, sizeof(double), 0, e) ||
        grow_array(&A->force, od, nd, sizeof(double), 0, e) ||
        grow_array(&A->f, od, nd, sizeof(double), 0, e) ||
        grow_array(&A->fh, od, nd, sizeof(double), 0, e) ||
        grow_array(&A->cons_step, od, nd, sizeof(int), 0xff, e) ||
        grow_array(&A->rhs_step, od, nd, sizeof(int), 0xff, e) ||
        grow_array(&A->Lpos, od, nd, sizeof(int), 0xff, e) || grow_array(&A->ind, od, nd, 1, 0, e) ||
        grow_array(&A->u, od, nd, sizeof(double), 0, e) ||
        grow_array(&A->react, od, nd, sizeof(double), 0, e) ||
        grow_array(&A->w, od, nd, sizeof(double), 0, e) ||
        grow_array(&A->w2, od, nd, sizeof(double), 0, e) ||
        grow_array(&A->uprev, od, nd, sizeof(double), 0, e) ||
        grow_array(&A->pad, od, nd, sizeof(double), 0, e) ||
        grow_array(&A->dmark, od, nd, sizeof(int), 0, e))
        return e->code;
    if (A->outmask && grow_array(&A->outmask, od, nd, 1, 0, e)) return e->code;
    A->cap_nn = (int)n;
    return KT_OK;
}

/* Append x to the list v[node] (count n[node], capacity cap[node]). */
static int list_add(int **v, int *n, int *cap, int node, int x, kt_err *e)
{
    if (n[node] == cap[node]) {
        int c = cap[node] ? 2 * cap[node] : 8;
        int *p = kt_realloc(v[node], (size_t)c, sizeof(int), e);
        if (!p) return e->code;
        v[node] = p;
        cap[node] = c;
    }
    v[node][n[node]++] = x;
    return KT_OK;
}

static int adj_add(kt_aug *A, int node, int tet, kt_err *e)
{
    return list_add(A->adj, A->adj_n, A->adj_cap, node, tet, e);
}

static void adj_remove(kt_aug *A, int node, int tet)
{
    for (int k = 0; k < A->adj_n[node]; k++)
        if (A->adj[node][k] == tet) {
            A->adj[node][k] = A->adj[node][--A->adj_n[node]];
            return;
        }
}

static int build_adjacency(kt_aug *A, kt_err *e)
{
    int nv = kt_tet_nv(A->mesh.order);
    for (int t = 0; t < A->mesh.ne; t++)
        for (int l = 0; l < nv; l++)
            if (adj_add(A, A->mesh.tet[(size_t)t * nv + l], t, e)) return e->code;
    for (int a = 0; a < A->mesh.nn; a++)
        if (A->adj_n[a] == 0)
            return kt_fail(e, KT_EINPUT, "node %d belongs to no tet (its stiffness would be zero)",
                           a + 1);
    return KT_OK;
}

/* Triangles of the pressure and fixation surfaces, found once; cuts only renumber their nodes. */
static int surface_lists(kt_aug *A, kt_err *e)
{
    A->ptri = kt_calloc((size_t)A->mesh.nf * (A->npress ? A->npress : 1), sizeof(aug_ptri), e);
    A->ftri = kt_calloc((size_t)A->mesh.nf * (A->nfix ? A->nfix : 1), sizeof(aug_fixtri), e);
    if (e->code) return e->code;
    for (int t = 0; t < A->mesh.nf; t++) {
        for (int k = 0; k < A->npress; k++)
            if (A->mesh.tri_tag[t] == A->press[k].tag) A->ptri[A->nptri++] = (aug_ptri){t, k};
        for (int k = 0; k < A->nfix; k++)
            if (A->mesh.tri_tag[t] == A->fix[k].tag) A->ftri[A->nftri++] = (aug_fixtri){t, k};
    }
    return KT_OK;
}

int aug_full_loads(const kt_aug *A, double *f, kt_err *e)
{
    size_t n = 3 * (size_t)A->mesh.nn;
    memset(f, 0, n * sizeof(double));
    for (int k = 0; k < A->npress; k++)
        if (kt_fem_pressure(&A->mesh, A->press[k].tag, A->press[k].p, f, e)) return e->code;
    if (kt_fem_release_loads(&A->mesh, &A->mats, f, e)) return e->code;
    for (size_t i = 0; i < n; i++) f[i] += A->force[i];
    return KT_OK;
}

/* fh = f lifted by the constraints (kt_fem_lift with the unconstrained K). */
static int initial_fh(kt_aug *A, kt_err *e)
{
    cholmod_sparse *K = kt_fem_assemble(&A->mesh, &A->mats, NULL, &A->c, e);
    if (!K) return e->code;
    memcpy(A->fh, A->f, 3 * (size_t)A->mesh.nn * sizeof(double));
    kt_fem_lift(K, A->cons, A->g, A->fh, e);
    cholmod_free_sparse(&K, &A->c);
    return e->code;
}

int aug_state_init(kt_aug *A, const kt_aug_problem *p, kt_err *e)
{
    if (kt_mesh_copy(&A->mesh, p->mesh, e)) return e->code;
    A->mats.nmat = p->mats->nmat;
    A->mats.mat = kt_calloc((size_t)p->mats->nmat, sizeof(kt_material), e);
    A->press = kt_calloc((size_t)(p->npress ? p->npress : 1), sizeof(kt_aug_pressure), e);
    A->fix = kt_calloc((size_t)(p->nfix ? p->nfix : 1), sizeof(kt_aug_fixsurf), e);
    if (e->code) return e->code;
    memcpy(A->mats.mat, p->mats->mat, (size_t)p->mats->nmat * sizeof(kt_material));
    A->mats.td = p->mats->td; /* per-tet data: shared, owned by the caller */
    A->npress = p->npress;
    if (p->npress) memcpy(A->press, p->press, (size_t)p->npress * sizeof(kt_aug_pressure));
    A->nfix = p->nfix;
    if (p->nfix) memcpy(A->fix, p->fix, (size_t)p->nfix * sizeof(kt_aug_fixsurf));
    int nn = A->mesh.nn;
    if (aug_grow(A, nn, e) || build_adjacency(A, e) || surface_lists(A, e)) return e->code;
    for (int a = 0; a < nn; a++) A->origin[a] = a;
    for (int i = 0; i < 3 * nn; i++)
        if (p->fixed && p->fixed[i]) {
            A->cons[i] = 1;
            A->cons_step[i] = 0;
            A->g[i] = p->g ? p->g[i] : 0.0;
        }
    if (aug_full_loads(A, A->f, e)) return e->code;
    return initial_fh(A, e);
}

void aug_state_free(kt_aug *A)
{
    for (int a = 0; a < A->cap_nn; a++) free(A->adj[a]);
    for (int a = 0; a < A->cap_nn && A->kids; a++) free(A->kids[a]);
    free(A->kids);
    free(A->kids_n);
    free(A->kids_cap);
    free(A->par);
    free(A->adj);
    free(A->adj_n);
    free(A->adj_cap);
    free(A->touch_step);
    free(A->origin);
    free(A->nmark);
    free(A->cons);
    free(A->g);
    free(A->force);
    free(A->f);
    free(A->fh);
    free(A->cons_step);
    free(A->rhs_step);
    free(A->Lpos);
    free(A->ind);
    free(A->outmask);
    free(A->u);
    free(A->react);
    free(A->w);
    free(A->w2);
    free(A->uprev);
    free(A->pad);
    free(A->dmark);
    free(A->ptri);
    free(A->ftri);
    free(A->press);
    free(A->fix);
    free(A->mats.mat);
    kt_mesh_free(&A->mesh);
}

/* ------------------------------------------------------------------ the rhs */

static int base_fixed(const kt_aug *A, int i)
{
    return A->base && i < A->base->n0 && A->base->B[i];
}

int aug_mark_rhs(kt_aug *A, int dof, kt_err *e)
{
    A->rhs_step[dof] = A->step;
    return aug_dlist_add(A, dof, e);
}

int aug_dlist_add(kt_aug *A, int dof, kt_err *e)
{
    if (A->ind[dof]) return KT_OK;
    if (A->nd == A->dcap) {
        int cap = A->dcap ? 2 * A->dcap : 256;
        int *p = kt_realloc(A->dlist, (size_t)cap, sizeof(int), e);
        if (!p) return e->code;
        A->dlist = p;
        A->dcap = cap;
    }
    A->ind[dof] = 1;
    A->dlist[A->nd++] = dof;
    return KT_OK;
}

/* fh -= K(:,j) dg off the base's fixed rows (the lifting of a prescribed value). */
static int lift_column(kt_aug *A, const aug_col *col, double dg, kt_err *e)
{
    for (int p = 0; p < col->n; p++) {
        int i = col->i[p];
        if (base_fixed(A, i) || col->x[p] == 0) continue;
        A->fh[i] -= col->x[p] * dg;
        if (aug_mark_rhs(A, i, e)) return e->code;
    }
    return KT_OK;
}

/* Take out (sign -1) or put in (sign +1) the lifting of the constrained DOFs of these nodes. */
static int relift_nodes(kt_aug *A, const int *nodes, int n, double sign, kt_err *e)
{
    aug_col col[3] = {{0}};
    for (int k = 0; k < n && !e->code; k++) {
        int a = nodes[k], any = 0;
        for (int c = 0; c < 3; c++) any |= A->cons[3 * a + c] && A->g[3 * a + c] != 0;
        if (!any || aug_node_columns(A, a, col, e)) continue;
        for (int c = 0; c < 3; c++)
            if (A->cons[3 * a + c] && A->g[3 * a + c] != 0)
                lift_column(A, &col[c], sign * A->g[3 * a + c], e);
    }
    for (int c = 0; c < 3; c++) aug_col_free(&col[c]);
    return e->code;
}

/* ----------------------------------------------------------- pressure loads */

static int has(const int *v, int n, int x)
{
    for (int i = 0; i < n; i++)
        if (v[i] == x) return 1;
    return 0;
}

/* Pressure triangles that hold a node a dup of this step splits. */
static int loaded_candidates(kt_aug *A, const kt_step *s, int **cand, int *nc, kt_err *e)
{
    int fv = kt_tri_nv(A->mesh.order);
    A->nstamp++;
    for (int i = 0; i < s->n; i++)
        if (s->edit[i].kind == KT_EDIT_DUP && s->edit[i].node >= 0 && s->edit[i].node < A->mesh.nn)
            A->nmark[s->edit[i].node] = A->nstamp;
    *nc = 0;
    *cand = kt_calloc((size_t)(A->nptri ? A->nptri : 1), sizeof(int), e);
    if (!*cand) return e->code;
    for (int k = 0; k < A->nptri; k++) {
        const int *t = A->mesh.tri + (size_t)A->ptri[k].tri * fv;
        for (int l = 0; l < fv; l++)
            if (A->nmark[t[l]] == A->nstamp) {
                (*cand)[(*nc)++] = k;
                break;
            }
    }
    return KT_OK;
}

/* A mesh that shares nodes and groups with the current one but holds only the given pressure
 * triangles of pressure k and the tets they are faces of. */
static int load_view(kt_aug *A, const int *cand, int nc, int k, kt_mesh *v, kt_err *e)
{
    int nv = kt_tet_nv(A->mesh.order), fv = kt_tri_nv(A->mesh.order);
    *v = A->mesh;
    v->ne = v->nf = 0;
    v->tet = kt_calloc((size_t)nc * 2 * nv, sizeof(int), e);
    v->tet_tag = kt_calloc((size_t)nc * 2, sizeof(int), e);
    v->tri = kt_calloc((size_t)nc * fv, sizeof(int), e);
    v->tri_tag = kt_calloc((size_t)nc, sizeof(int), e);
    if (e->code) return e->code;
    int *ids = kt_calloc((size_t)nc * 2, sizeof(int), e);
    if (!ids) return e->code;
    for (int q = 0; q < nc; q++) {
        if (A->ptri[cand[q]].press != k) continue;
        int tri = A->ptri[cand[q]].tri;
        const int *t = A->mesh.tri + (size_t)tri * fv;
        memcpy(v->tri + (size_t)v->nf * fv, t, sizeof(int) * fv);
        v->tri_tag[v->nf++] = A->mesh.tri_tag[tri];
        for (int j = 0; j < A->adj_n[t[0]]; j++) {
            int tet = A->adj[t[0]][j];
            const int *tn = A->mesh.tet + (size_t)tet * nv;
            int on = 1;
            for (int l = 0; l < fv && on; l++) on = has(tn, nv, t[l]);
            if (!on || has(ids, v->ne, tet) || v->ne >= 2 * nc) continue;
            ids[v->ne] = tet;
            memcpy(v->tet + (size_t)v->ne * nv, tn, sizeof(int) * nv);
            v->tet_tag[v->ne++] = A->mesh.tet_tag[tet];
        }
    }
    free(ids);
    return KT_OK;
}

static void view_free(kt_mesh *v)
{
    free(v->tet);
    free(v->tet_tag);
    free(v->tri);
    free(v->tri_tag);
}

/* f and fh += sign * the loads of the candidate triangles on the current mesh. */
static int candidate_loads(kt_aug *A, const int *cand, int nc, double sign, kt_err *e)
{
    if (nc == 0) return KT_OK;
    int fv = kt_tri_nv(A->mesh.order);
    double *acc = A->w2; /* zero outside use */
    for (int k = 0; k < A->npress && !e->code; k++) {
        kt_mesh v;
        if (load_view(A, cand, nc, k, &v, e) == KT_OK && v.nf > 0)
            kt_fem_pressure(&v, A->press[k].tag, A->press[k].p, acc, e);
        view_free(&v);
    }
    for (int q = 0; q < nc; q++) {
        const int *t = A->mesh.tri + (size_t)A->ptri[cand[q]].tri * fv;
        for (int l = 0; l < fv; l++)
            for (int c = 0; c < 3; c++) {
                int i = 3 * t[l] + c;
                if (acc[i] == 0) continue;
                if (!e->code) {
                    A->f[i] += sign * acc[i];
                    if (!base_fixed(A, i)) A->fh[i] += sign * acc[i];
                    aug_mark_rhs(A, i, e);
                }
                acc[i] = 0;
            }
    }
    return e->code;
}

/* ------------------------------------------------------- prestress release */

/* f and fh += sign * the prestress internal forces of the tets the dups move, at the mesh's
 * current node numbers: taken out before the cut and put back after it, so the forces of a
 * moved tet go to its new nodes and the traction across the cut faces is released. */
static int cmp_tet(const void *a, const void *b)
{
    int x = *(const int *)a, y = *(const int *)b;
    return (x > y) - (x < y);
}

static int moved_release(kt_aug *A, const kt_step *s, double sign, kt_err *e)
{
    if (!A->mats.td || !A->mats.td->sig) return KT_OK;
    int nv = kt_tet_nv(A->mesh.order), cap = 0, n = 0;
    for (int i = 0; i < s->n; i++)
        if (s->edit[i].kind == KT_EDIT_DUP) cap += s->edit[i].nel;
    int *tets = kt_calloc((size_t)(cap ? cap : 1), sizeof(int), e);
    if (!tets) return e->code;
    for (int i = 0; i < s->n; i++) /* a tet moved by several dups counts once */
        if (s->edit[i].kind == KT_EDIT_DUP)
            for (int j = 0; j < s->edit[i].nel; j++)
                if (s->edit[i].el[j] >= 0 && s->edit[i].el[j] < A->mesh.ne) tets[n++] = s->edit[i].el[j];
    qsort(tets, n, sizeof(int), cmp_tet);
    double fe[30];
    for (int k = 0; k < n && !e->code; k++) {
        if (k > 0 && tets[k] == tets[k - 1]) continue;
        if (kt_fem_element_release(&A->mesh, &A->mats, tets[k], fe, e)) break;
        const int *t = A->mesh.tet + (size_t)tets[k] * nv;
        for (int l = 0; l < nv && !e->code; l++)
            for (int c = 0; c < 3; c++) {
                int d = 3 * t[l] + c;
                A->f[d] += sign * fe[3 * l + c];
                if (!base_fixed(A, d)) A->fh[d] += sign * fe[3 * l + c];
                if (aug_mark_rhs(A, d, e)) break;
            }
    }
    free(tets);
    return e->code;
}

/* ----------------------------------------------------------------- the edits */

/* Nodes of the tets the dups move (before the cut), for the lifting of constrained nodes. */
static int moved_nodes(kt_aug *A, const kt_step *s, int **nodes, int *n, kt_err *e)
{
    int nv = kt_tet_nv(A->mesh.order), cap = 0;
    for (int i = 0; i < s->n; i++)
        if (s->edit[i].kind == KT_EDIT_DUP) cap += s->edit[i].nel * nv;
    *n = 0;
    *nodes = kt_calloc((size_t)(cap ? cap : 1), sizeof(int), e);
    if (!*nodes) return e->code;
    A->nstamp++;
    for (int i = 0; i < s->n; i++) {
        const kt_edit *ed = &s->edit[i];
        if (ed->kind != KT_EDIT_DUP) continue;
        for (int j = 0; j < ed->nel; j++) {
            if (ed->el[j] < 0 || ed->el[j] >= A->mesh.ne) continue; /* kt_cut_apply reports it */
            const int *t = A->mesh.tet + (size_t)ed->el[j] * nv;
            for (int l = 0; l < nv; l++)
                if (A->nmark[t[l]] != A->nstamp) {
                    A->nmark[t[l]] = A->nstamp;
                    (*nodes)[(*n)++] = t[l];
                }
        }
    }
    return KT_OK;
}

/* Move the tets of each dup in the adjacency; a node left with no tet is bad input. */
static int update_adjacency(kt_aug *A, const kt_step *s, int nn_old, kt_err *e)
{
    for (int i = 0; i < s->n; i++) {
        const kt_edit *ed = &s->edit[i];
        if (ed->kind != KT_EDIT_DUP) continue;
        A->origin[ed->new_node] = A->origin[ed->node];
        for (int c = 0; c < 3; c++) {
            int j = 3 * ed->new_node + c, p = 3 * ed->node + c;
            A->uprev[j] = A->uprev[p];
            A->par[j] = A->cons[p] ? -1 : p; /* the split-off side moves relative to its parent */
        }
        if (list_add(A->kids, A->kids_n, A->kids_cap, ed->node, ed->new_node, e)) return e->code;
        for (int j = 0; j < ed->nel; j++) {
            adj_remove(A, ed->node, ed->el[j]);
            if (adj_add(A, ed->new_node, ed->el[j], e)) return e->code;
        }
    }
    for (int i = 0; i < s->n; i++) {
        const kt_edit *ed = &s->edit[i];
        if (ed->kind == KT_EDIT_DUP && A->adj_n[ed->node] == 0)
            return kt_fail(e, KT_EINPUT, "step %d: dup of node %d moves every tet of it, leaving a "
                           "node in no element", s->index, ed->node + 1);
    }
    for (int i = 3 * nn_old; i < 3 * A->mesh.nn; i++)
        if (aug_mark_rhs(A, i, e)) return e->code;
    return KT_OK;
}

/* Fixations: a node created on a fixation surface is fixed like the surface. */
static int auto_fixes(kt_aug *A, int nn_old, kt_step *fixes, kt_err *e)
{
    int fv = kt_tri_nv(A->mesh.order);
    for (int k = 0; k < A->nftri; k++) {
        const int *t = A->mesh.tri + (size_t)A->ftri[k].tri * fv;
        const kt_aug_fixsurf *fs = &A->fix[A->ftri[k].fix];
        for (int l = 0; l < fv; l++)
            if (t[l] >= nn_old) {
                kt_edit ed = {.kind = KT_EDIT_FIX, .node = t[l], .mask = fs->mask};
                memcpy(ed.v, fs->v, sizeof ed.v);
                if (kt_step_add(fixes, &ed, e)) return e->code;
            }
    }
    return KT_OK;
}

/* The dups: old lifting and loads out, cut, adjacency, new loads and lifting in. */
static int apply_dups(kt_aug *A, const kt_step *s, int **touched, int *nt, kt_step *fixes,
                      kt_err *e)
{
    int *pre = NULL, npre = 0, *cand = NULL, nc = 0, nn_old = A->mesh.nn;
    if (moved_nodes(A, s, &pre, &npre, e) || relift_nodes(A, pre, npre, -1.0, e) ||
        loaded_candidates(A, s, &cand, &nc, e) || candidate_loads(A, cand, nc, -1.0, e) ||
        moved_release(A, s, -1.0, e) ||
        kt_cut_apply(&A->mesh, s, touched, nt, e) || aug_grow(A, A->mesh.nn, e) ||
        update_adjacency(A, s, nn_old, e) || candidate_loads(A, cand, nc, +1.0, e) ||
        moved_release(A, s, +1.0, e) ||
        relift_nodes(A, *touched, *nt, +1.0, e) || auto_fixes(A, nn_old, fixes, e)) {
        free(pre);
        free(cand);
        return e->code;
    }
    for (int k = 0; k < *nt; k++) A->touch_step[(*touched)[k]] = A->step;
    free(pre);
    free(cand);
    return KT_OK;
}

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

/* A constrained DOF is its own variable: it hangs on no parent and nothing hangs on it. */
static void detach(kt_aug *A, int j)
{
    int a = j / 3, c = j % 3;
    A->par[j] = -1;
    for (int k = 0; k < A->kids_n[a]; k++)
        if (A->par[3 * A->kids[a][k] + c] == j) A->par[3 * A->kids[a][k] + c] = -1;
}

/* One fix edit: new constraints are recorded in newc; value changes are lifted into fh. */
static int apply_fix(kt_aug *A, const kt_edit *ed, int **newc, int *nc, int *ccap, kt_err *e)
{
    aug_col col[3] = {{0}};
    int have = 0;
    for (int c = 0; c < 3 && !e->code; c++) {
        if (!(ed->mask & (1u << c))) continue;
        int j = 3 * ed->node + c;
        double dg = ed->v[c] - (A->cons[j] ? A->g[j] : 0.0);
        if (!A->cons[j]) {
            A->cons[j] = 1;
            A->cons_step[j] = A->step;
            append_int(newc, nc, ccap, j, e);
            detach(A, j);
        }
        A->g[j] = ed->v[c];
        if (dg == 0 || e->code) continue;
        if (!have && aug_node_columns(A, ed->node, col, e)) break;
        have = 1;
        lift_column(A, &col[c], dg, e);
        if (base_fixed(A, j)) {
            A->fh[j] = ed->v[c];
            aug_mark_rhs(A, j, e);
        }
    }
    for (int c = 0; c < 3; c++) aug_col_free(&col[c]);
    return e->code;
}

static int apply_force(kt_aug *A, const kt_edit *ed, kt_err *e)
{
    for (int c = 0; c < 3; c++) {
        int i = 3 * ed->node + c;
        double d = ed->v[c] - A->force[i];
        if (d == 0) continue;
        A->force[i] = ed->v[c];
        A->f[i] += d;
        if (!base_fixed(A, i)) A->fh[i] += d;
        if (aug_mark_rhs(A, i, e)) return e->code;
    }
    return KT_OK;
}

static int check_node(const kt_aug *A, const kt_step *s, const kt_edit *ed, kt_err *e)
{
    if (ed->node < 0 || ed->node >= A->mesh.nn)
        return kt_fail(e, KT_EINPUT, "step %d: %s names node %d (expected 1..%d)", s->index,
                       ed->kind == KT_EDIT_FIX ? "fix" : "force", ed->node + 1, A->mesh.nn);
    return KT_OK;
}

int aug_apply_edits(kt_aug *A, const kt_step *s, int **touched, int *nt, int **newc, int *nc,
                    kt_err *e)
{
    *touched = *newc = NULL;
    *nt = *nc = 0;
    int ccap = 0;
    kt_step fixes = {0};
    int ndup = 0;
    for (int i = 0; i < s->n; i++) ndup += s->edit[i].kind == KT_EDIT_DUP;
    if (ndup && apply_dups(A, s, touched, nt, &fixes, e)) goto done;
    for (int i = 0; i < s->n; i++)
        if (s->edit[i].kind == KT_EDIT_FIX || s->edit[i].kind == KT_EDIT_FORCE)
            if (check_node(A, s, &s->edit[i], e)) goto done;
    for (int i = 0; i < fixes.n; i++)
        if (apply_fix(A, &fixes.edit[i], newc, nc, &ccap, e)) goto done;
    for (int i = 0; i < s->n; i++)
        if (s->edit[i].kind == KT_EDIT_FIX && apply_fix(A, &s->edit[i], newc, nc, &ccap, e))
            goto done;
    for (int i = 0; i < s->n; i++)
        if (s->edit[i].kind == KT_EDIT_FORCE && apply_force(A, &s->edit[i], e)) goto done;
done:
    kt_step_free(&fixes);
    return e->code;
}

/* ----------------------------------------------------------- output set */

int aug_output_mask(kt_aug *A, kt_err *e)
{
    if (!A->o.output[0]) return KT_OK;
    const kt_group *g = kt_mesh_find_group(&A->mesh, 2, A->o.output);
    if (!g) g = kt_mesh_find_group(&A->mesh, 3, A->o.output);
    if (!g)
        return kt_fail(e, KT_EINPUT, "--output %s: no surface or region of that name in the mesh",
                       A->o.output);
    if (!A->outmask) {
        A->outmask = kt_calloc(3 * (size_t)A->cap_nn, 1, e);
        if (!A->outmask) return e->code;
    }
    memset(A->outmask, 0, 3 * (size_t)A->cap_nn);
    int *nodes = NULL, cnt = 0;
    if (kt_mesh_group_nodes(&A->mesh, g, &nodes, &cnt, e)) return e->code;
    for (int k = 0; k < cnt; k++)
        for (int c = 0; c < 3; c++) A->outmask[3 * nodes[k] + c] = 1;
    free(nodes);
    return KT_OK;
}
