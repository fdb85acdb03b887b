/* test_chol.c: the CHOLMOD factor-and-check helper: an SPD matrix factors and solves to its
 * known solution; a stiffness that is not positive definite is reported with the node and
 * component of the failing pivot (an unsupported box; a node in no element, which must be
 * named exactly); kt_chol_analyze, which makes CHOLMOD's METIS orderings itself (status
 * checked), gives the factor cholmod_analyze gives: the same permutation, nnz(L) and flops, with
 * METIS alone and with CHOLMOD's default strategy (AMD, METIS when AMD fills much). */
#include <stdlib.h>
#include <string.h>

#include "chol.h"
#include "fem.h"
#include "grid.h"
#include "kt_test.h"
#include "order.h"

/* The 1D Laplacian tridiag(-1, 2, -1) of order n, lower triangle stored. */
static cholmod_sparse *laplacian(int n, cholmod_common *c)
{
    cholmod_sparse *A = cholmod_allocate_sparse(n, n, 2 * n - 1, 1, 1, -1, CHOLMOD_REAL, c);
    if (!A) return NULL;
    int *Ap = A->p, *Ai = A->i, q = 0;
    double *Ax = A->x;
    for (int j = 0; j < n; j++) {
        Ap[j] = q;
        Ai[q] = j, Ax[q++] = 2;
        if (j + 1 < n) Ai[q] = j + 1, Ax[q++] = -1;
    }
    Ap[n] = q;
    return A;
}

static void test_spd(cholmod_common *c)
{
    enum { N = 30 };
    cholmod_sparse *A = laplacian(N, c);
    CHECK(A != NULL, "allocate");
    if (!A) return;
    kt_err e = {0};
    cholmod_factor *L = kt_chol_analyze_factor(A, c, "laplacian", &e);
    CHECK(L != NULL && e.code == 0, "%s", e.msg);
    if (!L) {
        cholmod_free_sparse(&A, c);
        return;
    }
    CHECK(L->is_super, "the helper makes a supernodal factor");
    /* x_i = i^2 - 3i: b = A x, then solve and compare */
    double xs[N], b[N], x[N];
    for (int i = 0; i < N; i++) xs[i] = (double)i * i - 3.0 * i;
    for (int i = 0; i < N; i++) b[i] = 2 * xs[i] - (i > 0 ? xs[i - 1] : 0) - (i + 1 < N ? xs[i + 1] : 0);
    cholmod_dense B = kt_chol_column(b, N);
    cholmod_dense *X = cholmod_solve(CHOLMOD_A, L, &B, c);
    CHECK(X != NULL, "solve");
    if (X) {
        memcpy(x, X->x, sizeof x);
        double err = 0, mag = 0;
        for (int i = 0; i < N; i++) err = fmax(err, fabs(x[i] - xs[i])), mag = fmax(mag, fabs(xs[i]));
        CHECK(err <= 1e-11 * mag, "solution error %.3g of %.3g", err, mag);
        cholmod_free_dense(&X, c);
    }
    /* the determinant of the Laplacian of order n is n + 1: product of the pivots */
    cholmod_factor *Ls = cholmod_copy_factor(L, c);
    if (Ls && cholmod_change_factor(CHOLMOD_REAL, 1, 0, 1, 1, Ls, c)) {
        const int *Lp = Ls->p;
        const double *Lx = Ls->x;
        double logdet = 0;
        for (int j = 0; j < N; j++) logdet += 2 * log(Lx[Lp[j]]);
        CHECK_NEAR(logdet, log(N + 1.0), 1e-12, "log det = log(n + 1)");
    } else {
        CHECK(0, "could not convert the factor to simplicial");
    }
    cholmod_free_factor(&Ls, c);
    /* refactor the same pattern with new values through kt_chol_factor: 3 * A */
    double *Ax = A->x;
    for (size_t k = 0; k < A->nzmax; k++) Ax[k] *= 3;
    CHECK(kt_chol_factor(A, L, c, "scaled", &e) == 0, "%s", e.msg);
    cholmod_dense *X3 = cholmod_solve(CHOLMOD_A, L, &B, c);
    if (X3) {
        const double *x3 = X3->x;
        double err = 0;
        for (int i = 0; i < N; i++) err = fmax(err, fabs(3 * x3[i] - xs[i]));
        CHECK(err <= 1e-10, "refactored solution error %.3g", err);
        cholmod_free_dense(&X3, c);
    }
    /* the same pattern made indefinite at DOF 3*5 + 1 = 16 (node 6, y): the pivot is named */
    Ax[((int *)A->p)[16]] = -1;
    kt_err e2 = {0};
    CHECK(kt_chol_factor(A, L, c, "step 3", &e2) == KT_ERUN, "indefinite matrix factored");
    /* every leading block that avoids DOF 16 is a block of the Laplacian (definite), and the
     * pivot of 16 is at most -1 whenever it comes: the failure is there, in any ordering */
    const char *pre = "step 3: stiffness matrix is not positive definite at node 6, DOF y (pivot ";
    CHECK(strncmp(e2.msg, pre, strlen(pre)) == 0 && strstr(e2.msg, " of 30)"), "'%s'", e2.msg);
    cholmod_free_factor(&L, c);
    cholmod_free_sparse(&A, c);

    /* a 1 x 1 negative matrix: the only DOF is node 1, x */
    cholmod_sparse *M = laplacian(1, c);
    ((double *)M->x)[0] = -4;
    kt_err e3 = {0};
    cholmod_factor *Lm = kt_chol_analyze_factor(M, c, "tiny", &e3);
    CHECK(Lm == NULL && e3.code == KT_ERUN, "negative 1x1 factored");
    CHECK(strstr(e3.msg, "at node 1, DOF x (pivot 1 of 1)") != NULL, "'%s'", e3.msg);
    cholmod_free_factor(&Lm, c);
    cholmod_free_sparse(&M, c);
}

