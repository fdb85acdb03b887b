/* prep.c: mesh-prep's pipeline: build, group, check, order, renumber, write, summarize. */
#include "prep.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cgalmesh.h"
#include "eye.h"
#include "fem.h"
#include "grid.h"
#include "msh.h"
#include "refgeom.h"

#define PI 3.14159265358979323846

static const char *const FACE_NAMES[] = {"xmin", "xmax", "ymin", "ymax", "zmin", "zmax"};

/* ---- building ----------------------------------------------------------------------------- */

static int build_box(const kt_scene *s, kt_mesh *m, kt_err *e)
{
    const kt_box *b = &s->box;
    if (kt_grid_box(m, b->n[0], b->n[1], b->n[2], b->len[0], b->len[1], b->len[2], e)) return e->code;
    if (b->fixed_face < 0) return KT_OK;
    /* The fixed end keeps its tag and takes the name the fixation refers to. */
    for (int i = 0; i < m->ng; i++)
        if (m->group[i].dim == 2 && strcmp(m->group[i].name, FACE_NAMES[b->fixed_face]) == 0) {
            snprintf(m->group[i].name, sizeof m->group[i].name, "fixed");
            return KT_OK;
        }
    return kt_fail(e, KT_ERUN, "box mesh has no face group '%s'", FACE_NAMES[b->fixed_face]);
}

/* CGAL with the scene's sizes (mm, converted to file units), rescaled up to three times to
 * come within 10% of target_nodes; then coordinates scaled to mm. */
static int build_cgal(const kt_scene *s, int quiet, kt_mesh *m, kt_err *e)
{
    const kt_cgal *g = &s->cgal;
    double scale = 1.0;
    for (int it = 0;; it++) {
        double fs = g->facet_size * scale / g->unit, cs = g->cell_size * scale / g->unit;
        double fd = g->facet_distance / g->unit;
        int rc = s->model == KT_MODEL_SURFACE ? kt_cgal_mesh_surface(g->path, fs, fd, cs, m, e)
                                              : kt_cgal_mesh_image(g->path, fs, fd, cs, m, e);
        if (rc) return rc;
        double ratio = g->target_nodes > 0 ? (double)m->nn / g->target_nodes : 1.0;
        kt_log(quiet, "mesh-prep: CGAL pass %d: facet_size %g cell_size %g (file units): %d nodes\n",
               it + 1, fs, cs, m->nn);
        if (fabs(ratio - 1) < 0.1 || it == 3) break;
        scale *= cbrt(ratio); /* node count ~ size^-3 */
        kt_mesh_free(m);
    }
    for (size_t k = 0; k < 3 * (size_t)m->nn; k++) m->xyz[k] *= g->unit;
    return KT_OK;
}

/* Outward orientation of face (a,b,c) of a tet whose fourth vertex is d. */
static void orient_out(const double *X, int *f, int d)
{
    const double *a = X + 3 * f[0], *b = X + 3 * f[1], *c = X + 3 * f[2];
    if (kt_tet_volume(a, b, c, X + 3 * d) > 0) {
        int t = f[1];
        f[1] = f[2];
        f[2] = t;
    }
}

typedef struct face {
    int v[3];       /* sorted vertices */
    int tet, opp;   /* one tet holding it and that tet's fourth vertex */
} face;

static int cmp_face(const void *pa, const void *pb)
{
    const face *a = pa, *b = pb;
    for (int k = 0; k < 3; k++)
        if (a->v[k] != b->v[k]) return a->v[k] < b->v[k] ? -1 : 1;
    return 0;
}

static void sort3(int *v)
{
    for (int i = 0; i < 2; i++)
        for (int j = 0; j < 2 - i; j++)
            if (v[j] > v[j + 1]) {
                int t = v[j];
                v[j] = v[j + 1];
                v[j + 1] = t;
            }
}

