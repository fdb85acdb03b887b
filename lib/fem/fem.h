/* fem.h: linear elasticity on 4- and 10-node tetrahedra, assembled for CHOLMOD: isotropic or
 * fibre-reinforced lamellar material, and the tangent stiffness of a prestressed body under a
 * follower pressure (stress stiffness, load stiffness, release of prestress across cuts). */
#ifndef KT_FEM_H
#define KT_FEM_H

#include <cholmod.h>

#include "mesh.h"

/* Units throughout: mm, MPa (N/mm^2), N. */
typedef struct kt_material {
    double E;   /* Young's modulus, MPa */
    double nu;  /* Poisson ratio */
} kt_material;

/* A lamellar (fibre-reinforced) material; its per-tet matrices go into kt_fem_tetdata.C. */
typedef struct kt_fibre_material {
    double E1, E2; /* in-plane tensile moduli along the fibre directions a1, a2, MPa */
    double Gt;     /* transverse (interlamellar) shear modulus, MPa */
    double nu;     /* Poisson ratio of the lamellar matrix (sets lambda) */
} kt_fibre_material;

/* Per-tet data beyond the region material, indexed by tet number (cuts keep tet numbers, so it
 * travels with a tet that moves to a child node). Every array may be NULL.
 *   C     ne x 36: constitutive matrix in global axes (Voigt 11 22 33 23 13 12, engineering
 *         shear strains); replaces the region's isotropic E, nu.
 *   sig   ne x KT_FEM_NQ x 6: prestress (MPa, Voigt) at the element's quadrature points. It adds
 *         the stress (geometric) stiffness K_sigma, and its internal forces -int B^T sig are
 *         part of the loads (kt_fem_release_loads): on an intact body in equilibrium with its
 *         loads they cancel those loads; on a cut one they release the traction of the cut faces.
 *   pface ne x 4: follower pressure (MPa) on local face f (the face opposite vertex f), pushing
 *         into the solid; adds -sym(K_p), K_p = d f_pressure / d u. */
#define KT_FEM_NQ 14
typedef struct kt_fem_tetdata {
    int ne;
    double *C, *sig, *pface;
} kt_fem_tetdata;

/* Materials by region tag: region tag t uses mat[t]; nmat > every tag in the mesh. td (may be
 * NULL) adds per-tet data; the caller owns it. wound (may be NULL; wound.h) bridges the cut
 * face pairs of a healed wound: kt_fem_assemble, kt_fem_nl_assemble and kt_fem_nl_residual of
 * a cut mesh include it (the element kernels do not); the caller owns it. */
struct kt_wound;
typedef struct kt_materials {
    int nmat;
    kt_material *mat;
    const kt_fem_tetdata *td;
    const struct kt_wound *wound;
} kt_materials;

/* Constitutive matrix (Voigt, global axes) of the lamellar material: an isotropic matrix
 * (lambda, mu) whose shear in the planes containing the normal n is Gt instead of mu (nearly
 * incompressible transverse isotropy, NITI), plus fibre terms E_f a (x) a (x) a (x) a: with
 * Em = min(E1, E2), mu = Em / (2 (1 + nu)), lambda = 2 mu nu / (1 - 2 nu), a fibre term
 * E1 - Em along a1 or E2 - Em along a2, and Ec along the unit in-plane vector c (the limbal
 * circumferential fibres). With Ec = 0, uniaxial stress along the stiffer of a1, a2 has modulus
 * E_t = max(E1, E2) exactly, along the softer E_s E_t / (E_t - nu^2 (E_t - E_s)) (the stiffer
 * fibres restrain its lateral contraction; E_s only when E1 = E2); with E1 = E2 = E, along an
 * in-plane c it has E + Ec exactly (keratome-scene(5), MATERIALS; tests/fem/test_fem_tangent.c).
 * Shear on the planes containing n has modulus Gt, in-plane shear mu. a1, a2, n orthonormal. */
void kt_fem_fibre_matrix(const kt_fibre_material *mat, const double a1[3], const double a2[3],
                         const double n[3], const double c[3], double Ec, double C[36]);

/* Isotropic constitutive matrix (Voigt) of E, nu. */
void kt_fem_iso_matrix(double E, double nu, double C[36]);

/* DOF numbering everywhere: DOF 3*node + c (c = x, y, z), so the node order is the DOF order. */

