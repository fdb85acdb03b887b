/* test_fem_nl.c: the total Lagrangian kernels (kt_fem_nl_element) on single P1 and P2 (curved)
 * tets with a fibre material in a rotated frame, a prestress varying over the quadrature points
 * and a follower pressure on all four faces (a closed surface, so the load stiffness is
 * symmetric and the element tangent is the exact derivative of the residual):
 *  - the tangent equals the central-difference derivative of the residual at a large
 *    displacement (relative 1e-6);
 *  - at u = 0 the tangent is the linear kernel's (kt_fem_element) and the residual is minus
 *    the release forces (kt_fem_element_release) minus the pressure forces;
 *  - objectivity: a rigid rotation by 90 deg of an unstressed element leaves no internal force
 *    (the linear kernel's K u is of the order of E |u| there);
 *  - uniaxial stretch lambda of an isotropic nu = 0 P1 tet gives S11 = E (lambda^2 - 1) / 2:
 *    the force on the face x = 1 of the unit corner tet is S11 lambda (area 1/2). */
#include <stdlib.h>
#include <string.h>

#include "fem.h"
#include "kt_test.h"

/* The unit corner tet (P2 edge nodes bent by `bend`), one region (tag 0). */
static void one_tet(kt_mesh *m, int order, double bend)
{
    static const double V[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    static const int EDGE[6][2] = {{0, 1}, {1, 2}, {2, 0}, {3, 0}, {3, 2}, {3, 1}};
    memset(m, 0, sizeof *m);
    m->order = order;
    m->nn = order == 1 ? 4 : 10;
    m->ne = 1;
    m->xyz = calloc(3 * m->nn, sizeof(double));
    m->tet = calloc(m->nn, sizeof(int));
    m->tet_tag = calloc(1, sizeof(int));
    for (int a = 0; a < m->nn; a++) m->tet[a] = a;
    memcpy(m->xyz, V, sizeof V);
    if (order == 2)
        for (int s = 0; s < 6; s++)
            for (int k = 0; k < 3; k++)
                m->xyz[12 + 3 * s + k] = 0.5 * (V[EDGE[s][0]][k] + V[EDGE[s][1]][k]) +
                                         bend * (k == s % 3 ? 1 : -0.5);
}

static void free_tet(kt_mesh *m)
{
    free(m->xyz);
    free(m->tet);
    free(m->tet_tag);
}

static void fibre_C(double C[36])
{
    double c1 = cos(0.4), s1 = sin(0.4), c2 = cos(0.7), s2 = sin(0.7);
    double a1[3] = {c1, s1, 0}, n[3] = {-s1 * s2, c1 * s2, c2}, a2[3];
    a2[0] = n[1] * a1[2] - n[2] * a1[1];
    a2[1] = n[2] * a1[0] - n[0] * a1[2];
    a2[2] = n[0] * a1[1] - n[1] * a1[0];
    kt_fibre_material fm = {3.0, 2.0, 0.05, 0.45};
    double c[3] = {a1[0] * 0.6 + a2[0] * 0.8, a1[1] * 0.6 + a2[1] * 0.8, a1[2] * 0.6 + a2[2] * 0.8};
    kt_fem_fibre_matrix(&fm, a1, a2, n, c, 0.7, C);
}

static void tangent_check(int order, double bend)
{
    kt_mesh m;
    one_tet(&m, order, bend);
    int nd = 3 * m.nn;
    double C[36], sig[KT_FEM_NQ * 6], pface[4] = {0.02, 0.02, 0.02, 0.02};
    fibre_C(C);
    for (int q = 0; q < KT_FEM_NQ * 6; q++) sig[q] = 0.01 * sin(1.0 + 0.7 * q);
    kt_fem_tetdata td = {1, C, sig, pface};
    kt_material mat = {1, 0.3};
    kt_materials mats = {1, &mat, &td, NULL};
    double u[30], Ke[900], Kfd[900], fp[30], fm[30], fe[30];
    for (int i = 0; i < nd; i++) u[i] = 0.15 * sin(2.3 * i + 0.4);
    kt_err e = {0};
    CHECK(kt_fem_nl_element(&m, &mats, 0, u, 1.0, fe, Ke, &e) == KT_OK, "%s", e.msg);
    double h = 1e-6, err = 0, big = 0;
    for (int j = 0; j < nd; j++) {
        double s = u[j];
        u[j] = s + h;
        kt_fem_nl_element(&m, &mats, 0, u, 1.0, fp, NULL, &e);
        u[j] = s - h;
        kt_fem_nl_element(&m, &mats, 0, u, 1.0, fm, NULL, &e);
        u[j] = s;
        for (int i = 0; i < nd; i++) Kfd[i * nd + j] = (fp[i] - fm[i]) / (2 * h);
    }
    for (int k = 0; k < nd * nd; k++) {
        err = fmax(err, fabs(Ke[k] - Kfd[k]));
        big = fmax(big, fabs(Kfd[k]));
    }
    printf("P%d bend %.2f: max |K - dR/du| = %.3e of max |K| = %.3e\n", order, bend, err, big);
    CHECK(err <= 1e-6 * big, "P%d tangent vs finite differences: %.3e of %.3e", order, err, big);

    /* u = 0: the linear kernel's tangent; residual = -release - pressure forces */
    double zero[30] = {0}, Kl[900], rel[30];
    CHECK(kt_fem_nl_element(&m, &mats, 0, zero, 1.0, fe, Ke, &e) == KT_OK, "%s", e.msg);
    CHECK(kt_fem_element(&m, &mats, 0, Kl, &e) == KT_OK, "%s", e.msg);
    CHECK(kt_fem_element_release(&m, &mats, 0, rel, &e) == KT_OK, "%s", e.msg);
    err = 0, big = 0;
    for (int k = 0; k < nd * nd; k++) {
        err = fmax(err, fabs(Ke[k] - Kl[k]));
        big = fmax(big, fabs(Kl[k]));
    }
    CHECK(err <= 1e-13 * big, "P%d tangent at u = 0 vs linear: %.3e of %.3e", order, err, big);
    /* a closed surface under uniform pressure has zero net force: sum of fe + rel = 0 */
    td.pface = NULL;
    CHECK(kt_fem_nl_element(&m, &mats, 0, zero, 1.0, fe, NULL, &e) == KT_OK, "%s", e.msg);
    err = 0;
    for (int i = 0; i < nd; i++) err = fmax(err, fabs(fe[i] + rel[i]));
    CHECK(err <= 1e-15, "P%d residual at u = 0 vs -release: %.3e", order, err);
    free_tet(&m);
}

static void rotation_check(int order)
{
    kt_mesh m;
    one_tet(&m, order, order == 2 ? 0.05 : 0);
    int nd = 3 * m.nn;
    kt_material mat = {2.0, 0.3};
    kt_materials mats = {1, &mat, NULL, NULL};
    double u[30], fe[30], Kl[900];
    for (int a = 0; a < m.nn; a++) { /* 90 deg about z: (x, y, z) -> (-y, x, z) */
        const double *X = m.xyz + 3 * a;
        u[3 * a] = -X[1] - X[0];
        u[3 * a + 1] = X[0] - X[1];
        u[3 * a + 2] = 0;
    }
    kt_err e = {0};
    CHECK(kt_fem_nl_element(&m, &mats, 0, u, 1.0, fe, NULL, &e) == KT_OK, "%s", e.msg);
    CHECK(kt_fem_element(&m, &mats, 0, Kl, &e) == KT_OK, "%s", e.msg);
    double fmaxnl = 0, fmaxl = 0;
    for (int i = 0; i < nd; i++) {
        double s = 0;
        for (int j = 0; j < nd; j++) s += Kl[i * nd + j] * u[j];
        fmaxl = fmax(fmaxl, fabs(s));
        fmaxnl = fmax(fmaxnl, fabs(fe[i]));
    }
    printf("P%d rigid rotation 90 deg: max |f_int| = %.3e (linear K u: %.3e)\n", order, fmaxnl, fmaxl);
    CHECK(fmaxnl <= 1e-14 * mat.E, "P%d rotation leaves force %.3e", order, fmaxnl);
    CHECK(fmaxl >= 0.1 * mat.E, "the linear kernel's K u under rotation (%.3e) is not small", fmaxl);
    free_tet(&m);
}

static void stretch_check(void)
{
    kt_mesh m;
    one_tet(&m, 1, 0);
    kt_material mat = {2.0, 0.0};
    kt_materials mats = {1, &mat, NULL, NULL};
    double lam = 1.6, u[12], fe[12];
    for (int a = 0; a < 4; a++) {
        u[3 * a] = (lam - 1) * m.xyz[3 * a];
        u[3 * a + 1] = u[3 * a + 2] = 0;
    }
    kt_err e = {0};
    CHECK(kt_fem_nl_element(&m, &mats, 0, u, 1.0, fe, NULL, &e) == KT_OK, "%s", e.msg);
    /* the force F S N dA0 on the face x = 0 side: node 1 alone carries the x = 1 vertex; the
     * tet's internal force on node 1 is int B^T S = S11 F11 g_1x V = S11 lam (1)(1/6) */
    double S11 = mat.E * (lam * lam - 1) / 2, want = S11 * lam / 6;
    printf("uniaxial stretch %.2f: f_x(node 1) = %.12g, closed form %.12g\n", lam, fe[3], want);
    CHECK_NEAR(fe[3], want, 1e-14, "S11 lambda V");
    CHECK(fabs(fe[4]) < 1e-15 && fabs(fe[5]) < 1e-15, "no lateral force (nu = 0): %g %g", fe[4], fe[5]);
    free_tet(&m);
}

int main(void)
{
    tangent_check(1, 0);
    tangent_check(2, 0);
    tangent_check(2, 0.08);
    rotation_check(1);
    rotation_check(2);
    stretch_check();
    return kt_test_done("test_fem_nl");
}
