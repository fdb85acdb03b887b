/* build.c: a scene's mesh (the eye with gmsh, a box grid, a CGAL surface or image), with the
 * surface groups its 'below' fixations ask for, at element order 1 or 2. */
#include "build.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cgalin.h"
#include "cgalmesh.h"
#include "eye.h"
#include "grid.h"
#include "topology.h"

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
    if (kt_cgalin_check(g->path, e)) return e->code;
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


int kt_build_below_group(kt_mesh *m, const char *name, int axis, double level, kt_err *e)
{
    if (m->order != 1) return kt_fail(e, KT_ERUN, "below groups are made before order elevation");
    if (kt_mesh_find_group(m, 2, name))
        return kt_fail(e, KT_EINPUT, "fixation: surface '%s' exists already; name the 'below' group differently", name);
    kt_face *f = NULL;
    if (kt_mesh_tet_faces(m, &f, e)) return e->code;
    size_t nf = 4 * (size_t)m->ne;
    int tag = 0, nnew = 0;
    for (int i = 0; i < m->ng; i++)
        if (m->group[i].dim == 2 && m->group[i].tag > tag) tag = m->group[i].tag;
    tag++;
    /* Boundary faces appear once; keep those under the level. */
    for (size_t i = 0; i < nf;) {
        size_t j = i + 1;
        while (j < nf && kt_face_cmp_v(&f[i], &f[j]) == 0) j++;
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
        orient_out(m->xyz, q, m->tet[4 * (size_t)(f[k].id / 4) + f[k].id % 4]); /* face f is opposite vertex f */
        m->tri_tag[m->nf + k] = tag;
    }
    m->nf += nnew;
    free(f);
    return KT_OK;
}

int kt_build_mesh(const kt_scene *s, int order, int quiet, kt_mesh *m, kt_err *e)
{
    memset(m, 0, sizeof *m);
    if (s->model == KT_MODEL_EYE) return kt_eye_mesh(&s->eye, order, quiet, m, e);
    int rc = s->model == KT_MODEL_BOX ? build_box(s, m, e) : build_cgal(s, quiet, m, e);
    for (int i = 0; !rc && i < s->nfix; i++) {
        const kt_fixation *f = &s->fix[i];
        if (f->below_axis >= 0) rc = kt_build_below_group(m, f->surface, f->below_axis, f->below_value, e);
    }
    if (!rc && order == 2) rc = kt_mesh_elevate(m, e);
    if (rc) kt_mesh_free(m);
    return rc;
}

