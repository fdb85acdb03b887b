/* incise_deform.c: progressive constraints and forces on a node set (the paper's deformation
 * experiments, section 4.3.1): either every node of the set with the value ramped over the
 * steps, or nodes_per_step more nodes per step at the full value. */
#include "incise_int.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct ranked {
    double key, x[3];
    int node;
} ranked;

static int cmp_ranked(const void *pa, const void *pb)
{
    const ranked *a = pa, *b = pb;
    if (a->key != b->key) return (a->key > b->key) - (a->key < b->key);
    for (int k = 0; k < 3; k++)
        if (a->x[k] != b->x[k]) return (a->x[k] > b->x[k]) - (a->x[k] < b->x[k]);
    return (a->node > b->node) - (a->node < b->node);
}

/* The set's nodes in the order they are taken: by x . order, then x, y, z. */
static int order_nodes(const kt_mesh *m, const kt_deform *d, int *nodes, int n, kt_err *e)
{
    ranked *r = kt_calloc((size_t)n, sizeof *r, e);
    if (!r) return e->code;
    for (int i = 0; i < n; i++) {
        const double *x = m->xyz + 3 * (size_t)nodes[i];
        r[i].node = nodes[i];
        memcpy(r[i].x, x, sizeof r[i].x);
        r[i].key = d->order[0] * x[0] + d->order[1] * x[1] + d->order[2] * x[2];
    }
    qsort(r, (size_t)n, sizeof *r, cmp_ranked);
    for (int i = 0; i < n; i++) nodes[i] = r[i].node;
    free(r);
    return KT_OK;
}

int kt_incise_deform_phase(kt_incise *c, const kt_deform *d, int index, kt_phase *ph,
                           kt_err *e)
{
    ph->kind = KT_PHASE_DEFORM;
    ph->def = d;
    snprintf(ph->name, sizeof ph->name, "deform %d", index + 1);
    const kt_group *g = kt_mesh_find_group(c->m, d->set_dim, d->set);
    if (!g) {
        char at[1100];
        kt_plan_where(c->plan, d->at_set, at, sizeof at);
        return kt_fail(e, KT_EINPUT, "%s: expected a %s '%s' in the mesh", at,
                       d->set_dim == 3 ? "region" : "surface", d->set);
    }
    if (kt_mesh_group_nodes(c->m, g, &ph->nodes, &ph->nnodes, e)) return e->code;
    if (order_nodes(c->m, d, ph->nodes, ph->nnodes, e)) return e->code;
    if (d->max_nodes > 0 && d->max_nodes < ph->nnodes) ph->nnodes = d->max_nodes;
    ph->nsteps = d->nodes_per_step > 0 ? (ph->nnodes + d->nodes_per_step - 1) / d->nodes_per_step
                                       : d->steps;
    return KT_OK;
}

int kt_incise_deform_step(kt_incise *c, kt_phase *ph, kt_step *s, kt_err *e)
{
    const kt_deform *d = ph->def;
    ph->k++;
    c->st.work_done++;
    int by_nodes = d->nodes_per_step > 0;
    int active = by_nodes ? ph->k * d->nodes_per_step : ph->nnodes;
    if (active > ph->nnodes) active = ph->nnodes;
    double scale = by_nodes ? 1.0 : (double)ph->k / ph->nsteps;
    /* constraints persist: by nodes, only the new ones; ramped, all with the new value */
    int from = d->kind == KT_DEFORM_FIX && by_nodes ? (ph->k - 1) * d->nodes_per_step : 0;
    for (int i = from; i < active; i++) {
        kt_edit ed = {0};
        ed.node = ph->nodes[i];
        if (d->kind == KT_DEFORM_FIX) {
            ed.kind = KT_EDIT_FIX;
            ed.mask = d->mask;
            for (int k = 0; k < 3; k++) ed.v[k] = scale * d->v[k];
            c->st.fixes++;
        } else {
            ed.kind = KT_EDIT_FORCE;
            for (int k = 0; k < 3; k++) ed.v[k] = scale * d->v[k] / active;
            c->st.forces++;
        }
        if (kt_step_add(s, &ed, e)) return e->code;
    }
    snprintf(s->label, sizeof s->label, "%s: %d of %d nodes at %.4g of the %s (%s)",
             d->kind == KT_DEFORM_FIX ? "constrain" : "force", active, ph->nnodes, scale,
             d->kind == KT_DEFORM_FIX ? "displacement" : "force", ph->name);
    return KT_OK;
}