/* Element stiffness, row-major (3nv x 3nv), nv = kt_tet_nv(order), x = 3nv coordinates.
 * Fails (KT_ERUN) when the Jacobian is not positive at a quadrature point. */
int kt_fem_tet_stiffness(int order, const double *x, kt_material mat, double *Ke, kt_err *e);

/* Element (tangent) stiffness of tet `tet` of m, row-major 3nv x 3nv: material stiffness with
 * the region's material or td->C, plus the stress stiffness of td->sig, minus the symmetric part
 * of the load stiffness of td->pface. */
int kt_fem_element(const kt_mesh *m, const kt_materials *mats, int tet, double *Ke, kt_err *e);

/* kt_fem_element and kt_fem_element_release of tet `tet` under nd sets of per-tet data at once
 * (td[k] in place of mats->td; the region materials where td[k]->C is NULL): Ke + k (3nv)^2
 * and fe + k 3nv (each may be NULL), the quadrature points' gradients and strain matrices
 * computed once for all of them. */
#define KT_FEM_MULTI_MAX 8 /* data sets kt_fem_element_multi takes at once */
int kt_fem_element_multi(const kt_mesh *m, const kt_materials *mats,
                         const kt_fem_tetdata *const *td, int nd, int tet, double *Ke,
                         double *fe, kt_err *e);

/* Prestress internal forces of tet `tet`: fe (3nv) = -int B^T sig (zero without td->sig). */
int kt_fem_element_release(const kt_mesh *m, const kt_materials *mats, int tet, double *fe,
                           kt_err *e);

/* f (3*nn) += the prestress internal forces of every tet (nothing without td->sig). */
int kt_fem_release_loads(const kt_mesh *m, const kt_materials *mats, double *f, kt_err *e);

/* Stress C eps(u) at the quadrature points of every tet, into sig (ne x KT_FEM_NQ x 6), with
 * the material stiffness of mats (region material or td->C). */
int kt_fem_stress(const kt_mesh *m, const kt_materials *mats, const double *u, double *sig,
                  kt_err *e);

/* mean (6, Voigt 11 22 33 23 13 12, MPa) := the volume average of tet `tet`'s prestress
 * td->sig: its quadrature-point values weighted by the element rule's weights times det J (the
 * rule and points the stiffness uses); zero without td->sig. */
int kt_fem_prestress_mean(const kt_mesh *m, const kt_materials *mats, int tet, double mean[6],
                          kt_err *e);

/* pface (ne x 4) += p on the local face of the tet each triangle of surface surf_tag bounds. */
int kt_fem_pressure_faces(const kt_mesh *m, int surf_tag, double p, double *pface, kt_err *e);

/* Load stiffness of a follower pressure p on one face: Kf (3fv x 3fv, row-major, fv = 3 or 6)
 * = d f / d u, f_a = -p int N_a n dA; xf = the face's nodes (gmsh tri order), oriented so that
 * (x1 - x0) x (x2 - x0) points out of the solid. Not symmetric in general: its assembly over a
 * closed surface (or one whose boundary nodes are fixed) is, on the free DOFs. */
void kt_fem_face_load_stiffness(int order, const double *xf, double p, double *Kf);

/* Global stiffness of the whole mesh (3*nn DOFs), symmetric, lower triangle stored (stype -1):
 * the elements and, with mats->wound, the bridge of the mesh's cut face pairs (wound.h).
 * DOFs marked in fixed (may be NULL) get identity rows and columns: the matrix a Dirichlet
 * problem factors, with values lifted into the right-hand side by kt_fem_lift. */
cholmod_sparse *kt_fem_assemble(const kt_mesh *m, const kt_materials *mats,
                                const unsigned char *fixed, cholmod_common *c, kt_err *e);

/* The pattern of kt_fem_assemble's matrix without fixed DOFs (CHOLMOD_PATTERN, lower, sorted
 * rows, whole 3 x 3 node blocks): every entry an element of m couples, and with wound (may be
 * NULL) every node pair a cut face pair couples; no values. */
cholmod_sparse *kt_fem_pattern(const kt_mesh *m, const struct kt_wound *wound, cholmod_common *c,
                               kt_err *e);

/* Consistent nodal forces of a pressure p (MPa) on the boundary surface with tag surf_tag,
 * pushing into the solid (traction -p n, n the solid's outward normal); added to f (3*nn).
 * A triangle that is not a face of exactly one tet is an error. */
int kt_fem_pressure(const kt_mesh *m, int surf_tag, double p, double *f, kt_err *e);

