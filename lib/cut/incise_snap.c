/* incise_snap.c: cuts on meshes without an incision-ready surface. Every tet is put on one
 * side of the cutting surface by the exact side of its centroid; the faces between the two
 * sides (restricted to the cut's extent) are the cut. Their vertices closer to the surface than
 * a fraction of their shortest edge are snapped onto it, except those whose move would invert an
 * element or push its quality below the plan's limit: they stay where they are. */
#include "incise_int.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "eye.h"
#include "predicates.h"


static double dist(const double *a, const double *b)
{
    return sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                (a[2] - b[2]) * (a[2] - b[2]));
}

/* Mean-ratio quality of the vertex tet: 1 for a regular tet, 0 flat, negative inverted. */
static double quality(const double *xyz, const int *tv)
{
    const double *x[4];
    for (int k = 0; k < 4; k++) x[k] = xyz + 3 * (size_t)tv[k];
    double v = kt_tet_volume(x[0], x[1], x[2], x[3]), s = 0;
    for (int k = 0; k < 6; k++) {
        double l = dist(x[kt_tet_edge[k][0]], x[kt_tet_edge[k][1]]);
        s += l * l;
    }
    double q = s > 0 ? 12.0 * pow(3.0 * fabs(v), 2.0 / 3.0) / s : 0.0;
    return v > 0 ? q : -q;
}

/* Shortest vertex-to-vertex edge at every node. */
static double *shortest_edges(const kt_incise *c, kt_err *e)
{
    const kt_mesh *m = c->m;
    double *h = kt_calloc((size_t)m->nn, sizeof(double), e);
    if (!h) return NULL;
    for (int v = 0; v < m->nn; v++) h[v] = HUGE_VAL;
    for (int t = 0; t < m->ne; t++) {
        const int *tv = m->tet + (size_t)t * c->nv;
        for (int k = 0; k < 6; k++) {
            int a = tv[kt_tet_edge[k][0]], b = tv[kt_tet_edge[k][1]];
            double l = dist(m->xyz + 3 * (size_t)a, m->xyz + 3 * (size_t)b);
            if (l < h[a]) h[a] = l;
            if (l < h[b]) h[b] = l;
        }
    }
    return h;
}

/* Move mid-edge nodes with their edges' vertices (keeping any curvature offset). */
static void move_mid_edges(kt_incise *c, const double *old, const unsigned char *moved)
{
    kt_mesh *m = c->m;
    for (int t = 0; t < m->ne; t++) {
        const int *tv = m->tet + (size_t)t * c->nv;
        for (int k = 0; k < 6; k++) {
            int a = tv[kt_tet_edge[k][0]], b = tv[kt_tet_edge[k][1]], mid = tv[4 + k];
            if (!moved[a] && !moved[b]) continue;
            for (int q = 0; q < 3; q++)
                m->xyz[3 * (size_t)mid + q] =
                    old[3 * (size_t)mid + q] +
                    0.5 * (m->xyz[3 * (size_t)a + q] - old[3 * (size_t)a + q] +
                           m->xyz[3 * (size_t)b + q] - old[3 * (size_t)b + q]);
        }
    }
}

/* Is the tet acceptable after the moves: a positive volume, and a quality at least the plan's
 * limit or at least its own before? */
static int tet_ok(const kt_incise *c, const double *old, const int *tv)
{
    double qn = quality(c->m->xyz, tv), qo = quality(old, tv);
    return qn > 0 && (qn >= c->plan->snap.min_quality || qn >= qo); /* NaN fails */
}

/* A node whose move would invert a tet, or push its quality below the plan's limit (and below
 * its own before), is not snapped: every bad tet's moved vertices go back, until every tet
 * touching a moved node is acceptable (with none moved, the mesh is the input). The cut then
 * runs along those nodes as meshed, a little off the surface. *kept counts them. */
