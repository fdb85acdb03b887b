/* aug_plan.h: the planned method: every step of a complete edits stream from one factorization
 * (the augmented method in principal-submatrix form).
 *
 * Variables. A node c created by a dup of node p is written as an increment over its parent,
 * u_c = u_p + d_c (a node split twice chains: u_c2 = u_c1 + d_c2). The variables are then the
 * intact nodes' u and the new nodes' d, numbered as the final mesh's DOFs (3 node + comp), so
 * the increments come after every intact DOF in the order the plan releases them. With T the
 * map from variables to the final mesh's displacements, the energy is 1/2 v^T A v - v^T T^T f,
 * A = T^T K_final T = [K C; C^T D], and K is exactly the intact stiffness: d = 0 glues every
 * child to its parent. Step k's system is the leading principal block A_k of A (the increments
 * released by step k); unreleased increments are zero. This holds because a dup moves tets from
 * a node to its new child only (cut/apply.c checks that every moved tet holds the node), so a tet's
 * node at step k is the nearest released ancestor of its final node.
 *
 * One factorization. P = [a fill-reducing order of K's free DOFs, then the free increments in
 * release order]; L L^T = P A_FF P^T. Then chol(A_k) is the leading block of L, and a step is
 * exact with the whole factor: forward-solve L on P [b_k; 0], zero the entries of the
 * unreleased increments, back-solve L^T: the leading part is A_k^-1 b_k, the rest 0.
 *
 * Where the form does not hold (a fix edit in the stream changes K's block; a node created on
 * a fixation surface whose parent is free there couples u_p + d_c = g) the plan says why and
 * the caller falls back to the iterative method. */
#ifndef KT_AUG_PLAN_H
#define KT_AUG_PLAN_H

#include "aug.h"

/* The plan: the whole stream and what it implies for the variables. Owner: kt_edits_plan_read /
 * kt_edits_plan_free. */
typedef struct kt_edits_plan {
    int nsteps, cap;
    kt_step *step;              /* steps 1..nsteps at step[0..nsteps) */
    int nn0, nn;                /* intact and final node counts */
    int *nn_at;                 /* nsteps+1: node count after step k (nn_at[0] = nn0) */
    int *parent;                /* nn: the node a node was split from, -1 for intact nodes */
    unsigned char *fixed;       /* 3 nn: constrained variables */
    double *gv;                 /* 3 nn: their values (an increment's: g_child - g_parent) */
    double *g;                  /* 3 nn: the prescribed displacement of each constrained DOF */
    int usable;                 /* 1: the principal-submatrix form holds */
    char why[512];              /* else: where and why it does not */
} kt_edits_plan;

/* Read the rest of the stream (every step to the end) into p. Bad input is KT_EINPUT. */
int kt_edits_plan_read(kt_edits_plan *p, kt_edits_reader *r, kt_err *e);
/* The in-memory entry (a caller that makes the steps itself, kt_incise_next, instead of reading
 * a stream): append step s as the plan's next step; its edits move into p and s is left empty
 * (kt_step_free of it is harmless). kt_edits_plan_check validates the whole plan afterwards, as
 * for a stream read. */
int kt_edits_plan_add(kt_edits_plan *p, kt_step *s, kt_err *e);
/* Validate every step against the intact mesh before anything is factored (a bad tet is
 * KT_EINPUT "stream:line:col: ..."), and set parents, constrained variables and p->usable.
 * The final cut mesh is written to final (caller frees). */
int kt_edits_plan_check(kt_edits_plan *p, const char *stream, const kt_aug_problem *prob,
                        kt_mesh *final, kt_err *e);
void kt_edits_plan_free(kt_edits_plan *p);
/* Every prescribed value zero (g and gv): the plan of a problem whose values kt_physics_finish
 * zeroed after kt_edits_plan_check read them (a prestressed scene's steps are increments from the
 * loaded state). */
void kt_edits_plan_zero_values(kt_edits_plan *p);

/* The factor of the final augmented matrix and the variables' positions in it: the symbolic
 * and numeric work of one plan, immutable once built (a step's substitutions keep their state
 * in kt_plan_state). Owner: kt_plan_factor_build / kt_plan_factor_free (nothing else writes). */
