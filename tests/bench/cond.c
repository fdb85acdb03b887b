/* bench_cond: condition number estimates of a scene's stiffness matrix (its free-DOF block).
 *
 *   bench_cond MESH SCENE [--steps K] [--tag NAME]
 *
 * Three numbers, from cheap to sound:
 *   pivot_ratio  max/min pivot of the LDL^T factor: a LOWER bound on cond(K) (every pivot of
 *                an SPD matrix lies in [lambda_min, lambda_max]); CHOLMOD's rcond is its
 *                inverse (square root for LL^T);
 *   lambda_max   Lanczos (K steps, full re-orthogonalisation) on K;
 *   lambda_min   Lanczos on K^-1, each product one solve with the factor;
 *   cond         lambda_max / lambda_min (Ritz values: lambda_max from below, lambda_min from
 *                above, so cond is a lower estimate; converged to the digits shown when
 *                lanczos_change, the relative change of cond over the last K/4 steps, is small).
 * stdout: TSV with a header, one row. */
#define _POSIX_C_SOURCE 200809L
#include "bench.h"

typedef int (*op_fn)(void *ctx, const double *x, double *y);

typedef struct kop {
    cholmod_sparse *K;
    cholmod_factor *L;
    cholmod_dense *X, *B;
    cholmod_common *c;
} kop;

/* y = K x, K lower-stored symmetric. */
static int apply_k(void *ctx, const double *x, double *y)
{
    kop *k = ctx;
    const cholmod_sparse *K = k->K;
    const int *Kp = K->p, *Ki = K->i;
    const double *Kx = K->x;
    int n = (int)K->ncol;
    memset(y, 0, sizeof(double) * n);
    for (int j = 0; j < n; j++) {
        double s = 0;
        for (int p = Kp[j]; p < Kp[j + 1]; p++) {
            int i = Ki[p];
            s += Kx[p] * x[i];
            if (i != j) y[i] += Kx[p] * x[j];
        }
        y[j] += s;
    }
    return 0;
}

/* y = K^-1 x with the factor. */
static int apply_kinv(void *ctx, const double *x, double *y)
{
    kop *k = ctx;
    memcpy(k->B->x, x, sizeof(double) * k->B->nrow);
    cholmod_dense *X = cholmod_solve(CHOLMOD_A, k->L, k->B, k->c);
    if (!X) return -1;
    memcpy(y, X->x, sizeof(double) * k->B->nrow);
    cholmod_free_dense(&X, k->c);
    return 0;
}

/* Sturm count: eigenvalues of the tridiagonal (a, b) below x. */
static int sturm(const double *a, const double *b, int k, double x)
{
    int cnt = 0;
    double q = 1;
    for (int i = 0; i < k; i++) {
        q = a[i] - x - (i > 0 ? b[i - 1] * b[i - 1] / q : 0);
        if (q == 0) q = -1e-300;
        cnt += q < 0;
    }
    return cnt;
}

/* Largest eigenvalue of the k x k tridiagonal by bisection. */
static double tri_max(const double *a, const double *b, int k)
{
    double lo = INFINITY, hi = -INFINITY;
    for (int i = 0; i < k; i++) {
        double r = (i > 0 ? fabs(b[i - 1]) : 0) + (i + 1 < k ? fabs(b[i]) : 0);
        lo = fmin(lo, a[i] - r);
        hi = fmax(hi, a[i] + r);
    }
    for (int it = 0; it < 200 && hi - lo > 1e-15 * fabs(hi); it++) {
        double mid = 0.5 * (lo + hi);
        if (sturm(a, b, k, mid) == k) hi = mid;
        else lo = mid;
    }
    return 0.5 * (lo + hi);
}

/* Lanczos with full re-orthogonalisation from a fixed pseudo-random start: the largest
 * eigenvalue of op after k steps, and after 3k/4 steps (convergence check). */
static int lanczos_max(int n, op_fn op, void *ctx, int k, double *lmax, double *lprev, kt_err *e)
{
    double *V = kt_calloc((size_t)n * (k + 1), sizeof(double), e);
    double *a = kt_calloc((size_t)k, sizeof(double), e), *b = kt_calloc((size_t)k, sizeof(double), e);
    double *w = kt_calloc((size_t)n, sizeof(double), e);
    if (e->code) goto done;
    unsigned s = 12345u;
    double nrm = 0;
    for (int i = 0; i < n; i++) {
        s = s * 1103515245u + 12345u;
        V[i] = (double)(s >> 8) / 16777216.0 - 0.5;
        nrm += V[i] * V[i];
    }
    for (int i = 0; i < n; i++) V[i] /= sqrt(nrm);
    int steps = k;
    for (int j = 0; j < k; j++) {
        double *v = V + (size_t)j * n;
        if (op(ctx, v, w)) {
            kt_fail(e, KT_ERUN, "operator failed");
            goto done;
        }
        for (int pass = 0; pass < 2; pass++) /* twice is enough (Kahan) */
            for (int q = 0; q <= j; q++) {
                const double *u = V + (size_t)q * n;
                double d = 0;
                for (int i = 0; i < n; i++) d += u[i] * w[i];
                if (pass == 0 && q == j) a[j] = d;
                else if (pass == 1 && q == j) a[j] += d;
                for (int i = 0; i < n; i++) w[i] -= d * u[i];
            }
        double bn = 0;
        for (int i = 0; i < n; i++) bn += w[i] * w[i];
        bn = sqrt(bn);
        if (j == (3 * k) / 4 - 1) *lprev = tri_max(a, b, j + 1);
        if (bn < 1e-14 * fabs(a[j])) { /* invariant subspace: exact */
            steps = j + 1;
            break;
        }
        b[j] = bn;
        double *vn = V + (size_t)(j + 1) * n;
        for (int i = 0; i < n; i++) vn[i] = w[i] / bn;
    }
    *lmax = tri_max(a, b, steps);
    if (steps < (3 * k) / 4) *lprev = *lmax;
done:
    free(V), free(a), free(b), free(w);
    return e->code;
}

