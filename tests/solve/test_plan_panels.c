/* test_plan_panels.c: the planned factor with its increments' block stored in panels
 * (kt_plan_split_panels, aug_plan.h) on random sparse SPD matrices shaped like the plan's
 * [K C; C^T D] (a grid-like intact block in AMD order, then coupled "increments" in their own
 * order): the split factor holds the same L as CHOLMOD's own supernodes (every entry, to
 * rounding), CHOLMOD's workspace sizes cover it, and the planned substitutions on it
 * (kt_plan_forward, continued at any column, and kt_plan_back on a released prefix) solve the
 * whole matrix and every leading block as CHOLMOD's solve and a fresh factorization of the
 * block do; their blocked forms for several right-hand sides at once (kt_plan_forward_multi /
 * kt_plan_back_multi, supernodal and simplicial) equal them column by column. The eye-level
 * check (augsolve --verify with and without panels) is tests/augsolve_panels.sh. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "aug_plan.h"
#include "kt_test.h"

typedef struct rnd {
    unsigned long long s;
} rnd;

static double uni(rnd *r) /* uniform in [0, 1) */
{
    r->s = r->s * 6364136223846793005ULL + 1442695040888963407ULL;
    return (double)(r->s >> 11) * (1.0 / 9007199254740992.0);
}

/* Lower triangle (i >= j) of a random SPD matrix: an nx x ny x nz 7-point grid for the intact
 * block, then m variables each coupled to 4 random intact ones and 2 earlier variables;
 * diagonally dominant. */
typedef struct trip {
    int n, nz, cap;
    int *i, *j;
    double *x;
} trip;

static void add(trip *t, int i, int j, double x)
{
    if (t->nz == t->cap) {
        t->cap = t->cap ? 2 * t->cap : 1024;
        t->i = realloc(t->i, (size_t)t->cap * sizeof(int));
        t->j = realloc(t->j, (size_t)t->cap * sizeof(int));
        t->x = realloc(t->x, (size_t)t->cap * sizeof(double));
        CHECK(t->i && t->j && t->x, "out of memory");
    }
    if (i < j) {
        int s = i;
        i = j;
        j = s;
    }
    t->i[t->nz] = i;
    t->j[t->nz] = j;
    t->x[t->nz++] = x;
}

static void random_spd(trip *t, int nx, int ny, int nz, int m, unsigned long long seed)
{
    rnd r = {seed};
    int nK = nx * ny * nz;
    t->n = nK + m;
    double *diag = calloc((size_t)t->n, sizeof(double));
    CHECK(diag != NULL, "out of memory");
    for (int z = 0; z < nz; z++)
        for (int y = 0; y < ny; y++)
            for (int x = 0; x < nx; x++) {
                int a = x + nx * (y + ny * z), nb[3] = {x + 1 < nx ? a + 1 : -1,
                                                        y + 1 < ny ? a + nx : -1,
                                                        z + 1 < nz ? a + nx * ny : -1};
                for (int k = 0; k < 3; k++)
                    if (nb[k] >= 0) {
                        double v = uni(&r) * 2 - 1;
                        add(t, a, nb[k], v);
                        diag[a] += fabs(v);
                        diag[nb[k]] += fabs(v);
                    }
            }
    for (int c = 0; c < m; c++) {
        int v = nK + c;
        for (int k = 0; k < 6; k++) {
            int w = k < 4 ? (int)(uni(&r) * nK) : (c > 0 ? nK + (int)(uni(&r) * c) : -1);
            if (w < 0) continue;
            double x = uni(&r) * 2 - 1;
            add(t, v, w, x);
            diag[v] += fabs(x);
            diag[w] += fabs(x);
        }
    }
    for (int a = 0; a < t->n; a++) add(t, a, a, diag[a] + 0.5 + uni(&r));
    free(diag);
}

