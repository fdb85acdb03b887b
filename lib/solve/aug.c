/* aug.c: the augmented solver's public interface: options, set-up, one step (edits, Lset, the
 * chosen method, re-factorization policy, verification) and the results. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "aug_impl.h"

void kt_aug_opts_default(kt_aug_opts *o)
{
    memset(o, 0, sizeof *o);
    o->method = KT_AUG_AUGMENTED;
    o->precond = KT_AUG_PRECOND_LOCAL;
    o->ordering = KT_AUG_ORDER_NATURAL;
    o->factor = KT_AUG_FACTOR_SUPERNODAL;
    o->tol = 1e-10;
    o->restart = 200;
    o->maxit = 0;
    o->refactor = KT_AUG_REFACTOR_NEVER;
    o->verify_tol = 1e-8;
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

static const char *const METHODS[] = {NULL, "augmented", "refactor", "cg", "pcg-jacobi", "planned"};

int kt_aug_parse_method(const char *s, int *m) { return word(s, METHODS, 6, m); }
const char *kt_aug_method_name(int m) { return m >= 1 && m <= 5 ? METHODS[m] : "?"; }


int kt_aug_parse_precond(const char *s, int *p)
{
    static const char *const names[] = {"none", "diag", "spai", "local"};
    return word(s, names, 4, p);
}

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

int kt_aug_parse_refactor(const char *s, int *policy, int *n)
{
    *n = 0;
    if (strcmp(s, "never") == 0) *policy = KT_AUG_REFACTOR_NEVER;
    else if (strcmp(s, "auto") == 0) *policy = KT_AUG_REFACTOR_AUTO;
    else if (strncmp(s, "m>", 2) == 0 && kt_parse_int(s + 2, n) == 0 && *n >= 0)
        *policy = KT_AUG_REFACTOR_M_ABOVE;
    else if (strncmp(s, "every:", 6) == 0 && kt_parse_int(s + 6, n) == 0 && *n >= 1)
        *policy = KT_AUG_REFACTOR_EVERY;
    else return -1;
    return 0;
}

/* ------------------------------------------------------------------ results */

const kt_aug_row *kt_aug_last(const kt_aug *a) { return &a->row; }
const kt_mesh *kt_aug_mesh(const kt_aug *a) { return &a->mesh; }
const double *kt_aug_displacement(const kt_aug *a) { return a->u; }
const int *kt_aug_origin(const kt_aug *a) { return a->origin; }
const double *kt_aug_load(const kt_aug *a) { return a->f; }

void kt_aug_factor_info(const kt_aug *a, double *nnzL, double *seconds)
{
    *nnzL = a->base ? a->base->nnzL : 0;
    *seconds = a->base ? a->base->t_factor : 0;
}

/* K(:,j).u - f_j at constrained DOFs from element columns (D DOFs of the augmented method
 * already have theirs from a2). */
const double *kt_aug_reaction(kt_aug *A, kt_err *e)
{
    if (A->react_valid) return A->react;
    int nn = A->mesh.nn;
    memset(A->react, 0, 3 * (size_t)nn * sizeof(double));
    if (A->o.method == KT_AUG_AUGMENTED) aug_react_from_a2(A);
    aug_col col[3] = {{0}};
    for (int a = 0; a < nn && !e->code; a++) {
        int need = 0;
        for (int c = 0; c < 3; c++) {
            int j = 3 * a + c;
            need |= A->cons[j] && !(A->o.method == KT_AUG_AUGMENTED && A->Lpos[j] >= 0);
        }
        if (!need || aug_node_columns(A, a, col, e)) continue;
        for (int c = 0; c < 3; c++) {
            int j = 3 * a + c;
            if (!A->cons[j] || (A->o.method == KT_AUG_AUGMENTED && A->Lpos[j] >= 0)) continue;
            double s = -A->f[j];
            for (int p = 0; p < col[c].n; p++) s += col[c].x[p] * A->u[col[c].i[p]];
            A->react[j] = s;
        }
    }
    for (int c = 0; c < 3; c++) aug_col_free(&col[c]);
    if (e->code) return NULL;
    A->react_valid = 1;
    return A->react;
}

