/* physics.h: the per-tet physics of a scene on its mesh (keratome-scene(5), MATERIALS, LOADS): the
 * lamellar (fibre) material in its local frames, and, for loads.reference prestressed, the
 * tangent stiffness of the pressurized measured geometry: the prestress of the loads (stress
 * stiffness, and its release across cut faces) and the follower pressure's load stiffness. */
#ifndef KT_PHYSICS_H
#define KT_PHYSICS_H

#include "bind.h"
#include "fem.h"
#include "scene.h"
#include "vtk.h"

/* Cell fields of the per-tet inputs: lamellar, 5 constants, a1 a2 n c, limbal_weight, sigma0. */
#define KT_PHYSICS_NFIELD 12
#define KT_PHYSICS_NCST 6

typedef struct kt_physics {
    kt_fem_tetdata td;  /* owned; mats->td points here */
    int fibre;          /* some region is model fibre */
    int prestressed;    /* sig and pface are set */
    double t_build;     /* seconds (prestress solve included) */
    double sig_apex;    /* the apex membrane stress augsolve prints, MPa: the volume mean of
                           (sig_11 + sig_22 + sig_33) / 2 over the tets whose centroid is within
                           0.5 mm of the axis and 1 mm of the apex (keratome-scene(5), LOADS) */
    double *frame;      /* owned, fibre scenes: ne x 13, kt_eye_fibre_frames (a1 a2 n c w) */
    double *cst;        /* owned: ne x KT_PHYSICS_NCST, the tet's constants E_inplane,
                           E_inplane_2, G_transverse (MPa), nu, E_circumferential (MPa), and
                           1 for a fibre region, else 0; an isotropic tet: E, E,
                           E / (2 (1 + nu)), nu, 0, 0 (kt_fem_fibre_matrix of these is its C) */
    double *cellv;      /* owned: the values of cell[] */
    int *perm;          /* owned, NULL: the fill-reducing order of the intact stiffness (3 nn
                           DOFs) the prestress solve factored with (kt_fem_solve_order): the
                           same pattern as every later stiffness of the intact mesh, so
                           augsolve's planned method orders its intact block by it */
    kt_vtk_field cell[KT_PHYSICS_NFIELD]; /* every per-tet input as a VTK cell field */
    int ncell;          /* (keratome-vtk(5)); kt_physics_cell_fields */
} kt_physics;

/* Fill ph for scene s on mesh m, bound as problem fp (kt_fem_bind), and set fp->mats.td =
 * &ph->td. With loads.reference prestressed: sig = the stress of one direct solve of the
 * material stiffness under fp's pressures with its Dirichlet data on the measured geometry, and
 * pface = the pressures as follower loads. Otherwise only the fibre matrices (if any). */
int kt_physics_build(const kt_scene *s, const kt_mesh *m, kt_fem_problem *fp, kt_physics *ph,
                     cholmod_common *c, kt_err *e);
void kt_physics_free(kt_physics *ph);

/* ph->cell[0 .. ncell-1] := the per-tet inputs of ph on mesh m (tets numbered as m's; a cut
 * keeps tet numbers) as VTK cell fields, values in ph->cellv: lamellar (int: 1 for a fibre
 * region), E_inplane, E_inplane_2, G_transverse, nu, E_circumferential (ph->cst); with fibre
 * frames a1, a2, n, c and limbal_weight (ph->frame); prestressed: sigma0, the volume average
 * of the prestress over the tet's quadrature points (kt_fem_prestress_mean), MPa, in VTK's
 * symmetric-tensor order xx yy zz xy yz xz. Called by kt_physics_build. */
int kt_physics_cell_fields(kt_physics *ph, const kt_mesh *m, kt_err *e);

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

/* Problem fp (kt_fem_bind of the scene and mesh m that ph was built for) takes ph's per-tet
 * data: fp->mats.td = &ph->td, and for a prestressed ph the prescribed values zeroed, as
 * kt_physics_finish leaves them. What a caller does with a physics solved once and lent to
 * several runs on the same intact mesh (augsolve_run.h, kt_aug_physics): ph is only read, and
 * must outlive fp's use. */
void kt_physics_adopt(const kt_physics *ph, const kt_mesh *m, kt_fem_problem *fp);

#endif
