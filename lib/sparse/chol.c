/* chol.c: CHOLMOD factorization with the bad pivot named by node and component. */
#include "chol.h"

#include <metis.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "order.h"

static const char COMPONENT[3] = {'x', 'y', 'z'};

/* CHOLMOD's errors (status < 0) and warnings on stderr, one line each; the not-positive-definite
 * warning is the caller's to report. */
static void to_stderr(int status, const char *file, int line, const char *message)
{
    if (status == CHOLMOD_NOT_POSDEF) return;
    fprintf(stderr, "CHOLMOD %s: %s (%s:%d)\n", status < 0 ? "error" : "warning", message ? message : "",
            file ? file : "?", line);
}

void kt_chol_start(cholmod_common *c)
{
    cholmod_start(c);
    c->print = 0;
    c->error_handler = to_stderr;
}

int kt_chol_budget(const cholmod_factor *L, const cholmod_common *c, const char *what, kt_err *e)
{
    if (L->xtype != CHOLMOD_PATTERN) return KT_OK;
    double vals = L->is_super ? (double)L->xsize + (double)L->maxcsize : c->lnz;
    char w[256];
    snprintf(w, sizeof w, "%s: the Cholesky factor", what);
    return kt_mem_budget(sizeof(double) * vals, w, e);
}

int kt_chol_failed(int status, const char *what, kt_err *e)
{
    if (status == CHOLMOD_OUT_OF_MEMORY)
        return kt_fail(e, KT_ERUN, "%s: CHOLMOD factorization failed: out of memory", what);
    return kt_fail(e, KT_ERUN, "%s: CHOLMOD factorization failed (status %d)", what, status);
}

int kt_chol_factor(cholmod_sparse *A, cholmod_factor *L, cholmod_common *c, const char *what,
                   kt_err *e)
{
    if (kt_chol_budget(L, c, what, e)) return e->code;
    cholmod_factorize(A, L, c);
    if (c->status != CHOLMOD_OK && c->status != CHOLMOD_NOT_POSDEF)
        return kt_chol_failed(c->status, what, e);
    if (c->status == CHOLMOD_NOT_POSDEF || L->minor < L->n) {
        int dof = L->Perm ? ((const int *)L->Perm)[L->minor] : (int)L->minor;
        return kt_fail(e, KT_ERUN, "%s: stiffness matrix is not positive definite at node %d, DOF %c "
                       "(pivot %zu of %zu): is a body free to move rigidly, or a node in no element?",
                       what, dof / 3 + 1, COMPONENT[dof % 3], L->minor + 1, L->n);
    }
    return KT_OK;
}

/* A's graph as CHOLMOD's METIS and AMD wrappers build it: A + A' without the diagonal. */
static cholmod_sparse *graph(cholmod_sparse *A, cholmod_common *c, kt_err *e)
{
    cholmod_sparse *B = cholmod_copy(A, 0, -1, c);
    if (!B) kt_fail(e, KT_ERUN, "CHOLMOD could not form the matrix graph (status %d)", c->status);
    return B;
}

/* Analysis with METIS's ordering of the graph B of A, made here and given to CHOLMOD
 * (postordered as c says); as CHOLMOD's wrapper, the identity for a B without edges or a
 * large dense one. */
static cholmod_factor *analyze_metis(cholmod_sparse *A, cholmod_sparse *B, cholmod_common *c, kt_err *e)
{
    size_t n = A->nrow;
    double nz = ((const int *)B->p)[n];
    int *perm = kt_calloc(n ? n : 1, sizeof(int), e);
    idx_t *iperm = kt_calloc(n ? n : 1, sizeof(idx_t), e);
    int st = METIS_OK;
    if (!perm || !iperm) {
        st = METIS_ERROR_MEMORY;
    } else if (nz == 0 || (c->metis_nswitch > 0 && n > c->metis_nswitch &&
                           nz / ((double)n * (double)n) > c->metis_dswitch)) {
        for (size_t k = 0; k < n; k++) perm[k] = (int)k;
    } else {
        st = kt_metis_nodend((int)n, (const int *)B->p, (const int *)B->i, NULL, perm, (int *)iperm);
        if (st != METIS_OK) kt_fail(e, KT_ERUN, "METIS_NodeND failed (%s)", kt_metis_status(st));
    }
    cholmod_factor *L = NULL;
    if (st == METIS_OK) {
        int nm = c->nmethods, ord = c->method[0].ordering;
        c->nmethods = 1;
        c->method[0].ordering = CHOLMOD_GIVEN;
        L = cholmod_analyze_p(A, perm, NULL, 0, c);
        c->nmethods = nm;
        c->method[0].ordering = ord;
        if (!L) kt_fail(e, KT_ERUN, "CHOLMOD analysis failed (status %d)", c->status);
    }
    free(perm);
    free(iperm);
    return L;
}

