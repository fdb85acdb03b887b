/* test_newton_plan.c: kt_newton_plan on a prestressed bar with a cut, against the linear
 * answer (the tangent at the prestressed state, as augsolve's methods solve it).
 *
 * A bar 4 x 1 x 1 mm (P2 tets, 8 x 2 x 2 box grid), E = 1 MPa, nu = 0.3, both ends clamped,
 * under a uniform axial prestress s (in equilibrium with the clamps' reactions: its internal
 * forces vanish on every free node). One step cuts the upper half of the section at x = 2
 * (the nodes of that plane with z > 0.5 split; the tets on the x > 2 side take the new ones).
 * The cut's faces lose their traction s; the linear answer solves K_T u = f_release with
 * K_T = material + stress stiffness (kt_fem_solve, kt_fem_release_loads); the nonlinear one
 * releases the cut in increments (kt_newton_plan). At s = 0.0002 E (1% of s = 0.02 E, a 2%
 * prestrain) the two fields agree to 1e-3 relative, and their gap is first order in s (10 times
 * larger at s = 0.002 E, within 20%). The gap is about 3 s / E: the displacement gradients
 * near the cut's front are a few times s / E. Printed too: s = 0.005 E, about the eye's
 * membrane prestress over its in-plane modulus (p R / 2 t over E). kt_newton_plan's linear
 * option (one full step from u = 0) equals the linear answer to 1e-9 relative. */
#include <stdlib.h>
#include <string.h>

#include "fem.h"
#include "grid.h"
#include "kt_test.h"
#include "newton.h"

/* The bar after the cut, its linear and nonlinear fields under prestress s: the gap
 * ||u_nl - u_lin|| / ||u_lin||. */
