/* fem.h: isotropic linear elasticity on 4- and 10-node tetrahedra, assembled for CHOLMOD. */
#ifndef KT_FEM_H
#define KT_FEM_H

#include <cholmod.h>

#include "mesh.h"

/* Units throughout: mm, MPa (N/mm^2), N. */
typedef struct kt_material {
    double E;   /* Young's modulus, MPa */
    double nu;  /* Poisson ratio */
} kt_material;

/* Materials by region tag: region tag t uses mat[t]; nmat > every tag in the mesh. */
typedef struct kt_materials {
    int nmat;
    kt_material *mat;
} kt_materials;

/* DOF numbering everywhere: DOF 3*node + c (c = x, y, z), so the node order is the DOF order. */

/* Element stiffness, row-major (3nv x 3nv), nv = kt_tet_nv(order), x = 3nv coordinates.
 * Fails (KT_ERUN) when the Jacobian is not positive at a quadrature point. */
int kt_fem_tet_stiffness(int order, const double *x, kt_material mat, double *Ke, kt_err *e);

/* Global stiffness of the whole mesh (3*nn DOFs), symmetric, lower triangle stored (stype -1).
 * DOFs marked in fixed (may be NULL) get identity rows and columns: the matrix a Dirichlet
 * problem factors, with values lifted into the right-hand side by kt_fem_lift. */
cholmod_sparse *kt_fem_assemble(const kt_mesh *m, const kt_materials *mats,
                                const unsigned char *fixed, cholmod_common *c, kt_err *e);

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

#endif