typedef struct kt_plan_factor {
    cholmod_common c;
    int started;
    int nvar;                   /* 3 nn (final) */
    int nfree, nK;              /* free variables; the first nK are intact DOFs */
    int *pos;                   /* nvar: position among the free variables, -1: constrained */
    int *nfree_at;              /* nsteps+1: free variables present after step k */
    double *fro_at;             /* nsteps+1: ||A_k||_F, the leading block of step k */
    cholmod_sparse *A;          /* A_FF: the free block, lower triangle, in free positions */
    cholmod_factor *L;          /* L L^T = P A_FF P^T, P = L->Perm */
    int maxrow;                 /* supernodal: rows of the tallest supernode (workspace size) */
    int rows_sorted;            /* 1: every supernode's row list is ascending */
    int nlift;                  /* A(i, j) with i or j constrained, both orientations: */
    int *lrow, *lcol;           /* variables */
    double *lval;
    double t_assemble, t_order, t_factor, nnzL;
    double lnz_ref, fl_ref;     /* predicted nonzeros and flops of METIS on the intact block */
    double lnz_plan, fl_plan;   /* predicted for the planned order */
    /* Where the planned factor's flops and values go (supernodal analysis; kt_plan_factor_build):
     * K: the intact columns' intact rows (chol of the intact block); W: the intact columns'
     * increment rows (L21 = (L_K^-1 C)^T and its updates of the increments' block); S: the
     * increments' columns (the Schur complement's factor). fl_*: sum of squared column counts
     * (CHOLMOD's flop measure); x_*: stored values (supernodes are full rectangles). nsuper,
     * root_cols: supernodes, columns of the last one. */
    double fl_K, fl_W, fl_S, x_K, x_W, x_S;
    int nsuper, root_cols;
    int reused_order;           /* 1: the intact block is in the given order (perm0), no METIS run */
    int refused;                /* 1: the planned factor is too large (why), not factored */
    char why[384];
} kt_plan_factor;

/* Default of max_ratio (augsolve --plan-max-ratio): the planned factor may hold this many
 * times the nonzeros of METIS's factor of the intact block. The factor is most of a run's
 * peak memory and the memory budget is 2x a METIS refactor run; the eye's plan predicts
 * 1.29x (flops 2.2x), the 5,000-node split of the 5x5x1024 beam far more (a dense Schur block
 * on its 15,000 increments; tests/bench/README.md). */
#define KT_PLAN_MAX_RATIO 4.0

/* How many times faster a flop of the planned factorization runs than a flop of a METIS
 * refactor step, the step's assembly, ordering and analysis included: the planned factor's
 * flops lie mostly in the increments' dense block and the dense rows below the intact columns
 * (BLAS-3 on panels of 256 columns), a refactor step's in small supernodes, after a METIS run
 * of its own. Measured on the demo eye (2-core machine, quiet, 2026-12-07, docs/solver.md):
 * the planned factor 6.38e11 flops in 15.6 s (2.44e-11 s a flop), a METIS refactor step 8.45e10
 * flops in 6.26 s (7.41e-11 s), 3.04x; wtr-od's paired family 2.04e12 flops in 44.5 s
 * (2.18e-11 s). The size check compares the planned flops with nsteps + 1 refactor steps'
 * at this rate: a plan is refused on cost only when refactoring would take less time. */
#define KT_PLAN_FLOP_SPEEDUP 3.0

/* Assemble A on the final mesh, order (ordering: KT_AUG_ORDER_* for K's block) and factor.
 * After the analysis, when the planned order's predicted factor holds more than max_ratio
 * times the nonzeros of the intact block's fill-reducing order (a lower bound of a fresh
 * factorization of any step, up to its new DOFs), or needs more flops than KT_PLAN_FLOP_SPEEDUP
 * x (nsteps + 1) fresh factorizations of it (the time of refactoring every step; max_ratio <= 0,
 * or the natural order: no check), nothing is factored:
 * F->refused = 1 and F->why says so (the caller falls back). */
int kt_plan_factor_build(kt_plan_factor *F, const kt_edits_plan *p, const kt_mesh *final,
                         const kt_materials *mats, int ordering, int factor, int panel,
                         double max_ratio, kt_err *e);
