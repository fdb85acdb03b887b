/* fem_int.h: the element building blocks fem.c defines and the other kernels of this folder
 * share (the linear kernels of fem.c, the total Lagrangian ones of fem_nl.c): one copy of the
 * quadrature, the gradients, the strain matrix and the element terms. Not for other layers. */
#ifndef KT_FEM_INT_H
#define KT_FEM_INT_H

#include "fem.h"

/* A rule on the reference tet (0,0,0) (1,0,0) (0,1,0) (0,0,1): points (xi, eta, zeta) and
 * weights summing to its volume 1/6. */
typedef struct kt_tet_rule {
    int n;
    const double (*p)[3];
    const double *w;
} kt_tet_rule;

/* The rule the element kernels use on the element with coordinates x (3nv): P1 the centroid;
 * P2 4 points (degree 2) if straight-sided, else 14 (degree 5). */
kt_tet_rule kt_fem_rule(int order, const double *x);

/* Physical gradients g[a] (d N_a / d x at x, 3nv coordinates) at point q of rule and det J;
 * KT_ERUN for an inverted or degenerate element. */
int kt_fem_point_gradients(int nv, const double *x, const kt_tet_rule *rule, int q,
                           double (*g)[3], double *det, kt_err *e);

/* B (6 x 3nv, row-major) = d E / d u of the Green-Lagrange strain at deformation gradient F
 * (NULL: identity, the small-strain B). */
void kt_fem_strain_matrix(int nv, double (*g)[3], const double (*F)[3], double *B);

/* Ke (3nv x 3nv) += w B^T C B. */
void kt_fem_add_btcb(int nv, const double *B, const double *C, double w, double *Ke);

/* Ke(3a+i, 3b+i) += w g_a . S g_b: the stress (geometric) stiffness of a stress S (Voigt). */
void kt_fem_add_sigma(int nv, double (*g)[3], const double *S, double w, double *Ke);

/* Follower pressure p on local face f (opposite vertex f) of a tet: X the reference coordinates
 * (they orient the face outward), x the current ones (3nv each). Ke -= sym(d f / d u) of the
 * face forces at x (Ke may be NULL); fe (may be NULL) -= the forces f_a = -p int N_a n da at x. */
void kt_fem_add_face_load(int order, const double *X, const double *x, int f, double p,
                          double *Ke, double *fe);

/* The coordinates (3nv) of tet `tet`'s nodes. */
void kt_fem_gather_x(const kt_mesh *m, int tet, double *x);

/* The element's constitutive matrix C (Voigt): td->C, or the region's isotropic material. */
int kt_fem_element_C(const kt_mesh *m, const kt_materials *mats, int tet, double C[36],
                     kt_err *e);

/* Radon's 7-point rule on the reference triangle (0,0) (1,0) (0,1), degree 5: exact for
 * N_a (x_s x x_t) on a curved 6-node triangle (degree 4) and for N_a N_b on a straight one.
 * Points (s, t); weights relative to the area 1/2 (they sum to 1). fem_load.c defines them. */
extern const double kt_fem_t7_p[7][2];
extern const double kt_fem_t7_w[7];
/* tri6 shape functions N (6) and their (s, t) derivatives dN at (s, t); edge nodes on 01 12 20
 * (gmsh). */
void kt_fem_tri6_shape(double s, double t, double *N, double (*dN)[2]);

#endif
