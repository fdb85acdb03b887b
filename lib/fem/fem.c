/* fem.c: linear elasticity on 4- and 10-node tets: quadrature, the element stiffness (isotropic,
 * fibre, prestress stiffening, pressure load stiffness), release loads and element stresses.
 * Assembly is in fem_assemble.c, Dirichlet lifting and the direct solve in fem_solve.c. */
#include "fem.h"
#include "fem_int.h"

#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "chol.h"
#include "topology.h"

/* ---------------------------------------------------------------- quadrature */

/* 4 points, degree 2: exact for the P2 stiffness of a straight-sided tet. */
#define R4A 0.58541019662496845 /* (5 + 3 sqrt 5) / 20 */
#define R4B 0.13819660112501051 /* (5 - sqrt 5) / 20 */
static const double Q4_P[4][3] = {{R4B, R4B, R4B}, {R4A, R4B, R4B}, {R4B, R4A, R4B}, {R4B, R4B, R4A}};
static const double Q4_W[4] = {1.0 / 24, 1.0 / 24, 1.0 / 24, 1.0 / 24};

/* 14 points, degree 5, positive weights (Walkington): for curved (isoparametric) tets, where
 * det(J) grad(N) is cubic, so the integral of grad(N) and the patch test stay exact. */
#define R14A 0.045503704125647207
#define R14B (0.5 - R14A)
#define R14C 0.09273525031089172
#define R14C1 (1.0 - 3.0 * R14C)
#define R14D 0.31088591926330084
#define R14D1 (1.0 - 3.0 * R14D)
#define W14A 0.0070910034628465669
#define W14C 0.012248840519393811
#define W14D 0.018781320953002997
static const double Q14_P[14][3] = {
    {R14A, R14A, R14B}, {R14A, R14B, R14A}, {R14B, R14A, R14A},
    {R14B, R14B, R14A}, {R14B, R14A, R14B}, {R14A, R14B, R14B},
    {R14C, R14C, R14C}, {R14C1, R14C, R14C}, {R14C, R14C1, R14C}, {R14C, R14C, R14C1},
    {R14D, R14D, R14D}, {R14D1, R14D, R14D}, {R14D, R14D1, R14D}, {R14D, R14D, R14D1}};
static const double Q14_W[14] = {W14A, W14A, W14A, W14A, W14A, W14A, W14C,
                                  W14C, W14C, W14C, W14D, W14D, W14D, W14D};

/* gmsh tet10 edge nodes 4..9 lie on these vertex pairs. */

