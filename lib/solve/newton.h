/* newton.h: the geometrically nonlinear reference: Newton's method on the total Lagrangian
 * problem of lib/fem (kt_fem_nl_*), with load increments, a backtracking line search and a
 * fresh CHOLMOD factorization of the tangent at every iteration. */
#ifndef KT_NEWTON_H
#define KT_NEWTON_H

#include <stdio.h>

#include "bind.h"
#include "edits.h"
#include "fem.h"

typedef struct kt_newton_opts {
    int increments; /* equal load increments to start with (>= 1) */
    int max_iter;   /* Newton iterations in one increment before it is cut */
    int max_cuts;   /* increment halvings allowed over the whole path */
    double rtol;    /* converged when ||R_free|| <= rtol * the size of the terms R sums (the
                     * norm of sum_e |f_e| + |lambda fdead| + |(1 - lambda) r0|, f_e the
                     * elements' forces, fixed DOFs included): R's rounding floor is a small
                     * multiple of eps times that */
    FILE *log;      /* one line per iteration and per cut, or NULL */
    int linear;     /* 1: one increment, one full step from u = 0 and return: the linear answer
                     * about the start, K_T(0) u = -R(0, 1) (what the constant-tangent methods
                     * solve); for comparisons with the same assembly */
} kt_newton_opts;

/* 10 increments, 25 iterations, 12 cuts, rtol 1e-12, no log, not linear. */
void kt_newton_defaults(kt_newton_opts *o);

/* The load path, lambda from 0 to 1:
 *   R(u, lambda) = r(u; ps) - lambda fdead - (1 - lambda) r0,   u = lambda g on fixed DOFs,
 * r = kt_fem_nl_residual (internal forces minus follower pressures scaled by ps), ps = lambda
 * when pressure_ramp, else 1. r0 (NULL: zero) is the residual the path starts from: with
 * r0 = r(0; 1) and g = 0, u = 0 solves lambda = 0 and lambda = 1 releases what r0 holds (a cut
 * in a prestressed body: the tractions its faces lose). */
typedef struct kt_newton_problem {
    const kt_mesh *m;
    const kt_materials *mats;
    const unsigned char *fixed; /* 3*nn, or NULL */
    const double *g;            /* 3*nn prescribed displacements at lambda = 1, or NULL (zero) */
    const double *fdead;        /* 3*nn dead loads at lambda = 1, or NULL */
    int pressure_ramp;
    const double *r0;           /* 3*nn, or NULL */
} kt_newton_problem;

#define KT_NEWTON_HIST 64
typedef struct kt_newton_stats {
    int increments;  /* accepted increments */
    int iterations;  /* Newton iterations (= factorizations) in all */
    int cuts;        /* halved increments: failed Cholesky, line search or iteration limit */
    int nres;        /* relative residuals of the last increment, res[0] at its start */
    double res[KT_NEWTON_HIST];
    double t;        /* seconds */
    double lambda;   /* the last load level reached (1 on success) */
    char cause[300]; /* why the last increment was cut ("" if none was) */
} kt_newton_stats;

/* u (3*nn, overwritten; its input is ignored) := the equilibrium at lambda = 1 reached along the
 * path above from u = 0. Each increment iterates K du = -R_free (K the symmetric tangent of
 * kt_fem_nl_assemble, fixed DOFs held) with a step du * alpha, alpha halved from 1 until
 * ||R_free|| decreases (Armijo, at most 12 halvings). A tangent that is not positive definite,
 * a failed line search or max_iter iterations restore the increment's start and halve it
 * (logged); past max_cuts that is KT_ERUN naming lambda and the cause. st may be NULL. */
int kt_newton_solve(const kt_newton_problem *p, const kt_newton_opts *o, double *u,
                    kt_newton_stats *st, kt_err *e);

/* The nonlinear reference on a plan's edits (augsolve --method newton). m: the intact mesh on
 * entry, the cut mesh on return (steps[0..nsteps) applied: dups, fixes, forces). fp: the
 * problem bound on the intact mesh (kt_physics_problem: materials with their per-tet data,
 * Dirichlet DOFs and values, pressures, fixation surfaces); a node a dup creates on a fixation
 * surface is fixed like the surface. With a prestress (fp->mats.td->sig) the path starts from
 * the mesh as the pressurized state (u = 0, in equilibrium before the cut) and releases the
 * cut in load increments: r0 = r(0; 1) on the cut mesh, pressures (td->pface) at full value
 * throughout, the edits' forces and fixes growing with lambda. Without one, the pressures (as
 * follower loads), forces and prescribed values grow together from the stress-free mesh.
 * *u := the 3 * m->nn displacements (allocated; the caller frees it). */
int kt_newton_plan(kt_mesh *m, const kt_fem_problem *fp, const kt_step *steps, int nsteps,
                   const kt_newton_opts *o, double **u, kt_newton_stats *st, kt_err *e);

#endif
