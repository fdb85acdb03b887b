/* fem_nl.c: the total Lagrangian (geometrically nonlinear) kernels: a St Venant-Kirchhoff
 * material with the linear kernels' constitutive matrix, the prestress as an initial second
 * Piola-Kirchhoff stress, follower pressures on the current faces. The quadrature, gradients,
 * strain matrix and element terms are fem.c's (fem_int.h). */
#include "fem.h"
#include "fem_int.h"
#include "wound.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* F = I + H, H = sum_a u_a (x) g_a, and the Green-Lagrange strain E = (H + H^T + H^T H) / 2
 * (Voigt, engineering shears), formed from H: (F^T F - I) / 2 would lose the digits of a
 * small strain to the cancellation against I (a rounding floor of eps / |E| relative). */
static void deformation(int nv, double (*g)[3], const double *ue, double F[3][3], double E[6])
{
    double H[3][3];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            double s = 0;
            for (int a = 0; a < nv; a++) s += ue[3 * a + i] * g[a][j];
            H[i][j] = s;
            F[i][j] = (i == j) + s;
        }
    double G[3][3]; /* H^T H */
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            G[i][j] = H[0][i] * H[0][j] + H[1][i] * H[1][j] + H[2][i] * H[2][j];
    E[0] = H[0][0] + 0.5 * G[0][0];
    E[1] = H[1][1] + 0.5 * G[1][1];
    E[2] = H[2][2] + 0.5 * G[2][2];
    E[3] = H[1][2] + H[2][1] + G[1][2];
    E[4] = H[0][2] + H[2][0] + G[0][2];
    E[5] = H[0][1] + H[1][0] + G[0][1];
}

int kt_fem_nl_element(const kt_mesh *m, const kt_materials *mats, int tet, const double *u,
                      double pscale, double *fe, double *Ke, kt_err *e)
{
    int nv = kt_tet_nv(m->order), ld = 3 * nv;
    const int *t = m->tet + (size_t)tet * nv;
    double X[30], x[30], ue[30], C[36], B[6 * 30], g[10][3], det, F[3][3], E[6], S[6];
    kt_fem_gather_x(m, tet, X);
    for (int a = 0; a < nv; a++)
        for (int i = 0; i < 3; i++) {
            ue[3 * a + i] = u[3 * (size_t)t[a] + i];
            x[3 * a + i] = X[3 * a + i] + ue[3 * a + i];
        }
    if (kt_fem_element_C(m, mats, tet, C, e)) return e->code;
    const kt_fem_tetdata *td = mats->td;
    kt_tet_rule rule = kt_fem_rule(m->order, X);
    memset(fe, 0, sizeof(double) * ld);
    if (Ke) memset(Ke, 0, sizeof(double) * ld * ld);
    for (int q = 0; q < rule.n; q++) {
        if (kt_fem_point_gradients(nv, X, &rule, q, g, &det, e)) return e->code;
        deformation(nv, g, ue, F, E);
        for (int p = 0; p < 6; p++) {
            double s = td && td->sig ? td->sig[((size_t)tet * KT_FEM_NQ + q) * 6 + p] : 0.0;
            for (int k = 0; k < 6; k++) s += C[6 * p + k] * E[k];
            S[p] = s;
        }
        kt_fem_strain_matrix(nv, g, (const double(*)[3])F, B);
        double w = rule.w[q] * det;
        for (int r = 0; r < ld; r++) {
            double s = 0;
            for (int p = 0; p < 6; p++) s += B[p * ld + r] * S[p];
            fe[r] += w * s;
        }
        if (Ke) {
            kt_fem_add_btcb(nv, B, C, w, Ke);
            kt_fem_add_sigma(nv, g, S, w, Ke);
        }
    }
    if (td && td->pface && pscale != 0) {
        for (int f = 0; f < 4; f++) {
            double p = pscale * td->pface[4 * (size_t)tet + f];
            if (p != 0) kt_fem_add_face_load(m->order, X, x, f, p, Ke, fe);
        }
    }
    return KT_OK;
}

int kt_fem_nl_residual(const kt_mesh *m, const kt_materials *mats, const double *u,
                       double pscale, double *r, double *rabs, kt_err *e)
{
    int nv = kt_tet_nv(m->order);
    double fe[30];
    memset(r, 0, 3 * (size_t)m->nn * sizeof(double));
    if (rabs) memset(rabs, 0, 3 * (size_t)m->nn * sizeof(double));
    for (int el = 0; el < m->ne; el++) {
        kt_err le = {0};
        if (kt_fem_nl_element(m, mats, el, u, pscale, fe, NULL, &le))
            return kt_fail(e, le.code, "tet %d (region %d): %s", el + 1, m->tet_tag[el], le.msg);
        const int *t = m->tet + (size_t)el * nv;
        for (int a = 0; a < nv; a++)
            for (int c = 0; c < 3; c++) {
                r[3 * (size_t)t[a] + c] += fe[3 * a + c];
                if (rabs) rabs[3 * (size_t)t[a] + c] += fabs(fe[3 * a + c]);
            }
    }
    if (!kt_wound_on(mats)) return KT_OK;
    /* the bridge's forces B u (linear in u in the reference configuration, wound.h) */
    size_t n = 3 * (size_t)m->nn;
    double *bu = kt_calloc(n, sizeof(double), e);
    if (bu && !kt_wound_apply(mats->wound, m, u, 1.0, bu, e))
        for (size_t i = 0; i < n; i++) {
            r[i] += bu[i];
            if (rabs) rabs[i] += fabs(bu[i]);
        }
    free(bu);
    return e->code;
}
