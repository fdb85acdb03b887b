/* test_fem_rigid.c: the unconstrained stiffness annihilates the six rigid-body modes (P1 and P2,
 * jittered and curved meshes, two materials); the sparse lower triangle equals an independent
 * dense assembly; hand-computed P1 entries; lifting; and the error paths (inverted element,
 * pressure on an interior face, bad material, unconstrained solve). */
#include <stdlib.h>
#include <string.h>

#include "fem.h"
#include "grid.h"
#include "kt_test.h"

static double rnd(unsigned long long *s) /* uniform in [-1, 1) */
{
    *s = *s * 6364136223846793005ULL + 1442695040888963407ULL;
    return (double)(*s >> 11) / (double)(1ULL << 52) - 1.0;
}

static int all_positive(const kt_mesh *m)
{
    int nv = kt_tet_nv(m->order);
    for (int i = 0; i < m->ne; i++) {
        const int *t = m->tet + (size_t)nv * i;
        if (!(kt_tet_volume(m->xyz + 3 * t[0], m->xyz + 3 * t[1], m->xyz + 3 * t[2],
                            m->xyz + 3 * t[3]) > 0))
            return 0;
    }
    return 1;
}

/* Move every listed node by up to amp in each coordinate, undoing a move that inverts a tet. */
static void jitter(kt_mesh *m, int first, int last, double amp, unsigned long long *seed)
{
    for (int i = first; i < last; i++) {
        double old[3];
        memcpy(old, m->xyz + 3 * i, sizeof old);
        for (int k = 0; k < 3; k++) m->xyz[3 * i + k] += amp * rnd(seed);
        if (!all_positive(m)) memcpy(m->xyz + 3 * i, old, sizeof old);
    }
}

/* A 4x4x4-node box, all nodes jittered, half the tets in a second, stiffer region; order 2
 * with mid-edge nodes moved off their edges (curved elements). */
static void make_mesh(kt_mesh *m, int order, kt_err *e)
{
    unsigned long long seed = 12345;
    kt_grid_box(m, 4, 4, 4, 3.0, 3.0, 3.0, e);
    jitter(m, 0, m->nn, 0.2, &seed);
    kt_mesh_add_group(m, 3, 2, "stiff", e);
    for (int i = 0; i < m->ne; i += 2) m->tet_tag[i] = 2;
    if (order == 2) {
        int nn1 = m->nn;
        kt_mesh_elevate(m, e);
        for (int i = nn1; i < m->nn; i++)
            for (int k = 0; k < 3; k++) m->xyz[3 * i + k] += 0.05 * rnd(&seed);
    }
}

static void rigid_mode(const kt_mesh *m, int r, double *u)
{
    for (int i = 0; i < m->nn; i++) {
        const double *x = m->xyz + 3 * i;
        double *v = u + 3 * i;
        v[0] = v[1] = v[2] = 0;
        if (r < 3) v[r] = 1;
        else if (r == 3) v[1] = -x[2], v[2] = x[1]; /* rotation about x */
        else if (r == 4) v[0] = x[2], v[2] = -x[0];
        else v[0] = -x[1], v[1] = x[0];
    }
}

static double max_abs(const double *x, size_t n)
{
    double s = 0;
    for (size_t i = 0; i < n; i++) s = fmax(s, fabs(x[i]));
    return s;
}

/* Dense 3nn x 3nn assembly straight from the element matrices (both triangles). */
static double *dense_stiffness(const kt_mesh *m, const kt_materials *mats, kt_err *e)
{
    int nv = kt_tet_nv(m->order), n = 3 * m->nn;
    double *D = calloc((size_t)n * n, sizeof(double)), x[30], Ke[900];
    for (int el = 0; el < m->ne && D; el++) {
        const int *t = m->tet + (size_t)el * nv;
        for (int a = 0; a < nv; a++) memcpy(x + 3 * a, m->xyz + 3 * t[a], 3 * sizeof(double));
        if (kt_fem_tet_stiffness(m->order, x, mats->mat[m->tet_tag[el]], Ke, e)) break;
        for (int a = 0; a < 3 * nv; a++)
            for (int b = 0; b < 3 * nv; b++)
                D[(size_t)(3 * t[a / 3] + a % 3) * n + 3 * t[b / 3] + b % 3] += Ke[a * 3 * nv + b];
    }
    return D;
}

static void check_structure(const cholmod_sparse *K, int n)
{
    CHECK(K->stype == -1 && K->sorted && K->packed && (int)K->nrow == n, "stype/sorted/packed");
    const int *Kp = K->p, *Ki = K->i;
    int ok = 1;
    for (int j = 0; j < n; j++)
        for (int p = Kp[j]; p < Kp[j + 1]; p++)
            if (Ki[p] < j || (p > Kp[j] && Ki[p] <= Ki[p - 1])) ok = 0;
    CHECK(ok, "entries sorted, strictly increasing, lower triangle");
}