/* The whole mesh's stiffness with no DOF fixed: rigid motions make it singular. */
static void test_unsupported_box(cholmod_common *c)
{
    kt_mesh m;
    kt_err e = {0};
    CHECK(kt_grid_box(&m, 3, 3, 3, 2, 2, 2, &e) == 0, "%s", e.msg);
    kt_material mat[2] = {{0, 0}, {1.0, 0.3}};
    kt_materials mats = {.nmat = 2, .mat = mat};
    cholmod_sparse *K = kt_fem_assemble(&m, &mats, NULL, c, &e);
    CHECK(K != NULL, "%s", e.msg);
    if (!K) return;
    kt_err e2 = {0};
    cholmod_factor *L = kt_chol_analyze_factor(K, c, "free box", &e2);
    CHECK(L == NULL && e2.code == KT_ERUN, "a free box factored");
    int node = 0;
    char comp = 0;
    size_t piv = 0, n = 0;
    const char *at = strstr(e2.msg, "at node ");
    int got = at ? sscanf(at, "at node %d, DOF %c (pivot %zu of %zu)", &node, &comp, &piv, &n) : 0;
    CHECK(strncmp(e2.msg, "free box: ", 10) == 0 && got == 4, "'%s'", e2.msg);
    CHECK(node >= 1 && node <= m.nn && (comp == 'x' || comp == 'y' || comp == 'z'), "node %d comp %c", node, comp);
    /* a leading block is singular only if it holds the support of a rigid motion, and every
     * rigid motion moves at least nn DOFs (a translation): no failure before pivot nn */
    CHECK(n == 3 * (size_t)m.nn && piv >= (size_t)m.nn && piv <= n, "pivot %zu of %zu", piv, n);
    cholmod_free_factor(&L, c);
    cholmod_free_sparse(&K, c);

    /* fixing zmin makes it definite */
    unsigned char *fixed = calloc(3 * (size_t)m.nn, 1);
    if (!fixed) exit(1);
    for (int i = 0; i < m.nn; i++)
        if (m.xyz[3 * i + 2] == 0) fixed[3 * i] = fixed[3 * i + 1] = fixed[3 * i + 2] = 1;
    K = kt_fem_assemble(&m, &mats, fixed, c, &e);
    L = K ? kt_chol_analyze_factor(K, c, "fixed box", &e) : NULL;
    CHECK(L != NULL && e.code == 0, "fixed box: %s", e.msg);
    cholmod_free_factor(&L, c);
    cholmod_free_sparse(&K, c);

    /* a node in no element (the last one), the rest held: exactly that node is named */
    double *xyz = realloc(m.xyz, sizeof(double) * 3 * (size_t)(m.nn + 1));
    unsigned char *fx = realloc(fixed, 3 * (size_t)(m.nn + 1));
    if (!xyz || !fx) exit(1);
    m.xyz = xyz;
    fixed = fx;
    xyz[3 * m.nn] = 5, xyz[3 * m.nn + 1] = 5, xyz[3 * m.nn + 2] = 5;
    fixed[3 * m.nn] = fixed[3 * m.nn + 1] = fixed[3 * m.nn + 2] = 0;
    m.nn++;
    kt_err e3 = {0};
    K = kt_fem_assemble(&m, &mats, fixed, c, &e3);
    CHECK(K != NULL, "%s", e3.msg);
    if (K) {
        L = kt_chol_analyze_factor(K, c, "orphan", &e3);
        char want[64];
        snprintf(want, sizeof want, "at node %d, DOF ", m.nn);
        CHECK(L == NULL && e3.code == KT_ERUN && strstr(e3.msg, want), "'%s' lacks '%s'", e3.msg, want);
        cholmod_free_factor(&L, c);
        cholmod_free_sparse(&K, c);
    }
    free(fixed);
    kt_mesh_free(&m);
}

