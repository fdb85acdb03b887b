/* aug_base.c: factorizations of R (at step 0 and in a background thread), what is precomputed
 * with each (R^-1 fh0, D^-1, the tridiagonal SPAI), and the swap to a fresh one. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "aug_impl.h"

int aug_analyze(cholmod_sparse *K, int ordering, int factor, cholmod_common *c,
                cholmod_factor **L, kt_err *e)
{
    c->nmethods = 1;
    c->method[0].ordering = ordering == KT_AUG_ORDER_AMD     ? CHOLMOD_AMD
                            : ordering == KT_AUG_ORDER_METIS ? CHOLMOD_METIS
                                                             : CHOLMOD_NATURAL;
    /* natural: keep mesh-prep's elimination order exactly (no postordering) */
    c->postorder = ordering != KT_AUG_ORDER_NATURAL;
    c->supernodal = factor == KT_AUG_FACTOR_SIMPLICIAL ? CHOLMOD_SIMPLICIAL : CHOLMOD_SUPERNODAL;
    c->final_ll = 0;
    *L = cholmod_analyze(K, c);
    if (!*L) return kt_fail(e, KT_ERUN, "CHOLMOD analyze failed (status %d)", c->status);
    return KT_OK;
}

void aug_snapshot_free(aug_snapshot *s)
{
    kt_mesh_free(&s->mesh);
    free(s->C);
    free(s->fh);
    memset(s, 0, sizeof *s);
}

int aug_snapshot_take(kt_aug *A, aug_snapshot *s, kt_err *e)
{
    memset(s, 0, sizeof *s);
    size_t n = 3 * (size_t)A->mesh.nn;
    s->step = A->step;
    s->mats = &A->mats;
    s->ordering = A->o.ordering;
    s->factor = A->o.factor;
    s->precond = A->o.precond;
    s->C = kt_calloc(n, 1, e);
    s->fh = kt_calloc(n, sizeof(double), e);
    if (e->code || kt_mesh_copy(&s->mesh, &A->mesh, e)) {
        aug_snapshot_free(s);
        return e->code;
    }
    memcpy(s->C, A->cons, n);
    for (size_t i = 0; i < n; i++) s->fh[i] = A->cons[i] ? A->g[i] : A->fh[i];
    return KT_OK;
}

void aug_base_free(aug_base *b)
{
    if (!b) return;
    if (b->started) {
        cholmod_free_factor(&b->L, &b->c);
        cholmod_free_sparse(&b->R, &b->c);
        cholmod_finish(&b->c);
    }
    free(b->B);
    free(b->fh0);
    free(b->y0);
    free(b->dinv);
    free(b->spai);
    free(b->perm);
    free(b->iperm);
    free(b);
}

/* Permutation of L (identity when natural) and D^-1 in the original numbering. */
static int factor_tables(aug_base *b, kt_err *e)
{
    int n = b->n0;
    b->perm = kt_calloc((size_t)n, sizeof(int), e);
    b->iperm = kt_calloc((size_t)n, sizeof(int), e);
    b->dinv = kt_calloc((size_t)n, sizeof(double), e);
    if (e->code) return e->code;
    const int *P = b->L->Perm, *Lp = b->L->p, *Lnz = b->L->nz;
    const double *Lx = b->L->x;
    double nnz = 0;
    for (int k = 0; k < n; k++) {
        b->perm[k] = (P && b->L->ordering != CHOLMOD_NATURAL) ? P[k] : k;
        b->iperm[b->perm[k]] = k;
        double d = Lx[Lp[k]];
        b->dinv[b->perm[k]] = 1.0 / (b->L->is_ll ? d * d : d);
        nnz += Lnz[k];
    }
    b->nnzL = nnz;
    return KT_OK;
}

/* Sorted-merge dot product of two columns of an unsymmetric CSC matrix. */
static double col_dot(const cholmod_sparse *A, int a, int b)
{
    const int *Ap = A->p, *Ai = A->i;
    const double *Ax = A->x;
    int p = Ap[a], q = Ap[b], pe = Ap[a + 1], qe = Ap[b + 1];
    double s = 0;
    while (p < pe && q < qe) {
        if (Ai[p] < Ai[q]) p++;
        else if (Ai[p] > Ai[q]) q++;
        else s += Ax[p++] * Ax[q++];
    }
    return s;
}