/* The leading n0 x n0 block of t as a CHOLMOD matrix (lower, stype -1). */
static cholmod_sparse *to_sparse(const trip *t, int n0, cholmod_common *c)
{
    cholmod_triplet *T = cholmod_allocate_triplet(n0, n0, t->nz, -1, CHOLMOD_REAL, c);
    CHECK(T != NULL, "triplet");
    int *Ti = T->i, *Tj = T->j;
    double *Tx = T->x;
    size_t k = 0;
    for (int q = 0; q < t->nz; q++)
        if (t->i[q] < n0 && t->j[q] < n0) {
            Ti[k] = t->i[q];
            Tj[k] = t->j[q];
            Tx[k++] = t->x[q];
        }
    T->nnz = k;
    cholmod_sparse *A = cholmod_triplet_to_sparse(T, k, c);
    cholmod_free_triplet(&T, c);
    CHECK(A != NULL, "sparse");
    return A;
}

/* The planned order: AMD on the intact block (postordered), then the m variables as given. */
static int *planned_order(const trip *t, int nK, cholmod_common *c)
{
    cholmod_sparse *B = to_sparse(t, nK, c);
    c->nmethods = 1;
    c->method[0].ordering = CHOLMOD_AMD;
    c->postorder = 1;
    c->supernodal = CHOLMOD_SIMPLICIAL;
    cholmod_factor *L = cholmod_analyze(B, c);
    CHECK(L != NULL, "analysis of the intact block");
    int *P = malloc((size_t)t->n * sizeof(int));
    CHECK(P != NULL, "out of memory");
    memcpy(P, L->Perm, (size_t)nK * sizeof(int));
    for (int q = nK; q < t->n; q++) P[q] = q;
    cholmod_free_factor(&L, c);
    cholmod_free_sparse(&B, c);
    return P;
}

/* Supernodal symbolic analysis in the given order, nothing reordered or postordered. */
static cholmod_factor *analyze(cholmod_sparse *A, int *P, cholmod_common *c)
{
    c->nmethods = 1;
    c->method[0].ordering = CHOLMOD_GIVEN;
    c->postorder = 0;
    c->supernodal = CHOLMOD_SUPERNODAL;
    c->final_ll = 0;
    cholmod_factor *L = cholmod_analyze_p(A, P, NULL, 0, c);
    CHECK(L != NULL && L->is_super, "analysis (status %d)", c->status);
    return L;
}

/* L as a dense n x n column-major lower triangle. */
static double *dense_L(const cholmod_factor *L)
{
    int n = (int)L->n;
    double *D = calloc((size_t)n * n, sizeof(double));
    CHECK(D != NULL, "out of memory");
    const int *S = L->super, *pi = L->pi, *px = L->px, *Ls = L->s;
    const double *Lx = L->x;
    for (size_t s = 0; s < L->nsuper; s++) {
        int k1 = S[s], nscol = S[s + 1] - k1, nsrow = pi[s + 1] - pi[s];
        for (int cc = 0; cc < nscol; cc++)
            for (int r = cc; r < nsrow; r++)
                D[(size_t)(k1 + cc) * n + Ls[pi[s] + r]] = Lx[px[s] + (size_t)cc * nsrow + r];
    }
    return D;
}

/* What CHOLMOD's numeric factorization needs of the partition: every supernode's rows sorted,
 * its first rows its own columns, the workspace sizes large enough for every update. */
