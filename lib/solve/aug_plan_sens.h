/* aug_plan_sens.h: the planned method's derivatives (augsolve --uncertainty): for each
 * derivative quantity q of a kt_fem_sens and each solved step k,
 *   A_k dv/dq = T^T (df/dq) - (dA/dq)_k v,
 * with dA/dq = T^T dK_final/dq T assembled once on the final cut mesh in the plan's variables:
 * its leading principal block is step k's (as A_k is A's), so a step's matrix derivative is
 * a product with the leading block, and its solve one more forward and back substitution
 * with the plan's factor, every quantity in the same pass (kt_plan_forward_multi /
 * kt_plan_back_multi). The forward substitution of a
 * derivative starts from column 0 every step: its right-hand side holds dA v, and v changes
 * in every row from one step to the next, so there is no consumed prefix to continue; and, not
 * continued, it updates no row of an unreleased increment (kt_plan_forward_multi's upto = N),
 * so it reads none of the factor's values there. */
#ifndef KT_AUG_PLAN_SENS_H
#define KT_AUG_PLAN_SENS_H

#include "aug_plan.h"
#include "sens.h"

typedef struct kt_plan_sens {
    const kt_fem_sens *S;
    int nvar;                        /* 3 nn of the final mesh */
    int nd;                          /* S->nd: the quantities, solved together */
    cholmod_common c;
    int started;
    cholmod_sparse *P;               /* the pattern of T^T K T over every variable (lower,
                                        variable numbering, sorted rows) */
    double *dAx;                     /* nnz(P) x nd: dA/dq of quantity k at entry p of P in
                                        dAx[nd p + k] (zeros where dA/dq = 0) */
    double *dfe;                     /* ne x 3 nv x nd: each tet's release forces of dsig0/dq
                                        (NULL without prestress), interleaved as dAx */
    int *var;                        /* nfree: the variable at each free position */
    double *r, *tf, *y;              /* 3 nn (final) x nd scratch, interleaved */
    double *z;                       /* nfree x nd: L's numbering, interleaved */
    double *p1;                      /* 3 nn: one pressure load */
    double *work;                    /* F->maxrow x nd: the substitutions' */
    unsigned char *want;             /* NULL, or the supernodes the output set needs (owned) */
    double t_setup, t_steps;         /* s */
} kt_plan_sens;

/* Set up the derivatives of S for plan p (final: the final cut mesh, mats: the tangent's
 * materials) in two parts. kt_plan_sens_matrices: the pattern once, then one element pass
 * gives every dA/dq into it (kt_fem_element_multi, scattered through the variables' chains);
 * it needs no factor, and reads p, final and mats only, so it may run on a thread of its own
 * beside the factorization (solver_planned.c). kt_plan_sens_bind, once the plan is factored as
 * F: the substitutions' arrays, sized by F. */
int kt_plan_sens_matrices(kt_plan_sens *D, const kt_fem_sens *S, const kt_edits_plan *p,
                          const kt_mesh *final, const kt_materials *mats, kt_err *e);
int kt_plan_sens_bind(kt_plan_sens *D, const kt_plan_factor *F, kt_err *e);
void kt_plan_sens_free(kt_plan_sens *D);
/* The derivative fields of the step state s has just solved (kt_plan_solve, unrestricted:
 * s->v holds every variable) into du (S->nd x 3 nn of the cut mesh); with D->want valid on
 * the output set's nodes only. Every quantity at once: one product with the dA/dq, one
 * forward and one back substitution with nd right-hand sides (kt_plan_forward_multi). */
int kt_plan_sens_solve(kt_plan_sens *D, kt_plan_state *s, const kt_edits_plan *p,
                       const kt_plan_factor *F, double *du, kt_err *e);

#endif