static double cut_bar(double s)
{
    kt_mesh m;
    kt_err e = {0};
    CHECK(kt_grid_box(&m, 9, 3, 3, 4.0, 1.0, 1.0, &e) == KT_OK && kt_mesh_elevate(&m, &e) == KT_OK,
          "%s", e.msg);
    int nn0 = m.nn, nv = 10;
    /* the per-tet data: uniform sigma_xx = s at every quadrature point */
    double *sig = calloc((size_t)m.ne * KT_FEM_NQ * 6, sizeof(double));
    for (int i = 0; i < m.ne * KT_FEM_NQ; i++) sig[6 * i] = s;
    kt_fem_tetdata td = {m.ne, NULL, sig, NULL};
    kt_material mat[2] = {{1, 0.3}, {1, 0.3}};
    kt_fem_problem fp;
    memset(&fp, 0, sizeof fp);
    fp.nn = nn0;
    fp.mats = (kt_materials){2, mat, &td, NULL};
    fp.fixed = calloc(3 * (size_t)nn0, 1);
    fp.g = calloc(3 * (size_t)nn0, sizeof(double));
    fp.nfix = 2;
    fp.fix[0] = (kt_fem_fix_surf){1, 7, {0, 0, 0}};
    fp.fix[1] = (kt_fem_fix_surf){2, 7, {0, 0, 0}};
    for (int i = 0; i < nn0; i++) {
        double x = m.xyz[3 * i];
        if (fabs(x) < 1e-12 || fabs(x - 4) < 1e-12) memset(fp.fixed + 3 * i, 1, 3);
    }
    /* the step: one dup per cut node, moving its tets on the x > 2 side */
    kt_step step = {0};
    step.index = 1;
    int next = nn0;
    for (int i = 0; i < nn0; i++) {
        const double *x = m.xyz + 3 * i;
        if (fabs(x[0] - 2) > 1e-12 || x[2] < 0.5 + 1e-9) continue;
        kt_edit ed = {.kind = KT_EDIT_DUP, .node = i, .new_node = next++};
        ed.el = malloc(sizeof(int) * m.ne);
        for (int t = 0; t < m.ne; t++) {
            double cx = 0;
            int has = 0;
            for (int a = 0; a < 4; a++) cx += 0.25 * m.xyz[3 * m.tet[nv * t + a]];
            for (int a = 0; a < nv; a++) has |= m.tet[nv * t + a] == i;
            if (has && cx > 2) ed.el[ed.nel++] = t;
        }
        CHECK(kt_step_add(&step, &ed, &e) == KT_OK, "%s", e.msg);
        free(ed.el);
    }
    kt_newton_opts o;
    kt_newton_defaults(&o);
    o.increments = 2;
    o.log = getenv("KT_NEWTON_LOG") ? stderr : NULL;
    double *u = NULL;
    kt_newton_stats st;
    CHECK(kt_newton_plan(&m, &fp, &step, 1, &o, &u, &st, &e) == KT_OK, "%s", e.msg);
    CHECK(m.nn == next, "cut mesh has %d nodes, expected %d", m.nn, next);
    /* the linear answer on the cut mesh */
    size_t n = 3 * (size_t)m.nn;
    double *f = calloc(n, sizeof(double)), *ul = calloc(n, sizeof(double));
    unsigned char *fixed = calloc(n, 1);
    for (size_t i = 0; i < n; i++) {
        double x = m.xyz[3 * (i / 3)];
        fixed[i] = fabs(x) < 1e-12 || fabs(x - 4) < 1e-12;
    }
    kt_materials mats = fp.mats;
    CHECK(kt_fem_release_loads(&m, &mats, f, &e) == KT_OK, "%s", e.msg);
    cholmod_common c;
    cholmod_start(&c);
    CHECK(kt_fem_solve(&m, &mats, fixed, NULL, f, ul, &c, &e) == KT_OK, "%s", e.msg);
    cholmod_finish(&c);
    /* the linear option: the same answer through the total Lagrangian assembly */
    kt_mesh m2;
    double *u2 = NULL, d2 = 0, n2 = 0;
    CHECK(kt_grid_box(&m2, 9, 3, 3, 4.0, 1.0, 1.0, &e) == KT_OK && kt_mesh_elevate(&m2, &e) == KT_OK,
          "%s", e.msg);
    o.linear = 1;
    CHECK(kt_newton_plan(&m2, &fp, &step, 1, &o, &u2, NULL, &e) == KT_OK, "%s", e.msg);
    for (size_t i = 0; u2 && i < n; i++) {
        d2 += (u2[i] - ul[i]) * (u2[i] - ul[i]);
        n2 += ul[i] * ul[i];
    }
    CHECK(u2 && sqrt(d2 / n2) <= 1e-9, "linear option vs kt_fem_solve: %.3e", sqrt(d2 / n2));
    kt_mesh_free(&m2);
    free(u2);
    double d = 0, nl = 0, open = 0;
    for (size_t i = 0; u && i < n; i++) {
        d += (u[i] - ul[i]) * (u[i] - ul[i]);
        nl += ul[i] * ul[i];
    }
    for (int i = nn0; u && i < m.nn; i++) /* the cut's opening at its top edge: new - parent */
        open = fmax(open, u[3 * i]);
    double gap = sqrt(d / nl);
    printf("s = %g E: %d cut nodes, %d increments, %d iterations, %.2f s; max u_x of the new "
           "nodes %.4g mm; ||u_nl - u_lin|| / ||u_lin|| = %.3e\n", s, m.nn - nn0, st.increments,
           st.iterations, st.t, open, gap);
    CHECK(open > 0, "the cut did not open (u_x of the new nodes %g)", open);
    kt_step_free(&step);
    kt_mesh_free(&m);
    free(sig);
    free(fp.fixed);
    free(fp.g);
    free(u);
    free(f);
    free(ul);
    free(fixed);
    return gap;
}

int main(void)
{
    double g1 = cut_bar(0.0002), g10 = cut_bar(0.002);
    cut_bar(0.005);
    CHECK(g1 <= 1e-3, "at s = 0.0002 E: %.3e", g1);
    CHECK(fabs(g10 / g1 - 10) <= 2, "gap ratio %.3f (first order in s: 10)", g10 / g1);
    return kt_test_done("test_newton_plan");
}