/* ------------------------------------------------------------------- a step */

static void row_start(kt_aug *A)
{
    memset(&A->row, 0, sizeof A->row);
    A->row.step = A->step;
    A->row.t_update = A->row.t_step1 = A->row.t_step2 = A->row.t_step3 = 0;
    A->row.rel_residual = A->row.verify_rel_diff = A->row.t_verify = NAN;
    strcpy(A->row.refactor, "-");
}

static void row_finish(kt_aug *A, int nn_before)
{
    kt_aug_row *r = &A->row;
    r->n_dofs = 3 * A->mesh.nn;
    r->new_dofs = 3 * (A->mesh.nn - nn_before);
    if (A->o.method == KT_AUG_AUGMENTED) {
        r->m = A->m;
        r->nnz_L = A->base->nnzL;
    } else {
        r->m = 0;
        r->closure_max = 0;
    }
    if (A->o.method == KT_AUG_CG || A->o.method == KT_AUG_PCG_JACOBI) r->t_step1 = r->t_step3 = NAN;
    if (A->o.method != KT_AUG_AUGMENTED && A->o.method != KT_AUG_CG &&
        A->o.method != KT_AUG_PCG_JACOBI)
        r->iters = 0;
    r->t_total = r->t_update + (isnan(r->t_step1) ? 0 : r->t_step1) + r->t_step2 +
                 (isnan(r->t_step3) ? 0 : r->t_step3);
}

static int solve_method(kt_aug *A, kt_err *e)
{
    switch (A->o.method) {
    case KT_AUG_AUGMENTED: return aug_solve_augmented(A, e);
    case KT_AUG_REFACTOR: return aug_solve_refactor(A, e);
    case KT_AUG_CG: return aug_solve_cg(A, 0, e);
    case KT_AUG_PCG_JACOBI: return aug_solve_cg(A, 1, e);
    }
    return kt_fail(e, KT_EINPUT, "unknown method %d", A->o.method);
}

/* Fresh factorization with CHOLMOD's defaults; compares on the output DOFs. */
static int verify(kt_aug *A, kt_err *e)
{
    int n = 3 * A->mesh.nn;
    double *ref = kt_calloc((size_t)n, sizeof(double), e), relres = NAN, t0 = kt_now();
    if (!ref) return e->code;
    if (aug_fresh_solve(A, 0, ref, NULL, &relres, e) == KT_OK) {
        A->row.t_verify = aug_ms(kt_now() - t0);
        double dmax = 0, rmax = 0;
        for (int i = 0; i < n; i++) {
            if (A->outmask && !A->outmask[i]) continue;
            dmax = fmax(dmax, fabs(A->u[i] - ref[i]));
            rmax = fmax(rmax, fabs(ref[i]));
        }
        A->row.verify_rel_diff = rmax > 0 ? dmax / rmax : dmax;
        if (!(A->row.verify_rel_diff <= A->o.verify_tol))
            kt_fail(e, KT_ERUN, "step %d: --verify: %s and a fresh factorization differ by %.3g "
                    "(relative, max norm) > --verify-tol %.3g", A->step,
                    kt_aug_method_name(A->o.method), A->row.verify_rel_diff, A->o.verify_tol);
    }
    free(ref);
    return e->code;
}

/* Start a background factorization if the policy says so. */
static int policy(kt_aug *A, kt_err *e)
{
    if (A->o.method != KT_AUG_AUGMENTED || A->job) return KT_OK;
    int go = 0;
    switch (A->o.refactor) {
    case KT_AUG_REFACTOR_M_ABOVE: go = A->m > A->o.refactor_n; break;
    case KT_AUG_REFACTOR_EVERY: go = A->step % A->o.refactor_n == 0; break;
    case KT_AUG_REFACTOR_AUTO: go = A->t_since_factor > A->base->t_factor; break;
    }
    if (!go) return KT_OK;
    if (aug_job_start(A, e)) return e->code;
    strcpy(A->row.refactor, strcmp(A->row.refactor, "swap") == 0 ? "swap+start" : "start");
    return KT_OK;
}

/* GMRES stopped above --tol (at the floor rounding in the factor's solves sets, or at --maxit):
 * the step stands only if the whole system's backward error meets --tol instead. */