static void check_snapped(kt_incise *c, const double *old, unsigned char *moved, int *kept)
{
    kt_mesh *m = c->m;
    *kept = 0;
    for (int again = 1; again;) {
        again = 0;
        for (int t = 0; t < m->ne; t++) {
            const int *tv = m->tet + (size_t)t * c->nv;
            if ((!moved[tv[0]] && !moved[tv[1]] && !moved[tv[2]] && !moved[tv[3]]) || tet_ok(c, old, tv)) continue;
            for (int k = 0; k < 4; k++)
                if (moved[tv[k]]) {
                    memcpy(m->xyz + 3 * (size_t)tv[k], old + 3 * (size_t)tv[k], 3 * sizeof(double));
                    moved[tv[k]] = 0, (*kept)++, again = 1;
                }
        }
        if (again && m->order == 2) { /* the mid-edge nodes anew from their vertices */
            for (int t = 0; t < m->ne; t++)
                for (int k = 4; k < c->nv; k++) {
                    size_t v = (size_t)m->tet[(size_t)t * c->nv + k];
                    memcpy(m->xyz + 3 * v, old + 3 * v, 3 * sizeof(double));
                }
            move_mid_edges(c, old, moved);
        }
    }
}

int kt_incise_snap(kt_incise *c, const unsigned char *flag, kt_incise_proj proj,
                   const void *surf, const char *what, kt_err *e)
{
    kt_mesh *m = c->m;
    double *h = shortest_edges(c, e);
    double *old = kt_calloc((size_t)3 * m->nn, sizeof(double), e);
    unsigned char *moved = kt_calloc((size_t)m->nn, 1, e);
    int nmoved = 0;
    double maxd = 0;
    if (e->code) goto done;
    memcpy(old, m->xyz, (size_t)3 * m->nn * sizeof(double));
    for (int v = 0; v < m->nn; v++) {
        if (!flag[v]) continue;
        double y[3], d = proj(surf, m->xyz + 3 * (size_t)v, y);
        const double *x = m->xyz + 3 * (size_t)v;
        double scale = 1.0 + fabs(x[0]) + fabs(x[1]) + fabs(x[2]);
        /* on the surface up to round-off: not a move (no new mesh needed) */
        if (d <= 1e-12 * scale || d > c->plan->snap.fraction * h[v]) continue;
        memcpy(m->xyz + 3 * (size_t)v, y, sizeof y);
        moved[v] = 1;
        nmoved++;
        maxd = fmax(maxd, d);
    }
    if (nmoved == 0) goto done;
    if (m->order == 2) move_mid_edges(c, old, moved);
    int kept = 0;
    check_snapped(c, old, moved, &kept);
    nmoved -= kept;
    c->st.snapped += nmoved;
    c->st.max_snap = fmax(c->st.max_snap, maxd);
    kt_log(c->quiet, "cutplan: snapped %d nodes onto the %s (at most %.3g mm)", nmoved, what, maxd);
    kt_log(c->quiet, kept ? "; %d left where they were (snapping them would invert or flatten a tet)\n" : "\n", kept);
done:
    free(h);
    free(old);
    free(moved);
    return e->code;
}

/* ---- sides ---- */

/* Side of every tet's centroid: +1 or -1 (a centroid exactly on the surface counts as -1). */
typedef int (*side_fn)(const void *surf, const double *const *x);

static signed char *classify(const kt_incise *c, side_fn fn, const void *surf, kt_err *e)
{
    const kt_mesh *m = c->m;
    signed char *cls = kt_calloc((size_t)m->ne, 1, e);
    if (!cls) return NULL;
    for (int t = 0; t < m->ne; t++) {
        const double *x[4];
        for (int k = 0; k < 4; k++) x[k] = m->xyz + 3 * (size_t)m->tet[(size_t)t * c->nv + k];
        cls[t] = (signed char)(fn(surf, x) > 0 ? 1 : -1);
    }
    return cls;
}

typedef struct plane {
    double p[3], n[3];
} plane;

static int plane_side(const void *s, const double *const *x)
{
    const plane *pl = s;
    return kt_pred_plane_side(pl->p, pl->n, x, 4);
}

static double plane_proj(const void *s, const double *x, double *y)
{
    const plane *pl = s;
    double d = 0;
    for (int k = 0; k < 3; k++) d += pl->n[k] * (x[k] - pl->p[k]);
    for (int k = 0; k < 3; k++) y[k] = x[k] - d * pl->n[k];
    return fabs(d);
}