static void rigid_and_dense(int order, cholmod_common *c)
{
    kt_err e = {0};
    kt_mesh m;
    make_mesh(&m, order, &e);
    CHECK(e.code == 0 && kt_mesh_check(&m, "jittered", &e) == 0, "%s", e.msg);
    kt_material mat[3] = {{0, 0}, {1.0, 0.3}, {7.0, 0.45}};
    kt_materials mats = {.nmat = 3, .mat = mat};
    cholmod_sparse *K = kt_fem_assemble(&m, &mats, NULL, c, &e);
    CHECK(K != NULL, "assemble P%d: %s", order, e.msg);
    if (!K) {
        kt_mesh_free(&m);
        return;
    }
    int n = 3 * m.nn;
    check_structure(K, n);
    double normK = cholmod_norm_sparse(K, 1, c);
    double *u = malloc(sizeof(double) * n), *y = malloc(sizeof(double) * n);
    for (int r = 0; r < 6; r++) {
        rigid_mode(&m, r, u);
        cholmod_dense U = {n, 1, n, n, u, NULL, CHOLMOD_REAL, CHOLMOD_DOUBLE};
        cholmod_dense Y = {n, 1, n, n, y, NULL, CHOLMOD_REAL, CHOLMOD_DOUBLE};
        double one[2] = {1, 0}, zero[2] = {0, 0};
        cholmod_sdmult(K, 0, one, zero, &U, &Y, c);
        double rel = max_abs(y, n) / (normK * max_abs(u, n));
        CHECK(rel <= 1e-12, "P%d rigid mode %d: |K u| / (|K| |u|) = %.3g", order, r, rel);
        if (r == 5) printf("P%d: n = %d, |K|_1 = %.3g, last rigid-mode residual %.3g\n", order, n,
                           normK, rel);
    }

    /* The sparse lower triangle equals the dense assembly; the dense one is symmetric. */
    double *D = dense_stiffness(&m, &mats, &e);
    CHECK(D != NULL && e.code == 0, "dense assembly");
    double diff = 0, asym = 0, scale = max_abs(D, (size_t)n * n);
    const int *Kp = K->p, *Ki = K->i;
    const double *Kx = K->x;
    double *S = calloc((size_t)n * n, sizeof(double));
    for (int j = 0; j < n; j++)
        for (int p = Kp[j]; p < Kp[j + 1]; p++) S[(size_t)Ki[p] * n + j] = Kx[p];
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++) {
            if (i >= j) diff = fmax(diff, fabs(S[(size_t)i * n + j] - D[(size_t)i * n + j]));
            asym = fmax(asym, fabs(D[(size_t)i * n + j] - D[(size_t)j * n + i]));
        }
    CHECK(diff <= 1e-14 * scale, "P%d sparse vs dense: %.3g (scale %.3g)", order, diff, scale);
    CHECK(asym <= 1e-14 * scale, "P%d dense asymmetry %.3g", order, asym);

    /* Lift: f - K(:,D) g on free rows, g on fixed rows, against the dense matrix. */
    unsigned char *fixed = calloc(n, 1);
    double *g = malloc(sizeof(double) * n), *f = malloc(sizeof(double) * n), *ref = malloc(sizeof(double) * n);
    unsigned long long seed = 99;
    for (int i = 0; i < n; i++) {
        fixed[i] = rnd(&seed) > 0.5;
        g[i] = rnd(&seed);
        f[i] = ref[i] = rnd(&seed);
    }
    for (int i = 0; i < n; i++) {
        if (fixed[i]) ref[i] = g[i];
        else
            for (int j = 0; j < n; j++)
                if (fixed[j]) ref[i] -= D[(size_t)i * n + j] * g[j];
    }
    CHECK(kt_fem_lift(K, fixed, g, f, &e) == 0, "lift: %s", e.msg);
    double ld = 0;
    for (int i = 0; i < n; i++) ld = fmax(ld, fabs(f[i] - ref[i]));
    CHECK(ld <= 1e-13 * scale, "P%d lift vs dense: %.3g", order, ld);

    /* Fixed DOFs: identity rows and columns, other entries untouched. */
    cholmod_sparse *Kd = kt_fem_assemble(&m, &mats, fixed, c, &e);
    CHECK(Kd != NULL, "assemble with fixed: %s", e.msg);
    if (Kd) {
        check_structure(Kd, n);
        memset(S, 0, sizeof(double) * n * n);
        const int *Dp = Kd->p, *Di = Kd->i;
        const double *Dx = Kd->x;
        for (int j = 0; j < n; j++)
            for (int p = Dp[j]; p < Dp[j + 1]; p++) S[(size_t)Di[p] * n + j] = Dx[p];
        double dd = 0;
        for (int i = 0; i < n; i++)
            for (int j = 0; j <= i; j++) {
                double want = (fixed[i] || fixed[j]) ? (i == j) : D[(size_t)i * n + j];
                dd = fmax(dd, fabs(S[(size_t)i * n + j] - want));
            }
        CHECK(dd <= 1e-14 * scale, "P%d constrained matrix vs dense: %.3g", order, dd);
        cholmod_free_sparse(&Kd, c);
    }
    free(fixed);
    free(g);
    free(f);
    free(ref);
    free(S);
    free(D);
    free(u);
    free(y);
    cholmod_free_sparse(&K, c);
    kt_mesh_free(&m);
}

