/* test_newton.c: the nonlinear reference (kt_newton_solve) on a cantilever at large rotation.
 *
 * A clamped beam, length L = 20, square section b = h = 1 (mm), E = 1000 MPa, nu = 0 (no
 * Poisson coupling, so the 3D solid is a beam), P2 tets on a 40 x 2 x 2 box grid, a dead
 * transverse load P on its free end (the consistent traction of a uniform shear). The tip
 * displacements of the inextensible elastica of a cantilever under a tip load, with
 * alpha = P L^2 / (E I), I = b h^3 / 12, as tabulated by Mattiasson (1981, Int. J. Numer. Meth.
 * Eng. 17:145-153, Table 1; first given by Bisshopp & Drucker 1945, Q. Appl. Math. 3:272):
 *   alpha    -u/L (shortening)   v/L (deflection)
 *     2          0.16064             0.49346
 *    10          0.55500             0.81061
 * (our own shooting solution of theta'' = -alpha cos theta, theta(0) = 0, theta'(1) = 0,
 * reproduces all ten digits shown). The solid differs from the elastica by shear (3 E I /
 * (k G A L^2) = 0.15% of the deflection for nu = 0, k = 5/6), axial stretch (P/(EA) ~ 1e-4)
 * and discretization: tolerance 1% of L on each component.
 *
 * Also: (c) at 1% of a load alpha = 0.3 (tip rotation 8 deg) the nonlinear and linear
 * (kt_fem_solve) fields agree to 1e-3 relative, and the difference is first order in the load
 * (halving the load halves it, within 10%); (d) Newton converges quadratically: in the last
 * increment of the alpha = 10 path, the last pair of relative residuals above the rounding floor
 * has log r_k+1 / log r_k >= 1.8; (e) past the buckling load the indefinite tangent fails
 * loudly. */
#include <stdlib.h>
#include <string.h>

#include "fem.h"
#include "grid.h"
#include "kt_test.h"
#include "newton.h"

#define LEN 20.0
#define YOUNG 1000.0

typedef struct beam {
    kt_mesh m;
    kt_material mat[2];
    kt_materials mats;
    unsigned char *fixed;
    double *w; /* 3*nn: the end face's consistent weights along z, summing to -1 */
    int tip;   /* the node at the centre of the end face */
} beam;

static int beam_make(beam *B, kt_err *e)
{
    memset(B, 0, sizeof *B);
    if (kt_grid_box(&B->m, 41, 3, 3, LEN, 1.0, 1.0, e) || kt_mesh_elevate(&B->m, e)) return e->code;
    kt_mesh *m = &B->m;
    B->mat[1] = (kt_material){YOUNG, 0.0};
    B->mats = (kt_materials){2, B->mat, NULL, NULL};
    size_t n = 3 * (size_t)m->nn;
    B->fixed = calloc(n, 1);
    B->w = calloc(n, sizeof(double));
    double *f = calloc(n, sizeof(double));
    if (kt_fem_pressure(m, 2, 1.0, f, e)) return e->code; /* xmax: force -n dA along -x */
    for (int i = 0; i < m->nn; i++) {
        const double *x = m->xyz + 3 * i;
        if (fabs(x[0]) < 1e-12) B->fixed[3 * i] = B->fixed[3 * i + 1] = B->fixed[3 * i + 2] = 1;
        B->w[3 * i + 2] = f[3 * i]; /* the same weights turned to -z */
        if (fabs(x[0] - LEN) < 1e-12 && fabs(x[1] - 0.5) < 1e-12 && fabs(x[2] - 0.5) < 1e-12)
            B->tip = i;
    }
    free(f);
    return KT_OK;
}

static void beam_free(beam *B)
{
    kt_mesh_free(&B->m);
    free(B->fixed);
    free(B->w);
}

/* Newton on tip load alpha (E I alpha / L^2), into u; st filled. */
static int solve_nl(beam *B, double alpha, int increments, double *u, kt_newton_stats *st,
                    kt_err *e)
{
    size_t n = 3 * (size_t)B->m.nn;
    double P = alpha * YOUNG / 12.0 / (LEN * LEN), *f = calloc(n, sizeof(double));
    for (size_t i = 0; i < n; i++) f[i] = P * B->w[i];
    kt_newton_problem p = {&B->m, &B->mats, B->fixed, NULL, f, 1, NULL};
    kt_newton_opts o;
    kt_newton_defaults(&o);
    o.increments = increments;
    o.log = getenv("KT_NEWTON_LOG") ? stderr : NULL;
    int rc = kt_newton_solve(&p, &o, u, st, e);
    free(f);
    return rc;
}