/* The elliptic cylinder x^2 + (sy y)^2 = r^2 about the z axis: sy = 1 the circle of radius r;
 * on an oval cornea r / sy is the incision's vertical radius (kt_eye_oval_radius). */
typedef struct cylinder {
    double r, sy;
} cylinder;

static int cylinder_side(const void *s, const double *const *x)
{
    const cylinder *cy = s;
    if (cy->sy == 1) return kt_pred_cylinder_side(cy->r, x, 4);
    double p[4][3];
    const double *q[4];
    for (int k = 0; k < 4; k++) p[k][0] = x[k][0], p[k][1] = cy->sy * x[k][1], p[k][2] = x[k][2], q[k] = p[k];
    return kt_pred_cylinder_side(cy->r, q, 4);
}

static double cylinder_proj(const void *s, const double *x, double *y)
{
    const cylinder *cy = s;
    double R = cy->r, r = hypot(x[0], x[1]), re = cy->sy == 1 ? r : hypot(x[0], cy->sy * x[1]);
    y[2] = x[2];
    if (r == 0) {
        y[0] = x[0], y[1] = x[1];
        return 0;
    }
    y[0] = x[0] * (R / re);
    y[1] = x[1] * (R / re);
    return cy->sy == 1 ? fabs(r - R) : fabs(r - r * (R / re));
}

/* The vertex of face slot k (0..2). */
static const double *face_x(const kt_incise *c, int slot, int k)
{
    int v = c->m->tet[(size_t)(slot / 4) * c->nv + kt_tet_face[slot % 4][k]];
    return c->m->xyz + 3 * (size_t)v;
}

static int face_v(const kt_incise *c, int slot, int k)
{
    return c->m->tet[(size_t)(slot / 4) * c->nv + kt_tet_face[slot % 4][k]];
}

/* Faces between a -1 tet and a +1 tet, slot on the -1 side. */
static int interface(const kt_incise *c, const signed char *cls, kt_phase *ph, kt_err *e)
{
    int n = 0;
    for (int s = 0; s < 4 * c->m->ne; s++)
        n += c->nbr[s] >= 0 && cls[s / 4] < 0 && cls[c->nbr[s] / 4] > 0;
    ph->face = kt_calloc((size_t)n, sizeof *ph->face, e);
    if (!ph->face) return e->code;
    ph->nface = 0;
    for (int s = 0; s < 4 * c->m->ne; s++)
        if (c->nbr[s] >= 0 && cls[s / 4] < 0 && cls[c->nbr[s] / 4] > 0) {
            ph->face[ph->nface].slot = s;
            ph->face[ph->nface].side = -1;
            ph->face[ph->nface++].key = 0;
        }
    return KT_OK;
}

/* Flag the vertices of the phase's faces and snap them. */
static int snap_faces(kt_incise *c, kt_phase *ph, kt_incise_proj proj, const void *surf,
                      const char *what, kt_err *e)
{
    unsigned char *flag = kt_calloc((size_t)c->m->nn, 1, e);
    if (!flag) return e->code;
    for (int i = 0; i < ph->nface; i++)
        for (int k = 0; k < 3; k++) flag[face_v(c, ph->face[i].slot, k)] = 1;
    kt_incise_snap(c, flag, proj, surf, what, e);
    free(flag);
    return e->code;
}

/* ---- planar cut ---- */

static double advance_key(const kt_incise *c, int slot, const double *adv, int use_max)
{
    double k = use_max ? -HUGE_VAL : HUGE_VAL;
    for (int q = 0; q < 3; q++) {
        const double *x = face_x(c, slot, q);
        double a = adv[0] * x[0] + adv[1] * x[1] + adv[2] * x[2];
        k = use_max ? fmax(k, a) : fmin(k, a);
    }
    return k;
}

/* Keys = the front position (mm from where the plane enters the body) that passes the face. */
static void planar_keys(const kt_incise *c, kt_phase *ph, const double *adv)
{
    double start = HUGE_VAL;
    for (int i = 0; i < ph->nface; i++) start = fmin(start, advance_key(c, ph->face[i].slot, adv, 0));
    ph->total = 0;
    for (int i = 0; i < ph->nface; i++) {
        ph->face[i].key = advance_key(c, ph->face[i].slot, adv, 1) - start;
        ph->total = fmax(ph->total, ph->face[i].key);
    }
}

