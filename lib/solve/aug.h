/* aug.h: solving a mesh that is cut and constrained step by step, as the edits stream arrives:
 * the augmented-matrix method of Yeung, Crouch and Pothen (paper 000) on the append-only form,
 * with the baselines it is measured against.
 *
 * Formulation. A node created by a dup is written as an increment over the node it was split
 * from (u_child = u_parent + d; chains for nodes split twice). In these variables the block of
 * the intact DOFs is exactly the intact stiffness K at every step (d = 0 glues each child back
 * to its parent), and a step only appends: the increments' columns [C; D] (from the element
 * stiffness of the tets around each new node) and, for each DOF constrained after step 0, a
 * Lagrange multiplier (a bordered row). K (its free DOFs) is factored once, L L^T, in the run's
 * ordering; the Schur complement S = D - W^T W, W = L^-1 P C, is dense and its factor
 * Ls Ds Ls^T grows by the appended rows (no pivoting: positive on the increments, negative on
 * the multipliers, which come after every variable their rows hold). A step is
 *   y = L^-1 P b_K,  d = S^-1 (b_R - W^T y),  x_K = P^T L^-T (y - W d),  u = T v,
 * with b from the fem layer on the current mesh (pressures, the prestress's released loads,
 * forces, the lifting of prescribed values), the backward error checked and one step of
 * iterative refinement where it exceeds --tol. See aug_impl.h for the state. */
#ifndef KT_AUG_H
#define KT_AUG_H

#include "edits.h"
#include "bind.h"
#include "mesh.h"

/* KT_AUG_PLANNED (augsolve's default, aug_plan.h) needs the whole stream first: it runs behind
 * the front door only (solver.h), as every method does in augsolve. kt_aug_create solves a
 * stream step by step with the other methods. */
enum { KT_AUG_AUGMENTED = 1, KT_AUG_REFACTOR, KT_AUG_CG, KT_AUG_PCG_JACOBI, KT_AUG_PLANNED,
       KT_AUG_NEWTON /* the nonlinear reference (newton.h), behind the front door only */ };
/* KT_AUG_ORDER_DEFAULT (augsolve): metis for the planned and augmented methods, natural (the
 * mesh's order) for the baselines; kt_aug_opts_default itself gives natural */
enum { KT_AUG_ORDER_DEFAULT = -1, KT_AUG_ORDER_NATURAL = 0, KT_AUG_ORDER_AMD, KT_AUG_ORDER_METIS };
enum { KT_AUG_FACTOR_SUPERNODAL = 0, KT_AUG_FACTOR_SIMPLICIAL };

typedef struct kt_aug_opts {
    int method;        /* KT_AUG_* */
    int ordering;      /* KT_AUG_ORDER_* for the factor (augmented: of the intact K; refactor) */
    int factor;        /* KT_AUG_FACTOR_*: CHOLMOD supernodal LL^T or simplicial LDL^T
                        * (refactor, planned; the augmented method's factor is supernodal) */
    double tol;        /* augmented, planned: largest backward error of the system solved,
                        * ||r|| / (|| |A||x| || + ||b||); CG: relative residual
                        * ||(K u - f)_free|| / ||f_free|| */
    int maxit;         /* CG iteration cap; 0: 20000 */
    int plan_panel;    /* planned: columns of the panels the increments' block is stored in
                        * (KT_AUG_PLAN_PANEL; 0: CHOLMOD's own supernodes) */
    /* the front door's (solver.h), for every method; kt_aug itself reads none of them: */
    int verify;        /* also factor the current K from scratch each step and compare */
    double verify_tol; /* exit 1 beyond this relative difference */
    char output[KT_NAME_MAX]; /* "" for every node, else a surface or region: u only on its
                               * nodes */
    int quiet;
} kt_aug_opts;

/* Default of kt_aug_opts.plan_panel (aug_plan_factor.c, split_panels): the stored lower
 * triangle of the increments' block wastes at most half a panel a column, CHOLMOD's update
 * workspace holds a panel's width times the rows below it, and the BLAS 3 updates between
 * panels stay efficient from a few hundred columns on. */
#define KT_AUG_PLAN_PANEL 256

/* tol 1e-10, natural ordering, supernodal, verify-tol 1e-8, panels KT_AUG_PLAN_PANEL. */
void kt_aug_opts_default(kt_aug_opts *o);