int kt_prep_below_group(kt_mesh *m, const char *name, int axis, double level, kt_err *e)
{
    if (m->order != 1) return kt_fail(e, KT_ERUN, "below groups are made before order elevation");
    if (kt_mesh_find_group(m, 2, name))
        return kt_fail(e, KT_EINPUT, "fixation: surface '%s' exists already; name the 'below' group differently", name);
    face *f = kt_calloc(4 * (size_t)m->ne, sizeof *f, e);
    if (!f) return e->code;
    size_t nf = 0;
    for (int t = 0; t < m->ne; t++)
        for (int k = 0; k < 4; k++) {
            face *q = &f[nf++];
            for (int j = 0, c = 0; j < 4; j++)
                if (j != k) q->v[c++] = m->tet[4 * (size_t)t + j];
            sort3(q->v);
            q->tet = t;
            q->opp = m->tet[4 * (size_t)t + k];
        }
    qsort(f, nf, sizeof *f, cmp_face);
    int tag = 0, nnew = 0;
    for (int i = 0; i < m->ng; i++)
        if (m->group[i].dim == 2 && m->group[i].tag > tag) tag = m->group[i].tag;
    tag++;
    /* Boundary faces appear once; keep those under the level. */
    for (size_t i = 0; i < nf;) {
        size_t j = i + 1;
        while (j < nf && cmp_face(&f[i], &f[j]) == 0) j++;
        int under = 1;
        for (int k = 0; k < 3; k++) under &= m->xyz[3 * (size_t)f[i].v[k] + axis] <= level;
        if (j == i + 1 && under) f[nnew++] = f[i];
        i = j;
    }
    if (nnew == 0) {
        free(f);
        return kt_fail(e, KT_EINPUT, "fixation: no boundary face lies below %c = %g mm for surface '%s'",
                       'x' + axis, level, name);
    }
    int *tri = kt_realloc(m->tri, (size_t)m->nf + nnew, 3 * sizeof(int), e);
    if (tri) m->tri = tri;
    int *tag_of = tri ? kt_realloc(m->tri_tag, (size_t)m->nf + nnew, sizeof(int), e) : NULL;
    if (tag_of) m->tri_tag = tag_of;
    if (!tri || !tag_of || kt_mesh_add_group(m, 2, tag, name, e)) {
        free(f);
        return e->code;
    }
    for (int k = 0; k < nnew; k++) {
        int *q = m->tri + 3 * (size_t)(m->nf + k);
        memcpy(q, f[k].v, sizeof f[k].v);
        orient_out(m->xyz, q, f[k].opp);
        m->tri_tag[m->nf + k] = tag;
    }
    m->nf += nnew;
    free(f);
    return KT_OK;
}

int kt_prep_build(const kt_scene *s, int order, int quiet, kt_mesh *m, kt_err *e)
{
    memset(m, 0, sizeof *m);
    if (s->model == KT_MODEL_EYE) return kt_eye_mesh(&s->eye, order, quiet, m, e);
    int rc = s->model == KT_MODEL_BOX ? build_box(s, m, e) : build_cgal(s, quiet, m, e);
    for (int i = 0; !rc && i < s->nfix; i++) {
        const kt_fixation *f = &s->fix[i];
        if (f->below_axis >= 0) rc = kt_prep_below_group(m, f->surface, f->below_axis, f->below_value, e);
    }
    if (!rc && order == 2) rc = kt_mesh_elevate(m, e);
    if (rc) kt_mesh_free(m);
    return rc;
}

/* ---- quality ------------------------------------------------------------------------------- */

static void sub(const double *a, const double *b, double *r)
{
    for (int k = 0; k < 3; k++) r[k] = a[k] - b[k];
}

static void cross(const double *a, const double *b, double *r)
{
    r[0] = a[1] * b[2] - a[2] * b[1];
    r[1] = a[2] * b[0] - a[0] * b[2];
    r[2] = a[0] * b[1] - a[1] * b[0];
}