/* kt_plan_factor_build with perm0 (NULL, or a fill-reducing order of the intact mesh's 3 nn0
 * DOFs made for a matrix of the same pattern: kt_aug_problem.perm): with ordering METIS the
 * intact block is ordered by perm0 restricted to its free DOFs (then postordered on its tree)
 * instead of a METIS run of its own; the reference figures lnz_ref and fl_ref are then those
 * of that order. */
int kt_plan_factor_build_with(kt_plan_factor *F, const kt_edits_plan *p, const kt_mesh *final,
                              const kt_materials *mats, int ordering, const int *perm0,
                              int factor, int panel, double max_ratio, kt_err *e);
void kt_plan_factor_free(kt_plan_factor *F);
/* A = T^T K T: every entry K(i, j) of the final mesh's lower-stored symmetric stiffness K (and
 * its mirror K(j, i)) handed to put(ctx, v, w, x) for every pair of variables v >= w whose
 * chains (a DOF's node and the node's ancestors, same component) hold i and j (x 0 when K is a
 * pattern). KT_EINPUT when a node is split more than KT_PLAN_CHAIN_MAX times. */
enum { KT_PLAN_CHAIN_MAX = 256 };
/* The variables DOF i of the final mesh sums (its chain) into v: the count, -1 when the chain
 * is deeper than KT_PLAN_CHAIN_MAX. */
int kt_plan_chain(const kt_edits_plan *p, int i, int *v);
int kt_plan_transform(const kt_edits_plan *p, const cholmod_sparse *K,
                      void (*put)(void *ctx, int v, int w, double x), void *ctx, kt_err *e);
/* Split every supernode of the symbolic supernodal factor L that holds a column >= nK into
 * panels of width columns, each with the supernode's rows from its first column on (a finer
 * supernodal partition of the same L: the dense trailing block is then stored lower, in
 * panels); CHOLMOD's workspace sizes follow. width <= 0 or a simplicial L: nothing. Before
 * cholmod_factorize; c is L's common. */
int kt_plan_split_panels(cholmod_factor *L, int nK, int width, cholmod_common *c, kt_err *e);

/* Substitutions on the factor in place (aug_plan_subst.c), vectors in L's numbering; work
 * holds F->maxrow values of scratch.
 * kt_plan_forward continues a forward substitution over the columns c0..c1-1: on entry y[0..c0)
 * is solved and every later row holds its right-hand side minus the updates of the columns
 * before c0; on exit the same holds with c1 (rows >= c1 receive their updates, whatever they
 * hold). So a forward substitution can be split at any column, and continued when more rows
 * are released.
 * kt_plan_back (supernodal only): y[0..N) := L^-T y[0..N), rows >= N (the unreleased
 * increments) zero on entry and left so, on the supernodes want marks (all when NULL); the
 * entries of the others are left as they were. */
void kt_plan_forward(const kt_plan_factor *F, double *work, int c0, int c1, double *y);
void kt_plan_back(const kt_plan_factor *F, const unsigned char *want, double *work, int N,
                  double *y);
/* The same with nrhs right-hand sides at once, Y interleaved (row q's values at
 * Y[q nrhs .. q nrhs + nrhs)): one pass over the factor for all of them (BLAS 3 per supernode);
 * work holds F->maxrow * nrhs values. kt_plan_forward_multi updates only the rows below upto
 * (F->nfree: every row, as kt_plan_forward; c1: a substitution that is not continued, whose
 * rows >= c1 the caller zeroes, reads none of the factor's rows there: a supernodal factor
 * with sorted row lists skips them, a simplicial one updates them all the same).
 * kt_plan_back_multi takes a simplicial factor too (then want is ignored: every column). */
void kt_plan_forward_multi(const kt_plan_factor *F, double *work, int c0, int c1, int nrhs,
                           int upto, double *Y);
void kt_plan_back_multi(const kt_plan_factor *F, const unsigned char *want, double *work, int N,
                        int nrhs, double *Y);
/* Set F->maxrow and F->rows_sorted (kt_plan_factor_build, after the factorization). */
void kt_plan_subst_init(kt_plan_factor *F);

