/* test_fem_patch.c: patch tests on an irregular mesh. A linear displacement imposed on every
 * boundary node is reproduced at the interior nodes (P1; P2 with curved, jittered mid-edge
 * nodes), and P2 on straight-sided tets reproduces a quadratic field under the constant body
 * force that balances it. */
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

/* Every tet keeps at least vmin volume (jitter without slivers). */
static int tets_fat(const kt_mesh *m, double vmin)
{
    int nv = kt_tet_nv(m->order);
    for (int i = 0; i < m->ne; i++) {
        const int *t = m->tet + (size_t)nv * i;
        if (!(kt_tet_volume(m->xyz + 3 * t[0], m->xyz + 3 * t[1], m->xyz + 3 * t[2],
                            m->xyz + 3 * t[3]) >= vmin))
            return 0;
    }
    return 1;
}

/* A 5x5x5-node unit cube whose interior nodes are moved by up to 0.35 of the grid step
 * (a move that would shrink a tet below a third of its grid volume h^3/6 is undone). */
static int irregular_cube(kt_mesh *m, kt_err *e)
{
    int N = 5;
    if (kt_grid_box(m, N, N, N, 1.0, 1.0, 1.0, e)) return e->code;
    unsigned long long seed = 2024;
    double h = 1.0 / (N - 1);
    int moved = 0;
    for (int i = 0; i < m->nn; i++) {
        int ix = i % N, iy = (i / N) % N, iz = i / (N * N);
        if (ix == 0 || iy == 0 || iz == 0 || ix == N - 1 || iy == N - 1 || iz == N - 1) continue;
        double old[3];
        memcpy(old, m->xyz + 3 * i, sizeof old);
        for (int k = 0; k < 3; k++) m->xyz[3 * i + k] += 0.35 * h * rnd(&seed);
        if (tets_fat(m, h * h * h / 18)) moved++;
        else memcpy(m->xyz + 3 * i, old, sizeof old);
    }
    printf("irregular cube: %d of 27 interior nodes moved\n", moved);
    return KT_OK;
}

/* Nodes on any of the six box faces (after elevation, mid-edge nodes included). */
static unsigned char *boundary_mask(const kt_mesh *m, kt_err *e)
{
    unsigned char *b = kt_calloc(m->nn, 1, e);
    for (int g = 1; b && g <= 6; g++) {
        int *nodes = NULL, cnt = 0;
        if (kt_mesh_group_nodes(m, kt_mesh_find_tag(m, 2, g), &nodes, &cnt, e)) break;
        for (int i = 0; i < cnt; i++) b[nodes[i]] = 1;
        free(nodes);
    }
    return b;
}

/* A field u_i = c_i + G_ij x_j + H_ijk x_j x_k / 2 (H symmetric in j, k). */
typedef struct field {
    double c[3], G[3][3], H[3][3][3];
} field;

static void field_random(field *F, int quadratic, unsigned long long *seed)
{
    memset(F, 0, sizeof *F);
    for (int i = 0; i < 3; i++) {
        F->c[i] = 0.01 * rnd(seed);
        for (int j = 0; j < 3; j++) F->G[i][j] = 0.01 * rnd(seed);
        for (int j = 0; quadratic && j < 3; j++)
            for (int k = 0; k <= j; k++) F->H[i][j][k] = F->H[i][k][j] = 0.01 * rnd(seed);
    }
}

static void field_eval(const field *F, const double *x, double *u)
{
    for (int i = 0; i < 3; i++) {
        u[i] = F->c[i];
        for (int j = 0; j < 3; j++) {
            u[i] += F->G[i][j] * x[j];
            for (int k = 0; k < 3; k++) u[i] += 0.5 * F->H[i][j][k] * x[j] * x[k];
        }
    }
}

/* Equilibrium div(sigma) + b = 0 with div(sigma)_i = (lambda + mu) d_i d_k u_k + mu lap u_i,
 * and d_j d_k u_i = H_ijk. */
static void field_body_force(const field *F, kt_material mat, double *b)
{
    double lam = mat.E * mat.nu / ((1 + mat.nu) * (1 - 2 * mat.nu)), mu = mat.E / (2 * (1 + mat.nu));
    for (int i = 0; i < 3; i++) {
        double graddiv = 0, lap = 0;
        for (int k = 0; k < 3; k++) graddiv += F->H[k][k][i], lap += F->H[i][k][k];
        b[i] = -((lam + mu) * graddiv + mu * lap);
    }
}

/* Consistent nodal forces of a constant body force b on straight-sided tets:
 * int N_a dV = V/4 (P1); -V/20 at a vertex, V/5 at an edge node (P2). */
