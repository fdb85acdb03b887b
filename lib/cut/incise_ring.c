/* incise_ring.c: arcs cut along an incision-ready surface (the eye's embedded rings), and the
 * depth of nodes below the anterior surface. */
#include "incise_int.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "predicates.h"

/* Side of the tet of slot across its face: -1 on the axis side (inner, keeps the original
 * nodes), +1 outer. Exact: the opposite vertex against the axis point at the face's height. */
static int ring_side(const kt_incise *c, int slot, kt_err *e)
{
        const kt_mesh *m = c->m;
    const int *tv = m->tet + (size_t)(slot / 4) * c->nv;
    int j = slot % 4;
    const double *a = m->xyz + 3 * (size_t)tv[kt_tet_face[j][0]];
    const double *b = m->xyz + 3 * (size_t)tv[kt_tet_face[j][1]];
    const double *d = m->xyz + 3 * (size_t)tv[kt_tet_face[j][2]];
    const double *opp = m->xyz + 3 * (size_t)tv[j];
    double axis[3] = {0.0, 0.0, a[2]};
    int so = kt_pred_orient3d(a, b, d, opp), sa = kt_pred_orient3d(a, b, d, axis);
    if (so == 0 || sa == 0) {
        kt_fail(e, KT_EINPUT, "mesh: cannot tell the inner from the outer side of the incision "
                              "surface at tet %d (a flat tet, or a face in a plane through the axis)",
                slot / 4 + 1);
        return 0;
    }
    return so == sa ? -1 : 1;
}

/* Collect the ring's triangles as interior tet faces. */
static int ring_faces(kt_incise *c, const kt_incision *inc, int **tris, int **slots, int *nt,
                      kt_err *e)
{
    const kt_mesh *m = c->m;
    const kt_group *g = kt_mesh_find_group(m, 2, inc->surface);
    char at[1100];
    kt_plan_where(c->plan, inc->at_position, at, sizeof at);
    if (!g) return kt_fail(e, KT_EINPUT, "%s: expected a surface '%s' in the mesh", at, inc->surface);
    int fv = kt_tri_nv(m->order), n = 0;
    for (int i = 0; i < m->nf; i++) n += m->tri_tag[i] == g->tag;
    *tris = kt_calloc((size_t)n, sizeof(int), e);
    *slots = kt_calloc((size_t)n, sizeof(int), e);
    if (e->code) return e->code;
    n = 0;
    for (int i = 0; i < m->nf; i++) {
        if (m->tri_tag[i] != g->tag) continue;
        const int *t = m->tri + (size_t)i * fv;
        int slot = kt_incise_find_face(c, t[0], t[1], t[2]);
        if (slot < 0 || c->nbr[slot] < 0)
            return kt_fail(e, KT_EINPUT, "%s: triangle %d of surface '%s' is %s", at, i + 1,
                           inc->surface, slot < 0 ? "not a face of any tet"
                                                  : "on the boundary, not embedded in the tissue");
        (*tris)[n] = i;
        (*slots)[n++] = slot;
    }
    *nt = n;
    if (n == 0) return kt_fail(e, KT_EINPUT, "%s: surface '%s' has no triangles", at, inc->surface);
    return KT_OK;
}

/* Depth of every vertex of the ring (indexed by input node; NAN elsewhere). */
static int ring_depths(kt_incise *c, const int *tris, int nt, double **depth, kt_err *e)
{
    const kt_mesh *m = c->m;
    int fv = kt_tri_nv(m->order);
    *depth = kt_calloc((size_t)m->nn, sizeof(double), e);
    int *nodes = kt_calloc((size_t)3 * nt, sizeof(int), e);
    double *dn = kt_calloc((size_t)3 * nt, sizeof(double), e);
    int n = 0;
    if (!e->code) {
        for (int v = 0; v < m->nn; v++) (*depth)[v] = NAN;
        for (int i = 0; i < nt; i++)
            for (int k = 0; k < 3; k++) {
                int v = m->tri[(size_t)tris[i] * fv + k];
                if (isnan((*depth)[v])) {
                    (*depth)[v] = 0;
                    nodes[n++] = v;
                }
            }
        if (kt_incise_depths(m, nodes, n, dn, e) == KT_OK)
            for (int i = 0; i < n; i++) (*depth)[nodes[i]] = dn[i];
    }
    free(nodes);
    free(dn);
    return e->code;
}

/* Select the faces of one arc (centre in degrees) and append them to the phase. */
static int ring_arc(kt_incise *c, const kt_incision *inc, int side, const int *tris,
                    const int *slots, int nt, const double *depth, double dmax, kt_phase *ph,
                    kt_err *e)
{
    const kt_mesh *m = c->m;
    int fv = kt_tri_nv(m->order), found = 0;
    double centre = inc->meridian + 180.0 * side, arc = side && inc->arc_opposite > 0 ? inc->arc_opposite : inc->arc;
    for (int i = 0; i < nt; i++) {
        const int *t = m->tri + (size_t)tris[i] * fv;
        double d[3];
        int deep = 0;
        for (int k = 0; k < 3; k++) {
            d[k] = kt_incise_rel_angle(kt_incise_theta(m->xyz + 3 * (size_t)t[k]), centre);
            deep |= depth[t[k]] > dmax;
        }
        double key = deep ? -1.0 : kt_incise_arc_key(inc, d, side);
        if (key < 0) continue;
        int side = ring_side(c, slots[i], e);
        if (e->code) return e->code;
        kt_cutface *f = &ph->face[ph->nface++];
        f->slot = slots[i];
        f->side = side;
        f->key = key;
        found++;
    }
    if (!found) {
        char at[1100];
        kt_plan_where(c->plan, inc->at, at, sizeof at);
        return kt_fail(e, KT_EINPUT, "%s: expected the arc %g-%g deg to cross surface '%s', "
                       "which has no faces there", at, centre - arc / 2, centre + arc / 2,
                       inc->surface);
    }
    return KT_OK;
}

int kt_incise_ring_phase(kt_incise *c, const kt_incision *inc, int index, kt_phase *ph,
                         kt_err *e)
{
    int *tris = NULL, *slots = NULL, nt = 0;
    double *depth = NULL;
    kt_incise_arc_phase(inc, index, ph);
    if (ring_faces(c, inc, &tris, &slots, &nt, e) || ring_depths(c, tris, nt, &depth, e)) goto done;
    /* the floor snaps to the ring layer within a quarter element of the requested depth */
    double h = kt_incise_median_edge(c->m, tris, nt, e), deepest = 0;
    for (int v = 0; v < c->m->nn; v++)
        if (!isnan(depth[v]) && depth[v] > deepest) deepest = depth[v];
    if (inc->depth > deepest + 0.25 * h) {
        char at[1100];
        kt_plan_where(c->plan, inc->at_depth, at, sizeof at);
        kt_fail(e, KT_EINPUT, "%s: expected a depth within the incision-ready surface '%s' "
                "(%.3f mm deep in the mesh), found %.3f mm", at, inc->surface, deepest, inc->depth);
        goto done;
    }
    ph->face = kt_calloc((size_t)2 * nt, sizeof *ph->face, e);
    if (!ph->face) goto done;
    double dmax = inc->depth + 0.25 * h;
    if (ring_arc(c, inc, 0, tris, slots, nt, depth, dmax, ph, e)) goto done;
    if (inc->paired && ring_arc(c, inc, 1, tris, slots, nt, depth, dmax, ph, e))
        goto done;
    kt_incise_sort_faces(ph);
done:
    free(tris);
    free(slots);
    free(depth);
    return e->code;
}
