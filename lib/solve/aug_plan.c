/* aug_plan.c: the plan of the planned method: the whole edits stream read to its end, checked
 * against the intact mesh before any factorization, and the variables it implies (parents of
 * the new nodes, constrained variables and their values). */
#include "aug_plan.h"

#include <stdlib.h>
#include <string.h>

#include "apply.h"

void kt_edits_plan_free(kt_edits_plan *p)
{
    for (int k = 0; k < p->nsteps; k++) kt_step_free(&p->step[k]);
    free(p->step);
    free(p->nn_at);
    free(p->parent);
    free(p->fixed);
    free(p->gv);
    free(p->g);
    memset(p, 0, sizeof *p);
}

/* Room for one more step at p->step[p->nsteps] (zeroed). */
static int room(kt_edits_plan *p, kt_err *e)
{
    if (p->nsteps < p->cap) return KT_OK;
    int cap = p->cap ? 2 * p->cap : 16;
    kt_step *s = kt_realloc(p->step, (size_t)cap, sizeof *s, e);
    if (!s) return e->code;
    memset(s + p->cap, 0, (size_t)(cap - p->cap) * sizeof *s);
    p->step = s;
    p->cap = cap;
    return KT_OK;
}

int kt_edits_plan_add(kt_edits_plan *p, kt_step *s, kt_err *e)
{
    if (room(p, e)) return e->code;
    p->step[p->nsteps++] = *s; /* the edits move over: s is left empty */
    memset(s, 0, sizeof *s);
    return KT_OK;
}

int kt_edits_plan_read(kt_edits_plan *p, kt_edits_reader *r, kt_err *e)
{
    for (;;) {
        if (room(p, e)) return e->code;
        int rc = kt_edits_next(r, &p->step[p->nsteps], e);
        if (rc <= 0) { /* the slot is not counted: free what a failed or empty read left in it */
            kt_step_free(&p->step[p->nsteps]);
            return rc < 0 ? e->code : KT_OK;
        }
        p->nsteps++;
    }
}

/* Room for nn nodes in the per-node arrays. */
static int grow(kt_edits_plan *p, int nn, kt_err *e)
{
    int *par = kt_realloc(p->parent, (size_t)nn, sizeof(int), e);
    if (par) p->parent = par;
    unsigned char *fx = par ? kt_realloc(p->fixed, 3 * (size_t)nn, 1, e) : NULL;
    if (fx) p->fixed = fx;
    double *gv = fx ? kt_realloc(p->gv, 3 * (size_t)nn, sizeof(double), e) : NULL;
    if (gv) p->gv = gv;
    double *g = gv ? kt_realloc(p->g, 3 * (size_t)nn, sizeof(double), e) : NULL;
    if (g) p->g = g;
    if (!g) return e->code;
    for (int a = p->nn; a < nn; a++) {
        p->parent[a] = -1;
        for (int c = 0; c < 3; c++) {
            p->fixed[3 * a + c] = 0;
            p->gv[3 * a + c] = p->g[3 * a + c] = 0;
        }
    }
    p->nn = nn;
    return KT_OK;
}

/* One dup applied alone (equivalent to the whole step applied at once, which cut/apply.c does edit
 * by edit on scratch copies); a bad edit becomes stream:line:col. */
static int apply_one(kt_mesh *m, const kt_step *s, kt_edit *ed, const char *stream, kt_err *e)
{
    kt_step one = {.index = s->index, .n = 1, .cap = 1, .edit = ed};
    int *touched = NULL, nt = 0;
    if (kt_cut_apply(m, &one, &touched, &nt, e) == KT_OK) {
        free(touched);
        return KT_OK;
    }
    if (e->code != KT_EINPUT) return e->code; /* out of memory is not bad input */
    char msg[sizeof e->msg];
    memcpy(msg, e->msg, sizeof msg);
    e->code = KT_OK;
    return kt_fail(e, KT_EINPUT, "%s:%ld:%d: expected tets that hold node %d (%s)", stream,
                   ed->line, ed->col, ed->node + 1, msg);
}

static void not_usable(kt_edits_plan *p, const char *stream, long line, const char *what)
{
    if (!p->usable) return;
    p->usable = 0;
    snprintf(p->why, sizeof p->why, "%s:%ld: %s", stream, line, what);
}

/* A node created by this step on a fixation surface is fixed like the surface (as the
 * iterative method does); its increment is then fixed too if its parent is fixed there. */
