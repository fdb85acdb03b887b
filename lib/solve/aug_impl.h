/* aug_impl.h: internals of the stream solver (lib/solve/aug*.c; not a public contract).
 *
 * The state is split by concern, each struct with one owner that allocates and frees it:
 *   aug_stream  the cut mesh and what the edits change (aug_state.c)
 *   aug_intact  the factor of the intact stiffness, made once (aug_intact.c)
 *   aug_border  the appended variables in release order, W = L^-1 C and the dense factor of
 *               the Schur complement (aug_border.c)
 *   aug_rhs     one step's right-hand side and solution in the variables (aug_solve.c)
 *   kt_aug      the output (u, reactions, the step's row) and the four above (aug.c). */
#ifndef KT_AUG_IMPL_H
#define KT_AUG_IMPL_H

#include "aug.h"
#include "chol.h"

/* A sparse column: rows i[0..n) (unsorted, unique), values x. */
typedef struct aug_col {
    int n, cap;
    int *i;
    double *x;
} aug_col;

/* The cut mesh as the edits go, with what every method reads. Owner: kt_aug_stream_init/free. */
typedef struct aug_stream {
    kt_materials mats;
    kt_mesh mesh;               /* current, cut */
    int npress;
    kt_aug_pressure *press;
    int nfix;
    kt_aug_fixsurf *fix;
    int step;
    int nn0;                    /* intact nodes */
    /* per node, capacity cap_nn */
    int cap_nn;
    int **adj, *adj_n, *adj_cap; /* tets around each node */
    int *origin;                 /* 0-based input node it descends from */
    int *parent;                 /* node it was split from, -1 for intact nodes */
    int *nmark;                  /* node marks (stamped) */
    int nstamp;
    /* per DOF, capacity 3*cap_nn */
    unsigned char *cons;         /* constrained now */
    unsigned char *fixed0;       /* constrained by the intact scene (eliminated from K) */
    double *g;                   /* prescribed values */
    double *force;               /* nodal forces from edits */
    double *f;                   /* applied loads on the current mesh (kt_aug_stream_loads) */
} aug_stream;

int kt_aug_stream_init(aug_stream *s, const kt_aug_problem *p, kt_err *e);
void kt_aug_stream_free(aug_stream *s);
/* Apply a step's edits: cut, adjacency, parents, automatic fixes of new nodes on fixation
 * surfaces, fix and force edits. *newc gets the DOFs constrained by this step (allocated). */
int kt_aug_stream_apply(aug_stream *s, const kt_step *st, int **newc, int *nc, kt_err *e);
/* s->f = pressures + prestress release + forces, on the current mesh (fem layer). */
int kt_aug_stream_loads(aug_stream *s, kt_err *e);

/* aug_cols.c: K(:, 3a+0..2) of node a in the current mesh, from its tets' element stiffness. */
int kt_aug_col_reserve(aug_col *c, int n, kt_err *e);
void kt_aug_col_free(aug_col *c);
int kt_aug_node_columns(aug_stream *s, int a, aug_col col[3], kt_err *e);

/* The intact stiffness on its free DOFs, factored once: L L^T = P K P^T, supernodal, with the
 * supernodal tree for restricted forward solves. Owner: kt_aug_intact_build/free. */
typedef struct aug_intact {
    int nK;                     /* free intact DOFs */
    int *pos;                   /* 3 nn0: position of an intact DOF among them, -1: fixed */
    cholmod_sparse *K;          /* the free block, lower triangle (residuals) */
    cholmod_factor *L;
    int *iperm;                 /* nK: position in L of a free position */
    int nsuper;
    int *sparent;               /* nsuper: parent supernode, -1 at a root */
    int *col_super;             /* nK: supernode of each column of L */
    int maxrow;                 /* rows of the tallest supernode */
    cholmod_dense *w[2], *Y, *E; /* full-solve workspaces */
    double t_factor, nnzL;
} aug_intact;

int kt_aug_intact_build(aug_intact *F, const aug_stream *s, int ordering, cholmod_common *c,
                     kt_err *e);
void kt_aug_intact_free(aug_intact *F, cholmod_common *c);
/* y = L^-1 (P b) in L's numbering, or x = P^T L^-T y (back); in and out hold nK values. */
int kt_aug_intact_forward(aug_intact *F, const double *b, double *y, cholmod_common *c, kt_err *e);
int kt_aug_intact_back(aug_intact *F, const double *y, double *x, cholmod_common *c, kt_err *e);
/* The supernodes on the paths from the supernodes of rows[0..n) (L's numbering) to the roots,
 * ascending, into sup (nsuper capacity); mark: nsuper ints, stamp a fresh value. Returns the
 * count. */
int kt_aug_intact_closure(const aug_intact *F, const int *rows, int n, int *sup, int *mark,
                          int stamp);
/* x = L^-1 x on the supernodes sup[0..ns) (ascending closure): x is dense (nK), zero outside
 * the closure's rows. tmp: maxrow values of scratch. */
