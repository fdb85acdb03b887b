/* test_sens.c: the derivatives of the front door (solver.h, sens.h: augsolve --uncertainty)
 * against closed forms on a cantilever beam (3 x 3 x 12 nodes, clamped at zmin, pressures on
 * ymax and zmax, no prestress) cut layer by layer. Every load is independent of the modulus
 * and K is proportional to it, so u = K(E)^-1 f has du/dE = -u / E exactly (the discrete
 * model, not only beam theory); every load is a pressure in proportion to the first, so
 * du/dp = u / p (p in mmHg, as the iop quantity). Checked at every step for the planned
 * method (its own substitutions), with --output zmax (restricted back substitution: NaN off
 * the set, equal on it) and for refactor (the front door's derivatives from scratch), to
 * 1e-9 relative; newton is refused (KT_EINPUT). */
#include <stdio.h>

#include "solver.h"
#include "test_aug_scenario.h"
#include "kt_test.h"

enum { NSTEPS = 4 };
#define MMHG_MPA 133.322387415e-6

static int make_plan(const scenario *s, kt_edits_plan *p, kt_mesh *final, kt_err *e)
{
    FILE *f = tmpfile();
    kt_mesh cur;
    if (!f || kt_mesh_copy(&cur, &s->mesh, e)) return kt_fail(e, KT_ERUN, "tmpfile");
    kt_edits_header h = {.nn = s->mesh.nn, .ne = s->mesh.ne};
    snprintf(h.scene, sizeof h.scene, "box");
    snprintf(h.mesh, sizeof h.mesh, "box.msh");
    kt_edits_write_header(f, &h, e);
    kt_step st = {0};
    for (int k = 1; k <= NSTEPS && !e->code; k++) {
        kt_step_clear(&st);
        st.index = k;
        cut_layer(s, &cur, &st, 1, s->nz - 1 - k, 0.0, e); /* no forces: loads are pressures */
        int *touched = NULL, nt = 0;
        if (!e->code) kt_cut_apply(&cur, &st, &touched, &nt, e);
        free(touched);
        if (!e->code) kt_edits_write_step(f, &st, e);
    }
    if (!e->code) kt_edits_write_done(f, NSTEPS, e);
    kt_step_free(&st);
    kt_mesh_free(&cur);
    kt_edits_reader r;
    memset(p, 0, sizeof *p);
    rewind(f);
    if (!e->code && !kt_edits_open(&r, f, "stream", e) && !kt_edits_plan_read(p, &r, e))
        kt_edits_plan_check(p, "stream", &s->prob, final, e);
    fclose(f);
    return e->code;
}

/* Two derivative quantities by hand: the modulus (dC = C(E = 1)) and the pressure scale. */
static int make_sens(const scenario *s, kt_fem_sens *S, kt_err *e)
{
    memset(S, 0, sizeof *S);
    S->nd = 2;
    S->npress = 2;
    for (int i = 0; i < 2; i++) S->ptag[i] = s->press[i].tag;
    const kt_mesh *m = &s->mesh;
    for (int k = 0; k < 2; k++) {
        S->d[k].td.ne = m->ne;
        if (!(S->d[k].td.C = kt_calloc(36 * (size_t)m->ne, sizeof(double), e))) return e->code;
    }
    S->d[0].q = KT_UQ_E_INPLANE;
    for (int t = 0; t < m->ne; t++) kt_fem_iso_matrix(1.0, s->mat[1].nu, S->d[0].td.C + 36 * (size_t)t);
    S->d[1].q = KT_UQ_IOP;
    S->d[1].dK_zero = 1;
    for (int i = 0; i < 2; i++) S->d[1].dpress[i] = s->press[i].p / s->press[0].p * MMHG_MPA;
    return KT_OK;
}

static void check_method(const scenario *s, const kt_edits_plan *p, const kt_mesh *final,
                         const kt_fem_sens *S, int method, const char *output)
{
    kt_err e = {0};
    kt_solver_opts o = {.plan_max_ratio = 0, .sens = S};
    kt_aug_opts_default(&o.aug);
    o.aug.method = method;
    o.aug.quiet = 1;
    o.aug.tol = 1e-12;
    o.aug.ordering = method == KT_AUG_PLANNED ? KT_AUG_ORDER_METIS : KT_AUG_ORDER_NATURAL;
    snprintf(o.aug.output, sizeof o.aug.output, "%s", output);
    kt_solver *sv = NULL;
    const char *name = kt_aug_method_name(method);
    if (kt_solver_create(&sv, &s->prob, p, final, &o, &e)) {
        CHECK(0, "%s: %s", name, e.msg);
        return;
    }
    double E = s->mat[1].E, iop = s->press[0].p / MMHG_MPA;
    for (int k = 0; k <= p->nsteps && !e.code; k++) {
        int solved = 1;
        if (k > 0 && kt_solver_step(sv, &solved, &e)) break;
        const double *u = kt_solver_u(sv), *dE = kt_solver_dudp(sv, 0), *dp = kt_solver_dudp(sv, 1);
        int n = 3 * kt_solver_mesh(sv)->nn, nan_ok = 1, seen = 0;
        double mx = 0, d0 = 0, d1 = 0;
        for (int i = 0; i < n; i++) {
            if (isnan(u[i])) {
                nan_ok &= isnan(dE[i]) && isnan(dp[i]);
                continue;
            }
            seen++;
            mx = fmax(mx, fabs(u[i]));
            d0 = fmax(d0, fabs(dE[i] + u[i] / E) * E);
            d1 = fmax(d1, fabs(dp[i] - u[i] / iop) * iop);
        }
        CHECK(nan_ok && seen > 0, "%s '%s' step %d: the derivatives' NaN pattern is not u's", name,
              output, k);
        CHECK(mx > 0 && d0 <= 1e-9 * mx, "%s '%s' step %d: du/dE differs from -u/E by %g of %g",
              name, output, k, d0, mx);
        CHECK(d1 <= 1e-9 * mx, "%s '%s' step %d: du/dp differs from u/p by %g of %g", name, output,
              k, d1, mx);
    }
    CHECK(e.code == KT_OK, "%s: %s", name, e.msg);
    kt_solver_free(sv);
}

int main(void)
{
    kt_err e = {0};
    scenario s;
    CHECK(scenario_box(&s, 3, 3, 12, 1.0, 0.0, &e) == 0, "box: %s", e.msg);
    s.mat[1].E = 2.5;
    kt_edits_plan p;
    kt_mesh final = {0};
    CHECK(make_plan(&s, &p, &final, &e) == KT_OK, "plan: %s", e.msg);
    kt_fem_sens S;
    CHECK(make_sens(&s, &S, &e) == KT_OK, "sens: %s", e.msg);
    check_method(&s, &p, &final, &S, KT_AUG_PLANNED, "");
    check_method(&s, &p, &final, &S, KT_AUG_PLANNED, "zmax");
    check_method(&s, &p, &final, &S, KT_AUG_REFACTOR, "");
    /* the nonlinear reference gives no derivatives */
    kt_solver_opts o = {.sens = &S};
    kt_aug_opts_default(&o.aug);
    o.aug.method = KT_AUG_NEWTON;
    o.aug.quiet = 1;
    kt_solver *sv = NULL;
    e = (kt_err){0};
    CHECK(kt_solver_create(&sv, &s.prob, &p, &final, &o, &e) == KT_EINPUT && sv == NULL,
          "newton with derivatives: %d %s", e.code, e.msg);
    kt_fem_sens_free(&S);
    kt_edits_plan_free(&p);
    kt_mesh_free(&final);
    scenario_free(&s);
    return kt_test_done("test_sens");
}
