/* test_fem_beam.c: a slender cantilever (1 x 1 x 20 mm, clamped at z = 0, uniform shear
 * traction on the tip face) against Timoshenko beam theory. P2 must match within 3%; P1 shear-
 * locks on such meshes, so only its convergence toward the answer is asserted.
 * `test_fem_beam --bench` times assembly and the direct solve of ~100k-DOF P1 beams instead. */
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "fem.h"
#include "grid.h"
#include "kt_test.h"

enum { XMIN = 1, XMAX, YMIN, YMAX, ZMIN, ZMAX }; /* kt_grid_box surface tags */

/* Consistent nodal forces of a uniform traction t on the straight triangles of a surface:
 * int N_a dA = A/3 at each vertex (P1); 0 at a vertex and A/3 at an edge node (P2). */
static void traction_loads(const kt_mesh *m, int tag, const double *t, double *f)
{
    int fv = kt_tri_nv(m->order);
    for (int i = 0; i < m->nf; i++) {
        if (m->tri_tag[i] != tag) continue;
        const int *q = m->tri + (size_t)fv * i;
        const double *a = m->xyz + 3 * q[0], *b = m->xyz + 3 * q[1], *c = m->xyz + 3 * q[2];
        double u[3], v[3];
        for (int k = 0; k < 3; k++) u[k] = b[k] - a[k], v[k] = c[k] - a[k];
        double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
        double A = 0.5 * sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        for (int s = 0; s < fv; s++) {
            double w = fv == 3 ? A / 3 : (s < 3 ? 0.0 : A / 3);
            for (int k = 0; k < 3; k++) f[3 * q[s] + k] += w * t[k];
        }
    }
}

typedef struct beam {
    double L, b;    /* length (z) and square side, mm */
    kt_material mat;
    double F;       /* tip shear force along y, N */
} beam;

/* Euler-Bernoulli F L^3 / (3 E I) plus Timoshenko's shear term F L / (k G A), with Cowper's
 * k = 10 (1 + nu) / (12 + 11 nu) for a square section. */
static double timoshenko_tip(const beam *B, double *euler)
{
    double E = B->mat.E, nu = B->mat.nu, A = B->b * B->b, I = B->b * B->b * B->b * B->b / 12;
    double G = E / (2 * (1 + nu)), k = 10 * (1 + nu) / (12 + 11 * nu);
    *euler = B->F * B->L * B->L * B->L / (3 * E * I);
    return *euler + B->F * B->L / (k * G * A);
}

/* Mean deflection of the tip face (the traction-weighted mean f.u / F) of an nx x nx x nz
 * node grid of the given order; *dofs gets the unknown count. Returns NaN on failure. */
static double tip_deflection(const beam *B, int order, int nx, int nz, int *dofs, double *secs,
                             cholmod_common *c)
{
    kt_err e = {0};
    kt_mesh m;
    if (kt_grid_box(&m, nx, nx, nz, B->b, B->b, B->L, &e) || (order == 2 && kt_mesh_elevate(&m, &e))) {
        CHECK(0, "mesh: %s", e.msg);
        kt_mesh_free(&m);
        return NAN;
    }
    int n = 3 * m.nn;
    unsigned char *fixed = calloc(n, 1);
    double *f = calloc(n, sizeof(double)), *u = calloc(n, sizeof(double));
    int *root = NULL, nroot = 0;
    kt_mesh_group_nodes(&m, kt_mesh_find_tag(&m, 2, ZMIN), &root, &nroot, &e);
    for (int i = 0; i < nroot; i++) memset(fixed + 3 * root[i], 1, 3);
    double t[3] = {0, B->F / (B->b * B->b), 0};
    traction_loads(&m, ZMAX, t, f);
    kt_material mv[2] = {{0, 0}, B->mat};
    kt_materials mats = {.nmat = 2, .mat = mv};
    double t0 = kt_now();
    int rc = kt_fem_solve(&m, &mats, fixed, NULL, f, u, c, &e);
    *secs = kt_now() - t0;
    CHECK(rc == 0, "solve: %s", e.msg);
    double work = 0, fsum = 0;
    for (int i = 0; i < n; i++) work += f[i] * u[i], fsum += f[i];
    CHECK_NEAR(fsum, B->F, 1e-12, "total tip load");
    *dofs = n - 3 * nroot;
    free(root);
    free(fixed);
    free(f);
    free(u);
    kt_mesh_free(&m);
    return rc == 0 ? work / B->F : NAN;
}

