/* test_fem_tangent.c: the lamellar (fibre) material and the tangent stiffness of a prestressed
 * body under a follower pressure, against closed forms.
 *  - material: uniaxial stress along a1 strains it by sigma/E1 (E1 + Ec with the limbal
 *    circumferential term), transverse shear a1-n by tau/Gt, in-plane shear by tau/mu, in
 *    rotated frames; the orthotropic moduli keratome-scene(5) states (the stiffer direction's
 *    exactly, the softer one's closed form, the limbal fibres along an oblique c) and that an
 *    isotropic tet's constants give its isotropic matrix (keratome-vtk(5));
 *  - element: the six rigid modes are in the kernel of the fibre element (P1, P2 curved); a
 *    linear displacement field on an irregular box is reproduced (patch test: the interior
 *    rows of K u vanish) and its energy is V eps:C:eps;
 *  - stress stiffness: a string under tension T resists a transverse end displacement d with
 *    the force T d / L (u^T K_sigma u = T d^2 / L), translations are in its kernel;
 *  - load stiffness: assembled over a closed surface it is symmetric and has translations in
 *    its kernel; a box under hydrostatic prestress -p with the follower pressure p on its
 *    whole boundary is in equilibrium (pressure loads + release loads = 0), K_sigma - K_p keeps
 *    the rigid rotations in its kernel, and a uniform dilation e x has
 *    u^T (K_sigma - K_p) u = 3 p e^2 V (K_sigma: -3 p e^2 V, K_p = -p d2V: -6 p e^2 V). */
#include <stdlib.h>
#include <string.h>

#include "fem.h"
#include "grid.h"
#include "kt_test.h"

static const double NU = 0.49;

/* An orthonormal frame from three angles (rad): rows a1, a2, n. */
static void frame(double ax, double ay, double az, double Q[3][3])
{
    double cx = cos(ax), sx = sin(ax), cy = cos(ay), sy = sin(ay), cz = cos(az), sz = sin(az);
    double R[3][3] = {{cy * cz, -cy * sz, sy},
                      {sx * sy * cz + cx * sz, -sx * sy * sz + cx * cz, -sx * cy},
                      {-cx * sy * cz + sx * sz, cx * sy * sz + sx * cz, cx * cy}};
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) Q[i][j] = R[j][i]; /* columns of R as rows */
}

/* Solve C eps = s (6x6, Gaussian elimination with partial pivoting). */
static void solve6(const double *C, const double *s, double *x)
{
    double A[6][7];
    for (int i = 0; i < 6; i++) {
        for (int j = 0; j < 6; j++) A[i][j] = C[6 * i + j];
        A[i][6] = s[i];
    }
    for (int k = 0; k < 6; k++) {
        int p = k;
        for (int i = k + 1; i < 6; i++)
            if (fabs(A[i][k]) > fabs(A[p][k])) p = i;
        for (int j = 0; j < 7; j++) {
            double t = A[k][j];
            A[k][j] = A[p][j];
            A[p][j] = t;
        }
        for (int i = k + 1; i < 6; i++) {
            double f = A[i][k] / A[k][k];
            for (int j = k; j < 7; j++) A[i][j] -= f * A[k][j];
        }
    }
    for (int i = 5; i >= 0; i--) {
        double v = A[i][6];
        for (int j = i + 1; j < 6; j++) v -= A[i][j] * x[j];
        x[i] = v / A[i][i];
    }
}

/* Voigt stress of the symmetric tensor s (a (x) b + b (x) a) / (1 or 2). */
static void voigt_of(const double *a, const double *b, double s, double *v)
{
    double T[3][3];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) T[i][j] = 0.5 * s * (a[i] * b[j] + b[i] * a[j]);
    /* a == b: s a a; a orthogonal to b: s/2 (a b + b a) */
    v[0] = T[0][0], v[1] = T[1][1], v[2] = T[2][2], v[3] = T[1][2], v[4] = T[0][2], v[5] = T[0][1];
}