static void check_partition(const cholmod_factor *L, int nK, int width, const char *name)
{
    const int *S = L->super, *pi = L->pi, *px = L->px, *Ls = L->s;
    int ns = (int)L->nsuper, n = (int)L->n;
    int *sup = malloc((size_t)n * sizeof(int));
    CHECK(sup != NULL, "out of memory");
    for (int s = 0; s < ns; s++)
        for (int j = S[s]; j < S[s + 1]; j++) sup[j] = s;
    size_t csize = 1, esize = 1, xsize = 0;
    for (int s = 0; s < ns; s++) {
        int nscol = S[s + 1] - S[s], nsrow = pi[s + 1] - pi[s];
        CHECK(nscol > 0 && nsrow >= nscol, "%s: supernode %d: %d columns, %d rows", name, s,
              nscol, nsrow);
        if (width > 0 && S[s + 1] > nK)
            CHECK(nscol <= width, "%s: supernode %d has %d columns (> %d)", name, s, nscol, width);
        CHECK(px[s] == (int)xsize, "%s: px[%d]", name, s);
        xsize += (size_t)nscol * nsrow;
        for (int q = 0; q < nscol; q++)
            CHECK(Ls[pi[s] + q] == S[s] + q, "%s: supernode %d row %d", name, s, q);
        for (int q = pi[s] + 1; q < pi[s + 1]; q++)
            CHECK(Ls[q] > Ls[q - 1], "%s: supernode %d rows not ascending", name, s);
        int p = pi[s] + nscol, pend = pi[s + 1];
        if ((size_t)(pend - p) > esize) esize = (size_t)(pend - p);
        while (p < pend) {
            int q = p;
            while (q < pend && sup[Ls[q]] == sup[Ls[p]]) q++;
            if ((size_t)(q - p) * (size_t)(pend - p) > csize) csize = (size_t)(q - p) * (pend - p);
            p = q;
        }
    }
    CHECK(xsize == L->xsize && (size_t)pi[ns] == L->ssize, "%s: xsize %zu vs %zu", name, xsize,
          L->xsize);
    CHECK(L->maxcsize >= csize && L->maxesize >= esize, "%s: workspace %zu %zu < %zu %zu", name,
          L->maxcsize, L->maxesize, csize, esize);
    free(sup);
}

static double max_abs_diff(const double *a, const double *b, size_t n, double *scale)
{
    double d = 0, s = 0;
    for (size_t i = 0; i < n; i++) {
        d = kt_nanmax(d, fabs(a[i] - b[i]));
        s = kt_nanmax(s, fabs(b[i]));
    }
    *scale = s;
    return d;
}

/* Y (n x nrhs, interleaved) through the column-by-column substitutions: forward split at cut,
 * rows >= N zeroed, back (supernodal: kt_plan_back; simplicial: CHOLMOD's L^T or D L^T). */
static void by_columns(const kt_plan_factor *F, double *work, int cut, int N, int nrhs,
                       const double *Y, double *X, cholmod_common *c)
{
    int n = F->nfree;
    double *y = malloc((size_t)n * sizeof(double));
    CHECK(y != NULL, "out of memory");
    for (int k = 0; k < nrhs; k++) {
        for (int q = 0; q < n; q++) y[q] = Y[(size_t)q * nrhs + k];
        kt_plan_forward(F, work, 0, cut, y);
        kt_plan_forward(F, work, cut, N, y);
        for (int q = N; q < n; q++) y[q] = 0;
        if (F->L->is_super) {
            kt_plan_back(F, NULL, work, N, y);
        } else {
            cholmod_dense Z = {(size_t)n, 1, (size_t)n, (size_t)n, y, NULL, CHOLMOD_REAL,
                               CHOLMOD_DOUBLE};
            cholmod_dense *Z1 = cholmod_solve(F->L->is_ll ? CHOLMOD_Lt : CHOLMOD_DLt, F->L, &Z, c);
            CHECK(Z1 != NULL, "CHOLMOD back substitution");
            memcpy(y, Z1->x, (size_t)n * sizeof(double));
            cholmod_free_dense(&Z1, c);
        }
        for (int q = 0; q < n; q++) X[(size_t)q * nrhs + k] = y[q];
    }
    free(y);
}

/* The blocked substitutions (kt_plan_forward_multi / kt_plan_back_multi, nrhs interleaved
 * right-hand sides) against the same substitutions column by column, on every leading block
 * N, the forward one split at a column and continued: equal to 1e-13 relative. Not continued
 * (upto = N: the rows of the unreleased increments neither read nor updated, as the
 * derivatives of augsolve --uncertainty run it), the forward substitution gives the solution
 * of the one that updates every row to 1e-13 relative (not bit for bit: the BLAS's dgemm on
 * fewer rows may sum in another order; 2 of the 24,000 cases here differ, by 1e-17). */
