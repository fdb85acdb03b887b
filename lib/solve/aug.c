/* aug.c: the stream solver's public interface: options, set-up, one step (edits -> appended
 * variables -> the chosen method -> field -> verification) and the results. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "aug_impl.h"
#include "chol.h"

void kt_aug_opts_default(kt_aug_opts *o)
{
    memset(o, 0, sizeof *o);
    o->method = KT_AUG_AUGMENTED;
    o->ordering = KT_AUG_ORDER_NATURAL;
    o->factor = KT_AUG_FACTOR_SUPERNODAL;
    o->tol = 1e-10;
    o->maxit = 0;
    o->verify_tol = 1e-8;
    o->plan_panel = KT_AUG_PLAN_PANEL;
}

kt_aug_problem kt_aug_problem_of(const kt_mesh *m, const kt_fem_problem *fp)
{
    return (kt_aug_problem){m, &fp->mats, fp->fixed, fp->g, fp->npress, fp->press, fp->nfix,
                            fp->fix, NULL};
}

static int word(const char *s, const char *const *names, int n, int *v)
{
    for (int i = 0; i < n; i++)
        if (names[i] && strcmp(s, names[i]) == 0) {
            *v = i;
            return 0;
        }
    return -1;
}

static const char *const METHODS[] = {NULL, "augmented", "refactor", "cg", "pcg-jacobi", "planned",
                                      "newton"};

int kt_aug_parse_method(const char *s, int *m) { return word(s, METHODS, 7, m); }
const char *kt_aug_method_name(int m) { return m >= 1 && m <= 6 ? METHODS[m] : "?"; }


int kt_aug_parse_ordering(const char *s, int *o)
{
    static const char *const names[] = {"natural", "amd", "metis"};
    return word(s, names, 3, o);
}

int kt_aug_parse_factor(const char *s, int *f)
{
    static const char *const names[] = {"supernodal", "simplicial"};
    return word(s, names, 2, f);
}


/* ------------------------------------------------------------------ results */

const kt_aug_row *kt_aug_last(const kt_aug *a) { return &a->row; }
const kt_mesh *kt_aug_mesh(const kt_aug *a) { return &a->s.mesh; }
const double *kt_aug_displacement(const kt_aug *a) { return a->u; }
const int *kt_aug_origin(const kt_aug *a) { return a->s.origin; }
const double *kt_aug_load(const kt_aug *a) { return a->s.f; }

void kt_aug_factor_info(const kt_aug *a, double *nnzL, double *seconds)
{
    *nnzL = a->have_factor ? a->F.nnzL : 0;
    *seconds = a->have_factor ? a->F.t_factor : 0;
}

/* K(:,j).u - f_j at constrained DOFs, from element columns. */
const double *kt_aug_reaction(kt_aug *A, kt_err *e)
{
    if (A->react_valid) return A->react;
    aug_stream *s = &A->s;
    int nn = s->mesh.nn;
    memset(A->react, 0, 3 * (size_t)nn * sizeof(double));
    aug_col col[3] = {{0}};
    for (int a = 0; a < nn && !e->code; a++) {
        if (!(s->cons[3 * a] | s->cons[3 * a + 1] | s->cons[3 * a + 2]) ||
            kt_aug_node_columns(s, a, col, e))
            continue;
        for (int c = 0; c < 3; c++) {
            int j = 3 * a + c;
            if (!s->cons[j]) continue;
            double r = -s->f[j];
            for (int p = 0; p < col[c].n; p++) r += col[c].x[p] * A->u[col[c].i[p]];
            A->react[j] = r;
        }
    }
    for (int c = 0; c < 3; c++) kt_aug_col_free(&col[c]);
    if (e->code) return NULL;
    A->react_valid = 1;
    return A->react;
}

/* ------------------------------------------------------------------ output */

/* Room for the output arrays of the current mesh; a new node starts from its parent's u
 * (CG's initial guess), an intact node (at set-up) from 0. */
static int out_grow(kt_aug *A, int nn_old, kt_err *e)
{
    const aug_stream *s = &A->s;
    size_t n = 3 * (size_t)s->mesh.nn;
    if (n > (size_t)A->out_cap) {
        size_t cap = n > 2 * (size_t)A->out_cap ? n : 2 * (size_t)A->out_cap;
        double *u = kt_realloc(A->u, cap, sizeof(double), e);
        if (u) A->u = u;
        double *r = u ? kt_realloc(A->react, cap, sizeof(double), e) : NULL;
        if (r) A->react = r;
        double *p = r ? kt_realloc(A->uprev, cap, sizeof(double), e) : NULL;
        if (!p) return e->code;
        A->uprev = p;
        A->out_cap = (int)cap;
    }
    for (int a = nn_old; a < s->mesh.nn; a++)
        for (int c = 0; c < 3; c++) {
            int p = s->parent[a];
            A->uprev[3 * a + c] = p >= 0 ? A->uprev[3 * p + c] : 0.0;
            A->u[3 * a + c] = A->react[3 * a + c] = 0;
        }
    return KT_OK;
}

/* ------------------------------------------------------------------- a step */