/* a . eps b with eps from Voigt engineering strains. */
static double strain_ab(const double *e, const double *a, const double *b)
{
    double E[3][3] = {{e[0], e[5] / 2, e[4] / 2}, {e[5] / 2, e[1], e[3] / 2}, {e[4] / 2, e[3] / 2, e[2]}};
    double s = 0;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) s += a[i] * E[i][j] * b[j];
    return s;
}

/* Orthotropic (E1 > E2) with the limbal term along a1: a1 has modulus E1 + Ec exactly; a2 is
 * stiffer than E2 (the a1 fibres restrain its lateral contraction), so it is checked in the
 * transversely isotropic case. Shear stress tau = 1: voigt_of(a, b, 2) is tau (a b + b a). */
static void test_material(void)
{
    for (int r = 0; r < 3; r++) {
        double Q[3][3];
        frame(0.3 + r, -0.7 * r, 1.1 + 0.4 * r, Q);
        kt_fibre_material fm = {2.0 + r, 1.5, 0.05, NU};
        double C[36], eps[6], sig[6], Ec = 0.7 * r;
        kt_fem_fibre_matrix(&fm, Q[0], Q[1], Q[2], Q[0], Ec, C);
        voigt_of(Q[0], Q[0], 1.0, sig);
        solve6(C, sig, eps);
        CHECK_NEAR(strain_ab(eps, Q[0], Q[0]), 1.0 / (fm.E1 + Ec), 1e-12, "uniaxial along a1: 1/(E1 + Ec)");
        voigt_of(Q[0], Q[2], 2.0, sig);
        solve6(C, sig, eps);
        CHECK_NEAR(2 * strain_ab(eps, Q[0], Q[2]), 1.0 / fm.Gt, 1e-12, "transverse shear a1-n: 1/Gt");
        voigt_of(Q[1], Q[2], 2.0, sig);
        solve6(C, sig, eps);
        CHECK_NEAR(2 * strain_ab(eps, Q[1], Q[2]), 1.0 / fm.Gt, 1e-12, "transverse shear a2-n: 1/Gt");
        voigt_of(Q[0], Q[1], 2.0, sig);
        solve6(C, sig, eps);
        double mu = fmin(fm.E1, fm.E2) / (2 * (1 + NU));
        CHECK_NEAR(2 * strain_ab(eps, Q[0], Q[1]), 1.0 / mu, 1e-12, "in-plane shear: 1/mu");
        kt_fibre_material ti = {1.8, 1.8, 0.07, NU};
        kt_fem_fibre_matrix(&ti, Q[0], Q[1], Q[2], Q[0], 0, C);
        for (int k = 0; k < 2; k++) {
            voigt_of(Q[k], Q[k], 1.0, sig);
            solve6(C, sig, eps);
            CHECK_NEAR(strain_ab(eps, Q[k], Q[k]), 1.0 / ti.E1, 1e-12, "transversely isotropic: 1/E");
            CHECK_NEAR(strain_ab(eps, Q[1 - k], Q[1 - k]), -NU / ti.E1, 1e-12, "in-plane Poisson: -nu/E");
        }
    }
}

/* Uniaxial modulus along unit in-plane direction d of the material C: 1 / (d.eps.d) under the
 * unit stress d (x) d. */
static double uniaxial(const double *C, const double *d)
{
    double sig[6], eps[6];
    voigt_of(d, d, 1.0, sig);
    solve6(C, sig, eps);
    return 1.0 / strain_ab(eps, d, d);
}