/* CHOLMOD's default strategy with no user ordering, on the graph B of A: AMD; METIS only when
 * AMD's ordering takes 500 or more flops per nonzero of L and fills A (anz: its lower triangle
 * with the diagonal) at least 5 times over; the smaller nnz(L) kept, AMD on a tie. */
static cholmod_factor *analyze_default(cholmod_sparse *A, cholmod_sparse *B, cholmod_common *c, kt_err *e)
{
    double anz = ((const int *)B->p)[A->nrow] / 2 + (double)A->nrow;
    int nm = c->nmethods, ord = c->method[0].ordering;
    c->nmethods = 1;
    c->method[0].ordering = CHOLMOD_AMD;
    cholmod_factor *La = cholmod_analyze(A, c);
    double lnz = c->method[0].lnz, fl = c->method[0].fl, c_lnz = c->lnz, c_fl = c->fl;
    c->nmethods = nm;
    c->method[0].ordering = ord;
    if (!La) {
        kt_fail(e, KT_ERUN, "CHOLMOD analysis (AMD) failed (status %d)", c->status);
        return NULL;
    }
    if (fl < 500 * lnz || lnz < 5 * anz) return La;
    cholmod_factor *Lm = analyze_metis(A, B, c, e);
    if (!Lm) {
        cholmod_free_factor(&La, c);
        return NULL;
    }
    if (c->method[0].lnz < lnz) {
        cholmod_free_factor(&La, c);
        return Lm;
    }
    cholmod_free_factor(&Lm, c);
    c->lnz = c_lnz, c->fl = c_fl; /* AMD's analysis, as cholmod_analyze leaves them */
    return La;
}

cholmod_factor *kt_chol_analyze(cholmod_sparse *A, cholmod_common *c, kt_err *e)
{
    int nm = c->nmethods;
    if (A->stype == 0 || nm > 1 || (nm == 1 && c->method[0].ordering != CHOLMOD_METIS)) {
        cholmod_factor *L = cholmod_analyze(A, c);
        if (!L) kt_fail(e, KT_ERUN, "CHOLMOD analysis failed (status %d)", c->status);
        return L;
    }
    cholmod_sparse *B = graph(A, c, e);
    if (!B) return NULL;
    cholmod_factor *L = nm == 1 ? analyze_metis(A, B, c, e) : analyze_default(A, B, c, e);
    cholmod_free_sparse(&B, c);
    return L;
}

cholmod_factor *kt_chol_analyze_factor(cholmod_sparse *A, cholmod_common *c, const char *what,
                                       kt_err *e)
{
    int saved = c->supernodal;
    c->supernodal = CHOLMOD_SUPERNODAL;
    kt_err ae = {0};
    cholmod_factor *L = kt_chol_analyze(A, c, &ae);
    c->supernodal = saved;
    if (!L) {
        kt_fail(e, ae.code ? ae.code : KT_ERUN, "%s: %s", what, ae.msg);
        return NULL;
    }
    if (kt_chol_factor(A, L, c, what, e)) cholmod_free_factor(&L, c);
    return L;
}

cholmod_dense kt_chol_column(double *x, size_t n)
{
    cholmod_dense B;
    memset(&B, 0, sizeof B);
    B.nrow = B.nzmax = B.d = n;
    B.ncol = 1;
    B.x = x;
    B.xtype = CHOLMOD_REAL;
    B.dtype = CHOLMOD_DOUBLE;
    return B;
}
