/* aug_impl.h: internals of the augmented solver shared by lib/aug*.c (not a public contract). */
#ifndef KT_AUG_IMPL_H
#define KT_AUG_IMPL_H

#include <pthread.h>

#include "aug.h"
#include "chol.h"

/* A sparse column: rows i[0..n) (unsorted, unique), values x. */
typedef struct aug_col {
    int n, cap;
    int *i;
    double *x;
} aug_col;

/* One factorization of R and what is precomputed with it. It owns its cholmod_common, so a
 * background thread can build it while the main thread solves with the previous one. */
typedef struct aug_base {
    cholmod_common c;
    int started;        /* cholmod_start was called */
    int step;           /* state it was built from: edits up to this step */
    int n0;             /* its DOFs */
    unsigned char *B;   /* n0: Dirichlet DOFs of the base (identity rows and columns) */
    cholmod_factor *L;  /* simplicial after build (supernodal ones are converted once) */
    cholmod_sparse *R;  /* the matrix, both triangles, sorted: residuals, weights, SPAI */
    double *fh0;        /* n0: right-hand side it was built for */
    double *y0;         /* n0: R^-1 fh0 */
    double *dinv;       /* n0: D^-1 in the original numbering (diag preconditioner) */
    double *spai;       /* 3*n0: S(j-1,j), S(j,j), S(j+1,j) of the tridiagonal SAI */
    int *perm, *iperm;  /* n0: L's permutation and inverse (identity for natural) */
    double t_factor;    /* seconds to build, wall clock */
    double nnzL;
} aug_base;

/* What a factorization is built from: a copy of the state after some step. */
typedef struct aug_snapshot {
    int step;
    kt_mesh mesh;
    const kt_materials *mats;
    unsigned char *C;   /* 3*nn: constrained DOFs, the B of the new base */
    double *fh;         /* 3*nn: lifted right-hand side with g on C */
    int ordering, factor, precond;
} aug_snapshot;

/* Background factorization. */
typedef struct aug_job {
    pthread_t th;
    pthread_mutex_t mu;
    int done;           /* under mu */
    aug_snapshot snap;
    aug_base *base;     /* result */
    kt_err err;
} aug_job;

typedef struct aug_fixtri {
    int tri, fix;       /* a triangle of a fixation surface and the fixation's index */
} aug_fixtri;

typedef struct aug_ptri {
    int tri, press;     /* a triangle of a pressure surface and the pressure's index */
} aug_ptri;

struct kt_aug {
    kt_aug_opts o;
    kt_materials mats;
    kt_mesh mesh;               /* current, cut */
    int npress;
    kt_aug_pressure *press;
    int nptri;
    aug_ptri *ptri;
    int nfix;
    kt_aug_fixsurf *fix;
    int nftri;
    aug_fixtri *ftri;
    cholmod_common c;
    int c_started;
    int step;

    /* per node, capacity cap_nn */
    int cap_nn;
    int **adj, *adj_n, *adj_cap; /* tets around each node */
    int *touch_step;             /* last step the node's stiffness column changed */
    int *origin;                 /* 0-based input node it descends from */
    int *nmark;                  /* node marks (stamped) */
    int **kids, *kids_n, *kids_cap; /* nodes split off each node (dups), in creation order */
    int nstamp;

    /* per DOF, capacity 3*cap_nn */
    unsigned char *cons;         /* constrained now (B u D) */
    double *g;                   /* prescribed values */
    double *force;               /* nodal forces from edits */
    double *f;                   /* applied loads: pressure + forces */
    double *fh;                  /* f - K(:,C) g off B; g on B */
    int *cons_step;              /* step it was constrained (0: intact scene), -1 never */
    int *rhs_step;               /* last step fh changed */
    int *Lpos;                   /* index in Lset or -1 */
    int *par;                    /* DOF this new DOF hangs on (u_j = v_j + u_par), -1: none */
    unsigned char *ind;          /* in dlist */
    unsigned char *outmask;      /* in the output set (NULL: all) */
    double *u, *react, *w, *w2, *uprev;
    double *pad;                 /* R on the padding (0: not set yet, read as 1) */
    int *dmark;                  /* DOF marks (stamped) */
    int dstamp;