/* What keratome-scene(5) (MATERIALS, eye.fibres) states of the orthotropic fibre matrix, in
 * both orders of E1, E2 and rotated frames: uniaxial stress along the stiffer of a1, a2 has
 * modulus E_t = max(E1, E2) exactly; along the softer one E_s E_t / (E_t - nu^2 (E_t - E_s))
 * (the page's example: E_s 2.0, E_t 3.0, nu 0.49 gives 2.174 MPa, not 2.0); with E1 = E2 = E,
 * uniaxial stress along any in-plane c that carries the limbal fibres Ec has modulus E + Ec, and
 * along the in-plane direction normal to c E (E + Ec) / (E + Ec - nu^2 Ec). */
static void test_orthotropy(void)
{
    for (int r = 0; r < 3; r++) {
        double Q[3][3], C[36];
        frame(-0.4 + 0.9 * r, 0.6 * r, 0.2 + 1.3 * r, Q);
        for (int swap = 0; swap < 2; swap++) {
            double Es = 2.0, Et = 3.0 + r;
            kt_fibre_material fm = {swap ? Et : Es, swap ? Es : Et, 0.05, NU};
            kt_fem_fibre_matrix(&fm, Q[0], Q[1], Q[2], Q[0], 0, C);
            const double *soft = Q[swap ? 1 : 0], *stiff = Q[swap ? 0 : 1];
            double want = Es * Et / (Et - NU * NU * (Et - Es));
            CHECK_NEAR(uniaxial(C, stiff), Et, 1e-12, "uniaxial along the stiffer fibre direction: E_t");
            CHECK_NEAR(uniaxial(C, soft), want, 1e-12, "uniaxial along the softer direction: E_s E_t / (E_t - nu^2 (E_t - E_s))");
            if (r == 0) CHECK(fabs(uniaxial(C, soft) - 2.174) < 5e-4, "the page's example: %.4f MPa", uniaxial(C, soft));
        }
        /* transversely isotropic with the limbal term along an in-plane c at 35 deg from a1 */
        double E = 2.0, Ec = 0.91 * E, c[3], b[3], t = 35 * KT_PI / 180;
        for (int k = 0; k < 3; k++) {
            c[k] = cos(t) * Q[0][k] + sin(t) * Q[1][k];
            b[k] = -sin(t) * Q[0][k] + cos(t) * Q[1][k];
        }
        kt_fibre_material ti = {E, E, 0.05, NU};
        kt_fem_fibre_matrix(&ti, Q[0], Q[1], Q[2], c, Ec, C);
        CHECK_NEAR(uniaxial(C, c), E + Ec, 1e-12, "uniaxial along c: E_inplane + E_circumferential");
        CHECK_NEAR(uniaxial(C, b), E * (E + Ec) / (E + Ec - NU * NU * Ec), 1e-12,
                   "uniaxial normal to c in the plane: E (E + Ec) / (E + Ec - nu^2 Ec)");
        /* keratome-vtk(5): an isotropic tet's constants E, E, E / (2 (1 + nu)), nu, 0 give
         * exactly its isotropic matrix, in any frame */
        double Ci[36], Cf[36], err = 0, big = 0;
        kt_fibre_material iso = {3.0, 3.0, 3.0 / (2 * (1 + NU)), NU};
        kt_fem_iso_matrix(3.0, NU, Ci);
        kt_fem_fibre_matrix(&iso, Q[0], Q[1], Q[2], c, 0, Cf);
        for (int k = 0; k < 36; k++) err = fmax(err, fabs(Cf[k] - Ci[k])), big = fmax(big, fabs(Ci[k]));
        CHECK(err <= 1e-13 * big, "isotropic constants: the fibre matrix is the isotropic one (%.3g of %.3g)", err, big);
    }
}

/* ------------------------------------------------------------- element level */

static double rnd(unsigned long long *s)
{
    *s = *s * 6364136223846793005ULL + 1442695040888963407ULL;
    return (double)(*s >> 11) / (double)(1ULL << 52) - 1.0;
}

/* Box of (n x n x n) grid nodes, elevated to order 2 when asked; interior nodes (and, for a
 * curved P2 mesh, mid-edge nodes) jittered. */