/* Unit tet, E = 1, nu = 1/4: lambda = mu = 0.4, V = 1/6, grad L0 = (-1,-1,-1), grad L1 = e_x.
 * K(0x,0x) = V (lambda + mu + 3 mu) = 1/3; K(1x,1x) = V (lambda + 2 mu) = 0.2;
 * K(0x,1y) = V (lambda g0x g1y + mu g0y g1x) = -mu/6; K(2y,3z) = V (lambda g2y g3z) = lambda/6 */
static void hand_entries(void)
{
    kt_err e = {0};
    double x[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1}, Ke[144];
    kt_material mat = {1.0, 0.25};
    CHECK(kt_fem_tet_stiffness(1, x, mat, Ke, &e) == 0, "%s", e.msg);
    CHECK_NEAR(Ke[0 * 12 + 0], 1.0 / 3, 1e-15, "K(0x,0x)");
    CHECK_NEAR(Ke[3 * 12 + 3], 0.2, 1e-15, "K(1x,1x)");
    CHECK_NEAR(Ke[0 * 12 + 4], -0.4 / 6, 1e-15, "K(0x,1y)");
    CHECK_NEAR(Ke[4 * 12 + 0], -0.4 / 6, 1e-15, "K(1y,0x)");
    CHECK_NEAR(Ke[7 * 12 + 11], 0.4 / 6, 1e-15, "K(2y,3z)");

    /* P2 on the same tet with straight edges: a linear field u = G x stores the energy
     * V eps:C:eps exactly; with G = e_x e_x^T (eps_xx = 1) that is V (lambda + 2 mu). */
    double x2[30], u[30], K2[900];
    memcpy(x2, x, sizeof x);
    static const int EDGE[6][2] = {{0, 1}, {1, 2}, {2, 0}, {3, 0}, {3, 2}, {3, 1}};
    for (int s = 0; s < 6; s++)
        for (int k = 0; k < 3; k++) x2[12 + 3 * s + k] = 0.5 * (x[3 * EDGE[s][0] + k] + x[3 * EDGE[s][1] + k]);
    for (int a = 0; a < 10; a++) u[3 * a] = x2[3 * a], u[3 * a + 1] = u[3 * a + 2] = 0;
    CHECK(kt_fem_tet_stiffness(2, x2, mat, K2, &e) == 0, "%s", e.msg);
    double energy = 0;
    for (int a = 0; a < 30; a++)
        for (int b = 0; b < 30; b++) energy += u[a] * K2[a * 30 + b] * u[b];
    CHECK_NEAR(energy, (0.4 + 0.8) / 6, 1e-14, "P2 energy of a uniaxial strain");

    /* The curved-element rule (14 points) agrees with the straight one (4 points): a mid-edge
     * node moved by 1e-9 switches rules but may change K only by O(1e-9). */
    double K3[900], dmax = 0, kmax = 0;
    x2[12 + 3 * 2 + 1] += 1e-9;
    CHECK(kt_fem_tet_stiffness(2, x2, mat, K3, &e) == 0, "%s", e.msg);
    for (int a = 0; a < 900; a++) dmax = fmax(dmax, fabs(K3[a] - K2[a])), kmax = fmax(kmax, fabs(K2[a]));
    CHECK(dmax > 0 && dmax < 1e-7 * kmax, "14-point vs 4-point rule: %.3g of %.3g", dmax, kmax);

    /* Inverted and flat elements fail. */
    double xi[12] = {0, 0, 0, 0, 1, 0, 1, 0, 0, 0, 0, 1};
    kt_err e2 = {0};
    CHECK(kt_fem_tet_stiffness(1, xi, mat, Ke, &e2) == KT_ERUN && strstr(e2.msg, "inverted"),
          "inverted tet: %s", e2.msg);
    double xf[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0};
    kt_err e3 = {0};
    CHECK(kt_fem_tet_stiffness(1, xf, mat, Ke, &e3) == KT_ERUN && strstr(e3.msg, "degenerate"),
          "flat tet: %s", e3.msg);
    kt_material bad = {1.0, 0.5};
    kt_err e4 = {0};
    CHECK(kt_fem_tet_stiffness(1, x, bad, Ke, &e4) == KT_EINPUT, "nu = 0.5 rejected: %s", e4.msg);
}

