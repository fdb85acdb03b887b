/* solver.h: one front door for every method. A run solves a complete, checked edits stream
 * (a plan: aug_plan.h) as steps 0..nsteps with one of several backends behind one interface
 * (set up and solve step 0, apply and solve the next step, a fresh reference, free: the way
 * Redis's ae.c puts epoll and kqueue behind aeApi*). The planned method is a backend
 * (solver_planned.c), and so are the stream methods, augmented, refactor, cg and pcg-jacobi
 * (solver_stream.c, over kt_aug), and so is the nonlinear reference, newton (solver_newton.c,
 * over kt_newton_plan). The front door ends every backend's step in one place:
 *   output restriction: --output SET means the nodes of the surface or region SET of the
 *     current cut mesh (kt_mesh_group_nodes); the field holds NaN at every other node and the
 *     step has no reactions, whatever the method (a backend may compute less: the planned one
 *     limits its back substitution to the set);
 *   verification (--verify): the step against a fresh METIS factorization of the current cut
 *     mesh, max |u - u_fresh| / max |u_fresh| over the set's DOFs (all without --output);
 *   the step's row of steps.tsv (kt_aug_row).
 * A new method is one more kt_solver_backend (as the nonlinear reference is): it gets the
 * problem, the plan and each step's edits, and gives the step's displacement on the current
 * mesh. */
#ifndef KT_SOLVER_H
#define KT_SOLVER_H

#include "aug_plan.h"
#include "sens.h"

/* A step that is not written (augsolve --steps): a backend may skip its solve; CARRY: a later
 * step is solved and the backend keeps what it needs (the planned method continues its
 * forward substitution); SKIP: no later step is solved. */
enum { KT_SOLVER_SOLVE = 0, KT_SOLVER_CARRY, KT_SOLVER_SKIP };

/* What a backend gets at set-up. */
typedef struct kt_solver_in {
    const kt_aug_problem *prob;      /* the intact problem */
    const kt_edits_plan *plan;       /* the whole stream, read and checked (kt_edits_plan_check) */
    const kt_mesh *final;            /* the final cut mesh (valid during create only) */
    const unsigned char *out_final;  /* NULL, or the output set's nodes on the final mesh */
    const kt_aug_opts *o;
    double plan_max_ratio;           /* planned: kt_plan_factor_build's max_ratio */
    const kt_fem_sens *sens;         /* NULL, or the derivatives every solved step gives */
} kt_solver_in;

/* A step's field as a backend leaves it: on the current cut mesh, valid until its next step. */
typedef struct kt_solver_view {
    const kt_mesh *mesh;
    const double *u;                 /* 3 nn, mm (valid at least on the output set) */
    const int *origin;               /* nn: the input node each node descends from */
    kt_aug_row row;
} kt_solver_view;

typedef struct kt_solver_backend {
    const char *name;
    /* Set up and solve step 0. A method that does not apply to this plan returns KT_OK with
     * *st NULL and the reason in why (n bytes): the front door falls back. */
    int (*create)(void **st, const kt_solver_in *in, char *why, size_t n, kt_err *e);
    /* Apply step s (the next one) and, by mode (KT_SOLVER_*), solve it. */
    int (*step)(void *st, const kt_step *s, int mode, kt_err *e);
    void (*view)(void *st, kt_solver_view *v);
    /* K u - f at constrained DOFs (3 nn, valid until the next step), NULL: not computed. */
    const double *(*reaction)(void *st, kt_err *e);
    /* The current step solved from scratch (assembly, METIS, factorization: what a user would
     * run instead) into u (3 nn); *t the seconds it took. */
    int (*fresh)(void *st, double *u, double *t, kt_err *e);
    void (*free)(void *st);
    /* The derivatives of the last solved step's field (augsolve --uncertainty): du (in->sens->nd
     * x 3 nn) := du/dq of each derivative quantity (sens.h), valid at least on the output set.
     * NULL: the front door computes them from scratch (kt_fem_sens_fresh) on the backend's
     * cut mesh and field, which then must be valid everywhere (the stream methods). */
    int (*dudp)(void *st, double *du, kt_err *e);
    int no_dudp;                     /* 1: the method gives no derivatives (newton) */
} kt_solver_backend;

extern const kt_solver_backend kt_solver_planned, kt_solver_stream, kt_solver_newton;

typedef struct kt_solver_opts {
    kt_aug_opts aug;                 /* method, ordering, factor, tol, verify, output, quiet */
    double plan_max_ratio;
    const unsigned char *want;       /* nsteps+1: the steps to solve (NULL: all) */
    const kt_fem_sens *sens;         /* NULL, or the quantities whose derivatives every solved
                                        step gives (augsolve --uncertainty); a method that
                                        gives none (newton) is KT_EINPUT */
} kt_solver_opts;

typedef struct kt_solver kt_solver;

/* Set up the method on the problem and the plan (final: kt_edits_plan_check's final mesh) and solve
 * step 0. When the planned method does not apply, the run falls back (to augmented when the
 * plan breaks its form, to refactor with METIS when its factor is too large) and
 * kt_solver_fallback says why. An --output set the mesh lacks is KT_EINPUT. */
int kt_solver_create(kt_solver **out, const kt_aug_problem *prob, const kt_edits_plan *plan,
                     const kt_mesh *final, const kt_solver_opts *o, kt_err *e);
/* Apply the next step; *solved = 1 when it is solved (wanted), its field and row then ready. */
int kt_solver_step(kt_solver *sv, int *solved, kt_err *e);
void kt_solver_free(kt_solver *sv);

int kt_solver_at(const kt_solver *sv);                 /* the current step */
int kt_solver_method(const kt_solver *sv);             /* KT_AUG_* that runs */
const kt_aug_opts *kt_solver_opts_used(const kt_solver *sv); /* after a fallback */
const char *kt_solver_fallback(const kt_solver *sv);   /* NULL, or why the planned method fell back */
const kt_mesh *kt_solver_mesh(const kt_solver *sv);
const double *kt_solver_u(const kt_solver *sv);        /* 3 nn: NaN off the output set */
const int *kt_solver_origin(const kt_solver *sv);
const kt_aug_row *kt_solver_row(const kt_solver *sv);
/* The last solved step's derivative du/dq of derivative quantity k (0 .. sens->nd - 1), mm per
 * unit of q (3 nn, NaN off the output set like the field); NULL without sens. */
const double *kt_solver_dudp(const kt_solver *sv, int k);
/* Seconds the derivatives took so far (set-up included). */
double kt_solver_t_sens(const kt_solver *sv);
/* Reactions (3 nn), NULL with an --output set or when the backend has none. */
const double *kt_solver_reaction(kt_solver *sv, kt_err *e);

#endif