/* Reference gradients of the shape functions at (xi, eta, zeta): dN[a][k] = dN_a / dxi_k. */
static void shape_gradients(int nv, const double *q, double (*dN)[3])
{
    static const double dL[4][3] = {{-1, -1, -1}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    double L[4] = {1.0 - q[0] - q[1] - q[2], q[0], q[1], q[2]};
    if (nv == 4) {
        memcpy(dN, dL, sizeof dL);
        return;
    }
    for (int a = 0; a < 4; a++)
        for (int k = 0; k < 3; k++) dN[a][k] = (4.0 * L[a] - 1.0) * dL[a][k];
    for (int s = 0; s < 6; s++) {
        int i = kt_tet_edge[s][0], j = kt_tet_edge[s][1];
        for (int k = 0; k < 3; k++) dN[4 + s][k] = 4.0 * (L[i] * dL[j][k] + L[j] * dL[i][k]);
    }
}

/* Physical gradients g[a] = J^-T dN[a] and det J, J_ik = dx_i / dxi_k. */
static double physical_gradients(int nv, const double *x, double (*dN)[3], double (*g)[3])
{
    double J[3][3] = {{0}};
    for (int a = 0; a < nv; a++)
        for (int i = 0; i < 3; i++)
            for (int k = 0; k < 3; k++) J[i][k] += x[3 * a + i] * dN[a][k];
    double C[3][3]; /* cofactors: J^-1 = C^T / det */
    C[0][0] = J[1][1] * J[2][2] - J[1][2] * J[2][1];
    C[0][1] = J[1][2] * J[2][0] - J[1][0] * J[2][2];
    C[0][2] = J[1][0] * J[2][1] - J[1][1] * J[2][0];
    C[1][0] = J[0][2] * J[2][1] - J[0][1] * J[2][2];
    C[1][1] = J[0][0] * J[2][2] - J[0][2] * J[2][0];
    C[1][2] = J[0][1] * J[2][0] - J[0][0] * J[2][1];
    C[2][0] = J[0][1] * J[1][2] - J[0][2] * J[1][1];
    C[2][1] = J[0][2] * J[1][0] - J[0][0] * J[1][2];
    C[2][2] = J[0][0] * J[1][1] - J[0][1] * J[1][0];
    double det = J[0][0] * C[0][0] + J[0][1] * C[0][1] + J[0][2] * C[0][2];
    /* dN/dx_i = sum_k dN/dxi_k (J^-1)_ki = sum_k dN/dxi_k C_ik / det */
    for (int a = 0; a < nv; a++)
        for (int i = 0; i < 3; i++)
            g[a][i] = (dN[a][0] * C[i][0] + dN[a][1] * C[i][1] + dN[a][2] * C[i][2]) / det;
    return det;
}

/* ------------------------------------------------------------ element matrix */

/* Ke(3a+i, 3b+j) += w (lam g_a,i g_b,j + mu g_a,j g_b,i + mu delta_ij g_a . g_b), b <= a. */
static void add_point(int nv, double (*g)[3], double w, double lam, double mu, double *Ke)
{
    int ld = 3 * nv;
    for (int a = 0; a < nv; a++)
        for (int b = 0; b <= a; b++) {
            double dot = g[a][0] * g[b][0] + g[a][1] * g[b][1] + g[a][2] * g[b][2];
            double *K = Ke + (size_t)3 * a * ld + 3 * b;
            for (int i = 0; i < 3; i++)
                for (int j = 0; j < 3; j++)
                    K[i * ld + j] += w * (lam * g[a][i] * g[b][j] + mu * g[a][j] * g[b][i] +
                                          (i == j ? mu * dot : 0.0));
        }
}

/* Copy the lower node blocks to the upper ones. */
static void mirror(int nv, double *Ke)
{
    int ld = 3 * nv;
    for (int r = 0; r < ld; r++)
        for (int s = r + 1; s < ld; s++) Ke[r * ld + s] = Ke[s * ld + r];
}

/* A P2 tet is straight when every edge node sits at its edge's midpoint (to round-off). */
static int is_straight(const double *x)
{
    for (int s = 0; s < 6; s++) {
        const double *p = x + 3 * kt_tet_edge[s][0], *q = x + 3 * kt_tet_edge[s][1], *m = x + 12 + 3 * s;
        double len2 = 0, dev2 = 0, big = 0;
        for (int k = 0; k < 3; k++) {
            double d = m[k] - 0.5 * (p[k] + q[k]);
            dev2 += d * d;
            len2 += (q[k] - p[k]) * (q[k] - p[k]);
            big = kt_nanmax(big, kt_nanmax(fabs(p[k]), fabs(q[k])));
        }
        double tol = 1e-13 * sqrt(len2) + 8 * 2.2e-16 * big;
        if (!(dev2 <= tol * tol)) return 0;
    }
    return 1;
}

/* Longest vertex-to-vertex edge, the length scale of a degenerate-element test. */
static double longest_edge(const double *x)
{
    double h2 = 0;
    for (int s = 0; s < 6; s++) {
        const double *p = x + 3 * kt_tet_edge[s][0], *q = x + 3 * kt_tet_edge[s][1];
        double d2 = 0;
        for (int k = 0; k < 3; k++) d2 += (q[k] - p[k]) * (q[k] - p[k]);
        h2 = kt_nanmax(h2, d2);
    }
    return sqrt(h2);
}

int kt_fem_check_material(kt_material mat, kt_err *e)
{
    if (!(mat.E > 0) || !isfinite(mat.E))
        return kt_fail(e, KT_EINPUT, "Young's modulus %g MPa (expected > 0)", mat.E);
    if (!(mat.nu > -1.0 && mat.nu < 0.5))
        return kt_fail(e, KT_EINPUT, "Poisson ratio %g (expected -1 < nu < 0.5)", mat.nu);
    return KT_OK;
}

int kt_fem_tet_stiffness(int order, const double *x, kt_material mat, double *Ke, kt_err *e)
{
    if (order != 1 && order != 2)
        return kt_fail(e, KT_EINPUT, "element order %d (expected 1 or 2)", order);
    if (kt_fem_check_material(mat, e)) return e->code;
    int nv = kt_tet_nv(order);
    double lam = mat.E * mat.nu / ((1 + mat.nu) * (1 - 2 * mat.nu));
    double mu = mat.E / (2 * (1 + mat.nu));
    kt_tet_rule rule = kt_fem_rule(order, x);
    memset(Ke, 0, sizeof(double) * 9 * nv * nv);
    double g[10][3], det;
    for (int q = 0; q < rule.n; q++) {
        if (kt_fem_point_gradients(nv, x, &rule, q, g, &det, e)) return e->code;
        add_point(nv, g, rule.w[q] * det, lam, mu, Ke);
    }
    mirror(nv, Ke);
    return KT_OK;
}

/* ------------------------------------------------- general material, prestress */

/* The rule the element stiffness uses for this element (P1: centroid; P2: 4 points straight,
 * 14 curved). */
kt_tet_rule kt_fem_rule(int order, const double *x)
{
    static const double CENTROID[1][3] = {{0.25, 0.25, 0.25}};
    static const double W1[1] = {1.0 / 6};
    if (order == 1) return (kt_tet_rule){1, CENTROID, W1};
    if (is_straight(x)) return (kt_tet_rule){4, Q4_P, Q4_W};
    return (kt_tet_rule){14, Q14_P, Q14_W};
}

void kt_fem_iso_matrix(double E, double nu, double C[36])
{
    double lam = E * nu / ((1 + nu) * (1 - 2 * nu)), mu = E / (2 * (1 + nu));
    memset(C, 0, 36 * sizeof(double));
    for (int i = 0; i < 3; i++) {
        for (int j = 0; j < 3; j++) C[6 * i + j] = lam;
        C[6 * i + i] += 2 * mu;
        C[6 * (i + 3) + i + 3] = mu;
    }
}

static const int VOIGT[3][3] = {{0, 5, 4}, {5, 1, 3}, {4, 3, 2}};

/* C += s v(x)v(x)v(x)v in Voigt form (v unit). */
static void add_fibre(double C[36], const double v[3], double s)
{
    static const int I[6][2] = {{0, 0}, {1, 1}, {2, 2}, {1, 2}, {0, 2}, {0, 1}};
    for (int p = 0; p < 6; p++)
        for (int q = 0; q < 6; q++)
            C[6 * p + q] += s * v[I[p][0]] * v[I[p][1]] * v[I[q][0]] * v[I[q][1]];
}

void kt_fem_fibre_matrix(const kt_fibre_material *mat, const double a1[3], const double a2[3],
                         const double n[3], const double c[3], double Ec, double C[36])
{
    double Em = fmin(mat->E1, mat->E2), nu = mat->nu;
    double mu = Em / (2 * (1 + nu)), lam = 2 * mu * nu / (1 - 2 * nu);
    /* local Voigt matrix, axes (a1, a2, n) */
    double D[36] = {0};
    for (int i = 0; i < 3; i++) {
        for (int j = 0; j < 3; j++) D[6 * i + j] = lam;
        D[6 * i + i] += 2 * mu;
    }
    D[6 * 3 + 3] = mat->Gt; /* 23 = a2-n shear */
    D[6 * 4 + 4] = mat->Gt; /* 13 = a1-n shear */
    D[6 * 5 + 5] = mu;      /* 12: in-plane shear */
    D[0] += mat->E1 - Em;
    D[7] += mat->E2 - Em;
    /* rotate the tensor: C_ijkl = Q_ai Q_bj Q_ck Q_dl D_abcd, Q rows = local axes */
    const double *Q[3] = {a1, a2, n};
    memset(C, 0, 36 * sizeof(double));
    static const int I[6][2] = {{0, 0}, {1, 1}, {2, 2}, {1, 2}, {0, 2}, {0, 1}};
    for (int p = 0; p < 6; p++)
        for (int q = p; q < 6; q++) {
            int i = I[p][0], j = I[p][1], k = I[q][0], l = I[q][1];
            double sum = 0;
            for (int a = 0; a < 3; a++)
                for (int b = 0; b < 3; b++)
                    for (int cc = 0; cc < 3; cc++)
                        for (int d = 0; d < 3; d++) {
                            double dv = D[6 * VOIGT[a][b] + VOIGT[cc][d]];
                            if (dv != 0) sum += Q[a][i] * Q[b][j] * Q[cc][k] * Q[d][l] * dv;
                        }
            C[6 * p + q] = C[6 * q + p] = sum;
        }
    if (Ec > 0) add_fibre(C, c, Ec);
}

/* B (6 x 3nv): row p, column 3a+i = d E_p / d u_ai of the Green-Lagrange strain (Voigt,
 * engineering shears) at deformation gradient F: F_ik g_ak for p = (k,k), F_ik g_al + F_il g_ak
 * for p = (k,l). F = NULL is the identity: the small-strain B of the linear kernels. */
void kt_fem_strain_matrix(int nv, double (*g)[3], const double (*F)[3], double *B)
{
    static const int I[6][2] = {{0, 0}, {1, 1}, {2, 2}, {1, 2}, {0, 2}, {0, 1}};
    static const double ID[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    if (!F) F = ID;
    int ld = 3 * nv;
    for (int p = 0; p < 6; p++) {
        int k = I[p][0], l = I[p][1];
        for (int a = 0; a < nv; a++)
            for (int i = 0; i < 3; i++)
                B[p * ld + 3 * a + i] =
                    k == l ? F[i][k] * g[a][k] : F[i][k] * g[a][l] + F[i][l] * g[a][k];
    }
}

/* CB (6 x 3nv, row-major) := C B, C 6 x 6 and B 6 x 3nv row-major. */
static void c_times_b(int nv, const double *B, const double *C, double *CB)
{
    int ld = 3 * nv;
    for (int p = 0; p < 6; p++)
        for (int r = 0; r < ld; r++) {
            double s = 0;
            for (int q = 0; q < 6; q++) s += C[6 * p + q] * B[q * ld + r];
            CB[p * ld + r] = s;
        }
}

/* Ke += w B^T C B. */
void kt_fem_add_btcb(int nv, const double *B, const double *C, double w, double *Ke)
{
    int ld = 3 * nv;
    double CB[6 * 30];
    c_times_b(nv, B, C, CB);
    for (int r = 0; r < ld; r++)
        for (int s = 0; s < ld; s++) {
            double v = 0;
            for (int p = 0; p < 6; p++) v += B[p * ld + r] * CB[p * ld + s];
            Ke[r * ld + s] += w * v;
        }
}

/* The rows of the small-strain B (kt_fem_strain_matrix with F NULL) that may be nonzero in
 * column 3a+i, ascending: the normal strain of component i and the two shears holding i. Every
 * other entry of the column is a product with an exact zero, so a sum over these rows alone
 * equals the full sum over the six bit for bit (the skipped terms are +-0, the partial sums
 * start at +0 and never become -0): the linear kernels below do half the products. */
static const int SS_ROWS[3][3] = {{0, 4, 5}, {1, 3, 5}, {2, 3, 4}};

/* c_times_b for a small-strain B. */
static void c_times_b_ss(int nv, const double *B, const double *C, double *CB)
{
    int ld = 3 * nv;
    for (int r = 0; r < ld; r++) {
        const int *P = SS_ROWS[r % 3];
        double b0 = B[P[0] * ld + r], b1 = B[P[1] * ld + r], b2 = B[P[2] * ld + r];
        for (int p = 0; p < 6; p++) {
            double s = 0;
            s += C[6 * p + P[0]] * b0;
            s += C[6 * p + P[1]] * b1;
            s += C[6 * p + P[2]] * b2;
            CB[p * ld + r] = s;
        }
    }
}

/* v(r, s) of B^T (CB) for a small-strain B: row r's three rows of B (b) against CB. */
#define KT_SS_DOT(b, CB0, CB1, CB2, s) (((0.0 + (b)[0] * (CB0)[s]) + (b)[1] * (CB1)[s]) + (b)[2] * (CB2)[s])

/* Ke += w B^T C B for a small-strain B: kt_fem_add_btcb's sums, bit for bit, over B's nonzero
 * rows only. lower: only the lower triangle (r >= s) is computed and mirrored (half the
 * products; exactly symmetric, the same sums to rounding). */
static void add_btcb_ss(int nv, const double *B, const double *C, double w, int lower, double *Ke)
{
    int ld = 3 * nv;
    double CB[6 * 30];
    c_times_b_ss(nv, B, C, CB);
    for (int r = 0; r < ld; r++) {
        const int *P = SS_ROWS[r % 3];
        const double b[3] = {B[P[0] * ld + r], B[P[1] * ld + r], B[P[2] * ld + r]};
        const double *CB0 = CB + P[0] * ld, *CB1 = CB + P[1] * ld, *CB2 = CB + P[2] * ld;
        int end = lower ? r + 1 : ld;
        for (int s = 0; s < end; s++) {
            double v = KT_SS_DOT(b, CB0, CB1, CB2, s);
            Ke[r * ld + s] += w * v;
            if (lower && s != r) Ke[s * ld + r] += w * v;
        }
    }
}

/* Ke(3a+i, 3b+i) += w g_a . sig g_b: the stress stiffness of a prestress sig (Voigt). */
void kt_fem_add_sigma(int nv, double (*g)[3], const double *sig, double w, double *Ke)
{
    int ld = 3 * nv;
    double S[3][3];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) S[i][j] = sig[VOIGT[i][j]];
    for (int a = 0; a < nv; a++) {
        double Sg[3];
        for (int i = 0; i < 3; i++) Sg[i] = S[i][0] * g[a][0] + S[i][1] * g[a][1] + S[i][2] * g[a][2];
        for (int b = 0; b < nv; b++) {
            double v = w * (Sg[0] * g[b][0] + Sg[1] * g[b][1] + Sg[2] * g[b][2]);
            for (int i = 0; i < 3; i++) Ke[(3 * a + i) * ld + 3 * b + i] += v;
        }
    }
}

/* Local face f of a tet (opposite vertex f): its nodes in gmsh tri order, oriented outward. */
static int face_nodes(int nv, int f, const double *x, int *loc)
{
    int v[3] = {kt_tet_face[f][0], kt_tet_face[f][1], kt_tet_face[f][2]};
    const double *a = x + 3 * v[0], *b = x + 3 * v[1], *c = x + 3 * v[2], *d = x + 3 * f;
    if (kt_tet_volume(a, b, c, d) > 0) { /* (b-a) x (c-a) points towards d: flip */
        int t = v[1];
        v[1] = v[2];
        v[2] = t;
    }
    for (int k = 0; k < 3; k++) loc[k] = v[k];
    if (nv == 4) return 3;
    for (int k = 0; k < 3; k++) {
        int i = v[k], j = v[(k + 1) % 3];
        for (int s = 0; s < 6; s++)
            if ((kt_tet_edge[s][0] == i && kt_tet_edge[s][1] == j) ||
                (kt_tet_edge[s][0] == j && kt_tet_edge[s][1] == i))
                loc[3 + k] = 4 + s;
    }
    return 6;
}

void kt_fem_add_face_load(int order, const double *X, const double *x, int f, double p,
                          double *Ke, double *fe)
{
    int nv = kt_tet_nv(order), loc[6], fv = face_nodes(nv, f, X, loc), ld = 3 * nv, lf = 3 * fv;
    double xf[18], Kf[324];
    for (int a = 0; a < fv; a++) memcpy(xf + 3 * a, x + 3 * loc[a], 3 * sizeof(double));
    kt_fem_face_load_stiffness(order, xf, p, Kf);
    for (int a = 0; a < fv; a++)
        for (int i = 0; i < 3; i++) {
            /* f_face = Kf xf / 2: the pressure force is homogeneous of degree 2 in xf */
            double fa = 0;
            for (int r = 0; r < lf; r++) fa += Kf[(3 * a + i) * lf + r] * xf[r];
            if (fe) fe[3 * loc[a] + i] -= 0.5 * fa;
            for (int b = 0; b < fv && Ke; b++)
                for (int j = 0; j < 3; j++) {
                    double k = 0.5 * (Kf[(3 * a + i) * lf + 3 * b + j] + Kf[(3 * b + j) * lf + 3 * a + i]);
                    Ke[(3 * loc[a] + i) * ld + 3 * loc[b] + j] -= k;
                }
        }
}

void kt_fem_gather_x(const kt_mesh *m, int tet, double *x)
{
    int nv = kt_tet_nv(m->order);
    const int *t = m->tet + (size_t)tet * nv;
    for (int a = 0; a < nv; a++) memcpy(x + 3 * a, m->xyz + 3 * (size_t)t[a], 3 * sizeof(double));
}

/* The element's C (td->C or the region's isotropic one). */
int kt_fem_element_C(const kt_mesh *m, const kt_materials *mats, int tet, double C[36], kt_err *e)
{
    if (mats->td && mats->td->C) {
        memcpy(C, mats->td->C + 36 * (size_t)tet, 36 * sizeof(double));
        return KT_OK;
    }
    kt_material mat = mats->mat[m->tet_tag[tet]];
    if (kt_fem_check_material(mat, e)) return e->code;
    kt_fem_iso_matrix(mat.E, mat.nu, C);
    return KT_OK;
}

/* Physical gradients at quadrature point q of the element rule, with a degeneracy check. */
int kt_fem_point_gradients(int nv, const double *x, const kt_tet_rule *rule, int q, double (*g)[3],
                           double *det, kt_err *e)
{
    double dN[10][3], h = longest_edge(x), tiny = 1e-12 * h * h * h;
    shape_gradients(nv, rule->p[q], dN);
    *det = physical_gradients(nv, x, dN, g);
    if (!(*det > tiny))
        return kt_fail(e, KT_ERUN,
                       "%s element: Jacobian determinant %.3g at quadrature point %d of %d "
                       "(longest edge %.3g mm)",
                       *det < 0 ? "inverted" : "degenerate", *det, q + 1, rule->n, h);
    return KT_OK;
}

int kt_fem_element(const kt_mesh *m, const kt_materials *mats, int tet, double *Ke, kt_err *e)
{
    int nv = kt_tet_nv(m->order), ld = 3 * nv;
    double x[30];
    kt_fem_gather_x(m, tet, x);
    const kt_fem_tetdata *td = mats->td;
    if (!td) return kt_fem_tet_stiffness(m->order, x, mats->mat[m->tet_tag[tet]], Ke, e);
    double C[36], B[6 * 30], g[10][3], det;
    if (kt_fem_element_C(m, mats, tet, C, e)) return e->code;
    kt_tet_rule rule = kt_fem_rule(m->order, x);
    memset(Ke, 0, sizeof(double) * ld * ld);
    int material = 0; /* a zero C (a derivative's tet that q does not reach, sens.h) adds nothing */
    for (int i = 0; i < 36 && !material; i++) material = C[i] != 0;
    for (int q = 0; q < rule.n; q++) {
        if (kt_fem_point_gradients(nv, x, &rule, q, g, &det, e)) return e->code;
        if (material) {
            kt_fem_strain_matrix(nv, g, NULL, B);
            add_btcb_ss(nv, B, C, rule.w[q] * det, 0, Ke);
        }
        if (td->sig)
            kt_fem_add_sigma(nv, g, td->sig + ((size_t)tet * KT_FEM_NQ + q) * 6, rule.w[q] * det, Ke);
    }
    if (td->pface)
        for (int f = 0; f < 4; f++) {
            double p = td->pface[4 * (size_t)tet + f];
            if (p != 0) kt_fem_add_face_load(m->order, x, x, f, p, Ke, NULL);
        }
    return KT_OK;
}

/* Quadrature point q's share of every data set: w B^T C_k B + the stress stiffness into Ke_k,
 * -w B^T sig_k into fe_k. */
static void multi_point(int nv, double (*g)[3], const double *B, double w, int tet, int q,
                        const kt_fem_tetdata *const *td, int nd, const double *C,
                        const int *material, double *Ke, double *fe)
{
    int ld = 3 * nv;
    for (int k = 0; k < nd; k++) {
        const double *sig = td[k]->sig ? td[k]->sig + ((size_t)tet * KT_FEM_NQ + q) * 6 : NULL;
        if (Ke && material[k]) add_btcb_ss(nv, B, C + 36 * k, w, 1, Ke + (size_t)k * ld * ld);
        if (Ke && sig) kt_fem_add_sigma(nv, g, sig, w, Ke + (size_t)k * ld * ld);
        for (int r = 0; fe && sig && r < ld; r++) {
            double s = 0;
            for (int p = 0; p < 6; p++) s += B[p * ld + r] * sig[p];
            fe[k * ld + r] -= w * s;
        }
    }
}

int kt_fem_element_multi(const kt_mesh *m, const kt_materials *mats,
                         const kt_fem_tetdata *const *td, int nd, int tet, double *Ke,
                         double *fe, kt_err *e)
{
    int nv = kt_tet_nv(m->order), ld = 3 * nv, material[KT_FEM_MULTI_MAX];
    double x[30], C[36 * KT_FEM_MULTI_MAX], B[6 * 30], g[10][3], det;
    if (nd > KT_FEM_MULTI_MAX)
        return kt_fail(e, KT_ERUN, "%d data sets at once (at most %d)", nd, KT_FEM_MULTI_MAX);
    kt_fem_gather_x(m, tet, x);
    for (int k = 0; k < nd; k++) {
        kt_materials mk = *mats;
        mk.td = td[k];
        if (kt_fem_element_C(m, &mk, tet, C + 36 * k, e)) return e->code;
        material[k] = 0; /* a zero C (a derivative's tet that q does not reach) adds nothing */
        for (int i = 0; i < 36 && !material[k]; i++) material[k] = C[36 * k + i] != 0;
    }
    if (Ke) memset(Ke, 0, sizeof(double) * ld * ld * nd);
    if (fe) memset(fe, 0, sizeof(double) * ld * nd);
    kt_tet_rule rule = kt_fem_rule(m->order, x);
    for (int q = 0; q < rule.n; q++) {
        if (kt_fem_point_gradients(nv, x, &rule, q, g, &det, e)) return e->code;
        kt_fem_strain_matrix(nv, g, NULL, B);
        multi_point(nv, g, B, rule.w[q] * det, tet, q, td, nd, C, material, Ke, fe);
    }
    for (int k = 0; Ke && k < nd; k++)
        for (int f = 0; td[k]->pface && f < 4; f++) {
            double p = td[k]->pface[4 * (size_t)tet + f];
            if (p != 0) kt_fem_add_face_load(m->order, x, x, f, p, Ke + (size_t)k * ld * ld, NULL);
        }
    return KT_OK;
}

int kt_fem_element_release(const kt_mesh *m, const kt_materials *mats, int tet, double *fe,
                           kt_err *e)
{
    int nv = kt_tet_nv(m->order), ld = 3 * nv;
    memset(fe, 0, sizeof(double) * ld);
    if (!mats->td || !mats->td->sig) return KT_OK;
    double x[30], B[6 * 30], g[10][3], det;
    kt_fem_gather_x(m, tet, x);
    kt_tet_rule rule = kt_fem_rule(m->order, x);
    for (int q = 0; q < rule.n; q++) {
        if (kt_fem_point_gradients(nv, x, &rule, q, g, &det, e)) return e->code;
        kt_fem_strain_matrix(nv, g, NULL, B);
        const double *sig = mats->td->sig + ((size_t)tet * KT_FEM_NQ + q) * 6;
        for (int r = 0; r < ld; r++) {
            double s = 0;
            for (int p = 0; p < 6; p++) s += B[p * ld + r] * sig[p];
            fe[r] -= rule.w[q] * det * s;
        }
    }
    return KT_OK;
}

int kt_fem_release_loads(const kt_mesh *m, const kt_materials *mats, double *f, kt_err *e)
{
    if (!mats->td || !mats->td->sig) return KT_OK;
    int nv = kt_tet_nv(m->order);
    double fe[30];
    for (int el = 0; el < m->ne; el++) {
        if (kt_fem_element_release(m, mats, el, fe, e)) return e->code;
        const int *t = m->tet + (size_t)el * nv;
        for (int a = 0; a < nv; a++)
            for (int c = 0; c < 3; c++) f[3 * (size_t)t[a] + c] += fe[3 * a + c];
    }
    return KT_OK;
}

int kt_fem_stress(const kt_mesh *m, const kt_materials *mats, const double *u, double *sig,
                  kt_err *e)
{
    int nv = kt_tet_nv(m->order), ld = 3 * nv;
    double x[30], ue[30], C[36], B[6 * 30], g[10][3], det;
    for (int el = 0; el < m->ne; el++) {
        kt_fem_gather_x(m, el, x);
        const int *t = m->tet + (size_t)el * nv;
        for (int a = 0; a < nv; a++) memcpy(ue + 3 * a, u + 3 * (size_t)t[a], 3 * sizeof(double));
        if (kt_fem_element_C(m, mats, el, C, e)) return e->code;
        kt_tet_rule rule = kt_fem_rule(m->order, x);
        double *s_el = sig + (size_t)el * KT_FEM_NQ * 6;
        memset(s_el, 0, sizeof(double) * KT_FEM_NQ * 6);
        for (int q = 0; q < rule.n; q++) {
            if (kt_fem_point_gradients(nv, x, &rule, q, g, &det, e)) return e->code;
            kt_fem_strain_matrix(nv, g, NULL, B);
            double eps[6];
            for (int p = 0; p < 6; p++) {
                eps[p] = 0;
                for (int r = 0; r < ld; r++) eps[p] += B[p * ld + r] * ue[r];
            }
            for (int p = 0; p < 6; p++) {
                double s = 0;
                for (int k = 0; k < 6; k++) s += C[6 * p + k] * eps[k];
                s_el[6 * q + p] = s;
            }
        }
    }
    return KT_OK;
}

int kt_fem_prestress_mean(const kt_mesh *m, const kt_materials *mats, int tet, double mean[6],
                          kt_err *e)
{
    memset(mean, 0, 6 * sizeof(double));
    if (!mats->td || !mats->td->sig) return KT_OK;
    int nv = kt_tet_nv(m->order);
    double x[30], g[10][3], det, vol = 0;
    kt_fem_gather_x(m, tet, x);
    kt_tet_rule rule = kt_fem_rule(m->order, x);
    const double *sig = mats->td->sig + (size_t)tet * KT_FEM_NQ * 6;
    for (int q = 0; q < rule.n; q++) {
        if (kt_fem_point_gradients(nv, x, &rule, q, g, &det, e)) return e->code;
        vol += rule.w[q] * det;
        for (int p = 0; p < 6; p++) mean[p] += rule.w[q] * det * sig[6 * q + p];
    }
    for (int p = 0; p < 6; p++) mean[p] /= vol;
    return KT_OK;
}