static int pull_nodes(kt_incise *c, kt_phase *ph, const char *surface, kt_err *e)
{
    if (!surface[0]) return KT_OK;
    const kt_group *g = kt_mesh_find_group(c->m, 2, surface);
    if (!g) {
        char at[1100];
        kt_plan_where(c->plan, c->plan->planar.at_pull, at, sizeof at);
        return kt_fail(e, KT_EINPUT, "%s: expected a surface '%s' in the mesh", at, surface);
    }
    int *nodes = NULL, n = 0;
    if (kt_mesh_group_nodes(c->m, g, &nodes, &n, e)) return e->code;
    ph->pull_node = kt_calloc((size_t)c->m->nn, 1, e);
    if (ph->pull_node)
        for (int i = 0; i < n; i++) ph->pull_node[nodes[i]] = 1;
    free(nodes);
    return e->code;
}

int kt_incise_planar_phase(kt_incise *c, kt_phase *ph, kt_err *e)
{
    const kt_planar *pl = &c->plan->planar;
    ph->kind = KT_PHASE_CUT;
    snprintf(ph->name, sizeof ph->name, "planar cut");
    ph->key_unit = KT_KEY_MM;
    ph->nps = pl->nodes_per_step;
    plane surf;
    memcpy(surf.p, pl->point, sizeof surf.p);
    memcpy(surf.n, pl->normal, sizeof surf.n);
    signed char *cls = classify(c, plane_side, &surf, e);
    if (!cls || interface(c, cls, ph, e)) goto done;
    if (ph->nface == 0) {
        char at[1100];
        kt_plan_where(c->plan, pl->at, at, sizeof at);
        kt_fail(e, KT_EINPUT, "%s: expected the cutting plane to cross the mesh", at);
        goto done;
    }
    planar_keys(c, ph, pl->advance);
    if (pl->length > 0) { /* keep the faces the front passes within the length */
        int n = 0;
        for (int i = 0; i < ph->nface; i++)
            if (ph->face[i].key <= pl->length * (1 + 1e-12)) ph->face[n++] = ph->face[i];
        ph->nface = n;
    }
    if (snap_faces(c, ph, plane_proj, &surf, "cutting plane", e)) goto done;
    planar_keys(c, ph, pl->advance);
    kt_incise_sort_faces(ph);
    ph->pull_force = pl->pull_force;
    memcpy(ph->pull_dir, pl->normal, sizeof ph->pull_dir);
    pull_nodes(c, ph, pl->pull_surface, e);
done:
    free(cls);
    return e->code;
}

int kt_incise_plane_faces(kt_incise *c, const double *point, const double *normal, kt_phase *ph, kt_err *e)
{
    plane surf;
    memcpy(surf.p, point, sizeof surf.p);
    memcpy(surf.n, normal, sizeof surf.n);
    signed char *cls = classify(c, plane_side, &surf, e);
    if (cls) interface(c, cls, ph, e);
    free(cls);
    return e->code;
}

int kt_incise_snap_plane(kt_incise *c, kt_phase *ph, const double *point, const double *normal, const char *what,
                         kt_err *e)
{
    plane surf;
    memcpy(surf.p, point, sizeof surf.p);
    memcpy(surf.n, normal, sizeof surf.n);
    return snap_faces(c, ph, plane_proj, &surf, what, e);
}

/* ---- tets left hanging by one face ---- */

/* A cut's faces can wrap three faces of a tet that pokes across the cutting surface (its
 * centroid on one side, three neighbours on the other: where the surface passes through a
 * vertex), or two with the boundary. Cut, it hangs by its fourth face: held by the shear of that
 * tet alone. In the prestressed cornea the lamellae's transverse shear modulus (keratome-scene(5):
 * about 10 kPa) is of the prestress's order (11-20 kPa in the plane), and the prestressed tangent
 * of such a tet has negative directions (issue 34: two eigenvalues of -5e-5 N/mm at a tunnel's
 * floor, docs/every-eye.md). */
static int closed(const kt_incise *c, const unsigned char *sel, int s)
{
    return c->nbr[s] < 0 || c->cut[s] || sel[s];
}