static void check_multi(const kt_plan_factor *F, int nK, int nrhs, unsigned long long seed,
                        const char *name, cholmod_common *c)
{
    int n = F->nfree, m = n - nK;
    size_t sz = (size_t)n * nrhs;
    double *Y = malloc(sz * sizeof(double)), *X = malloc(sz * sizeof(double));
    double *B = malloc(sz * sizeof(double)), *work = malloc((size_t)F->maxrow * nrhs * sizeof(double));
    double *Z = malloc(sz * sizeof(double));
    CHECK(Y && X && B && work && Z, "out of memory");
    rnd r = {seed + 29};
    for (size_t i = 0; i < sz; i++) B[i] = uni(&r) * 2 - 1;
    int Ns[] = {nK / 2, nK, nK + 1, nK + m / 2 + 1, n};
    for (int t = 0; t < 5; t++) {
        int N = Ns[t] < n ? Ns[t] : n, cut = N > nK + 2 ? nK + (N - nK) / 2 : N / 2;
        for (size_t i = 0; i < sz; i++) Y[i] = (int)(i / nrhs) < N ? B[i] : 0;
        by_columns(F, work, cut, N, nrhs, Y, X, c);
        kt_plan_forward_multi(F, work, 0, cut, nrhs, n, Y);
        kt_plan_forward_multi(F, work, cut, N, nrhs, n, Y);
        for (size_t i = (size_t)N * nrhs; i < sz; i++) Y[i] = 0;
        kt_plan_back_multi(F, NULL, work, N, nrhs, Y);
        double scale, d = max_abs_diff(Y, X, sz, &scale);
        CHECK(d <= 1e-13 * scale, "%s: %d right-hand sides, leading block %d (%s): blocked and "
              "column by column differ by %g (scale %g)", name, nrhs, N,
              F->L->is_super ? "supernodal" : "simplicial", d, scale);
        /* not continued: every row updated, or only those < N */
        for (int up = 0; up < 2; up++) {
            double *W = up ? Z : Y;
            for (size_t i = 0; i < sz; i++) W[i] = (int)(i / nrhs) < N ? B[i] : 0;
            kt_plan_forward_multi(F, work, 0, N, nrhs, up ? N : n, W);
            for (size_t i = (size_t)N * nrhs; i < sz; i++) W[i] = 0;
            kt_plan_back_multi(F, NULL, work, N, nrhs, W);
        }
        d = max_abs_diff(Y, Z, sz, &scale);
        CHECK(d <= 1e-13 * scale, "%s: %d right-hand sides, leading block %d (%s): the forward "
              "substitution on the rows < N alone and the whole one differ by %g (scale %g)",
              name, nrhs, N, F->L->is_super ? "supernodal" : "simplicial", d, scale);
    }
    free(Z);
    free(Y);
    free(X);
    free(B);
    free(work);
}

/* A simplicial factor in the planned order (LDL^T, or LL^T with ll), for check_multi. */
static void check_multi_simplicial(const trip *t, int nK, int ll, unsigned long long seed)
{
    char name[96];
    snprintf(name, sizeof name, "simplicial %s, seed %llu", ll ? "LL^T" : "LDL^T", seed);
    cholmod_common c;
    cholmod_start(&c);
    cholmod_sparse *A = to_sparse(t, t->n, &c);
    int *P = planned_order(t, nK, &c);
    c.nmethods = 1;
    c.method[0].ordering = CHOLMOD_GIVEN;
    c.postorder = 0;
    c.supernodal = CHOLMOD_SIMPLICIAL;
    c.final_ll = ll;
    cholmod_factor *L = cholmod_analyze_p(A, P, NULL, 0, &c);
    CHECK(L != NULL, "%s: analysis", name);
    cholmod_factorize(A, L, &c);
    CHECK(c.status == CHOLMOD_OK && !L->is_super && L->is_ll == ll, "%s: factorize", name);
    kt_plan_factor F = {0};
    F.L = L;
    F.nfree = t->n;
    F.nK = nK;
    kt_plan_subst_init(&F);
    for (int nrhs = 1; nrhs <= 5; nrhs += 2) check_multi(&F, nK, nrhs, seed, name, &c);
    free(P);
    cholmod_free_factor(&L, &c);
    cholmod_free_sparse(&A, &c);
    cholmod_finish(&c);
}