    aug_base *base;
    /* Lset and J */
    int m, mcap;
    int *Ldof;
    aug_col *J;
    double *a2, *rhs;
    int *Jpat, njpat, jpcap;
    /* DOFs where fh differs from the base's fh0 */
    int nd, dcap;
    int *dlist;
    int ndpat, dpcap;            /* dlist and the ancestors of its new DOFs: where d != 0 */
    int *dpat;
    /* CHOLMOD workspaces of the main thread */
    cholmod_dense *Bd, *X, *Y, *E;
    cholmod_sparse *Bset, *Xset;
    int ws_n;
    /* background refactorization */
    aug_job *job;
    double t_since_factor;      /* s of step time since the factor in use was installed */
    int closure_max;
    double gmres_short;         /* relative residual GMRES stopped at above --tol (0: reached) */

    kt_aug_row row;
    int react_valid;
};

/* aug_cols.c: element-local stiffness columns */
int aug_col_reserve(aug_col *c, int n, kt_err *e);
void aug_col_free(aug_col *c);
/* K(:, 3a+0..2) of node a in the current mesh. */
int aug_node_columns(kt_aug *A, int a, aug_col col[3], kt_err *e);

/* aug_state.c: DOF arrays, adjacency, edits */
int aug_state_init(kt_aug *A, const kt_aug_problem *p, kt_err *e);
void aug_state_free(kt_aug *A);
int aug_grow(kt_aug *A, int nn, kt_err *e);
/* Apply a step's edits to mesh, loads, constraints and fh; *touched gets the nodes whose
 * columns changed and *newc the DOFs constrained by this step (both allocated). */
int aug_apply_edits(kt_aug *A, const kt_step *s, int **touched, int *nt, int **newc, int *nc,
                    kt_err *e);
/* fh changed at dof in this step: stamp it and list it among the DOFs where fh != fh0. */
int aug_mark_rhs(kt_aug *A, int dof, kt_err *e);
int aug_dlist_add(kt_aug *A, int dof, kt_err *e);
int aug_full_loads(const kt_aug *A, double *f, kt_err *e);
int aug_output_mask(kt_aug *A, kt_err *e);
/* Assemble and factor the current constrained K from scratch (loads recomputed from the mesh):
 * with the run's ordering and factor options (use_opts) or CHOLMOD's defaults. t[0..3] get the
 * seconds of assembly, analysis, factorization and solve. */
int aug_fresh_solve(kt_aug *A, int use_opts, double *u, double *t, double *relres, kt_err *e);

/* aug_base.c: factorizations */
int aug_snapshot_take(kt_aug *A, aug_snapshot *s, kt_err *e);
void aug_snapshot_free(aug_snapshot *s);
aug_base *aug_base_build(const aug_snapshot *s, kt_err *e);
void aug_base_free(aug_base *b);
int aug_job_start(kt_aug *A, kt_err *e);
int aug_job_poll(kt_aug *A, int wait, kt_err *e);  /* 1 when a new base was installed */
void aug_job_cancel(kt_aug *A);
int aug_install(kt_aug *A, aug_base *b, kt_err *e);
int aug_analyze(cholmod_sparse *K, int ordering, int factor, cholmod_common *c,
                cholmod_factor **L, kt_err *e);

/* aug_lset.c: Lset, J, H in the variables u = P v (new DOFs as increments over their parent) */
int aug_update_lset(kt_aug *A, const int *touched, int nt, const int *newc, int nc, kt_err *e);
int aug_rebuild_lists(kt_aug *A, kt_err *e);
double aug_padv(const kt_aug *A, int j);   /* R on the padding */
int aug_load_d(kt_aug *A, double *w, kt_err *e); /* w += P^T fh - fh0 on A->dpat */
void aug_unfold(const kt_aug *A, double *u);   /* u = P v in place */
int aug_solve_augmented(kt_aug *A, kt_err *e);
/* The residual of the system solved: relative to the right-hand side, and the backward error
 * ||r|| / || |T||a'| + |t| || (NAN both with a restricted output). */
int aug_residual(kt_aug *A, double *relres, double *backward, kt_err *e);
void aug_react_from_a2(kt_aug *A);
void aug_solve_free(kt_aug *A);

/* aug_cg.c: baselines */
int aug_solve_refactor(kt_aug *A, kt_err *e);
int aug_solve_cg(kt_aug *A, int jacobi, kt_err *e);

double aug_ms(double seconds);

#endif
