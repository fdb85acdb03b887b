/* aug.h: the augmented-matrix method of Yeung, Crouch and Pothen (paper 000, section 3) for a
 * mesh that is cut and constrained step by step, with the baselines it is measured against.
 *
 * Formulation. R is the stiffness of the base state (step 0, or the state a re-factorization
 * started from) with its Dirichlet DOFs B as identity rows and columns, padded with identity
 * for DOFs added later; R = L D L^T (or L L^T) is factored once. Relative to R the current
 * constrained stiffness differs in the columns Lset: every DOF outside B whose stiffness column
 * changed since the base (nodes of moved tets), every new DOF, and the DOFs D newly constrained
 * since the base. J(:,k) is the current column K(:,Lset_k) with the rows of B zeroed, or
 * s_k e_j for j in D (s_k = K(j,j): a scaling that keeps the Schur complement well balanced);
 * H = rows Lset of the identity. With f^ = f - K(:,C) g off B and g on B (C = B u D):
 *   (1) rhs = H R^-1 f^   (R^-1 f^_base once per factor, then one sparse-RHS solve per step)
 *   (2) GMRES on (H R^-1 J) a2 = rhs, each product one closure-restricted solve
 *       (cholmod_solve2 with a Bset)
 *   (3) a1 = R^-1 (f^ - J a2): the precomputed R^-1 f^_base plus a sparse forward solve and a
 *       full back-substitution, or a closure-restricted one when only a node set is wanted.
 * v = a1 off Lset, v = a2 on Lset \ D, v = g on D; the reaction at j in D is -s_k a2_k. A DOF
 * added since the base is written as an increment over the DOF it was split from, u = P v, and
 * the system solved is the congruent P^T K P v = P^T f^ (see aug_lset.c for why). J columns come
 * from the element stiffness of the tets around each node (a node->tet adjacency kept up to date
 * by the cuts), never from a reassembled K. */
#ifndef KT_AUG_H
#define KT_AUG_H

#include "edits.h"
#include "bind.h"
#include "mesh.h"

/* KT_AUG_PLANNED (augsolve's default, aug_plan.h) runs in kt_aug_run only: it reads the whole
 * stream first. kt_aug_create solves a stream step by step with the other methods. */
enum { KT_AUG_AUGMENTED = 1, KT_AUG_REFACTOR, KT_AUG_CG, KT_AUG_PCG_JACOBI, KT_AUG_PLANNED };
enum { KT_AUG_PRECOND_NONE = 0, KT_AUG_PRECOND_DIAG, KT_AUG_PRECOND_SPAI, KT_AUG_PRECOND_LOCAL };
/* KT_AUG_ORDER_DEFAULT: metis for the planned method, natural for the others */
enum { KT_AUG_ORDER_DEFAULT = -1, KT_AUG_ORDER_NATURAL = 0, KT_AUG_ORDER_AMD, KT_AUG_ORDER_METIS };
enum { KT_AUG_FACTOR_SUPERNODAL = 0, KT_AUG_FACTOR_SIMPLICIAL };
enum { KT_AUG_REFACTOR_NEVER = 0, KT_AUG_REFACTOR_M_ABOVE, KT_AUG_REFACTOR_EVERY,
       KT_AUG_REFACTOR_AUTO };

typedef struct kt_aug_opts {
    int method;        /* KT_AUG_* */
    int precond;       /* KT_AUG_PRECOND_* (augmented) */
    int ordering;      /* KT_AUG_ORDER_* for the factor (augmented and refactor) */
    int factor;        /* KT_AUG_FACTOR_*: CHOLMOD supernodal LL^T or simplicial LDL^T */
    double tol;        /* GMRES: relative residual of the Schur system (H R^-1 J) a2 = rhs;
                        * CG: relative residual ||(K u - f)_free|| / ||f_free|| */
    int restart;       /* GMRES restart length */
    int maxit;         /* iteration cap; 0: 2000 for GMRES, 20000 for CG */
    int refactor;      /* KT_AUG_REFACTOR_* policy for the background re-factorization */
    int refactor_n;    /* N of m>N and every:N */
    int refactor_sync; /* join the factor thread at the next step (deterministic runs) */
    int verify;        /* also factor the current K from scratch each step and compare */
    double verify_tol; /* exit 1 beyond this relative difference */
    char output[KT_NAME_MAX]; /* "" for every node, else a surface group: u only on its nodes */
    int quiet;
} kt_aug_opts;

/* tol 1e-10, restart 200, natural ordering, supernodal, local, refactor never, verify-tol 1e-8. */
void kt_aug_opts_default(kt_aug_opts *o);

/* Option words of the tool; 0 on success, -1 for a word not in the list. */
int kt_aug_parse_method(const char *s, int *method);
int kt_aug_parse_precond(const char *s, int *precond);
int kt_aug_parse_ordering(const char *s, int *ordering);
int kt_aug_parse_factor(const char *s, int *factor);
int kt_aug_parse_refactor(const char *s, int *policy, int *n); /* never, m>N, every:N, auto */
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
} kt_aug_problem;

/* One row of steps.tsv; times in ms, NaN where not measured. */
typedef struct kt_aug_row {
    int step, n_dofs, m, new_dofs, iters, closure_max;
    double t_update, t_step1, t_step2, t_step3, t_total;
    double rel_residual;      /* ||(K u - f)_free|| / ||(f - K(:,C) g)_free|| */
    double verify_rel_diff;   /* max |u - u_fresh| / max |u_fresh| over the output nodes */
    char refactor[32];        /* "-", "start", "swap" or "swap+start" */
    double nnz_L;             /* nonzeros of the factor used (augmented, refactor), else 0 */
    double t_verify;          /* ms of the --verify fresh solve (assembly, analysis, factor,
                               * solve: CHOLMOD's defaults; METIS for planned), NaN without */
} kt_aug_row;

typedef struct kt_aug kt_aug;

/* Set up (factor K0 for the augmented method) and solve step 0, the intact scene. */
int kt_aug_create(kt_aug **out, const kt_aug_problem *p, const kt_aug_opts *o, kt_err *e);
/* Apply one step of edits and solve. Bad edits are KT_EINPUT, numerical failure KT_ERUN
 * (a GMRES or CG that misses its tolerance, a factor that is not positive definite, a
 * --verify difference above verify_tol). */
int kt_aug_step(kt_aug *a, const kt_step *s, kt_err *e);
void kt_aug_free(kt_aug *a);

const kt_aug_row *kt_aug_last(const kt_aug *a);
const kt_mesh *kt_aug_mesh(const kt_aug *a);           /* the current, cut mesh */
const double *kt_aug_displacement(const kt_aug *a);    /* 3*nn, mm; NaN off the output set */
const int *kt_aug_origin(const kt_aug *a);             /* nn: input node each node comes from */
/* K u - f at every constrained DOF (the support force, N), 0 elsewhere; 3*nn values owned by
 * the solver, valid until the next step. */
const double *kt_aug_reaction(kt_aug *a, kt_err *e);
const double *kt_aug_load(const kt_aug *a);            /* 3*nn applied nodal loads, N */
/* Nonzeros of L and the time (s) of the factor in use (augmented), 0 otherwise. */
void kt_aug_factor_info(const kt_aug *a, double *nnzL, double *seconds);

#endif