static int box(kt_mesh *m, int n, double L, int order, int curve, kt_err *e)
{
    if (kt_grid_box(m, n, n, n, L, L, L, e)) return e->code;
    unsigned long long seed = 7;
    double h = L / (n - 1);
    for (int i = 0; i < m->nn; i++) {
        int ix = i % n, iy = (i / n) % n, iz = i / (n * n);
        if (ix == 0 || iy == 0 || iz == 0 || ix == n - 1 || iy == n - 1 || iz == n - 1) continue;
        for (int k = 0; k < 3; k++) m->xyz[3 * i + k] += 0.2 * h * rnd(&seed);
    }
    if (order == 2 && kt_mesh_elevate(m, e)) return e->code;
    if (curve)
        for (int i = m->nn; i-- > 0;) {
            int on = 0;
            for (int k = 0; k < 3; k++) on |= m->xyz[3 * i + k] < 1e-12 || m->xyz[3 * i + k] > L - 1e-12;
            if (on) continue;
            for (int k = 0; k < 3; k++) m->xyz[3 * i + k] += 0.05 * h * rnd(&seed);
        }
    return KT_OK;
}

/* Per-tet data with the same fibre C everywhere (frame Q), sig and pface allocated (zero). */
static int tetdata(const kt_mesh *m, double Q[3][3], kt_fem_tetdata *td, kt_err *e)
{
    td->ne = m->ne;
    td->C = kt_calloc(36 * (size_t)m->ne, sizeof(double), e);
    td->sig = kt_calloc((size_t)m->ne * KT_FEM_NQ * 6, sizeof(double), e);
    td->pface = kt_calloc(4 * (size_t)m->ne, sizeof(double), e);
    if (e->code) return e->code;
    kt_fibre_material fm = {2.0, 1.2, 0.05, NU};
    for (int t = 0; t < m->ne; t++) kt_fem_fibre_matrix(&fm, Q[0], Q[1], Q[2], Q[1], 0.3, td->C + 36 * (size_t)t);
    return KT_OK;
}

static void td_free(kt_fem_tetdata *td)
{
    free(td->C);
    free(td->sig);
    free(td->pface);
}

/* y = K x over all elements (K = kt_fem_element), dense vectors of 3*nn. */
static int apply_K(const kt_mesh *m, const kt_materials *mats, const double *x, double *y, kt_err *e)
{
    int nv = kt_tet_nv(m->order), ld = 3 * nv;
    double Ke[900];
    memset(y, 0, 3 * (size_t)m->nn * sizeof(double));
    for (int t = 0; t < m->ne; t++) {
        if (kt_fem_element(m, mats, t, Ke, e)) return e->code;
        const int *tn = m->tet + (size_t)t * nv;
        for (int a = 0; a < ld; a++)
            for (int b = 0; b < ld; b++) y[3 * tn[a / 3] + a % 3] += Ke[a * ld + b] * x[3 * tn[b / 3] + b % 3];
    }
    return KT_OK;
}

static double dot(const double *a, const double *b, size_t n)
{
    double s = 0;
    for (size_t i = 0; i < n; i++) s += a[i] * b[i];
    return s;
}

static double nrm(const double *a, size_t n) { return sqrt(dot(a, a, n)); }

/* Rigid mode k (0..2 translations, 3..5 rotations about x, y, z) at every node. */
static void rigid(const kt_mesh *m, int k, double *u)
{
    for (int i = 0; i < m->nn; i++) {
        const double *x = m->xyz + 3 * i;
        double *v = u + 3 * i;
        v[0] = v[1] = v[2] = 0;
        if (k < 3) v[k] = 1;
        else if (k == 3) v[1] = -x[2], v[2] = x[1];
        else if (k == 4) v[0] = x[2], v[2] = -x[0];
        else v[0] = -x[1], v[1] = x[0];
    }
}