/* Option words of the tool; 0 on success, -1 for a word not in the list. */
int kt_aug_parse_method(const char *s, int *method);
int kt_aug_parse_ordering(const char *s, int *ordering);
int kt_aug_parse_factor(const char *s, int *factor);
const char *kt_aug_method_name(int method);

/* Pressures and fixation surfaces by tag, as the scene binding gives them (bind.h). */
typedef kt_fem_load_surf kt_aug_pressure;
typedef kt_fem_fix_surf kt_aug_fixsurf;

/* What the scene provides. Everything is copied by kt_aug_create. */
typedef struct kt_aug_problem {
    const kt_mesh *mesh;           /* the intact mesh */
    const kt_materials *mats;
    const unsigned char *fixed;    /* 3*nn: Dirichlet DOFs of the intact scene */
    const double *g;               /* 3*nn: their values, mm (NULL: zero) */
    int npress;
    const kt_aug_pressure *press;
    int nfix;
    const kt_aug_fixsurf *fix;
    const int *perm;               /* NULL, or a fill-reducing order of the intact stiffness's
                                      3*nn DOFs already made (the prestress solve's,
                                      kt_physics.perm): the planned method orders its intact
                                      block by it instead of a METIS run of its own */
} kt_aug_problem;

/* The problem of mesh m bound as fp (kt_fem_bind or kt_physics_problem): pointers into both. */
kt_aug_problem kt_aug_problem_of(const kt_mesh *m, const kt_fem_problem *fp);

/* One row of steps.tsv; times in ms, NaN where not measured. Augmented: m appended variables
 * (increments and multipliers), iters the steps of iterative refinement (0 or 1),
 * closure_max the largest closure (columns of L) of a column appended by this step,
 * t_update the edits, t_step1 appending (W columns, Schur rows and their factor), t_step2 the
 * loads, right-hand side and substitutions, t_step3 the backward error, refinement and
 * field; planned: see aug_plan.h. */
typedef struct kt_aug_row {
    int step, n_dofs, m, new_dofs, iters, closure_max;
    double t_update, t_step1, t_step2, t_step3, t_total;
    double rel_residual;      /* ||r|| / ||b|| of the system solved (baselines: its free rows) */
    double verify_rel_diff;   /* max |u - u_fresh| / max |u_fresh| over the output nodes */
    double nnz_L;             /* nonzeros of the factor used: refactor its L; augmented
                               * L + W + the dense triangle of S; planned its L */
    double t_verify;          /* ms of the --verify fresh solve (assembly, METIS analysis,
                               * factor, solve), NaN without */
} kt_aug_row;

typedef struct kt_aug kt_aug;

/* Set up (factor the intact K for the augmented method) and solve step 0, the intact scene. */
int kt_aug_create(kt_aug **out, const kt_aug_problem *p, const kt_aug_opts *o, kt_err *e);
/* Apply one step of edits and solve. Bad edits are KT_EINPUT, numerical failure KT_ERUN
 * (a backward error above tol after refinement, a CG that misses its tolerance, a factor
 * that is not positive definite or quasi-definite). */
int kt_aug_step(kt_aug *a, const kt_step *s, kt_err *e);
void kt_aug_free(kt_aug *a);
/* The current step solved from scratch (assembly, METIS, factorization, solve: what a user
 * would run instead) into u (3 nn); *t gets the seconds it took. The --verify reference. */
int kt_aug_fresh(kt_aug *a, double *u, double *t, kt_err *e);

const kt_aug_row *kt_aug_last(const kt_aug *a);
const kt_mesh *kt_aug_mesh(const kt_aug *a);           /* the current, cut mesh */
const double *kt_aug_displacement(const kt_aug *a);    /* 3*nn, mm */
const int *kt_aug_origin(const kt_aug *a);             /* nn: input node each node comes from */
/* K u - f at every constrained DOF (the support force, N), 0 elsewhere; 3*nn values owned by
 * the solver, valid until the next step. */
const double *kt_aug_reaction(kt_aug *a, kt_err *e);
const double *kt_aug_load(const kt_aug *a);            /* 3*nn applied nodal loads, N */
/* Nonzeros of the intact factor L and the time (s) it took (augmented), 0 otherwise. */
void kt_aug_factor_info(const kt_aug *a, double *nnzL, double *seconds);

#endif