static void row_start(kt_aug *A)
{
    memset(&A->row, 0, sizeof A->row);
    A->row.step = A->s.step;
    A->row.rel_residual = A->row.verify_rel_diff = A->row.t_verify = NAN;
}

static void row_finish(kt_aug *A, int nn_before)
{
    kt_aug_row *r = &A->row;
    r->n_dofs = 3 * A->s.mesh.nn;
    r->new_dofs = 3 * (A->s.mesh.nn - nn_before);
    if (A->o.method == KT_AUG_AUGMENTED) {
        r->m = A->B.m;
        r->closure_max = A->B.closure_max;
        r->nnz_L = A->F.nnzL + A->B.wnnz + 0.5 * (double)A->B.m * (A->B.m + 1);
    }
    if (A->o.method == KT_AUG_CG || A->o.method == KT_AUG_PCG_JACOBI) r->t_step1 = r->t_step3 = NAN;
    r->t_total = r->t_update + (isnan(r->t_step1) ? 0 : r->t_step1) + r->t_step2 +
                 (isnan(r->t_step3) ? 0 : r->t_step3);
}

static int solve_method(kt_aug *A, kt_err *e)
{
    switch (A->o.method) {
    case KT_AUG_AUGMENTED: return kt_aug_solve_augmented(A, e);
    case KT_AUG_REFACTOR: return kt_aug_solve_refactor(A, e);
    case KT_AUG_CG: return kt_aug_solve_cg(A, 0, e);
    case KT_AUG_PCG_JACOBI: return kt_aug_solve_cg(A, 1, e);
    }
    return kt_fail(e, KT_EINPUT, "method %s does not solve a stream step by step",
                   kt_aug_method_name(A->o.method));
}

int kt_aug_fresh(kt_aug *A, double *u, double *t, kt_err *e)
{
    double relres = NAN, t0 = kt_now();
    kt_aug_fresh_solve(A, 0, u, NULL, &relres, e);
    *t = kt_now() - t0;
    return e->code;
}

/* The step's row, and its field kept as the next step's starting guess (CG). */
static void after_solve(kt_aug *A, int nn_before)
{
    row_finish(A, nn_before);
    memcpy(A->uprev, A->u, 3 * (size_t)A->s.mesh.nn * sizeof(double));
}

int kt_aug_create(kt_aug **out, const kt_aug_problem *p, const kt_aug_opts *o, kt_err *e)
{
    *out = NULL;
    kt_aug *A = kt_calloc(1, sizeof *A, e);
    if (!A) return e->code;
    A->o = *o;
    if (o->method == KT_AUG_AUGMENTED && o->factor == KT_AUG_FACTOR_SIMPLICIAL) {
        free(A);
        return kt_fail(e, KT_EINPUT, "--factor simplicial: the augmented method factors the "
                       "intact stiffness supernodally (its W columns are kept by supernode)");
    }
    kt_chol_start(&A->c);
    A->c_started = 1;
    row_start(A);
    double t0 = kt_now();
    if (kt_aug_stream_init(&A->s, p, e) || out_grow(A, 0, e)) goto fail;
    if (A->o.method == KT_AUG_AUGMENTED) {
        if (kt_aug_intact_build(&A->F, &A->s, A->o.ordering, &A->c, e)) goto fail;
        A->have_factor = 1;
        if (kt_aug_border_init(&A->B, &A->F, e)) goto fail;
    }
    A->row.t_update = kt_aug_ms(kt_now() - t0);
    if (solve_method(A, e)) goto fail;
    after_solve(A, A->s.mesh.nn);
    *out = A;
    return KT_OK;
fail:
    kt_aug_free(A);
    return e->code;
}

int kt_aug_step(kt_aug *A, const kt_step *st, kt_err *e)
{
    if (st->index != A->s.step + 1)
        return kt_fail(e, KT_EINPUT, "step %d follows step %d (expected step %d)", st->index,
                       A->s.step, A->s.step + 1);
    int nn_before = A->s.mesh.nn, *newc = NULL, nc = 0;
    double t0 = kt_now();
    if (kt_aug_stream_apply(&A->s, st, &newc, &nc, e) || out_grow(A, nn_before, e)) {
        free(newc);
        return e->code;
    }
    row_start(A);
    double t1 = kt_now();
    if (A->o.method == KT_AUG_AUGMENTED)
        kt_aug_border_append(&A->B, &A->F, &A->s, nn_before, newc, nc, e);
    free(newc);
    if (e->code) return e->code;
    A->row.t_update = kt_aug_ms(t1 - t0);
    A->row.t_step1 = kt_aug_ms(kt_now() - t1);
    if (solve_method(A, e)) return e->code;
    after_solve(A, nn_before);
    return KT_OK;
}

void kt_aug_free(kt_aug *A)
{
    if (!A) return;
    kt_aug_rhs_free(&A->r);
    if (A->have_factor) {
        kt_aug_border_free(&A->B, &A->F);
        kt_aug_intact_free(&A->F, &A->c);
    }
    kt_aug_stream_free(&A->s);
    free(A->u);
    free(A->react);
    free(A->uprev);
    if (A->c_started) cholmod_finish(&A->c);
    free(A);
}
