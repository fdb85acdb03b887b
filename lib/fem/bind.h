/* bind.h: a scene on a mesh as the elasticity problem it poses. This is the one place where
 * the scene's names (regions, fixation and pressure surfaces) become the mesh's tags:
 * materials by region tag, Dirichlet DOFs and values, pressures by surface tag, and the
 * fixation surfaces (a node a cut later creates on one is fixed like its parent). */
#ifndef KT_BIND_H
#define KT_BIND_H

#include "fem.h"
#include "scene.h"

typedef struct kt_fem_load_surf {
    int tag;           /* surface group (dim 2) the pressure acts on */
    double p;          /* MPa, pushing into the solid */
} kt_fem_load_surf;

typedef struct kt_fem_fix_surf {
    int tag;           /* surface group of a scene fixation */
    unsigned mask;     /* bit c set: component c fixed */
    double v[3];       /* prescribed displacement, mm */
} kt_fem_fix_surf;

/* Owned by whoever calls kt_fem_bind; kt_fem_problem_free releases it. */
typedef struct kt_fem_problem {
    int nn;                     /* nodes of the mesh it was bound to */
    kt_materials mats;          /* by region tag */
    unsigned char *fixed;       /* 3*nn: 1 for every fixed DOF (3*node + c) */
    double *g;                  /* 3*nn: prescribed values of the fixed DOFs, mm (0 elsewhere) */
    int npress;
    kt_fem_load_surf press[KT_SCENE_MAX];
    int nfix;
    kt_fem_fix_surf fix[KT_SCENE_MAX];
    struct kt_wound *wound;     /* owned, NULL: the healed wound's bridge on the mesh bound
                                   (wound.h; the scene's wound: state healed, k > 0); mats.wound
                                   points to it */
} kt_fem_problem;

/* Bind scene s to mesh m (intact). Regions are matched by name, then the scene's "default"
 * material; the scene's healed wound (kt_scene_wound_k > 0) becomes the bridge of m's faces; a
 * region without one, or a pressure or fixation surface missing from the mesh, is KT_EINPUT
 * naming the scene file and the entry. On failure *p holds nothing to free. */
int kt_fem_bind(const kt_scene *s, const kt_mesh *m, kt_fem_problem *p, kt_err *e);
void kt_fem_problem_free(kt_fem_problem *p);

/* Everything scene s's solvers will look up is in mesh m: each loads.pressure surface, and what
 * kt_fem_bind needs (KT_EINPUT naming the scene otherwise). fixed (NULL: not wanted) := the
 * bound problem's 3 nn fixed-DOF flags. */
int kt_fem_check_scene(const kt_scene *s, const kt_mesh *m, unsigned char *fixed, kt_err *e);

/* The Dirichlet part alone: fixed[dof] = 1 and (g not NULL) g[dof] = value for every DOF a
 * scene fixation holds; other entries are left alone. fix (s->nfix entries, may be NULL)
 * receives the fixation surfaces by tag. A surface missing from the mesh is KT_EINPUT. */
int kt_fem_dirichlet(const kt_scene *s, const kt_mesh *m, unsigned char *fixed, double *g,
                     kt_fem_fix_surf *fix, kt_err *e);

/* f (3*nn, overwritten) := the consistent nodal forces of scale x every pressure of p on the
 * mesh as it stands (the surface groups by tag). */
int kt_fem_problem_loads(const kt_fem_problem *p, const kt_mesh *m, double scale, double *f,
                         kt_err *e);

#endif