static int unhang_tet(kt_incise *c, kt_incise_face_ok ok, const void *ctx, unsigned char *sel, int tet, int *moved,
                      int *dropped)
{
    int nsel = 0, nclosed = 0, nok = 0, open[4];
    for (int j = 0; j < 4; j++) {
        int s = 4 * tet + j;
        open[j] = !closed(c, sel, s);
        nsel += sel[s], nclosed += !open[j];
        nok += open[j] && ok && ok(c, ctx, s);
    }
    if (nsel == 0 || nclosed < 3) return 0;
    /* moved across: its open faces cut, its cut ones open; then held by nsel faces */
    int flip = nok == 4 - nclosed && nclosed - nsel + (4 - nclosed) <= 2;
    for (int j = 0; j < 4; j++) {
        int s = 4 * tet + j;
        if (sel[s]) sel[s] = sel[c->nbr[s]] = 0;
        else if (flip && open[j]) sel[s] = sel[c->nbr[s]] = 1;
    }
    if (flip) (*moved)++;
    else (*dropped)++;
    return flip;
}

/* The phase's faces anew from sel: without ok, the faces kept (their keys too); with it, every
 * selected face from its tet on the minus side (key 0: the caller sets the keys). */
static int refill(kt_incise *c, kt_phase *ph, const unsigned char *sel, const signed char *minus, int added, kt_err *e)
{
    int n = 0;
    if (!added) {
        for (int i = 0; i < ph->nface; i++)
            if (sel[ph->face[i].slot]) ph->face[n++] = ph->face[i];
        ph->nface = n;
        return KT_OK;
    }
    int cap = 0;
    for (int s = 0; s < 4 * c->m->ne; s++) cap += sel[s] && s < c->nbr[s];
    kt_cutface *f = kt_calloc((size_t)cap + 1, sizeof *f, e);
    if (!f) return e->code;
    for (int s = 0; s < 4 * c->m->ne; s++) {
        if (!sel[s] || s > c->nbr[s]) continue;
        f[n].slot = minus[s / 4] ? s : c->nbr[s], f[n].side = -1, f[n++].key = 0;
    }
    free(ph->face);
    ph->face = f, ph->nface = n;
    return KT_OK;
}

int kt_incise_unhang(kt_incise *c, kt_phase *ph, const double *point, const double *normal, kt_incise_face_ok ok,
                     const void *ctx, int *moved, int *dropped, kt_err *e)
{
    int ne = c->m->ne;
    unsigned char *sel = kt_calloc((size_t)4 * ne, 1, e);
    signed char *minus = kt_calloc((size_t)ne, 1, e); /* 1: the tet keeps the original nodes */
    if (e->code) goto done;
    for (int k = 0; ok && k < ne; k++) { /* the side of its centroid; the faces' own sides below */
        const double *x[4];
        for (int v = 0; v < 4; v++) x[v] = c->m->xyz + 3 * (size_t)c->m->tet[(size_t)k * c->nv + v];
        minus[k] = kt_pred_plane_side(point, normal, x, 4) <= 0;
    }
    for (int i = 0; i < ph->nface; i++) {
        int s = ph->face[i].slot;
        sel[s] = sel[c->nbr[s]] = 1;
        minus[s / 4] = 1, minus[c->nbr[s] / 4] = 0;
    }
    for (int pass = 0, again = 1; again && pass < 100; pass++) {
        again = 0;
        for (int s = 0; s < 4 * ne; s++) {
            int before = *moved + *dropped;
            if (sel[s] && unhang_tet(c, ok, ctx, sel, s / 4, moved, dropped)) minus[s / 4] = !minus[s / 4];
            again |= *moved + *dropped != before;
        }
    }
    refill(c, ph, sel, minus, *moved > 0, e);
done:
    free(sel), free(minus);
    return e->code;
}

/* ---- an arc snapped onto a cylinder (an eye scene without a ring at that diameter) ---- */