static double entry(const cholmod_sparse *A, int i, int j)
{
    const int *Ap = A->p, *Ai = A->i;
    for (int p = Ap[j]; p < Ap[j + 1]; p++)
        if (Ai[p] == i) return ((const double *)A->x)[p];
    return 0;
}

/* Solve the k x k (k <= 3) system G s = r by Gaussian elimination with partial pivoting. */
static void small_solve(int k, double G[3][3], double *r)
{
    for (int c = 0; c < k; c++) {
        int piv = c;
        for (int i = c + 1; i < k; i++)
            if (fabs(G[i][c]) > fabs(G[piv][c])) piv = i;
        for (int j = 0; j < k; j++) {
            double t = G[c][j];
            G[c][j] = G[piv][j];
            G[piv][j] = t;
        }
        double t = r[c];
        r[c] = r[piv];
        r[piv] = t;
        for (int i = c + 1; i < k; i++) {
            double f = G[c][c] != 0 ? G[i][c] / G[c][c] : 0;
            for (int j = c; j < k; j++) G[i][j] -= f * G[c][j];
            r[i] -= f * r[c];
        }
    }
    for (int i = k - 1; i >= 0; i--) {
        double s = r[i];
        for (int j = i + 1; j < k; j++) s -= G[i][j] * r[j];
        r[i] = G[i][i] != 0 ? s / G[i][i] : 0;
    }
}

/* Tridiagonal sparse approximate inverse (Benson and Frederickson): column j of S, on rows
 * j-1..j+1, minimizes ||R s_j - e_j||_2. */
static int build_spai(aug_base *b, kt_err *e)
{
    int n = b->n0;
    b->spai = kt_calloc(3 * (size_t)n, sizeof(double), e);
    if (!b->spai) return e->code;
    const cholmod_sparse *F = b->R;
    for (int j = 0; j < n; j++) {
        int lo = j > 0 ? j - 1 : j, hi = j < n - 1 ? j + 1 : j, k = hi - lo + 1;
        double G[3][3], r[3];
        for (int a = 0; a < k; a++) {
            for (int c = 0; c < k; c++) G[a][c] = col_dot(F, lo + a, lo + c);
            r[a] = entry(F, j, lo + a);
        }
        small_solve(k, G, r);
        for (int a = 0; a < k; a++) b->spai[3 * (size_t)j + (lo + a - j + 1)] = r[a];
    }
    return KT_OK;
}

/* Keep R with both triangles, sorted: its columns give the residual weights and the SPAI. */
static int full_matrix(aug_base *b, kt_err *e)
{
    cholmod_sparse *F = cholmod_copy(b->R, 0, 1, &b->c);
    if (!F || !cholmod_sort(F, &b->c)) {
        cholmod_free_sparse(&F, &b->c);
        return kt_fail(e, KT_ERUN, "CHOLMOD copy failed (status %d)", b->c.status);
    }
    cholmod_free_sparse(&b->R, &b->c);
    b->R = F;
    return KT_OK;
}

/* R^-1 fh0 with a dense solve. */
static int base_rhs(aug_base *b, const double *fh, kt_err *e)
{
    size_t n = (size_t)b->n0;
    b->fh0 = kt_calloc(n, sizeof(double), e);
    b->y0 = kt_calloc(n, sizeof(double), e);
    if (e->code) return e->code;
    memcpy(b->fh0, fh, n * sizeof(double));
    cholmod_dense B = kt_chol_column(b->fh0, n);
    cholmod_dense *X = cholmod_solve(CHOLMOD_A, b->L, &B, &b->c);
    if (!X) return kt_fail(e, KT_ERUN, "CHOLMOD solve failed (status %d)", b->c.status);
    memcpy(b->y0, X->x, n * sizeof(double));
    cholmod_free_dense(&X, &b->c);
    return KT_OK;
}