void kt_aug_intact_forward_on(const aug_intact *F, const int *sup, int ns, double *x, double *tmp);

/* A variable appended after the intact ones: the increment d of a new node's DOF (u = u_parent
 * + d) or the Lagrange multiplier of a DOF constrained after step 0. Its column of the
 * bordered matrix: C (rows among the intact free DOFs, positions of K) and the part among the
 * appended variables up to itself (D, appended indices <= its own). */
enum { AUG_INCREMENT = 0, AUG_MULTIPLIER = 1 };
typedef struct aug_var {
    int kind, dof;              /* AUG_*, the DOF of the current mesh it belongs to */
    double scale;               /* multiplier: the row is scale * (u_dof - g) = 0 */
    aug_col C, D;
} aug_var;

/* The appended variables in release order and the factor of the bordered matrix
 * [K C; C^T D] = [L 0; W^T I] [I 0; 0 S] [L^T W; 0 I], S = D - W^T W = Ls Ds Ls^T (dense,
 * unit lower Ls, no pivoting: S is positive definite on the increments and the multipliers
 * come after every variable their row holds, so it is quasi-definite in release order).
 * W is kept by supernode: for supernode s, the appended columns whose closure holds it and
 * their values on its columns. Owner: kt_aug_border_init/free. */
typedef struct aug_wblock {
    int n, cap;                 /* appended columns held */
    int *col;                   /* their appended indices, ascending */
    double *x;                  /* ncols(s) x n, column-major */
} aug_wblock;

typedef struct aug_border {
    int m, cap;                 /* appended variables */
    aug_var *var;
    int *apos;                  /* per DOF (3 cap_nn): appended index of its increment, -1 */
    int *mpos;                  /* per DOF: appended index of its multiplier, -1 */
    int dof_cap;
    aug_wblock *wb;             /* nsuper */
    double wnnz;                /* values held in wb */
    double *Ls, *Ds;            /* m x m unit lower (leading dimension cap), m pivots */
    double *tmp;                /* cap values of scratch */
    int closure_max;            /* largest closure (columns of L) of the last step's columns */
} aug_border;

int kt_aug_border_init(aug_border *B, const aug_intact *F, kt_err *e);
void kt_aug_border_free(aug_border *B, const aug_intact *F);
/* Append the variables of a step: increments of the nodes nn_old.. of the current mesh, then
 * multipliers of the newly constrained DOFs newc; their W columns and the rows of Ls, Ds. */
int kt_aug_border_append(aug_border *B, const aug_intact *F, aug_stream *s, int nn_old,
                      const int *newc, int nc, kt_err *e);
/* d = S^-1 r (m values, in place). */
void kt_aug_border_solve(const aug_border *B, double *r);
/* r -= W^T y and y -= W d (y in L's numbering). */
void kt_aug_border_wt(const aug_border *B, const aug_intact *F, const double *y, double *r);
void kt_aug_border_w(const aug_border *B, const aug_intact *F, const double *d, double *y);

/* One step's right-hand side and solution. Owner: aug_rhs_init/free (sized per step). */
typedef struct aug_rhs {
    int nK, m, n;               /* intact free DOFs, appended variables, DOFs of the mesh */
    double *u0;                 /* n: displacement of the intact scene's constraints, 0 elsewhere */
    double *z;                  /* n: f - K u0 */
    double *b;                  /* nK + m: right-hand side [b_K; b_R] */
    double *x;                  /* nK + m: solution [x_K; d] */
    double *r, *dx, *y;         /* residual, correction, nK scratch in L's numbering */
} aug_rhs;

struct kt_aug {
    kt_aug_opts o;
    cholmod_common c;
    int c_started;
    aug_stream s;
    int have_factor;            /* augmented: F and B below are set up */
    aug_intact F;
    aug_border B;
    aug_rhs r;
    /* the output */
    double *u, *react, *uprev;  /* 3 cap_nn */
    int out_cap;
    int react_valid;
    kt_aug_row row;
};

/* aug_solve.c: the augmented method's step (rhs -> substitutions -> refinement -> field). */
int kt_aug_solve_augmented(kt_aug *A, kt_err *e);
void kt_aug_rhs_free(aug_rhs *r);

/* aug_cg.c: baselines and the fresh reference. */
int kt_aug_analyze(cholmod_sparse *K, int ordering, int factor, cholmod_common *c,
                cholmod_factor **L, kt_err *e);
/* Assemble and factor the current constrained K from scratch (loads from the mesh): with the
 * run's ordering and factor options (use_opts) or METIS, postordered (what a user would run).
 * t[0..3] get the seconds of assembly, analysis, factorization and solve. */
int kt_aug_fresh_solve(kt_aug *A, int use_opts, double *u, double *t, double *relres, kt_err *e);
int kt_aug_solve_refactor(kt_aug *A, kt_err *e);
int kt_aug_solve_cg(kt_aug *A, int jacobi, kt_err *e);

double kt_aug_ms(double seconds);

#endif