/* Lift Dirichlet values: f := f - K(:,D) g on free rows, f := g on fixed rows. K is the
 * unconstrained stiffness (no identity rows) as returned with fixed == NULL. */
int kt_fem_lift(const cholmod_sparse *K, const unsigned char *fixed, const double *g, double *f,
                kt_err *e);

/* Solve the Dirichlet problem directly with CHOLMOD: u (3*nn) from f and the fixed values g.
 * Reports a factor that is not positive definite (naming the node) and a relative residual
 * above 1e-10 as KT_ERUN. */
int kt_fem_solve(const kt_mesh *m, const kt_materials *mats, const unsigned char *fixed,
                 const double *g, const double *f, double *u, cholmod_common *c, kt_err *e);
/* kt_fem_solve, and *perm := a copy of the fill-reducing order its factorization used (3*nn
 * DOFs, L->Perm; caller frees), for a later factorization of a matrix of the same pattern
 * (augsolve's planned method reuses the prestress solve's: kt_aug_problem.perm). */
int kt_fem_solve_order(const kt_mesh *m, const kt_materials *mats, const unsigned char *fixed,
                       const double *g, const double *f, double *u, int **perm,
                       cholmod_common *c, kt_err *e);

/* kt_fem_solve, then nmore solves with the same factorization, in one substitution: more(ctx,
 * u, B) fills B (nmore x 3nn, column k at B + k 3nn, zeroed on entry) from the first solution u,
 * and umore + k 3nn gets the solution of K x = column k with zero values on the fixed DOFs
 * (fixed rows of B are zeroed), each checked like the first; perm (NULL: not wanted) as in
 * kt_fem_solve_order. The prestress's derivatives use it (lib/fem/sens.h). */
typedef int (*kt_fem_more_rhs)(void *ctx, const double *u, double *B, kt_err *e);
int kt_fem_solve_more(const kt_mesh *m, const kt_materials *mats, const unsigned char *fixed,
                      const double *g, const double *f, double *u, int nmore,
                      kt_fem_more_rhs more, void *ctx, double *umore, int **perm,
                      cholmod_common *c, kt_err *e);

/* ------------------------------------------------ total Lagrangian (nonlinear) kernels
 * The same element data read as a geometrically nonlinear problem: displacement u (3*nn) from the
 * mesh's coordinates X (the reference); F = I + du/dX, the Green-Lagrange strain
 * E = (F^T F - I) / 2 and the second Piola-Kirchhoff stress S = sig + C : E (St Venant-Kirchhoff
 * with the element's C, in whatever frame C was built in: the lamellar one for fibre tets; sig
 * = td->sig, the prestress, read as the initial S of the reference); follower pressures
 * pscale * td->pface on the faces in their current position. At u = 0 and pscale = 1 the tangent
 * is kt_fem_element's and the residual is -(kt_fem_element_release) - the pressure forces. */

/* Element residual fe (3nv) = int B(F)^T S dV - f_pressure(X + u) (no dead loads), and the
 * tangent Ke (3nv x 3nv, row-major, may be NULL) = int B^T C B dV + int g_a . S g_b dV (the
 * geometric stiffness) - sym(d f_pressure / d u). */
int kt_fem_nl_element(const kt_mesh *m, const kt_materials *mats, int tet, const double *u,
                      double pscale, double *fe, double *Ke, kt_err *e);

/* r (3*nn, overwritten) := the sum of the elements' fe at u; rabs (may be NULL; 3*nn,
 * overwritten) := the sum of their absolute values, the scale of r's rounding error. */
int kt_fem_nl_residual(const kt_mesh *m, const kt_materials *mats, const double *u,
                       double pscale, double *r, double *rabs, kt_err *e);

/* The tangent at u, assembled and constrained as kt_fem_assemble does, and r (3*nn,
 * overwritten) := the residual at u as kt_fem_nl_residual. */
cholmod_sparse *kt_fem_nl_assemble(const kt_mesh *m, const kt_materials *mats, const double *u,
                                   double pscale, const unsigned char *fixed, double *r,
                                   cholmod_common *c, kt_err *e);

/* KT_EINPUT unless E > 0 (finite) and -1 < nu < 0.5. */
int kt_fem_check_material(kt_material mat, kt_err *e);

/* Identity rows and columns on the fixed DOFs of an assembled stiffness (lower triangle). */
void kt_fem_apply_fixed(cholmod_sparse *A, const unsigned char *fixed);

#endif