static void error_paths(cholmod_common *c)
{
    kt_err e = {0};
    kt_mesh m;
    kt_grid_box(&m, 3, 3, 3, 1, 1, 1, &e);
    kt_material mat[2] = {{0, 0}, {1.0, 0.3}};
    kt_materials mats = {.nmat = 2, .mat = mat};
    int n = 3 * m.nn;

    /* Tet 5 (1-based) inverted by swapping two of its nodes. */
    int s = m.tet[4 * 4 + 1];
    m.tet[4 * 4 + 1] = m.tet[4 * 4 + 2];
    m.tet[4 * 4 + 2] = s;
    cholmod_sparse *K = kt_fem_assemble(&m, &mats, NULL, c, &e);
    CHECK(!K && e.code == KT_ERUN && strstr(e.msg, "tet 5 ") && strstr(e.msg, "inverted"),
          "inverted tet named: %s", e.msg);
    cholmod_free_sparse(&K, c);
    m.tet[4 * 4 + 2] = m.tet[4 * 4 + 1];
    m.tet[4 * 4 + 1] = s;

    /* A missing material is bad input. */
    kt_materials few = {.nmat = 1, .mat = mat};
    kt_err e1 = {0};
    K = kt_fem_assemble(&m, &few, NULL, c, &e1);
    CHECK(!K && e1.code == KT_EINPUT, "region without material: %s", e1.msg);

    /* Pressure on a triangle inside the body (a face of two tets), and on a tag with no group. */
    kt_mesh_add_group(&m, 2, 7, "inner", &e);
    int *tri = realloc(m.tri, sizeof(int) * 3 * (m.nf + 1)), *tag = realloc(m.tri_tag, sizeof(int) * (m.nf + 1));
    m.tri = tri;
    m.tri_tag = tag;
    /* node (1,1,1) is the box's only interior node: every face through it is interior */
    int center = 1 + 3 * (1 + 3 * 1), ci = -1, el = 0;
    for (; el < m.ne && ci < 0; el++)
        for (int a = 0; a < 4; a++)
            if (m.tet[4 * el + a] == center) ci = a;
    const int *t0 = m.tet + 4 * (el - 1);
    for (int a = 0, k = 0; a < 4; a++)
        if (a != (ci + 1) % 4) tri[3 * m.nf + k++] = t0[a];
    tag[m.nf++] = 7;
    double *f = calloc(n, sizeof(double));
    kt_err e2 = {0};
    CHECK(kt_fem_pressure(&m, 7, 1.0, f, &e2) == KT_EINPUT && strstr(e2.msg, "face of 2 tets"),
          "interior face: %s", e2.msg);
    kt_err e3 = {0};
    CHECK(kt_fem_pressure(&m, 42, 1.0, f, &e3) == KT_EINPUT, "unknown tag: %s", e3.msg);

    /* Pressure on the closed box surface sums to zero force; on zmax it is -p A e_z. */
    double fz = 0, ftot[3] = {0};
    kt_err e5 = {0};
    memset(f, 0, sizeof(double) * n);
    for (int g = 1; g <= 6; g++) CHECK(kt_fem_pressure(&m, g, 2.0, f, &e5) == 0, "%s", e5.msg);
    for (int i = 0; i < m.nn; i++)
        for (int d = 0; d < 3; d++) ftot[d] += f[3 * i + d];
    CHECK(fabs(ftot[0]) + fabs(ftot[1]) + fabs(ftot[2]) < 1e-14, "closed surface net force");
    memset(f, 0, sizeof(double) * n);
    kt_fem_pressure(&m, 6, 2.0, f, &e5);
    for (int i = 0; i < m.nn; i++) fz += f[3 * i + 2];
    CHECK_NEAR(fz, -2.0, 1e-14, "pressure on zmax pushes in -z");

    /* No support: the solve must fail loudly (not positive definite or residual). */
    memset(f, 0, sizeof(double) * n);
    f[3 * (m.nn - 1)] = 1.0;
    double *u = calloc(n, sizeof(double));
    kt_err e4 = {0};
    CHECK(kt_fem_solve(&m, &mats, NULL, NULL, f, u, c, &e4) == KT_ERUN, "free body solved?");
    printf("unsupported body: %s\n", e4.msg);
    free(u);
    free(f);
    kt_mesh_free(&m);
}

int main(void)
{
    cholmod_common c;
    cholmod_start(&c);
    c.print = 0;
    hand_entries();
    rigid_and_dense(1, &c);
    rigid_and_dense(2, &c);
    error_paths(&c);
    cholmod_finish(&c);
    return kt_test_done("test_fem_rigid");
}