static void test_patch(int order, int curve)
{
    kt_err e = {0};
    kt_mesh m;
    double Q[3][3];
    frame(0.4, 0.9, -0.3, Q);
    kt_fem_tetdata td = {0};
    if (box(&m, 4, 1.0, order, curve, &e) || tetdata(&m, Q, &td, &e)) {
        CHECK(0, "setup: %s", e.msg);
        return;
    }
    free(td.sig), td.sig = NULL; /* material stiffness only */
    kt_material mv[2] = {{1, 0.3}, {1, 0.3}};
    kt_materials mats = {.nmat = 2, .mat = mv, .td = &td};
    size_t n = 3 * (size_t)m.nn;
    double *u = kt_calloc(n, sizeof(double), &e), *y = kt_calloc(n, sizeof(double), &e);
    for (int k = 0; k < 6 && !e.code; k++) {
        rigid(&m, k, u);
        apply_K(&m, &mats, u, y, &e);
        double Ku = nrm(y, n);
        double scale = 3.0 * nrm(u, n); /* |K| ~ E1 + Ec */
        CHECK(Ku <= 1e-11 * scale, "P%d%s fibre element: rigid mode %d, |K u| = %.3g", order,
              curve ? " curved" : "", k, Ku);
    }
    /* linear field u = G x, G a general gradient; interior rows of K u vanish */
    double G[3][3] = {{0.01, -0.02, 0.005}, {0.013, -0.007, 0.02}, {-0.004, 0.011, 0.006}};
    for (int i = 0; i < m.nn; i++)
        for (int r = 0; r < 3; r++)
            u[3 * i + r] = G[r][0] * m.xyz[3 * i] + G[r][1] * m.xyz[3 * i + 1] + G[r][2] * m.xyz[3 * i + 2];
    apply_K(&m, &mats, u, y, &e);
    double worst = 0, big = 0;
    for (int i = 0; i < m.nn; i++) {
        int on = 0;
        for (int k = 0; k < 3; k++) on |= m.xyz[3 * i + k] < 1e-12 || m.xyz[3 * i + k] > 1 - 1e-12;
        for (int c = 0; c < 3; c++) {
            big = fmax(big, fabs(y[3 * i + c]));
            if (!on) worst = fmax(worst, fabs(y[3 * i + c]));
        }
    }
    CHECK(worst <= 1e-11 * big, "P%d%s patch test: interior |K u| %.3g of boundary %.3g", order,
          curve ? " curved" : "", worst, big);
    double eps[6] = {G[0][0], G[1][1], G[2][2], G[1][2] + G[2][1], G[0][2] + G[2][0], G[0][1] + G[1][0]};
    double energy = 0;
    for (int p = 0; p < 6; p++)
        for (int q = 0; q < 6; q++) energy += eps[p] * td.C[6 * p + q] * eps[q];
    CHECK_NEAR(dot(u, y, n), energy * 1.0, 1e-10, "patch test energy u^T K u = V eps:C:eps");
    free(u);
    free(y);
    td_free(&td);
    kt_mesh_free(&m);
}

/* A string: a bar L x b x b along x under sigma_xx = T / b^2. A transverse displacement growing
 * linearly from 0 to d along it stores u^T K_sigma u = T d^2 / L (the string's stiffness T/L). */