static void elastica(beam *B, double alpha, double ux_ref, double uz_ref, int increments)
{
    size_t n = 3 * (size_t)B->m.nn;
    double *u = calloc(n, sizeof(double));
    kt_newton_stats st;
    kt_err e = {0};
    CHECK(solve_nl(B, alpha, increments, u, &st, &e) == KT_OK, "%s", e.msg);
    double ux = -u[3 * B->tip] / LEN, uz = -u[3 * B->tip + 2] / LEN;
    printf("alpha %g: -u/L = %.5f (elastica %.5f), v/L = %.5f (elastica %.5f); %d increments, "
           "%d iterations, %d cuts, %.2f s\n", alpha, ux, ux_ref, uz, uz_ref, st.increments,
           st.iterations, st.cuts, st.t);
    CHECK(fabs(ux - ux_ref) <= 0.01, "alpha %g: shortening %.5f vs %.5f", alpha, ux, ux_ref);
    CHECK(fabs(uz - uz_ref) <= 0.01, "alpha %g: deflection %.5f vs %.5f", alpha, uz, uz_ref);
    if (alpha == 10) { /* (d) the rate, from the last increment's residuals */
        printf("residuals of the last increment:");
        for (int k = 0; k < st.nres; k++) printf(" %.3e", st.res[k]);
        printf("\n");
        /* the last pair above 1e-10, well above the rounding floor (near 1e-15: residuals are
         * relative to the size of the element forces, newton.h): log r_k+1 / log r_k is 2 for quadratic convergence with a constant near 1
         * (more with a smaller one) and below 1.2 for linear convergence at rate 0.3 from
         * r_k <= 1e-3 */
        double order = 0;
        for (int k = 0; k + 1 < st.nres; k++)
            if (st.res[k + 1] >= 1e-10 && st.res[k] < 0.5)
                order = log(st.res[k + 1]) / log(st.res[k]);
        printf("order log r_k+1 / log r_k of the last pair above 1e-10: %.2f\n", order);
        CHECK(order >= 1.8, "Newton's order %.2f (expected quadratic)", order);
    }
    free(u);
}

/* ||u_nl - u_lin|| / ||u_lin|| at load alpha. */
static double lin_gap(beam *B, double alpha)
{
    size_t n = 3 * (size_t)B->m.nn;
    double *u = calloc(n, sizeof(double)), *ul = calloc(n, sizeof(double));
    double *f = calloc(n, sizeof(double)), P = alpha * YOUNG / 12.0 / (LEN * LEN);
    for (size_t i = 0; i < n; i++) f[i] = P * B->w[i];
    kt_err e = {0};
    cholmod_common c;
    cholmod_start(&c);
    CHECK(kt_fem_solve(&B->m, &B->mats, B->fixed, NULL, f, ul, &c, &e) == KT_OK, "%s", e.msg);
    cholmod_finish(&c);
    CHECK(solve_nl(B, alpha, 1, u, NULL, &e) == KT_OK, "%s", e.msg);
    double d = 0, s = 0;
    for (size_t i = 0; i < n; i++) {
        d += (u[i] - ul[i]) * (u[i] - ul[i]);
        s += ul[i] * ul[i];
    }
    free(u);
    free(ul);
    free(f);
    return sqrt(d / s);
}

/* Past the buckling load the straight path's tangent is indefinite: a compressive dead load of
 * 3 P_cr (P_cr = pi^2 E I / (4 L^2), the clamped-free column) in 2 increments must fail loudly:
 * KT_ERUN naming the non-positive pivot, after max_cuts cuts, having reached lambda near 1/3
 * (P_cr) but not beyond 0.36 (the discrete P_cr is a little above the continuum's). */
static void buckling(beam *B)
{
    size_t n = 3 * (size_t)B->m.nn;
    double Pcr = M_PI * M_PI * YOUNG / 12.0 / (4 * LEN * LEN);
    double *f = calloc(n, sizeof(double)), *u = calloc(n, sizeof(double));
    for (size_t i = 0; i < n; i += 3) f[i] = 3 * Pcr * B->w[i + 2]; /* along -x */
    kt_newton_problem p = {&B->m, &B->mats, B->fixed, NULL, f, 1, NULL};
    kt_newton_opts o;
    kt_newton_defaults(&o);
    o.increments = 2;
    o.max_cuts = 6;
    kt_newton_stats st;
    kt_err e = {0};
    int rc = kt_newton_solve(&p, &o, u, &st, &e);
    printf("compression 3 P_cr: rc %d, lambda reached %.4f, %d cuts: %s\n", rc, st.lambda,
           st.cuts, e.msg);
    CHECK(rc == KT_ERUN && strstr(e.msg, "not positive definite"), "expected a loud failure: %s",
          e.msg);
    CHECK(st.cuts == o.max_cuts + 1 && st.lambda > 0.25 && st.lambda < 0.36,
          "cuts %d, lambda %.4f", st.cuts, st.lambda);
    free(f);
    free(u);
}

int main(void)
{
    beam B;
    kt_err e = {0};
    CHECK(beam_make(&B, &e) == KT_OK, "%s", e.msg);
    if (e.code) return kt_test_done("test_newton");
    printf("beam: %d nodes, %d P2 tets\n", B.m.nn, B.m.ne);
    buckling(&B);
    elastica(&B, 2, 0.16064, 0.49346, 4);
    elastica(&B, 10, 0.55500, 0.81061, 10);
    double g1 = lin_gap(&B, 0.003), g2 = lin_gap(&B, 0.006);
    printf("||u_nl - u_lin|| / ||u_lin||: %.3e at 1%% of alpha 0.3, %.3e at 2%%\n", g1, g2);
    CHECK(g1 <= 1e-3, "at 1%% of the load: %.3e", g1);
    CHECK(fabs(g2 / g1 - 2) <= 0.2, "gap ratio at 2%%/1%% of the load: %.3f (first order: 2)", g2 / g1);
    beam_free(&B);
    return kt_test_done("test_newton");
}
