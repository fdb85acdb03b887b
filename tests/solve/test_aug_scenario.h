/* test_aug_scenario.h: beam and brick problems and generators of edit steps (cuts along a plane,
 * nonzero Dirichlet constraints, forces) shared by the augmented-solver tests. */
#ifndef TEST_AUG_SCENARIO_H
#define TEST_AUG_SCENARIO_H

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "aug.h"
#include "apply.h"
#include "grid.h"

typedef struct scenario {
    kt_mesh mesh;
    kt_material mat[2];
    kt_materials mats;
    unsigned char *fixed;
    double *g;
    kt_aug_pressure press[2];
    kt_aug_fixsurf fix[1];
    kt_aug_problem prob;
    int nx, ny, nz;
    double h;                 /* grid spacing */
} scenario;

/* Box of nx*ny*nz nodes, spacing h, clamped on zmin (value gz in z), pressure p on ymax and
 * zmax. */
static inline int scenario_box(scenario *s, int nx, int ny, int nz, double h, double gz, kt_err *e)
{
    memset(s, 0, sizeof *s);
    s->nx = nx, s->ny = ny, s->nz = nz, s->h = h;
    if (kt_grid_box(&s->mesh, nx, ny, nz, h * (nx - 1), h * (ny - 1), h * (nz - 1), e)) return -1;
    s->mat[1] = (kt_material){1.0, 0.3};
    s->mats = (kt_materials){.nmat = 2, .mat = s->mat};
    s->fixed = calloc(3 * (size_t)s->mesh.nn, 1);
    s->g = calloc(3 * (size_t)s->mesh.nn, sizeof(double));
    const kt_group *zmin = kt_mesh_find_group(&s->mesh, 2, "zmin");
    int *nodes, cnt;
    if (kt_mesh_group_nodes(&s->mesh, zmin, &nodes, &cnt, e)) return -1;
    for (int k = 0; k < cnt; k++)
        for (int c = 0; c < 3; c++) {
            s->fixed[3 * nodes[k] + c] = 1;
            s->g[3 * nodes[k] + c] = c == 2 ? gz : 0;
        }
    free(nodes);
    s->press[0] = (kt_aug_pressure){kt_mesh_find_group(&s->mesh, 2, "ymax")->tag, 0.01};
    s->press[1] = (kt_aug_pressure){kt_mesh_find_group(&s->mesh, 2, "zmax")->tag, -0.004};
    s->fix[0] = (kt_aug_fixsurf){zmin->tag, 7u, {0, 0, gz}};
    s->prob = (kt_aug_problem){&s->mesh, &s->mats, s->fixed, s->g, 2, s->press, 1, s->fix, NULL};
    return 0;
}

static inline void scenario_free(scenario *s)
{
    kt_mesh_free(&s->mesh);
    free(s->fixed);
    free(s->g);
}

/* Grid node (i,j,k) of the input mesh. */
static inline int grid_node(const scenario *s, int i, int j, int k) { return i + s->nx * (j + s->ny * k); }

static inline double tet_cx(const kt_mesh *m, int t, int axis)
{
    double c = 0;
    for (int l = 0; l < 4; l++) c += m->xyz[3 * m->tet[4 * t + l] + axis];
    return c / 4;
}

/* Append a dup of node a moving its tets whose centroid has coordinate axis > x0. */
static inline int add_dup_axis(const kt_mesh *m, kt_step *st, int a, int new_node, int axis,
                               double x0, kt_err *e)
{
    int *el = malloc(sizeof(int) * 64), nel = 0;
    for (int t = 0; t < m->ne && nel < 64; t++)
        for (int l = 0; l < 4; l++)
            if (m->tet[4 * t + l] == a && tet_cx(m, t, axis) > x0) {
                el[nel++] = t;
                break;
            }
    kt_edit ed = {.kind = KT_EDIT_DUP, .node = a, .new_node = new_node, .nel = nel, .el = el};
    int rc = kt_step_add(st, &ed, e);
    free(el);
    return rc;
}

/* Append a dup of node a moving its tets whose centroid has x > x0 (the + side of the cut). */
static inline int add_dup(const kt_mesh *m, kt_step *st, int a, int new_node, double x0, kt_err *e)
{
    return add_dup_axis(m, st, a, new_node, 0, x0, e);
}

/* Cut step: split the nodes of layer k on the plane x = xi*h (all j), pulling each pair apart
 * with forces +-F in x. The current mesh m gives the tets; node numbers of the input mesh are
 * still valid for the original side of every split. */
static inline int cut_layer(const scenario *s, const kt_mesh *m, kt_step *st, int xi, int k, double F,
                     kt_err *e)
{
    int next = m->nn;
    double x0 = xi * s->h;
    for (int j = 0; j < s->ny; j++) {
        int a = grid_node(s, xi, j, k);
        if (add_dup(m, st, a, next, x0, e)) return -1;
        if (F != 0) {
            kt_edit f1 = {.kind = KT_EDIT_FORCE, .node = a, .v = {-F, 0, 0}};
            kt_edit f2 = {.kind = KT_EDIT_FORCE, .node = next, .v = {F, 0, 0}};
            if (kt_step_add(st, &f1, e) || kt_step_add(st, &f2, e)) return -1;
        }
        next++;
    }
    return 0;
}

static inline int add_fix(kt_step *st, int node, unsigned mask, double vx, double vy, double vz,
                   kt_err *e)
{
    kt_edit ed = {.kind = KT_EDIT_FIX, .node = node, .mask = mask, .v = {vx, vy, vz}};
    return kt_step_add(st, &ed, e);
}

/* The reference: current mesh, constraints tracked by the test, loads from scratch. */
static inline int reference_solve(const scenario *s, const kt_mesh *m, const unsigned char *fixed,
                           const double *g, const double *force, double *u, kt_err *e)
{
    size_t n = 3 * (size_t)m->nn;
    double *f = calloc(n, sizeof(double));
    for (int k = 0; k < 2; k++) kt_fem_pressure(m, s->press[k].tag, s->press[k].p, f, e);
    for (size_t i = 0; i < n; i++) f[i] += force[i];
    cholmod_common c;
    cholmod_start(&c);
    if (!e->code) kt_fem_solve(m, &s->mats, fixed, g, f, u, &c, e);
    cholmod_finish(&c);
    free(f);
    return e->code;
}

static inline double max_rel_diff(const double *u, const double *r, size_t n)
{
    double d = 0, m = 0;
    for (size_t i = 0; i < n; i++) {
        d = fmax(d, fabs(u[i] - r[i]));
        m = fmax(m, fabs(r[i]));
    }
    return m > 0 ? d / m : d;
}

#endif