/* The 7-point Laplacian of a k x k x k grid, lower triangle stored (pattern of a 3D stiffness). */
static cholmod_sparse *grid3(int k, cholmod_common *c)
{
    int n = k * k * k;
    cholmod_sparse *A = cholmod_allocate_sparse(n, n, 4 * (size_t)n, 1, 1, -1, CHOLMOD_REAL, c);
    if (!A) return NULL;
    int *Ap = A->p, *Ai = A->i, q = 0;
    double *Ax = A->x;
    for (int v = 0; v < n; v++) {
        int x = v % k, y = v / k % k, z = v / (k * k);
        Ap[v] = q;
        Ai[q] = v, Ax[q++] = 6.5;
        if (x + 1 < k) Ai[q] = v + 1, Ax[q++] = -1;
        if (y + 1 < k) Ai[q] = v + k, Ax[q++] = -1;
        if (z + 1 < k) Ai[q] = v + k * k, Ax[q++] = -1;
    }
    Ap[n] = q;
    return A;
}

/* cholmod_analyze and kt_chol_analyze, each with a fresh cholmod_common set by 'methods'
 * (1: METIS alone; 0: CHOLMOD's default strategy), on the grid of side k. */
static void same_analysis(int k, int methods)
{
    cholmod_common c1, c2;
    cholmod_start(&c1);
    cholmod_start(&c2);
    c1.print = c2.print = 0;
    if (methods == 1) {
        c1.nmethods = c2.nmethods = 1;
        c1.method[0].ordering = c2.method[0].ordering = CHOLMOD_METIS;
    }
    cholmod_sparse *A = grid3(k, &c1);
    kt_err e = {0};
    cholmod_factor *L1 = A ? cholmod_analyze(A, &c1) : NULL;
    cholmod_factor *L2 = A ? kt_chol_analyze(A, &c2, &e) : NULL;
    CHECK(L1 && L2 && e.code == 0, "grid %d, methods %d: both analyses (%s)", k, methods, e.msg);
    if (L1 && L2) {
        int n = (int)A->nrow, same = (int)L2->n == n;
        for (int i = 0; same && i < n; i++) same = ((int *)L1->Perm)[i] == ((int *)L2->Perm)[i];
        CHECK(same, "grid %d, methods %d: the same permutation (CHOLMOD chose %s)", k, methods,
              L1->ordering == CHOLMOD_METIS ? "METIS" : "AMD");
        CHECK(c1.lnz == c2.lnz && c1.fl == c2.fl && L1->is_super == L2->is_super,
              "grid %d, methods %d: nnz(L) %.0f / %.0f, flops %.0f / %.0f", k, methods, c1.lnz, c2.lnz,
              c1.fl, c2.fl);
        if (methods == 1) CHECK(L1->ordering == CHOLMOD_METIS, "METIS alone is METIS");
        printf("grid %d^3, %s: CHOLMOD chose %s, nnz(L) %.0f\n", k, methods ? "METIS alone" : "default strategy",
               L1->ordering == CHOLMOD_METIS ? "METIS" : "AMD", c1.lnz);
    }
    cholmod_free_factor(&L1, &c1);
    cholmod_free_factor(&L2, &c2);
    cholmod_free_sparse(&A, &c1);
    cholmod_finish(&c1);
    cholmod_finish(&c2);
}

static void test_metis(void)
{
    same_analysis(12, 1);
    same_analysis(4, 0);  /* small: AMD fills little, METIS not tried */
    same_analysis(24, 0); /* AMD fills much: METIS tried, the smaller factor kept */
    const char *s = kt_metis_status(-4);
    CHECK(strstr(s, "METIS_ERROR") && strstr(s, "SIGTERM"), "status -4 explained: %s", s);
}

int main(void)
{
    cholmod_common c;
    cholmod_start(&c);
    c.print = 0;
    c.error_handler = NULL;
    test_spd(&c);
    test_unsupported_box(&c);
    test_metis();
    cholmod_finish(&c);
    return kt_test_done("test_chol");
}
