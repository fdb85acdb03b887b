/* sens.h: the derivatives of a scene's elasticity problem with respect to its uncertain
 * quantities (keratome-scene(5), UNCERTAINTY; augsolve --uncertainty).
 *
 * A quantity q enters the prestressed tangent problem of a step, A(q) u = f(q), through the
 * constitutive matrices C (E_inplane, G_transverse, limbal_density, age_slope: C is linear in
 * each modulus at fixed nu), the pressures (iop), and the prestress sig0(q), the stress of the
 * one solve K0(C) u0 = f_p(iop) on the measured geometry, which sets the stress stiffness
 * K_sigma(sig0) and the traction a cut releases. So
 *   du/dq = A^-1 (df/dq - dA/dq u),
 *   dA/dq = K(dC/dq) + K_sigma(dsig0/dq) - sym(K_p(dpface/dq)),
 *   df/dq = pressures(dp/dq) + release(dsig0/dq),
 *   dsig0/dq = dC/dq eps(u0) + C eps(du0/dq), du0/dq = K0^-1 (df_p/dq - dK0/dq u0),
 * every term linear in its data, so one kt_fem_tetdata per quantity holds dC, dsig0 and
 * dpface, and heal = ln k (the healed wound's bridge stiffness, wound.h) adds dA/dheal = B, the
 * bridge itself, on the cut face pairs only (no load, no prestress: the intact mesh has none), and kt_fem_element / kt_fem_element_release with it give the element's dA/dq and
 * the release's derivative. du0/dq costs one more substitution with the prestress solve's own
 * factorization, every quantity at once (kt_physics_finish_sens). */
#ifndef KT_SENS_H
#define KT_SENS_H

#include "physics.h"

/* How a quantity's band is found (uncertainty.tsv's method column). */
enum { KT_SENS_NONE = 0, KT_SENS_DERIVATIVE, KT_SENS_FD };

typedef struct kt_fem_dparam {
    int q;                      /* KT_UQ_* */
    kt_fem_tetdata td;          /* owned: dC (ne x 36, zeros where q does not enter), dsig
                                   (prestressed scenes, else NULL), dpface (iop, else NULL) */
    double dpress[KT_SCENE_MAX];/* d p_k / dq, MPa per unit of q, of pressure k of the problem */
    int dK_zero;                /* dA/dq = 0 (iop on a scene without prestress) */
    double dwound;              /* dA/dq holds dwound x the wound's bridge B (wound.h): 1 for
                                   heal = ln k (dB/dln k = B), else 0 */
} kt_fem_dparam;

typedef struct kt_fem_sens {
    int method[KT_UQ_N];        /* KT_SENS_* of each quantity */
    double value[KT_UQ_N];      /* its value in this scene, in kt_uq_unit (NAN: none) */
    double sd[KT_UQ_N];
    int nd;                     /* quantities with method derivative, in KT_UQ_* order: */
    kt_fem_dparam d[KT_UQ_N];
    int npress, ptag[KT_SCENE_MAX]; /* the problem's pressure surfaces (tags) */
    int zero_at_0;              /* 1: the intact scene's field is zero for every value of every
                                   quantity, so are its derivatives (a prestressed scene, whose
                                   step 0 solves A(q) u = f_p(q) - K0(q) u0(q) = 0: the prestress
                                   u0 solves K0 u0 = f_p with these very loads, and its stress
                                   sig0 = C eps(u0) is integrated with the same rule; its
                                   prescribed values are zeroed) */
} kt_fem_sens;

/* Which quantities scene s (bound as fp) has, their values and methods (no derivative data:
 * kt_physics_finish_sens fills it). A quantity with sd 0 is none; so is one the scene lacks
 * (moduli without a fibre region, iop without a pressure, age_slope without an age). */
void kt_fem_sens_plan(const kt_scene *s, const kt_fem_problem *fp, kt_fem_sens *S);

/* kt_physics_finish with the derivative data of every quantity S plans as derivative: dC
 * from ph's frames, the prestress's derivatives from its own factorization. On failure ph
 * and S hold nothing to free. */
int kt_physics_finish_sens(const kt_scene *s, const kt_mesh *m, kt_fem_problem *fp,
                           kt_physics *ph, kt_fem_sens *S, kt_err *e);
void kt_fem_sens_free(kt_fem_sens *S);

/* The materials of derivative k: mats with td replaced by S->d[k].td and no wound (the
 * bridge's part of dA/dq is d->dwound B, added apart). */
kt_materials kt_fem_sens_mats(const kt_fem_sens *S, int k, const kt_materials *mats);

/* r (3*nn, overwritten) := df/dq of derivative k on mesh m (cut or not): pressures with
 * dpress on S's surfaces, and the prestress release of dsig0. */
int kt_fem_sens_loads(const kt_fem_sens *S, int k, const kt_mesh *m, const kt_materials *mats,
                      double *r, kt_err *e);

/* Every derivative field of a solved step from scratch: the tangent of mesh m (mats, fixed
 * DOFs with zero values) assembled and factored once, then du (S->nd x 3 nn) := A^-1 (df/dq -
 * dA/dq u) for each. What a backend without derivatives of its own gives (the stream methods),
 * and the reference the planned method's derivatives are tested against. */
int kt_fem_sens_fresh(const kt_fem_sens *S, const kt_mesh *m, const kt_materials *mats,
                      const unsigned char *fixed, const double *u, double *du, kt_err *e);

/* For physics.c: the quantities' dC (after the fibre frames, before the prestress), and the
 * prestress solve with its derivatives (u0 into u; mm the material stiffness it solves with,
 * f its loads; *perm the fill-reducing order it factored with, as kt_fem_solve_order's). */
int kt_physics_sens_tensors(const kt_scene *s, const kt_mesh *m, const kt_physics *ph,
                            kt_fem_sens *S, kt_err *e);
void kt_fem_sens_pressures(const kt_fem_problem *fp, kt_fem_sens *S);
int kt_fem_sens_prestress(kt_fem_sens *S, const kt_mesh *m, const kt_fem_problem *fp,
                          const kt_materials *mm, const double *f, double *u, int **perm,
                          cholmod_common *c, kt_err *e);

#endif