static void auto_fixes(kt_edits_plan *p, const kt_mesh *m, const kt_aug_problem *prob, int nn_old,
                       const kt_step *s, const char *stream)
{
    int fv = kt_tri_nv(m->order);
    for (int t = 0; t < m->nf; t++)
        for (int k = 0; k < prob->nfix; k++) {
            if (m->tri_tag[t] != prob->fix[k].tag) continue;
            for (int l = 0; l < fv; l++) {
                int a = m->tri[(size_t)t * fv + l];
                if (a < nn_old) continue;
                for (int c = 0; c < 3; c++) {
                    if (!(prob->fix[k].mask & (1u << c))) continue;
                    int j = 3 * a + c, pj = 3 * p->parent[a] + c;
                    p->fixed[j] = 1;
                    p->g[j] = prob->fix[k].v[c];
                    p->gv[j] = p->g[j] - p->g[pj];
                    if (!p->fixed[pj]) {
                        char w[200];
                        snprintf(w, sizeof w, "step %d: node %d is created on a fixation surface "
                                 "where its parent %d is free", s->index, a + 1, p->parent[a] + 1);
                        not_usable(p, stream, s->n ? s->edit[0].line : 0, w);
                    }
                }
            }
        }
}

/* Tets holding each node, kept through the dups (deg has room for every node of the plan). */
typedef struct degree {
    int *n;
} degree;

/* A dup leaves its node in at least one tet (keratome-edits(5)): a node in no tet has no
 * stiffness, and the factorization would find that only as a singular matrix. */
static int count_dup(degree *d, const kt_edit *ed, const kt_step *s, const char *stream,
                     kt_err *e)
{
    d->n[ed->node] -= ed->nel;
    d->n[ed->new_node] = ed->nel;
    if (d->n[ed->node] > 0) return KT_OK;
    return kt_fail(e, KT_EINPUT, "%s:%ld: step %d: expected a dup that leaves node %d in at least "
                   "one tetrahedron, found one that moves all %d of its tets to node %d", stream,
                   ed->line, s->index, ed->node + 1, ed->nel, ed->new_node + 1);
}

/* One step: every dup applied and checked, fix edits noted (they change K's block). */
static int check_step(kt_edits_plan *p, kt_mesh *m, const kt_aug_problem *prob, kt_step *s,
                      degree *d, const char *stream, kt_err *e)
{
    int nn_old = m->nn;
    for (int i = 0; i < s->n; i++) {
        kt_edit *ed = &s->edit[i];
        if (ed->kind == KT_EDIT_FIX) {
            char w[200];
            snprintf(w, sizeof w, "step %d fixes node %d: a constraint added by the plan changes "
                     "the intact block", s->index, ed->node + 1);
            not_usable(p, stream, ed->line, w);
        }
        if (ed->kind != KT_EDIT_DUP) continue;
        if (apply_one(m, s, ed, stream, e) || count_dup(d, ed, s, stream, e) ||
            grow(p, m->nn, e))
            return e->code;
        p->parent[ed->new_node] = ed->node;
    }
    auto_fixes(p, m, prob, nn_old, s, stream);
    return KT_OK;
}

int kt_edits_plan_check(kt_edits_plan *p, const char *stream, const kt_aug_problem *prob,
                        kt_mesh *final, kt_err *e)
{
    const kt_mesh *m0 = prob->mesh;
    p->usable = 1;
    p->why[0] = 0;
    p->nn0 = m0->nn;
    p->nn = 0;
    p->nn_at = kt_calloc((size_t)p->nsteps + 1, sizeof(int), e);
    if (!p->nn_at || grow(p, m0->nn, e) || kt_mesh_copy(final, m0, e)) return e->code;
    for (int j = 0; j < 3 * m0->nn; j++) {
        p->fixed[j] = prob->fixed && prob->fixed[j];
        p->g[j] = p->gv[j] = p->fixed[j] && prob->g ? prob->g[j] : 0;
    }
    p->nn_at[0] = m0->nn;
    long nn_end = m0->nn; /* the reader bounds the dups: nn_end <= KT_MESH_MAX_NODES */
    for (int k = 0; k < p->nsteps; k++)
        for (int i = 0; i < p->step[k].n; i++) nn_end += p->step[k].edit[i].kind == KT_EDIT_DUP;
    degree d = {kt_calloc((size_t)nn_end, sizeof(int), e)};
    if (!d.n) return e->code;
    int nv = kt_tet_nv(m0->order);
    for (size_t q = 0; q < (size_t)m0->ne * nv; q++) d.n[m0->tet[q]]++;
    for (int k = 0; k < p->nsteps; k++) {
        if (check_step(p, final, prob, &p->step[k], &d, stream, e)) break;
        p->nn_at[k + 1] = final->nn;
    }
    free(d.n);
    return e->code;
}

void kt_edits_plan_zero_values(kt_edits_plan *p)
{
    memset(p->g, 0, 3 * (size_t)p->nn * sizeof(double));
    memset(p->gv, 0, 3 * (size_t)p->nn * sizeof(double));
}