static void test_string(int order)
{
    kt_err e = {0};
    kt_mesh m;
    double L = 5.0, b = 0.2, T = 0.03, d = 0.01;
    if (kt_grid_box(&m, 6, 2, 2, L, b, b, &e) || (order == 2 && kt_mesh_elevate(&m, &e))) {
        CHECK(0, "string mesh: %s", e.msg);
        return;
    }
    kt_fem_tetdata td = {0};
    td.ne = m.ne;
    td.sig = kt_calloc((size_t)m.ne * KT_FEM_NQ * 6, sizeof(double), &e);
    for (int t = 0; t < m.ne * KT_FEM_NQ && td.sig; t++) td.sig[6 * t] = T / (b * b);
    kt_material mv[2] = {{1e-30, 0.3}, {1e-30, 0.3}}; /* no material stiffness to speak of */
    kt_materials mats = {.nmat = 2, .mat = mv, .td = &td};
    size_t n = 3 * (size_t)m.nn;
    double *u = kt_calloc(n, sizeof(double), &e), *y = kt_calloc(n, sizeof(double), &e);
    for (int i = 0; i < m.nn; i++) u[3 * i + 1] = d * m.xyz[3 * i] / L;
    apply_K(&m, &mats, u, y, &e);
    CHECK_NEAR(dot(u, y, n) / (T * d * d / L), 1.0, 1e-9, "string: u^T K_sigma u = T d^2 / L");
    for (int k = 0; k < 3; k++) {
        rigid(&m, k, u);
        apply_K(&m, &mats, u, y, &e);
        CHECK(nrm(y, n) <= 1e-12 * (T / (b * b)) * nrm(u, n), "P%d K_sigma translation %d: %.3g",
              order, k, nrm(y, n));
    }
    free(u);
    free(y);
    free(td.sig);
    kt_mesh_free(&m);
}

/* Dense assembly of the (unsymmetrized) load stiffness of pressure p on all six box faces. */
static double *closed_Kp(const kt_mesh *m, double p, kt_err *e)
{
    size_t n = 3 * (size_t)m->nn;
    double *K = kt_calloc(n * n, sizeof(double), e);
    double *pface = kt_calloc(4 * (size_t)m->ne, sizeof(double), e);
    if (e->code) {
        free(K);
        free(pface);
        return NULL;
    }
    for (int s = 1; s <= 6; s++) kt_fem_pressure_faces(m, s, p, pface, e);
    static const int FACE[4][3] = {{1, 2, 3}, {0, 2, 3}, {0, 1, 3}, {0, 1, 2}};
    static const int EDGE[6][2] = {{0, 1}, {1, 2}, {2, 0}, {3, 0}, {3, 2}, {3, 1}};
    int nv = kt_tet_nv(m->order), fv = kt_tri_nv(m->order);
    for (int t = 0; t < m->ne && !e->code; t++)
        for (int f = 0; f < 4; f++) {
            if (pface[4 * t + f] == 0) continue;
            const int *tn = m->tet + (size_t)t * nv;
            int v[6] = {FACE[f][0], FACE[f][1], FACE[f][2]};
            const double *x[4];
            for (int a = 0; a < 4; a++) x[a] = m->xyz + 3 * tn[a];
            if (kt_tet_volume(x[v[0]], x[v[1]], x[v[2]], x[f]) > 0) {
                int tmp = v[1];
                v[1] = v[2];
                v[2] = tmp;
            }
            for (int k = 0; k < 3 && fv == 6; k++)
                for (int s = 0; s < 6; s++)
                    if ((EDGE[s][0] == v[k] && EDGE[s][1] == v[(k + 1) % 3]) ||
                        (EDGE[s][1] == v[k] && EDGE[s][0] == v[(k + 1) % 3]))
                        v[3 + k] = 4 + s;
            double xf[18], Kf[324];
            for (int a = 0; a < fv; a++) memcpy(xf + 3 * a, m->xyz + 3 * tn[v[a]], 3 * sizeof(double));
            kt_fem_face_load_stiffness(m->order, xf, p, Kf);
            for (int a = 0; a < 3 * fv; a++)
                for (int b = 0; b < 3 * fv; b++)
                    K[(3 * (size_t)tn[v[a / 3]] + a % 3) * n + 3 * tn[v[b / 3]] + b % 3] += Kf[a * 3 * fv + b];
        }
    free(pface);
    return K;
}

