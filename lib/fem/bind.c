/* bind.c: scene names -> mesh tags: materials, Dirichlet data, pressures, fixation surfaces. */
#include "bind.h"
#include "wound.h"

#include <stdlib.h>
#include <string.h>

static const kt_region_mat *lookup_mat(const kt_scene *s, const char *region)
{
    const kt_region_mat *fallback = NULL;
    for (int i = 0; i < s->nmat; i++) {
        if (strcmp(s->mat[i].region, region) == 0) return &s->mat[i];
        if (strcmp(s->mat[i].region, "default") == 0) fallback = &s->mat[i];
    }
    return fallback;
}

/* mats->mat[tag] for every region tag of the mesh (nmat = largest tag + 1). */
static int bind_materials(const kt_scene *s, const kt_mesh *m, kt_materials *mats, kt_err *e)
{
    int max_tag = 0;
    for (int i = 0; i < m->ng; i++)
        if (m->group[i].dim == 3 && m->group[i].tag > max_tag) max_tag = m->group[i].tag;
    for (int i = 0; i < m->ne; i++)
        if (m->tet_tag[i] > max_tag) max_tag = m->tet_tag[i];
    mats->nmat = max_tag + 1;
    mats->mat = kt_calloc((size_t)mats->nmat, sizeof *mats->mat, e);
    if (!mats->mat) return e->code;
    for (int i = 0; i < m->ng; i++) {
        const kt_group *g = &m->group[i];
        if (g->dim != 3) continue;
        const kt_region_mat *r = lookup_mat(s, g->name);
        if (!r)
            return kt_fail(e, KT_EINPUT, "%s: materials: expected an entry for region '%s' (or 'default')",
                           s->path, g->name);
        mats->mat[g->tag].E = r->E;
        mats->mat[g->tag].nu = r->nu;
    }
    return KT_OK;
}

int kt_fem_dirichlet(const kt_scene *s, const kt_mesh *m, unsigned char *fixed, double *g,
                     kt_fem_fix_surf *fix, kt_err *e)
{
    for (int i = 0; i < s->nfix; i++) {
        const kt_fixation *f = &s->fix[i];
        const kt_group *grp = kt_mesh_find_group(m, 2, f->surface);
        if (!grp)
            return kt_fail(e, KT_EINPUT, "%s: fixation[%d]: expected surface '%s' in the mesh",
                           s->path, i, f->surface);
        if (fix) {
            fix[i].tag = grp->tag;
            fix[i].mask = f->mask;
            memcpy(fix[i].v, f->value, sizeof fix[i].v);
        }
        int *nodes = NULL, cnt = 0;
        if (kt_mesh_group_nodes(m, grp, &nodes, &cnt, e)) return e->code;
        for (int k = 0; k < cnt; k++)
            for (int c = 0; c < 3; c++)
                if (f->mask & (1u << c)) {
                    size_t dof = 3 * (size_t)nodes[k] + c;
                    fixed[dof] = 1;
                    if (g) g[dof] = f->value[c];
                }
        free(nodes);
    }
    return KT_OK;
}

int kt_fem_bind(const kt_scene *s, const kt_mesh *m, kt_fem_problem *p, kt_err *e)
{
    memset(p, 0, sizeof *p);
    p->nn = m->nn;
    size_t n = 3 * (size_t)m->nn;
    p->fixed = kt_calloc(n ? n : 1, 1, e);
    p->g = kt_calloc(n ? n : 1, sizeof(double), e);
    if (e->code || bind_materials(s, m, &p->mats, e)) goto fail;
    if (kt_fem_dirichlet(s, m, p->fixed, p->g, p->fix, e)) goto fail;
    p->nfix = s->nfix;
    for (int i = 0; i < s->npressure; i++) {
        const kt_group *g = kt_mesh_find_group(m, 2, s->pressure[i].surface);
        if (!g) {
            kt_fail(e, KT_EINPUT, "%s: loads.pressure[%d]: expected surface '%s' in the mesh",
                    s->path, i, s->pressure[i].surface);
            goto fail;
        }
        p->press[p->npress++] = (kt_fem_load_surf){g->tag, s->pressure[i].p};
    }
    double k = kt_scene_wound_k(s);
    if (k > 0) {
        if (!(p->wound = kt_calloc(1, sizeof *p->wound, e)) || kt_wound_build(p->wound, m, k, e)) goto fail;
        p->mats.wound = p->wound;
    }
    return KT_OK;
fail:
    kt_fem_problem_free(p);
    return e->code;
}

void kt_fem_problem_free(kt_fem_problem *p)
{
    free(p->mats.mat);
    free(p->fixed);
    free(p->g);
    if (p->wound) kt_wound_free(p->wound);
    free(p->wound);
    memset(p, 0, sizeof *p);
}

int kt_fem_problem_loads(const kt_fem_problem *p, const kt_mesh *m, double scale, double *f,
                         kt_err *e)
{
    memset(f, 0, 3 * (size_t)m->nn * sizeof(double));
    for (int i = 0; i < p->npress; i++)
        if (kt_fem_pressure(m, p->press[i].tag, scale * p->press[i].p, f, e)) return e->code;
    return KT_OK;
}

int kt_fem_check_scene(const kt_scene *s, const kt_mesh *m, unsigned char *fixed, kt_err *e)
{
    for (int i = 0; i < s->npressure; i++)
        if (!kt_mesh_find_group(m, 2, s->pressure[i].surface))
            return kt_fail(e, KT_EINPUT, "%s: loads.pressure: expected surface '%s' in the mesh", s->path,
                           s->pressure[i].surface);
    kt_fem_problem p;
    if (kt_fem_bind(s, m, &p, e)) return e->code;
    if (fixed) memcpy(fixed, p.fixed, 3 * (size_t)m->nn);
    kt_fem_problem_free(&p);
    return KT_OK;
}