int kt_incise_in_front(const kt_mesh *m, int t)
{
    const kt_group *gc = kt_mesh_find_group(m, 3, "cornea"), *gl = kt_mesh_find_group(m, 3, "limbus");
    if (!gc && !gl) return 1;
    return (gc && m->tet_tag[t] == gc->tag) || (gl && m->tet_tag[t] == gl->tag);
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Keep the interface faces in the front regions, within the arc(s), above the depth. */
static int select_arc_faces(kt_incise *c, const kt_incision *inc, kt_phase *ph, kt_err *e)
{
    const kt_mesh *m = c->m;
    int n = 0, *nodes = kt_calloc((size_t)3 * ph->nface + 1, sizeof(int), e);
    double *depth = kt_calloc((size_t)3 * ph->nface + 1, sizeof(double), e);
    double *len = kt_calloc((size_t)3 * ph->nface + 1, sizeof(double), e);
    if (e->code) goto done;
    /* arc and region first: depth is costlier */
    for (int i = 0; i < ph->nface; i++) {
        int s = ph->face[i].slot;
        if (!kt_incise_in_front(m, s / 4) || !kt_incise_in_front(m, c->nbr[s] / 4)) continue;
        double d[3], key = -1;
        for (int arcn = 0; arcn < 1 + inc->paired && key < 0; arcn++) {
            for (int k = 0; k < 3; k++)
                d[k] = kt_incise_rel_angle(kt_incise_theta(face_x(c, s, k)), inc->meridian + 180.0 * arcn);
            key = kt_incise_arc_key(inc, d, arcn);
        }
        if (key < 0) continue;
        ph->face[n] = ph->face[i];
        ph->face[n++].key = key;
    }
    ph->nface = n;
    for (int i = 0; i < n; i++)
        for (int k = 0; k < 3; k++) {
            nodes[3 * i + k] = face_v(c, ph->face[i].slot, k);
            len[3 * i + k] = dist(face_x(c, ph->face[i].slot, k), face_x(c, ph->face[i].slot, (k + 1) % 3));
        }
    if (kt_incise_depths(m, nodes, 3 * n, depth, e)) goto done;
    double h = 0;
    if (n > 0) {
        /* a quarter of the median edge as the depth tolerance, as on a ring */
        qsort(len, (size_t)3 * n, sizeof(double), cmp_double);
        h = len[(3 * n) / 2];
    }
    int kept = 0;
    for (int i = 0; i < n; i++) {
        double dm = fmax(depth[3 * i], fmax(depth[3 * i + 1], depth[3 * i + 2]));
        if (dm <= inc->depth + 0.25 * h) ph->face[kept++] = ph->face[i];
    }
    ph->nface = kept;
done:
    free(nodes);
    free(depth);
    free(len);
    return e->code;
}

int kt_incise_cylinder_phase(kt_incise *c, const kt_incision *inc, int index, kt_phase *ph,
                             kt_err *e)
{
    kt_incise_arc_phase(inc, index, ph);
    cylinder surf = {0.5 * inc->diameter, 1};
    /* on an oval cornea the incision's circle is the ellipse through the oval's horizontal and
     * vertical radii at its diameter (keratome-plan(5), INCISIONS) */
    if (c->plan && c->plan->scene.model == KT_MODEL_EYE) {
        double b = kt_eye_oval_radius(&c->plan->scene.eye, inc->diameter, 90);
        if (b > 0 && b < surf.r) surf.sy = surf.r / b;
    }
    signed char *cls = classify(c, cylinder_side, &surf, e);
    if (!cls || interface(c, cls, ph, e) || select_arc_faces(c, inc, ph, e)) goto done;
    if (ph->nface == 0) {
        char at[1100];
        kt_plan_where(c->plan, inc->at, at, sizeof at);
        kt_fail(e, KT_EINPUT, "%s: expected the %g mm circle to cross the cornea or limbus of the "
                "mesh within the arc", at, inc->diameter);
        goto done;
    }
    int moved = 0, hung = 0;
    if (kt_incise_unhang(c, ph, NULL, NULL, NULL, NULL, &moved, &hung, e)) goto done;
    if (hung) kt_log(c->quiet, "cutplan: %s: %d tets that would hang by one face left uncut\n", ph->name, hung);
    if (snap_faces(c, ph, cylinder_proj, &surf, "incision cylinder", e)) goto done;
    kt_incise_sort_faces(ph);
done:
    free(cls);
    return e->code;
}