static void test_hydrostatic(int order, int curve)
{
    kt_err e = {0};
    kt_mesh m;
    double p = 0.002, L = 1.3;
    if (box(&m, 3, L, order, curve, &e)) {
        CHECK(0, "box: %s", e.msg);
        return;
    }
    size_t n = 3 * (size_t)m.nn;
    double *K = closed_Kp(&m, p, &e);
    if (!K) {
        CHECK(0, "Kp: %s", e.msg);
        return;
    }
    double asym = 0, big = 0;
    for (size_t i = 0; i < n; i++)
        for (size_t j = 0; j < n; j++) {
            asym = fmax(asym, fabs(K[i * n + j] - K[j * n + i]));
            big = fmax(big, fabs(K[i * n + j]));
        }
    CHECK(asym <= 1e-13 * big, "P%d%s closed surface: K_p asymmetry %.3g of %.3g", order,
          curve ? " curved" : "", asym, big);
    double *u = kt_calloc(n, sizeof(double), &e), *y = kt_calloc(n, sizeof(double), &e);
    for (int k = 0; k < 3; k++) {
        rigid(&m, k, u);
        double worst = 0;
        for (size_t i = 0; i < n; i++) worst = fmax(worst, fabs(dot(K + i * n, u, n)));
        CHECK(worst <= 1e-14 * big * m.nn, "K_p translation %d: %.3g", k, worst);
    }
    free(K);
    /* hydrostatic prestress -p with the follower pressure p on the whole boundary */
    kt_fem_tetdata td = {0};
    td.ne = m.ne;
    td.sig = kt_calloc((size_t)m.ne * KT_FEM_NQ * 6, sizeof(double), &e);
    td.pface = kt_calloc(4 * (size_t)m.ne, sizeof(double), &e);
    for (int q = 0; q < m.ne * KT_FEM_NQ && td.sig; q++)
        for (int c = 0; c < 3; c++) td.sig[6 * q + c] = -p;
    for (int s = 1; s <= 6 && !e.code; s++) kt_fem_pressure_faces(&m, s, p, td.pface, &e);
    double *f = kt_calloc(n, sizeof(double), &e), *fp = kt_calloc(n, sizeof(double), &e);
    for (int s = 1; s <= 6 && !e.code; s++) kt_fem_pressure(&m, s, p, fp, &e);
    memcpy(f, fp, n * sizeof(double));
    kt_material mv[2] = {{1e-30, 0.3}, {1e-30, 0.3}};
    kt_materials mats = {.nmat = 2, .mat = mv, .td = &td};
    kt_fem_release_loads(&m, &mats, f, &e);
    CHECK(nrm(f, n) <= 1e-13 * nrm(fp, n), "P%d%s equilibrium: |f_p - int B^T sig| = %.3g of %.3g",
          order, curve ? " curved" : "", nrm(f, n), nrm(fp, n));
    for (int k = 3; k < 6; k++) {
        rigid(&m, k, u);
        apply_K(&m, &mats, u, y, &e);
        CHECK(nrm(y, n) <= 1e-12 * p * nrm(u, n), "P%d%s K_sigma - K_p rotation %d: %.3g", order,
              curve ? " curved" : "", k - 3, nrm(y, n));
    }
    double ex = 0.01, V = L * L * L;
    for (size_t i = 0; i < n; i++) u[i] = ex * m.xyz[i];
    apply_K(&m, &mats, u, y, &e);
    CHECK_NEAR(dot(u, y, n) / (3 * p * ex * ex * V), 1.0, 1e-10,
               "dilation: u^T (K_sigma - K_p) u = 3 p e^2 V");
    CHECK(!e.code, "%s", e.msg);
    free(u);
    free(y);
    free(f);
    free(fp);
    td_free(&td);
    kt_mesh_free(&m);
}

int main(void)
{
    test_material();
    test_orthotropy();
    test_patch(1, 0);
    test_patch(2, 0);
    test_patch(2, 1);
    test_string(1);
    test_string(2);
    test_hydrostatic(1, 0);
    test_hydrostatic(2, 0);
    test_hydrostatic(2, 1);
    return kt_test_done("test_fem_tangent");
}
