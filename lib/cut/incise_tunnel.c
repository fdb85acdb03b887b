/* incise_tunnel.c: a tunnel (the main cataract incision, keratome-plan(5) TUNNELS) as a cut
 * phase: the faces of the mesh between the two sides of the blade's plane, in the cornea or the
 * limbus, within the blade's width of the meridian and between the external entry and a
 * millimetre past the internal opening (no tissue lies on the plane beyond either lip within
 * the width: air outside the entry, the anterior chamber inside the opening); their vertices
 * snapped onto the plane as for a planar cut. The blade advances from the entry: a face is cut
 * when the front (distance from the entry along the chord to the internal opening) passes its
 * farthest vertex, in `steps` equal advances. */
#include "incise_int.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#define TUNNEL_MARGIN_OUT 0.5 /* mm before the entry kept (the entry lip of the faces) */
#define TUNNEL_MARGIN_IN 1.0  /* mm past the internal opening: the lateral edges of the blade
                                 reach the posterior surface a little farther in */

static const double *vertex(const kt_incise *c, int slot, int k)
{
    int v = c->m->tet[(size_t)(slot / 4) * c->nv + kt_tet_face[slot % 4][k]];
    return c->m->xyz + 3 * (size_t)v;
}

static double dot3(const double *a, const double *b, const double *o)
{
    return a[0] * (b[0] - o[0]) + a[1] * (b[1] - o[1]) + a[2] * (b[2] - o[2]);
}

/* The front's position that passes the face (its farthest vertex along the chord, >= 0), or
 * -1 when the face lies outside the blade's rectangle. */
static double face_key(const kt_incise *c, const kt_tunnel *t, int slot, int check)
{
    double key = 0;
    for (int k = 0; k < 3; k++) {
        const double *x = vertex(c, slot, k);
        double s = dot3(t->along, x, t->entry), w = dot3(t->across, x, t->entry);
        if (check && (fabs(w) > 0.5 * t->width * (1 + 1e-9) || s < -TUNNEL_MARGIN_OUT || s > t->length + TUNNEL_MARGIN_IN))
            return -1;
        key = fmax(key, s);
    }
    return key;
}

/* Where the blade's plane grazes a surface (at the entry, where it meets the outer surface at
 * a shallow angle) the faces between the plane's two sides can enclose a sliver of tets with
 * the surface; the cut would set it free. Those faces are dropped (the sliver stays with its
 * neighbours: the lip is resolved to an element) until every tet joins one body across the
 * faces not cut. *dropped counts them. */
static int drop_slivers(kt_incise *c, kt_phase *ph, int *dropped, kt_err *e)
{
    const kt_mesh *m = c->m;
    int ne = m->ne;
    unsigned char *sel = kt_calloc((size_t)4 * ne, 1, e);
    int *par = kt_calloc((size_t)ne, sizeof(int), e), *size = kt_calloc((size_t)ne, sizeof(int), e);
    *dropped = 0;
    for (int again = 1; again && !e->code;) {
        again = 0;
        for (int i = 0; i < 4 * ne; i++) sel[i] = 0;
        for (int i = 0; i < ph->nface; i++) sel[ph->face[i].slot] = sel[c->nbr[ph->face[i].slot]] = 1;
        for (int t = 0; t < ne; t++) par[t] = t, size[t] = 0;
        for (int s = 0; s < 4 * ne; s++) {
            if (c->nbr[s] < 0 || sel[s] || c->cut[s]) continue;
            int a = kt_incise_uf_find(par, s / 4), b = kt_incise_uf_find(par, c->nbr[s] / 4);
            if (a != b) par[a] = b;
        }
        int big = 0;
        for (int t = 0; t < ne; t++) size[kt_incise_uf_find(par, t)]++;
        for (int t = 0; t < ne; t++)
            if (size[t] > size[big]) big = t;
        int n = 0;
        for (int i = 0; i < ph->nface; i++) {
            int s = ph->face[i].slot;
            if (kt_incise_uf_find(par, s / 4) != big || kt_incise_uf_find(par, c->nbr[s] / 4) != big) {
                (*dropped)++, again = 1;
                continue;
            }
            ph->face[n++] = ph->face[i];
        }
        ph->nface = n;
    }
    free(sel), free(par), free(size);
    return e->code;
}

/* May the face at slot be cut by the tunnel (both tets in the cornea or limbus, the face within
 * the blade's rectangle)? For kt_incise_unhang. */
static int tunnel_face_ok(const kt_incise *c, const void *ctx, int slot)
{
    return kt_incise_in_front(c->m, c->nbr[slot] / 4) && kt_incise_in_front(c->m, slot / 4) &&
           face_key(c, ctx, slot, 1) >= 0;
}

int kt_incise_tunnel_phase(kt_incise *c, const kt_tunnel *t, int index, kt_phase *ph, kt_err *e)
{
    ph->kind = KT_PHASE_CUT;
    snprintf(ph->name, sizeof ph->name, "tunnel %d", index + 1);
    ph->key_unit = KT_KEY_MM;
    ph->at = t->at;
    if (kt_incise_plane_faces(c, t->entry, t->normal, ph, e)) return e->code;
    int n = 0;
    for (int i = 0; i < ph->nface; i++) {
        int s = ph->face[i].slot;
        if (!kt_incise_in_front(c->m, s / 4) || !kt_incise_in_front(c->m, c->nbr[s] / 4)) continue;
        if (face_key(c, t, s, 1) < 0) continue;
        ph->face[n++] = ph->face[i];
    }
    ph->nface = n;
    int dropped = 0, moved = 0, hung = 0;
    if (drop_slivers(c, ph, &dropped, e) || kt_incise_unhang(c, ph, t->entry, t->normal, tunnel_face_ok, t, &moved, &hung, e) || drop_slivers(c, ph, &dropped, e))
        return e->code;
    n = ph->nface;
    if (n == 0) {
        char at[1100];
        kt_plan_where(c->plan, t->at, at, sizeof at);
        return kt_fail(e, KT_EINPUT, "%s: expected the tunnel's plane to cross the cornea or limbus of the mesh", at);
    }
    if (kt_incise_snap_plane(c, ph, t->entry, t->normal, "tunnel's plane", e)) return e->code;
    ph->total = 0;
    for (int i = 0; i < n; i++) {
        ph->face[i].key = face_key(c, t, ph->face[i].slot, 0);
        ph->total = fmax(ph->total, ph->face[i].key);
    }
    ph->dps = ph->total / t->steps;
    kt_incise_sort_faces(ph);
    kt_log(c->quiet, "cutplan: tunnel %d: %d faces, %.2f mm of blade advance in %d steps (%d faces left uncut "
           "where the plane grazes a surface; %d tets that would hang by one face moved across the cut, %d "
           "left uncut)\n", index + 1, n, ph->total, t->steps, dropped, moved, hung);
    return KT_OK;
}
