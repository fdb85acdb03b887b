/* physics.h: the per-tet physics of a scene on its mesh (keratome-scene(5), MECHANICS): the
 * lamellar (fibre) material in its local frames, and, for loads.reference prestressed, the
 * tangent stiffness of the pressurized measured geometry: the prestress of the loads (stress
 * stiffness, and its release across cut faces) and the follower pressure's load stiffness. */
#ifndef KT_PHYSICS_H
#define KT_PHYSICS_H

#include "bind.h"
#include "fem.h"
#include "scene.h"

typedef struct kt_physics {
    kt_fem_tetdata td;  /* owned; mats->td points here */
    int fibre;          /* some region is model fibre */
    int prestressed;    /* sig and pface are set */
    double t_build;     /* seconds (prestress solve included) */
    double sig_apex;    /* mean in-plane prestress at the apex tets, MPa (report) */
} kt_physics;

/* Fill ph for scene s on mesh m, bound as problem fp (kt_fem_bind), and set fp->mats.td =
 * &ph->td. With loads.reference prestressed: sig = the stress of one direct solve of the
 * material stiffness under fp's pressures with its Dirichlet data on the measured geometry, and
 * pface = the pressures as follower loads. Otherwise only the fibre matrices (if any). */
int kt_physics_build(const kt_scene *s, const kt_mesh *m, kt_fem_problem *fp, kt_physics *ph,
                     cholmod_common *c, kt_err *e);
void kt_physics_free(kt_physics *ph);

/* The elasticity problem augsolve solves for scene s on mesh m, for every program that must
 * solve the same one (augsolve, the benchmarks): fp := kt_fem_bind(s, m), ph :=
 * kt_physics_build; for a prestressed scene the steps are increments from the loaded state, so
 * the prescribed values (already in the prestress) become zero: fp->g and fp->fix[k].v.
 * On failure fp and ph hold nothing to free. */
int kt_physics_problem(const kt_scene *s, const kt_mesh *m, kt_fem_problem *fp, kt_physics *ph,
                       kt_err *e);
/* The second half of kt_physics_problem, for a caller that checks its input against the bound
 * problem fp (kt_fem_bind, cheap) before the prestress solve: ph := kt_physics_build, then the
 * prescribed values zeroed as above. On failure ph holds nothing to free; fp stays the
 * caller's. */
int kt_physics_finish(const kt_scene *s, const kt_mesh *m, kt_fem_problem *fp, kt_physics *ph,
                      kt_err *e);

#endif