static int check_short(kt_aug *A, double backward, kt_err *e)
{
    if (!(backward <= A->o.tol))
        return kt_fail(e, KT_ERUN, "step %d: GMRES did not reach the relative residual %.3g "
                       "(stopped at %.3g after %d iterations; m = %d) and the system's backward "
                       "error %.3g exceeds it too: the answer is not accurate; use a "
                       "preconditioner, raise --restart, or loosen --tol", A->step, A->o.tol,
                       A->gmres_short, A->row.iters, A->m, backward);
    kt_log(A->o.quiet, "augsolve: step %d: GMRES stopped at the relative residual %.3g above --tol "
           "%.3g (the floor rounding in the factor's solves sets); the system's backward error "
           "%.3g meets it: accepted\n", A->step, A->gmres_short, A->o.tol, backward);
    return KT_OK;
}

static int after_solve(kt_aug *A, kt_err *e)
{
    if (A->o.method == KT_AUG_AUGMENTED) {
        double backward;
        if (aug_residual(A, &A->row.rel_residual, &backward, e)) return e->code;
        if (A->gmres_short > 0 && check_short(A, backward, e)) return e->code;
    }
    if (!e->code && A->o.verify) verify(A, e);
    if (!e->code) memcpy(A->uprev, A->u, 3 * (size_t)A->mesh.nn * sizeof(double));
    return e->code;
}

int kt_aug_create(kt_aug **out, const kt_aug_problem *p, const kt_aug_opts *o, kt_err *e)
{
    *out = NULL;
    kt_aug *A = kt_calloc(1, sizeof *A, e);
    if (!A) return e->code;
    A->o = *o;
    cholmod_start(&A->c);
    A->c_started = 1;
    row_start(A);
    double t0 = kt_now();
    if (aug_state_init(A, p, e) || aug_output_mask(A, e)) goto fail;
    if (A->o.method == KT_AUG_AUGMENTED) {
        aug_snapshot s;
        if (aug_snapshot_take(A, &s, e)) goto fail;
        aug_base *b = aug_base_build(&s, e);
        aug_snapshot_free(&s);
        if (!b || aug_install(A, b, e)) goto fail;
    }
    A->row.t_update = aug_ms(kt_now() - t0);
    if (solve_method(A, e)) goto fail;
    row_finish(A, A->mesh.nn);
    if (after_solve(A, e)) goto fail;
    *out = A;
    return KT_OK;
fail:
    kt_aug_free(A);
    return e->code;
}

int kt_aug_step(kt_aug *A, const kt_step *s, kt_err *e)
{
    if (s->index != A->step + 1)
        return kt_fail(e, KT_EINPUT, "step %d follows step %d (expected step %d)", s->index,
                       A->step, A->step + 1);
    A->step++;
    row_start(A);
    int nn_before = A->mesh.nn;
    if (A->o.method == KT_AUG_AUGMENTED) {
        int rc = aug_job_poll(A, A->o.refactor_sync, e);
        if (rc < 0) return e->code;
        if (rc > 0) strcpy(A->row.refactor, "swap");
    }
    double t0 = kt_now();
    int *touched = NULL, nt = 0, *newc = NULL, nc = 0;
    aug_apply_edits(A, s, &touched, &nt, &newc, &nc, e);
    if (!e->code && A->o.method == KT_AUG_AUGMENTED) aug_update_lset(A, touched, nt, newc, nc, e);
    free(touched);
    free(newc);
    if (e->code) return e->code;
    if (A->outmask && aug_output_mask(A, e)) return e->code;
    A->row.t_update = aug_ms(kt_now() - t0);
    if (solve_method(A, e)) return e->code;
    row_finish(A, nn_before);
    A->t_since_factor += A->row.t_total / 1e3;
    if (policy(A, e)) return e->code;
    return after_solve(A, e);
}

void kt_aug_free(kt_aug *A)
{
    if (!A) return;
    aug_job_cancel(A);
    aug_solve_free(A);
    aug_base_free(A->base);
    aug_state_free(A);
    if (A->c_started) cholmod_finish(&A->c);
    free(A);
}