static double dot(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/* Dihedral extremes and radius ratio of the tet p[0..3]. */
static double tet_quality(const double *p[4], double *dmin, double *dmax)
{
    static const int FACE[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
    double n[4][3], area = 0;
    for (int k = 0; k < 4; k++) {
        double u[3], v[3];
        sub(p[FACE[k][1]], p[FACE[k][0]], u);
        sub(p[FACE[k][2]], p[FACE[k][0]], v);
        cross(u, v, n[k]);
        area += 0.5 * sqrt(dot(n[k], n[k]));
    }
    /* Faces k and l meet at the edge of the other two vertices; the dihedral angle there is
     * pi minus the angle between their outward normals. */
    for (int k = 0; k < 4; k++)
        for (int l = k + 1; l < 4; l++) {
            double c = dot(n[k], n[l]) / sqrt(dot(n[k], n[k]) * dot(n[l], n[l]));
            double ang = 180.0 - acos(fmax(-1.0, fmin(1.0, c))) * 180.0 / PI;
            if (ang < *dmin) *dmin = ang;
            if (ang > *dmax) *dmax = ang;
        }
    double a[3], b[3], c[3], bc[3], ca[3], ab[3], o[3];
    sub(p[1], p[0], a);
    sub(p[2], p[0], b);
    sub(p[3], p[0], c);
    cross(b, c, bc);
    cross(c, a, ca);
    cross(a, b, ab);
    double det = dot(a, bc); /* 6 V */
    for (int k = 0; k < 3; k++)
        o[k] = (dot(a, a) * bc[k] + dot(b, b) * ca[k] + dot(c, c) * ab[k]) / (2 * det);
    double r_circ = sqrt(dot(o, o)), r_in = 3 * fabs(det / 6) / area;
    return 3 * r_in / r_circ;
}

void kt_prep_quality(const kt_mesh *m, kt_quality *q)
{
    int nv = kt_tet_nv(m->order);
    q->dihedral_min = 180;
    q->dihedral_max = 0;
    q->ratio_min = HUGE_VAL;
    q->ratio_mean = 0;
    q->worst = -1;
    for (int t = 0; t < m->ne; t++) {
        const int *v = m->tet + (size_t)t * nv;
        const double *p[4] = {m->xyz + 3 * (size_t)v[0], m->xyz + 3 * (size_t)v[1],
                              m->xyz + 3 * (size_t)v[2], m->xyz + 3 * (size_t)v[3]};
        double r = tet_quality(p, &q->dihedral_min, &q->dihedral_max);
        q->ratio_mean += r;
        if (r < q->ratio_min) {
            q->ratio_min = r;
            q->worst = t;
        }
    }
    if (m->ne) q->ratio_mean /= m->ne;
}

/* ---- the ordering set ------------------------------------------------------------------------ */

static int cmp_int(const void *a, const void *b)
{
    int x = *(const int *)a, y = *(const int *)b;
    return (x > y) - (x < y);
}

/* Append group g's nodes to *v (size *n), then the caller sorts and dedups. */
static int append_group(const kt_mesh *m, const kt_group *g, int **v, int *n, kt_err *e)
{
    int *nodes = NULL, cnt = 0;
    if (kt_mesh_group_nodes(m, g, &nodes, &cnt, e)) return e->code;
    int *w = kt_realloc(*v, (size_t)*n + cnt, sizeof(int), e);
    if (!w) {
        free(nodes);
        return e->code;
    }
    memcpy(w + *n, nodes, sizeof(int) * (size_t)cnt);
    *v = w;
    *n += cnt;
    free(nodes);
    return KT_OK;
}

/* Grow the sorted set by 'layers' layers of tet neighbours; the result stays sorted. */
static int grow(const kt_mesh *m, int layers, int **nodes, int *count, kt_err *e)
{
    if (layers <= 0) return KT_OK;
    unsigned char *in = kt_calloc((size_t)m->nn, 1, e), *add = kt_calloc((size_t)m->nn, 1, e);
    if (!in || !add) {
        free(in);
        free(add);
        return e->code;
    }
    int nv = kt_tet_nv(m->order);
    for (int k = 0; k < *count; k++) in[(*nodes)[k]] = 1;
    for (int l = 0; l < layers; l++) {
        for (int t = 0; t < m->ne; t++) {
            const int *q = m->tet + (size_t)t * nv;
            int touch = 0;
            for (int j = 0; j < nv; j++) touch |= in[q[j]];
            for (int j = 0; j < nv && touch; j++) add[q[j]] = 1;
        }
        memcpy(in, add, (size_t)m->nn);
    }
    int n = 0;
    for (int v = 0; v < m->nn; v++) n += in[v];
    int *v2 = kt_realloc(*nodes, (size_t)n, sizeof(int), e);
    if (v2) {
        *nodes = v2;
        *count = 0;
        for (int v = 0; v < m->nn; v++)
            if (in[v]) v2[(*count)++] = v;
    }
    free(in);
    free(add);
    return e->code;
}

/* The named surfaces' nodes, sorted and unique. */
static int surfaces_nodes(const kt_scene *s, const kt_mesh *m, int **nodes, int *count, char *label, kt_err *e)
{
    if (s->ordering_set[0]) {
        const kt_group *g = kt_mesh_find_group(m, 2, s->ordering_set);
        if (!g)
            return kt_fail(e, KT_EINPUT, "%s: ordering.last: expected surface '%s' in the mesh", s->path,
                           s->ordering_set);
        snprintf(label, 96, "surface '%s' (ordering.last)", s->ordering_set);
        return kt_mesh_group_nodes(m, g, nodes, count, e);
    }
    int len = snprintf(label, 96, "incision rings");
    for (int i = 0; i < s->eye.nring; i++) {
        const kt_group *g = kt_mesh_find_group(m, 2, s->eye.ring[i].name);
        if (!g) return kt_fail(e, KT_ERUN, "eye mesh lacks incision surface '%s'", s->eye.ring[i].name);
        if (len < 80) len += snprintf(label + len, 96 - len, "%s%s", i ? "," : " ", g->name);
        if (append_group(m, g, nodes, count, e)) return e->code;
    }
    qsort(*nodes, (size_t)*count, sizeof(int), cmp_int);
    int u = 0;
    for (int i = 0; i < *count; i++)
        if (u == 0 || (*nodes)[i] != (*nodes)[u - 1]) (*nodes)[u++] = (*nodes)[i];
    *count = u;
    return KT_OK;
}

static double meridian_distance(const kt_mesh *m, int v, double centre);

/* Eye: keep only the nodes within ordering.sector of the centre meridian or its opposite (a
 * smaller set last means a smaller dense root block of L; the cut arcs lie inside it). */
static int keep_sector(const kt_scene *s, const kt_mesh *m, int *nodes, int *count)
{
    if (s->model != KT_MODEL_EYE || isnan(s->ordering_centre) || isnan(s->ordering_sector)) return 0;
    int u = 0;
    for (int k = 0; k < *count; k++)
        if (meridian_distance(m, nodes[k], s->ordering_centre) <= s->ordering_sector) nodes[u++] = nodes[k];
    *count = u;
    return 0;
}

int kt_prep_set(const kt_scene *s, const kt_mesh *m, int **nodes, int *count, char *label, kt_err *e)
{
    *nodes = NULL;
    *count = 0;
    if (!s->ordering_set[0] && (s->model != KT_MODEL_EYE || s->eye.nring == 0)) {
        snprintf(label, 160, "all nodes (the scene names no incision surface)");
        return KT_OK;
    }
    char what[96];
    if (surfaces_nodes(s, m, nodes, count, what, e) || keep_sector(s, m, *nodes, count) ||
        grow(m, s->ordering_halo, nodes, count, e)) {
        free(*nodes);
        *nodes = NULL;
        *count = 0;
        return e->code;
    }
    int len = snprintf(label, 160, "%s", what);
    if (len < 160 && s->model == KT_MODEL_EYE && !isnan(s->ordering_centre) && !isnan(s->ordering_sector))
        len += snprintf(label + len, 160 - len, " within %g deg of meridian %g and its opposite",
                        s->ordering_sector, s->ordering_centre);
    if (len < 160 && s->ordering_halo)
        snprintf(label + len, 160 - len, " and %d layer%s of tet neighbours (ordering.halo)",
                 s->ordering_halo, s->ordering_halo > 1 ? "s" : "");
    return KT_OK;
}

/* Angular distance (deg, 0-90) of node v from the meridian line through centre. */
static double meridian_distance(const kt_mesh *m, int v, double centre)
{
    double t = atan2(m->xyz[3 * (size_t)v + 1], m->xyz[3 * (size_t)v]) * 180 / PI;
    double d = fmod(fabs(t - centre), 180.0);
    return fmin(d, 180.0 - d);
}

int kt_prep_set_ranks(const kt_scene *s, const kt_mesh *m, const int *nodes, int count, int **rank,
                      kt_err *e)
{
    *rank = NULL;
    if (s->model != KT_MODEL_EYE || isnan(s->ordering_centre) || count == 0) return KT_OK;
    *rank = kt_calloc((size_t)count, sizeof(int), e);
    if (!*rank) return e->code;
    for (int k = 0; k < count; k++)
        (*rank)[k] = (int)lround(2 * (90 - meridian_distance(m, nodes[k], s->ordering_centre)));
    return KT_OK;
}

/* The set's nodes within 30 deg of the centre meridian (what a paired 60-degree LRI cuts). */
static int sector_nodes(const kt_scene *s, const kt_mesh *m, const int *set, int nset, int **out,
                        int *count, kt_err *e)
{
    *out = NULL;
    *count = 0;
    if (s->model != KT_MODEL_EYE || isnan(s->ordering_centre) || nset == 0) return KT_OK;
    *out = kt_calloc((size_t)nset, sizeof(int), e);
    if (!*out) return e->code;
    for (int k = 0; k < nset; k++)
        if (meridian_distance(m, set[k], s->ordering_centre) <= 30) (*out)[(*count)++] = set[k];
    return KT_OK;
}

/* ---- the run --------------------------------------------------------------------------------- */

/* Everything the scene's solvers will look up must be in the mesh. */
static int check_scene_on_mesh(const kt_scene *s, const kt_mesh *m, unsigned char *fixed, kt_err *e)
{
    for (int i = 0; i < s->npressure; i++)
        if (!kt_mesh_find_group(m, 2, s->pressure[i].surface))
            return kt_fail(e, KT_EINPUT, "%s: loads.pressure: expected surface '%s' in the mesh", s->path,
                           s->pressure[i].surface);
    kt_materials mats = {0, NULL};
    if (kt_scene_materials(s, m, &mats, e)) return e->code;
    free(mats.mat);
    return kt_scene_dirichlet(s, m, fixed, NULL, e);
}

static const char *model_name(int model)
{
    static const char *N[] = {"?", "eye", "box", "surface", "image"};
    return model >= 1 && model <= 4 ? N[model] : "?";
}

/* Counts of tets per region and triangles per surface, in group order. */
static void print_groups(FILE *f, const kt_mesh *m, int dim)
{
    fprintf(f, "%-13s", dim == 3 ? "regions" : "surfaces");
    int first = 1;
    for (int g = 0; g < m->ng; g++) {
        if (m->group[g].dim != dim) continue;
        long cnt = 0;
        int n = dim == 3 ? m->ne : m->nf;
        const int *tag = dim == 3 ? m->tet_tag : m->tri_tag;
        for (int i = 0; i < n; i++) cnt += tag[i] == m->group[g].tag;
        fprintf(f, "%s%s %ld", first ? "" : ", ", m->group[g].name, cnt);
        first = 0;
    }
    fprintf(f, " %s\n", dim == 3 ? "tets" : "triangles");
}

typedef struct run_info {
    const kt_prep_opts *o;
    const kt_scene *s;
    int order, chosen, nfixed, nset, nsector;
    const char *set_label;
    double t_mesh, t_ref, t_write, t_total;
    int unloaded;           /* the stress-free geometry was computed */
    kt_refgeom_opts ro;
    kt_refgeom_stats rs;
    kt_quality q;
    int nrow;
    kt_prep_row row[6];
} run_info;

/* The eye's element sizes as meshed: the cornea and optical-zone ones follow the rule of
 * kt_eye_sizes, and a reduction is said, not hidden. */
static void print_sizes(FILE *f, const run_info *r)
{
    if (r->s->model != KT_MODEL_EYE) return;
    const kt_eye *eye = &r->s->eye;
    double hc, ho;
    kt_eye_sizes(eye, r->order, &hc, &ho);
    fprintf(f, "sizes        optical zone %g mm, incision %g mm, cornea %g mm, sclera %g mm\n", ho,
            eye->h_incision, hc, eye->h_sclera);
    if (hc < eye->h_cornea || ho < eye->h_optical)
        fprintf(f, "             (eye.mesh_size asks for optical zone %g mm, cornea %g mm: element order %d "
                   "allows at most %.3g mm, central_thickness/%g)\n", eye->h_optical, eye->h_cornea, r->order,
                eye->t_central / kt_eye_layers(r->order), kt_eye_layers(r->order));
}

/* What the written coordinates are: the stress-free shape computed from the measured one, or
 * the scene's geometry as it is. */
static void print_reference(FILE *f, const run_info *r)
{
    if (r->unloaded) {
        fprintf(f, "reference    stress-free shape that the loads deform into the scene's (measured) geometry\n"
                   "             (loads.reference: loaded): %d solves, residual max |X0 + u(X0) - X_measured| = %.3g um\n"
                   "             (tolerance %.3g um; %.3g um with the measured shape taken as stress-free),\n"
                   "             nodes moved up to %.1f um (%.2f s)\n",
                r->rs.iters, 1000 * r->rs.residual, 1000 * r->ro.tol, 1000 * r->rs.initial, 1000 * r->rs.shift,
                r->t_ref);
    } else if (r->s->reference == KT_REFERENCE_UNLOADED) {
        fprintf(f, "reference    the scene's geometry, taken as stress-free (loads.reference: unloaded)\n");
    } else {
        fprintf(f, "reference    the scene's geometry (no loads: it is stress-free)\n");
    }
}

static void print_summary(FILE *f, const kt_mesh *m, const run_info *r)
{
    fprintf(f, "scene        %s (model %s, element order %d)\n", r->o->scene, model_name(r->s->model), r->order);
    fprintf(f, "mesh         %d nodes, %d tets, %d surface triangles (%.2f s)\n", m->nn, m->ne, m->nf, r->t_mesh);
    print_groups(f, m, 3);
    print_groups(f, m, 2);
    print_sizes(f, r);
    print_reference(f, r);
    fprintf(f, "quality      dihedral angle min %.2f deg, max %.2f deg; radius ratio 3r_in/r_circ min %.3f (tet %d), mean %.3f\n",
            r->q.dihedral_min, r->q.dihedral_max, r->q.ratio_min, r->q.worst + 1, r->q.ratio_mean);
    fprintf(f, "dofs         %d, of which %d fixed (identity rows in the analysis)\n", 3 * m->nn, r->nfixed);
    fprintf(f, "closure set  %s: %d nodes\n", r->set_label, r->nrow ? r->row[0].st.nset : r->nset);
    fprintf(f, "orderings    (closures in DOFs: elimination-tree paths from a node's DOFs to the root)\n");
    fprintf(f, "  %-12s %12s %12s %8s %13s %12s %12s %9s\n", "method", "nnz(L)", "flops", "height",
            "closure mean", "closure max", "|closure(S)|", "order s");
    for (int i = 0; i < r->nrow; i++) {
        const kt_prep_row *w = &r->row[i];
        fprintf(f, "%c %-12s %12.4g %12.4g %8d %13.1f %12d %12ld %9.3f\n", w->method == r->chosen ? '*' : ' ',
                kt_order_name(w->method), w->st.nnz_L, w->st.flops, w->st.height, w->st.closure_mean,
                w->st.closure_max, w->st.closure_union, w->t_order);
    }
    const kt_prep_row *best = NULL, *chosen = NULL;
    for (int i = 0; i < r->nrow; i++) {
        if (!best || r->row[i].st.flops < best->st.flops) best = &r->row[i];
        if (r->row[i].method == r->chosen) chosen = &r->row[i];
    }
    if (chosen && best && chosen->st.flops > 5 * best->st.flops)
        fprintf(f, "note         %s costs %.1fx the factor flops and %.1fx the nnz(L) of %s\n",
                kt_order_name(chosen->method), chosen->st.flops / best->st.flops,
                chosen->st.nnz_L / best->st.nnz_L, kt_order_name(best->method));
    if (r->nsector) {
        fprintf(f, "sector       the %d set nodes within 30 deg of meridian %g deg and its opposite (a paired\n"
                   "             60-degree LRI there); the set is swept from that meridian (ordering.centre)\n",
                r->nsector, r->s->ordering_centre);
        fprintf(f, "  %-12s %13s %12s %12s\n", "method", "closure mean", "closure max", "|closure|");
        for (int i = 0; i < r->nrow; i++) {
            const kt_prep_row *w = &r->row[i];
            fprintf(f, "%c %-12s %13.1f %12d %12ld\n", w->method == r->chosen ? '*' : ' ',
                    kt_order_name(w->method), w->sector.closure_mean, w->sector.closure_max,
                    w->sector.closure_union);
        }
    }
    fprintf(f, "output       %s (%s MSH 4.1, nodes numbered in %s order; written in %.2f s)\n",
            r->o->out, r->o->binary ? "binary" : "ASCII", kt_order_name(r->chosen), r->t_write);
    fprintf(f, "time         %.2f s in all\n", r->t_total);
}

/* Fail early, before meshing, if the output cannot be created. */
static int probe_output(const char *path, kt_err *e)
{
    if (strcmp(path, "-") == 0) return KT_OK;
    kt_out o;
    if (kt_out_open(&o, path, e)) return e->code;
    kt_out_abort(&o);
    return KT_OK;
}

/* Compare the orderings on the unpermuted mesh; *perm gets the chosen one. */
static int compare_orderings(const kt_mesh *m, const unsigned char *fixed, const int *set,
                             const int *rank, int nset, const int *sector, int nsector,
                             run_info *r, int *perm, kt_err *e)
{
    int methods[] = {KT_ORDERING_AMD, KT_ORDERING_METIS, KT_ORDERING_CONSTRAINED,
                     KT_ORDERING_METIS_LAST, KT_ORDERING_NATURAL};
    int *p = kt_calloc((size_t)m->nn, sizeof(int), e);
    if (!p) return e->code;
    r->nrow = 0;
    for (int i = 0; i < 5; i++) {
        int meth = methods[i];
        if (meth == KT_ORDERING_NATURAL && r->chosen != meth) continue;
        kt_prep_row *w = &r->row[r->nrow++];
        w->method = meth;
        double t0 = kt_now();
        if (kt_order_nodes_ranked(m, meth, set, rank, nset, p, e)) break;
        w->t_order = kt_now() - t0;
        if (kt_order_analyze(m, p, fixed, set, nset, &w->st, e)) break;
        if (nsector && kt_order_analyze(m, p, fixed, sector, nsector, &w->sector, e)) break;
        if (meth == r->chosen) memcpy(perm, p, sizeof(int) * (size_t)m->nn);
        kt_log(r->o->quiet, "mesh-prep: ordering %s: nnz(L) %.4g\n", kt_order_name(meth), w->st.nnz_L);
    }
    free(p);
    return e->code;
}

/* The geometry is the measured shape under the loads: replace it by the stress-free one. */
static int unload(const kt_prep_opts *o, const kt_scene *s, run_info *r, kt_mesh *m, kt_err *e)
{
    if (s->reference != KT_REFERENCE_LOADED) return KT_OK;
    double t0 = kt_now();
    kt_refgeom_opts_default(s, &r->ro);
    r->ro.quiet = o->quiet;
    if (kt_refgeom_unload(s, m, &r->ro, &r->rs, e)) return e->code;
    r->unloaded = r->rs.iters > 0;
    r->t_ref = kt_now() - t0;
    return kt_mesh_check(m, "stress-free geometry", e);
}

static int run_mesh(const kt_prep_opts *o, const kt_scene *s, run_info *r, kt_mesh *m, FILE *summary, kt_err *e)
{
    double t0 = kt_now();
    if (kt_prep_build(s, r->order, o->quiet, m, e)) return e->code;
    r->t_mesh = kt_now() - t0;
    if (kt_mesh_check(m, o->scene, e)) return e->code;
    unsigned char *fixed = kt_calloc(3 * (size_t)m->nn, 1, e);
    int *set = NULL, *rank = NULL, *sector = NULL, *perm = kt_calloc((size_t)m->nn, sizeof(int), e);
    char label[160];
    if (!fixed || !perm || check_scene_on_mesh(s, m, fixed, e) || unload(o, s, r, m, e))
        goto done;
    kt_prep_quality(m, &r->q);
    if (kt_prep_set(s, m, &set, &r->nset, label, e) ||
        kt_prep_set_ranks(s, m, set, r->nset, &rank, e) ||
        sector_nodes(s, m, set, r->nset, &sector, &r->nsector, e))
        goto done;
    r->set_label = label;
    for (size_t k = 0; k < 3 * (size_t)m->nn; k++) r->nfixed += fixed[k];
    if (compare_orderings(m, fixed, set, rank, r->nset, sector, r->nsector, r, perm, e) ||
        kt_mesh_permute(m, perm, e))
        goto done;
    double t1 = kt_now();
    if (kt_msh_write(o->out, m, o->binary, e)) goto done;
    r->t_write = kt_now() - t1;
    r->t_total = kt_now() - t0;
    if (summary) print_summary(summary, m, r);
done:
    free(fixed);
    free(set);
    free(rank);
    free(sector);
    free(perm);
    return e->code;
}

int kt_prep_run(const kt_prep_opts *o, FILE *summary, kt_err *e)
{
    kt_scene *s = kt_calloc(1, sizeof *s, e);
    if (!s) return e->code;
    run_info r;
    memset(&r, 0, sizeof r);
    kt_mesh m;
    memset(&m, 0, sizeof m);
    if (kt_scene_load(o->scene, s, e) || probe_output(o->out, e)) goto done;
    r.o = o;
    r.s = s;
    r.order = o->order ? o->order : s->order;
    r.chosen = o->ordering ? o->ordering : s->ordering;
    run_mesh(o, s, &r, &m, summary, e);
done:
    kt_mesh_free(&m);
    free(s);
    return e->code;
}