/* The cut mesh as the steps go, its loads and the field. Owner: kt_plan_state_init / _free. */
typedef struct kt_plan_state {
    int step;                   /* edits applied up to this step */
    kt_mesh mesh;               /* the cut mesh after them */
    int *origin;                /* nn: input node each node descends from */
    double *force;              /* 3 nn: nodal forces from the edits, N */
    double *f;                  /* 3 nn: applied loads (pressures + forces), N */
    double *v;                  /* 3 nn: the variables (u of intact nodes, d of new ones) */
    double *u;                  /* 3 nn: displacement of the cut mesh, mm */
    double *react;              /* 3 nn: K u - f at constrained DOFs, else 0 */
    double *tf;                 /* 3 nn: T^T f, the loads each variable sums */
    int npown, *pown;           /* tets with 3 corners on a pressure surface (tet numbers) */
    kt_mesh pview;              /* the cut mesh restricted to them: what the pressures read */
    double *fe_rel;             /* ne x 3 nv: each tet's prestress internal forces, computed
                                   once (a cut moves a tet to other nodes, never changes its
                                   geometry or prestress); NULL without prestress */
    double *b, *x, *r, *ax;     /* right-hand side, solution, residual, scratch (free positions) */
    double t_edits;             /* s to apply the last step's edits */
    kt_aug_row row;
    /* the substitutions' state: the factor stays as built */
    cholmod_common c;           /* the solves' CHOLMOD workspace */
    int c_started;
    cholmod_dense *w[2], *Y, *E;/* solve workspaces */
    double *yf, *bf;            /* the plan's forward substitution, continued step by step: */
    int nf;                     /* yf[0..nf) solved from bf[0..nf) (L's numbering), later rows
                                   hold the updates of those columns */
    int ncont;                  /* steps that continued it (the others started it over) */
    unsigned char *want;        /* NULL, or the supernodes a restricted back substitution needs */
    int want_cols;              /* their columns */
    double *rwork;              /* F->maxrow values: the substitutions' workspace */
} kt_plan_state;

/* The state of step 0 for the plan p factored as F. */
int kt_plan_state_init(kt_plan_state *s, const kt_edits_plan *p, const kt_plan_factor *F,
                       const kt_aug_problem *prob, kt_err *e);
/* Restricted output (aug_plan_out.c): from now on the back substitution computes only what
 * the DOFs of the marked nodes of the final mesh (nodes, p->nn) need: the supernodes on their
 * paths to the roots of the supernodal tree. A simplicial factor keeps the full one. Then a
 * step's u is valid on the marked nodes only and it computes no residual and no reactions. */
int kt_plan_state_restrict(kt_plan_state *s, const kt_edits_plan *p, const kt_plan_factor *F,
                           const unsigned char *nodes, kt_err *e);
void kt_plan_state_free(kt_plan_state *s);
/* Apply step k's edits (k = s->step + 1) to the state without solving. */
int kt_plan_advance(kt_plan_state *s, const kt_edits_plan *p, kt_err *e);
/* Solve the current step: loads on the cut mesh -> right-hand side of the released rows ->
 * substitutions -> field (s->u, s->react) and s->row. Where the backward error exceeds tol,
 * one step of iterative refinement; still above it is KT_ERUN. */
int kt_plan_solve(kt_plan_state *s, const kt_edits_plan *p, const kt_plan_factor *F,
                  const kt_aug_problem *prob, double tol, kt_err *e);
/* A step that is not solved (augsolve --steps): its loads and right-hand side, and the plan's
 * forward substitution continued over its columns, so that every later step's field is
 * bitwise what it is when every step is solved. */
int kt_plan_continue(kt_plan_state *s, const kt_edits_plan *p, const kt_plan_factor *F,
                     const kt_aug_problem *prob, kt_err *e);
/* Solve the current cut mesh from scratch (assembly, METIS, factorization, solve: what a user
 * would run instead) into u (3 nn); t gets the seconds it took. The --verify reference. */
int kt_plan_fresh(const kt_plan_state *s, const kt_edits_plan *p, const kt_aug_problem *prob,
                  double *u, double *t, kt_err *e);

#endif