static void body_force_loads(const kt_mesh *m, const double *b, double *f)
{
    int nv = kt_tet_nv(m->order);
    for (int el = 0; el < m->ne; el++) {
        const int *t = m->tet + (size_t)nv * el;
        double V = kt_tet_volume(m->xyz + 3 * t[0], m->xyz + 3 * t[1], m->xyz + 3 * t[2],
                                 m->xyz + 3 * t[3]);
        for (int a = 0; a < nv; a++) {
            double w = nv == 4 ? V / 4 : (a < 4 ? -V / 20 : V / 5);
            for (int k = 0; k < 3; k++) f[3 * t[a] + k] += w * b[k];
        }
    }
}

/* Impose the field on the boundary, load the balancing body force, solve, and return the
 * largest interior error relative to the largest displacement. */
static double patch_error(const kt_mesh *m, const field *F, kt_material mat, cholmod_common *c)
{
    kt_err e = {0};
    int n = 3 * m->nn;
    unsigned char *bnd = boundary_mask(m, &e), *fixed = calloc(n, 1);
    double *g = calloc(n, sizeof(double)), *f = calloc(n, sizeof(double)),
           *u = calloc(n, sizeof(double)), *ex = calloc(n, sizeof(double)), b[3];
    kt_material mats_v[2] = {{0, 0}, mat};
    kt_materials mats = {.nmat = 2, .mat = mats_v};
    for (int i = 0; i < m->nn; i++) {
        field_eval(F, m->xyz + 3 * i, ex + 3 * i);
        for (int k = 0; k < 3; k++) {
            fixed[3 * i + k] = bnd[i];
            g[3 * i + k] = bnd[i] ? ex[3 * i + k] : 0;
        }
    }
    field_body_force(F, mat, b);
    body_force_loads(m, b, f);
    double err = INFINITY, umax = 0, emax = 0;
    int rc = kt_fem_solve(m, &mats, fixed, g, f, u, c, &e);
    CHECK(rc == 0, "solve: %s", e.msg);
    if (rc == 0) {
        int interior = 0;
        for (int i = 0; i < m->nn; i++) {
            for (int k = 0; k < 3; k++) umax = fmax(umax, fabs(ex[3 * i + k]));
            if (bnd[i]) continue;
            interior++;
            for (int k = 0; k < 3; k++) emax = fmax(emax, fabs(u[3 * i + k] - ex[3 * i + k]));
        }
        CHECK(interior > 0, "no interior nodes");
        err = emax / umax;
    }
    free(bnd);
    free(fixed);
    free(g);
    free(f);
    free(u);
    free(ex);
    return err;
}

int main(void)
{
    cholmod_common c;
    cholmod_start(&c);
    c.print = 0;
    kt_err e = {0};
    kt_material mat = {3.0, 0.35};
    unsigned long long seed = 7;
    field lin, quad;
    field_random(&lin, 0, &seed);
    field_random(&quad, 1, &seed);

    kt_mesh m;
    irregular_cube(&m, &e);
    CHECK(e.code == 0 && kt_mesh_check(&m, "cube", &e) == 0, "%s", e.msg);
    double e1 = patch_error(&m, &lin, mat, &c);
    printf("P1 linear patch: interior error %.3g\n", e1);
    CHECK(e1 <= 1e-12, "P1 linear patch error %.3g", e1);

    /* P1 cannot represent the quadratic field: its error must be visible (sanity of the check). */
    double e1q = patch_error(&m, &quad, mat, &c);
    printf("P1 quadratic field (not in the space): interior error %.3g\n", e1q);
    CHECK(e1q > 1e-6, "P1 reproduced a quadratic field?");

    kt_mesh m2;
    CHECK(kt_mesh_copy(&m2, &m, &e) == 0 && kt_mesh_elevate(&m2, &e) == 0, "%s", e.msg);
    double e2q = patch_error(&m2, &quad, mat, &c);
    printf("P2 quadratic patch (straight edges, body force): interior error %.3g\n", e2q);
    CHECK(e2q <= 1e-12, "P2 quadratic patch error %.3g", e2q);

    /* Curve every element: mid-edge nodes moved off their edges by up to 3% of the step. */
    int nn1 = m.nn;
    for (int i = nn1; i < m2.nn; i++)
        for (int k = 0; k < 3; k++) m2.xyz[3 * i + k] += 0.03 * 0.25 * rnd(&seed);
    double e2 = patch_error(&m2, &lin, mat, &c);
    printf("P2 linear patch (curved elements): interior error %.3g\n", e2);
    CHECK(e2 <= 1e-12, "P2 curved linear patch error %.3g", e2);

    /* Nearly incompressible: the linear patch still holds. */
    kt_material soft = {1.0, 0.499};
    double e3 = patch_error(&m2, &lin, soft, &c);
    printf("P2 linear patch, nu = 0.499: interior error %.3g\n", e3);
    CHECK(e3 <= 1e-10, "P2 nu=0.499 patch error %.3g", e3);

    kt_mesh_free(&m);
    kt_mesh_free(&m2);
    cholmod_finish(&c);
    return kt_test_done("test_fem_patch");
}