/* One matrix, one panel width: the same L, and the planned substitutions on the split factor
 * against CHOLMOD's solves. */
static void check_case(int nx, int ny, int nz, int m, int width, unsigned long long seed)
{
    char name[96];
    snprintf(name, sizeof name, "%dx%dx%d + %d, panels of %d, seed %llu", nx, ny, nz, m, width,
             seed);
    cholmod_common c;
    cholmod_start(&c);
    kt_err e = {0};
    trip t = {0};
    random_spd(&t, nx, ny, nz, m, seed);
    int n = t.n, nK = n - m;
    cholmod_sparse *A = to_sparse(&t, n, &c);
    int *P = planned_order(&t, nK, &c);
    cholmod_factor *L0 = analyze(A, P, &c), *L1 = analyze(A, P, &c);
    size_t ns0 = L0->nsuper, xs0 = L0->xsize;
    CHECK(kt_plan_split_panels(L1, nK, width, &c, &e) == KT_OK, "%s: split: %s", name, e.msg);
    check_partition(L1, nK, width, name);
    CHECK(L1->nsuper >= ns0 && L1->xsize <= xs0, "%s: %zu supernodes (%zu), xsize %zu (%zu)",
          name, L1->nsuper, ns0, L1->xsize, xs0);
    cholmod_factorize(A, L0, &c);
    CHECK(c.status == CHOLMOD_OK, "%s: factorize (status %d)", name, c.status);
    cholmod_factorize(A, L1, &c);
    CHECK(c.status == CHOLMOD_OK && L1->minor == L1->n, "%s: factorize split (status %d)", name,
          c.status);
    double *D0 = dense_L(L0), *D1 = dense_L(L1), scale;
    double d = max_abs_diff(D1, D0, (size_t)n * n, &scale);
    CHECK(d <= 1e-12 * scale, "%s: L differs by %g (scale %g)", name, d, scale);
    free(D0);
    free(D1);

    /* the substitutions on the split factor */
    kt_plan_factor F = {0};
    F.L = L1;
    F.nfree = n;
    F.nK = nK;
    kt_plan_subst_init(&F);
    CHECK(F.rows_sorted, "%s: rows not sorted", name);
    double *work = malloc((size_t)F.maxrow * sizeof(double));
    double *b = malloc((size_t)n * sizeof(double)), *y = malloc((size_t)n * sizeof(double));
    double *x = malloc((size_t)n * sizeof(double));
    CHECK(work && b && y && x, "out of memory");
    rnd r = {seed + 17};
    for (int i = 0; i < n; i++) b[i] = uni(&r) * 2 - 1;
    const int *Perm = L1->Perm;
    /* every leading block N (the whole matrix last), the forward substitution split at a column
     * inside the increments and continued */
    int Ns[] = {nK, nK + 1, nK + m / 3, nK + m / 2 + 1, n};
    for (int k = 0; k < 5; k++) {
        int N = Ns[k] < n ? Ns[k] : n, cut = N > nK + 2 ? nK + (N - nK) / 2 : N / 2;
        for (int q = 0; q < n; q++) y[q] = q < N ? b[Perm[q]] : 0;
        kt_plan_forward(&F, work, 0, cut, y);
        kt_plan_forward(&F, work, cut, N, y);
        for (int q = N; q < n; q++) y[q] = 0;
        kt_plan_back(&F, NULL, work, N, y);
        for (int q = 0; q < n; q++) x[Perm[q]] = y[q];
        /* the reference: CHOLMOD's own factor of the leading block (its own order) */
        cholmod_sparse *AN = to_sparse(&t, N, &c); /* P keeps the first nK + j variables */
        int *idx = malloc((size_t)N * sizeof(int));
        CHECK(idx != NULL, "out of memory");
        for (int q = 0; q < N; q++) idx[q] = Perm[q];
        int inside = 1;
        for (int q = 0; q < N; q++) inside &= idx[q] < N;
        CHECK(inside, "%s: the first %d positions are not the first %d variables", name, N, N);
        free(idx);
        c.nmethods = 0;
        c.postorder = 1;
        c.supernodal = CHOLMOD_AUTO;
        cholmod_factor *LN = cholmod_analyze(AN, &c);
        cholmod_factorize(AN, LN, &c);
        cholmod_dense *B = cholmod_zeros(N, 1, CHOLMOD_REAL, &c);
        memcpy(B->x, b, (size_t)N * sizeof(double));
        cholmod_dense *X = cholmod_solve(CHOLMOD_A, LN, B, &c);
        CHECK(X != NULL, "%s: reference solve", name);
        double dx = max_abs_diff(x, X->x, (size_t)N, &scale);
        CHECK(dx <= 1e-10 * scale, "%s: leading block %d: x differs by %g (scale %g)", name, N,
              dx, scale);
        double tail = 0;
        for (int i = N; i < n; i++) tail = kt_nanmax(tail, fabs(x[i]));
        CHECK(tail == 0, "%s: leading block %d: unreleased variables %g", name, N, tail);
        if (N == n) { /* and CHOLMOD's solve with the split factor itself */
            cholmod_dense *X1 = cholmod_solve(CHOLMOD_A, L1, B, &c);
            CHECK(X1 != NULL, "%s: CHOLMOD solve with the split factor", name);
            dx = max_abs_diff(x, X1->x, (size_t)n, &scale);
            CHECK(dx <= 1e-10 * scale, "%s: CHOLMOD's solve differs by %g", name, dx);
            cholmod_free_dense(&X1, &c);
        }
        cholmod_free_dense(&X, &c);
        cholmod_free_dense(&B, &c);
        cholmod_free_factor(&LN, &c);
        cholmod_free_sparse(&AN, &c);
    }
    for (int nrhs = 1; nrhs <= 5; nrhs += 2) check_multi(&F, nK, nrhs, seed, name, &c);
    if (width == 7) {
        check_multi_simplicial(&t, nK, 0, seed);
        check_multi_simplicial(&t, nK, 1, seed);
    }
    free(work);
    free(b);
    free(y);
    free(x);
    free(P);
    free(t.i);
    free(t.j);
    free(t.x);
    cholmod_free_factor(&L0, &c);
    cholmod_free_factor(&L1, &c);
    cholmod_free_sparse(&A, &c);
    cholmod_free_work(&c); /* the split frees what it replaces with the sizes it was given */
    CHECK(c.malloc_count == 0 && c.memory_inuse == 0, "%s: CHOLMOD blocks left: %zu (%zu bytes)",
          name, (size_t)c.malloc_count, (size_t)c.memory_inuse);
    cholmod_finish(&c);
}

int main(void)
{
    int widths[] = {1, 7, 32, 1000};
    for (int w = 0; w < 4; w++) check_case(7, 6, 5, 90, widths[w], 1);
    check_case(9, 8, 6, 150, 24, 2);
    check_case(4, 4, 3, 5, 2, 3); /* fewer increments than a panel's columns elsewhere */
    check_case(6, 5, 5, 0, 4, 4); /* no increments: nothing split */
    return kt_test_done("test_plan_panels");
}