static int bench(void)
{
    cholmod_common c;
    cholmod_start(&c);
    /* two ~100k-DOF beams solved, then a ~300k-DOF one only assembled */
    struct { double b, L; int nx, nz, solve; } cases[3] = {
        {1, 20, 9, 412, 1}, {5, 50, 16, 131, 1}, {5, 50, 22, 211, 0}};
    for (int k = 0; k < 3; k++) {
        kt_err e = {0};
        kt_mesh m;
        kt_grid_box(&m, cases[k].nx, cases[k].nx, cases[k].nz, cases[k].b, cases[k].b, cases[k].L, &e);
        kt_material mv[2] = {{0, 0}, {1.0, 0.3}};
        kt_materials mats = {.nmat = 2, .mat = mv};
        int n = 3 * m.nn;
        unsigned char *fixed = calloc(n, 1);
        double *f = calloc(n, sizeof(double)), *u = calloc(n, sizeof(double));
        for (int i = 0; i < m.nn; i++)
            if (m.xyz[3 * i + 2] == 0) memset(fixed + 3 * i, 1, 3);
        double t[3] = {0, 1, 0};
        traction_loads(&m, ZMAX, t, f);
        double t0 = kt_now(), c0 = clock();
        cholmod_sparse *K = kt_fem_assemble(&m, &mats, NULL, &c, &e);
        double ta = kt_now() - t0, ca = (clock() - c0) / CLOCKS_PER_SEC;
        t0 = kt_now(), c0 = clock();
        int rc = cases[k].solve ? kt_fem_solve(&m, &mats, fixed, NULL, f, u, &c, &e) : -1;
        double ts = cases[k].solve ? kt_now() - t0 : NAN, cs = (clock() - c0) / CLOCKS_PER_SEC;
        printf("P1 beam %gx%gx%g mm, %dx%dx%d nodes: %d DOFs, %d tets, nnz(K lower) %ld, "
               "assemble %.3f s (cpu %.3f), kt_fem_solve %.3f s (cpu %.3f; rc %d%s%s), nnz(L) %.3g, "
               "flops %.3g\n",
               cases[k].b, cases[k].b, cases[k].L, cases[k].nx, cases[k].nx, cases[k].nz, n, m.ne,
               K ? (long)cholmod_nnz(K, &c) : -1L, ta, ca, ts, cs, rc, rc ? ": " : "", rc ? e.msg : "",
               c.lnz, c.fl);
        cholmod_free_sparse(&K, &c);
        if (cases[k].solve) { /* the phases of the direct solve, timed one by one */
            K = kt_fem_assemble(&m, &mats, fixed, &c, &e);
            int saved = c.supernodal;
            c.supernodal = CHOLMOD_SUPERNODAL;
            t0 = kt_now();
            cholmod_factor *L = cholmod_analyze(K, &c);
            double tan = kt_now() - t0;
            t0 = kt_now();
            cholmod_factorize(K, L, &c);
            double tf = kt_now() - t0;
            c.supernodal = saved;
            cholmod_dense B = {n, 1, n, n, f, NULL, CHOLMOD_REAL, CHOLMOD_DOUBLE};
            t0 = kt_now();
            cholmod_dense *X = cholmod_solve(CHOLMOD_A, L, &B, &c);
            double tso = kt_now() - t0;
            printf("  phases: analyze %.3f s (ordering %d), supernodal factorize %.3f s, solve %.3f s\n",
                   tan, c.method[c.selected].ordering, tf, tso);
            cholmod_free_dense(&X, &c);
            cholmod_free_factor(&L, &c);
            cholmod_free_sparse(&K, &c);
        }
        free(fixed);
        free(f);
        free(u);
        kt_mesh_free(&m);
    }
    cholmod_finish(&c);
    return 0;
}

int main(int argc, char **argv)
{
    if (argc > 1 && strcmp(argv[1], "--bench") == 0) return bench();
    cholmod_common c;
    cholmod_start(&c);
    c.print = 0;
    printf("%-5s %-6s %-12s %-7s %-12s %-12s %-9s %s\n", "order", "nu", "nodes", "dofs",
           "tip_mm", "timoshenko", "error", "seconds");
    static const double NU[2] = {0.3, 0.49};
    for (int v = 0; v < 2; v++) {
        beam B = {20.0, 1.0, {200.0, NU[v]}, 0.01};
        double eb, ref = timoshenko_tip(&B, &eb);
        struct { int order, nx, nz; } runs[5] = {{1, 3, 41}, {1, 5, 81}, {1, 9, 161}, {2, 3, 41}, {2, 5, 81}};
        double err[5];
        for (int r = 0; r < 5; r++) {
            int dofs = 0;
            double secs = 0;
            double d = tip_deflection(&B, runs[r].order, runs[r].nx, runs[r].nz, &dofs, &secs, &c);
            err[r] = (d - ref) / ref;
            printf("P%-4d %-6.2f %2dx%2dx%-4d %-7d %-12.6g %-12.6g %+8.3f%% %.2f\n", runs[r].order,
                   NU[v], runs[r].nx, runs[r].nx, runs[r].nz, dofs, d, ref, 100 * err[r], secs);
        }
        printf("(Euler-Bernoulli %.6g; shear term %.3f%% of it)\n", eb, 100 * (ref - eb) / eb);
        /* P2: within 3% already with two elements across; P1: too stiff but converging. */
        CHECK(fabs(err[3]) < 0.03 && fabs(err[4]) < 0.03, "P2 nu=%.2f: %.3g %.3g", NU[v], err[3], err[4]);
        CHECK(err[0] < 0 && err[0] < err[1] && err[1] < err[2] && err[2] < 0,
              "P1 nu=%.2f stiff and converging from below: %.3g %.3g %.3g", NU[v], err[0], err[1], err[2]);
    }
    cholmod_finish(&c);
    return kt_test_done("test_fem_beam");
}