/* Smallest mean-ratio quality 12 (3V)^(2/3) / sum of squared edges over the tets' vertices
 * (1 regular, 0 degenerate): the slivers the stability cases ask about. */
static double min_quality(const kt_mesh *m)
{
    int nv = kt_tet_nv(m->order);
    double q = INFINITY;
    for (int t = 0; t < m->ne; t++) {
        const double *x[4];
        for (int k = 0; k < 4; k++) x[k] = m->xyz + 3 * (size_t)m->tet[(size_t)t * nv + k];
        double v = fabs(kt_tet_volume(x[0], x[1], x[2], x[3])), l2 = 0;
        for (int a = 0; a < 4; a++)
            for (int b = a + 1; b < 4; b++)
                for (int c = 0; c < 3; c++) l2 += (x[a][c] - x[b][c]) * (x[a][c] - x[b][c]);
        q = fmin(q, 12.0 * pow(3.0 * v, 2.0 / 3.0) / l2);
    }
    return q;
}

int main(int argc, char **argv)
{
    const char *mesh = NULL, *scene = NULL, *tag = "-";
    int steps = 60;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--steps") && i + 1 < argc && !kt_parse_int(argv[i + 1], &steps)) i++;
        else if (!strcmp(argv[i], "--tag") && i + 1 < argc) tag = argv[++i];
        else if (argv[i][0] != '-' && !mesh) mesh = argv[i];
        else if (argv[i][0] != '-' && !scene) scene = argv[i];
        else mesh = scene = NULL, i = argc;
    }
    if (!mesh || !scene || steps < 4) {
        fprintf(stderr, "usage: bench_cond MESH SCENE [--steps K >= 4] [--tag NAME]\n");
        return 2;
    }
    kt_err e = {0};
    bench_problem p;
    cholmod_common c;
    cholmod_start(&c);
    int *map = NULL, nf = 0;
    kop k = {0};
    k.c = &c;
    double t0 = kt_now();
    if (bench_problem_load(&p, mesh, scene, &e) || !(k.K = bench_free_block(&p, &map, &nf, &c, &e)))
        goto done;
    /* METIS, supernodal LL^T (fast), then simplicial so that diag(L)^2 gives the pivots */
    if (!(k.L = bench_analyze(k.K, "metis", 1, &c, &e)) || bench_factorize(k.K, k.L, &c, &e))
        goto done;
    if (!cholmod_change_factor(CHOLMOD_REAL, 1, 0, 1, 1, k.L, &c)) {
        kt_fail(&e, KT_ERUN, "cholmod_change_factor failed (status %d)", c.status);
        goto done;
    }
    const int *Lp = k.L->p;
    const double *Lx = k.L->x;
    double dmin = INFINITY, dmax = 0;
    for (int j = 0; j < nf; j++) {
        double d = k.L->is_ll ? Lx[Lp[j]] * Lx[Lp[j]] : Lx[Lp[j]];
        dmin = fmin(dmin, d);
        dmax = fmax(dmax, d);
    }
    k.B = cholmod_zeros(nf, 1, CHOLMOD_REAL, &c);
    if (!k.B) {
        kt_fail(&e, KT_ERUN, "out of memory");
        goto done;
    }
    double lmax, lmax_p, imax, imax_p;
    if (lanczos_max(nf, apply_k, &k, steps, &lmax, &lmax_p, &e) ||
        lanczos_max(nf, apply_kinv, &k, steps, &imax, &imax_p, &e))
        goto done;
    double cond = lmax * imax, cond_p = lmax_p * imax_p;
    printf("tag\tn_free\tpivot_ratio\tcholmod_rcond\tlambda_max\tlambda_min\tcond\t"
           "lanczos_steps\tlanczos_change\tmin_quality\tseconds\n");
    printf("%s\t%d\t%.3e\t%.3e\t%.6e\t%.6e\t%.4e\t%d\t%.1e\t%.4f\t%.2f\n", tag, nf, dmax / dmin,
           cholmod_rcond(k.L, &c), lmax, 1.0 / imax, cond, steps, fabs(cond - cond_p) / cond,
           min_quality(&p.mesh), kt_now() - t0);
done:
    if (e.code) fprintf(stderr, "bench_cond: %s\n", e.msg);
    cholmod_free_dense(&k.B, &c);
    cholmod_free_factor(&k.L, &c);
    cholmod_free_sparse(&k.K, &c);
    free(map);
    bench_problem_free(&p);
    cholmod_finish(&c);
    return e.code;
}