aug_base *aug_base_build(const aug_snapshot *s, kt_err *e)
{
    double t0 = kt_now();
    aug_base *b = kt_calloc(1, sizeof *b, e);
    if (!b) return NULL;
    cholmod_start(&b->c);
    b->started = 1;
    b->step = s->step;
    b->n0 = 3 * s->mesh.nn;
    b->B = kt_calloc((size_t)b->n0, 1, e);
    if (b->B) memcpy(b->B, s->C, (size_t)b->n0);
    if (!e->code) b->R = kt_fem_assemble(&s->mesh, s->mats, s->C, &b->c, e);
    if (!e->code) aug_analyze(b->R, s->ordering, s->factor, &b->c, &b->L, e);
    if (!e->code) kt_chol_factor(b->R, b->L, &b->c, "augmented", e);
    if (!e->code) full_matrix(b, e);
    /* Bset solves need a simplicial factor: convert once here, not in the first step */
    if (!e->code && b->L->is_super &&
        !cholmod_change_factor(CHOLMOD_REAL, 1, 0, 0, 0, b->L, &b->c))
        kt_fail(e, KT_ERUN, "CHOLMOD supernodal-to-simplicial conversion failed (status %d)",
                b->c.status);
    if (!e->code) factor_tables(b, e);
    if (!e->code) base_rhs(b, s->fh, e);
    if (!e->code && s->precond == KT_AUG_PRECOND_SPAI) build_spai(b, e);
    if (e->code) {
        aug_base_free(b);
        return NULL;
    }
    b->t_factor = kt_now() - t0;
    return b;
}

/* ------------------------------------------------------- background thread */

static void *job_main(void *arg)
{
    aug_job *j = arg;
    j->base = aug_base_build(&j->snap, &j->err);
    pthread_mutex_lock(&j->mu);
    j->done = 1;
    pthread_mutex_unlock(&j->mu);
    return NULL;
}

int aug_job_start(kt_aug *A, kt_err *e)
{
    if (A->job) return KT_OK;
    aug_job *j = kt_calloc(1, sizeof *j, e);
    if (!j) return e->code;
    if (aug_snapshot_take(A, &j->snap, e)) {
        free(j);
        return e->code;
    }
    pthread_mutex_init(&j->mu, NULL);
    if (pthread_create(&j->th, NULL, job_main, j) != 0) {
        pthread_mutex_destroy(&j->mu);
        aug_snapshot_free(&j->snap);
        free(j);
        return kt_fail(e, KT_ERUN, "cannot start the re-factorization thread");
    }
    A->job = j;
    return KT_OK;
}

static void job_free(aug_job *j)
{
    pthread_mutex_destroy(&j->mu);
    aug_snapshot_free(&j->snap);
    aug_base_free(j->base);
    free(j);
}

int aug_job_poll(kt_aug *A, int wait, kt_err *e)
{
    aug_job *j = A->job;
    if (!j) return 0;
    pthread_mutex_lock(&j->mu);
    int done = j->done;
    pthread_mutex_unlock(&j->mu);
    if (!done && !wait) return 0;
    pthread_join(j->th, NULL);
    A->job = NULL;
    if (j->err.code) {
        kt_fail(e, j->err.code, "background re-factorization: %s", j->err.msg);
        job_free(j);
        return -1;
    }
    aug_base *b = j->base;
    j->base = NULL;
    job_free(j);
    if (aug_install(A, b, e)) return -1;
    return 1;
}

void aug_job_cancel(kt_aug *A)
{
    if (!A->job) return;
    pthread_join(A->job->th, NULL); /* CHOLMOD cannot be interrupted: wait for it */
    job_free(A->job);
    A->job = NULL;
}

/* Workspaces sized for the new base's n0. */
static int main_workspaces(kt_aug *A, int n0, kt_err *e)
{
    if (A->ws_n == n0 && A->Bd) return KT_OK;
    cholmod_free_dense(&A->Bd, &A->c);
    cholmod_free_sparse(&A->Bset, &A->c);
    A->Bd = cholmod_zeros(n0, 1, CHOLMOD_REAL, &A->c);
    A->Bset = cholmod_allocate_sparse(n0, 1, n0, 0, 1, 0, CHOLMOD_PATTERN, &A->c);
    if (!A->Bd || !A->Bset) return kt_fail(e, KT_ERUN, "out of memory for solve workspaces");
    A->ws_n = n0;
    return KT_OK;
}

int aug_install(kt_aug *A, aug_base *b, kt_err *e)
{
    aug_base_free(A->base);
    A->base = b;
    for (int i = 0; i < b->n0; i++)
        if (b->B[i]) A->fh[i] = A->g[i];
    A->t_since_factor = 0;
    if (main_workspaces(A, b->n0, e)) return e->code;
    return aug_rebuild_lists(A, e);
}
