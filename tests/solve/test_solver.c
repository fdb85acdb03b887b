/* test_solver.c: the front door (solver.h) gives every method the same meaning of --output and
 * the same verification. On a beam cut layer by layer (splits, forces, a region of its own
 * material on top), each method (planned, augmented, refactor, cg, pcg-jacobi) runs with
 * --verify against a fresh factorization at every step; with --output SET (a surface, then a
 * region) the field is NaN exactly off SET's nodes of the current mesh and equals the planned
 * method's full field on SET; an unknown set is KT_EINPUT for every method. The nonlinear
 * reference (newton) behind the same door: test_newton. */
#include <stdio.h>

#include "solver.h"
#include "test_aug_scenario.h"
#include "kt_test.h"

enum { NSTEPS = 5 };
static const int METHOD[] = {KT_AUG_PLANNED, KT_AUG_AUGMENTED, KT_AUG_REFACTOR, KT_AUG_CG,
                             KT_AUG_PCG_JACOBI};

/* The stream: the top NSTEPS layers split at x = 2h one after the other, forces on every
 * other step; read back as a plan and checked (final: the final cut mesh). */
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
        cut_layer(s, &cur, &st, 2, s->nz - k, k % 2 ? 0.002 : 0.0, e);
        int *touched = NULL, nt = 0;
        if (!e->code) kt_cut_apply(&cur, &st, &touched, &nt, e);
        free(touched);
        if (!e->code) kt_edits_write_step(f, &st, e);
    }
    if (!e->code) kt_edits_write_done(f, NSTEPS, e); /* the stream's end (keratome-edits(5)) */
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

static kt_solver_opts opts(int method, const char *output)
{
    kt_solver_opts o = {.plan_max_ratio = 0};
    kt_aug_opts_default(&o.aug);
    o.aug.method = method;
    o.aug.quiet = 1;
    o.aug.tol = 1e-12;
    o.aug.ordering = method == KT_AUG_PLANNED || method == KT_AUG_AUGMENTED ? KT_AUG_ORDER_METIS
                                                                             : KT_AUG_ORDER_NATURAL;
    o.aug.verify = 1;
    /* the direct methods agree with a fresh factorization to rounding; CG to its tolerance */
    o.aug.verify_tol = method == KT_AUG_CG || method == KT_AUG_PCG_JACOBI ? 1e-7 : 1e-10;
    snprintf(o.aug.output, sizeof o.aug.output, "%s", output);
    return o;
}

/* Run method with output over every step; u[k] gets a copy of step k's field. */
static int run(const scenario *s, const kt_edits_plan *p, const kt_mesh *final, int method,
               const char *output, double **u, int *nn, kt_err *e)
{
    kt_solver_opts o = opts(method, output);
    kt_solver *sv = NULL;
    if (kt_solver_create(&sv, &s->prob, p, final, &o, e)) return e->code;
    CHECK(kt_solver_fallback(sv) == NULL, "%s: fell back: %s", kt_aug_method_name(method),
          kt_solver_fallback(sv));
    for (int k = 0; k <= p->nsteps && !e->code; k++) {
        int solved = 1;
        if (k > 0 && kt_solver_step(sv, &solved, e)) break;
        CHECK(solved && kt_solver_at(sv) == k, "step %d not solved", k);
        CHECK(kt_solver_row(sv)->verify_rel_diff <= o.aug.verify_tol, "%s %s step %d: verify %g",
              kt_aug_method_name(method), output, k, kt_solver_row(sv)->verify_rel_diff);
        nn[k] = kt_solver_mesh(sv)->nn;
        u[k] = malloc(3 * (size_t)nn[k] * sizeof(double));
        memcpy(u[k], kt_solver_u(sv), 3 * (size_t)nn[k] * sizeof(double));
        CHECK(!output[0] || kt_solver_reaction(sv, e) == NULL, "reactions with --output");
    }
    kt_solver_free(sv);
    return e->code;
}

/* The set's nodes on the current mesh of step k, from the plan (the intact mesh cut by steps
 * 1..k), independently of the front door. */
static unsigned char *set_on(const scenario *s, const kt_edits_plan *p, int k, const char *name)
{
    kt_err e = {0};
    kt_mesh m;
    if (kt_mesh_copy(&m, &s->mesh, &e)) return NULL;
    for (int j = 0; j < k; j++) {
        int *touched = NULL, nt = 0;
        kt_cut_apply(&m, &p->step[j], &touched, &nt, &e);
        free(touched);
    }
    const kt_group *g = kt_mesh_find_group(&m, 2, name);
    if (!g) g = kt_mesh_find_group(&m, 3, name);
    int *nodes = NULL, cnt = 0;
    unsigned char *on = calloc((size_t)m.nn, 1);
    if (g && on && !kt_mesh_group_nodes(&m, g, &nodes, &cnt, &e))
        for (int i = 0; i < cnt; i++) on[nodes[i]] = 1;
    free(nodes);
    kt_mesh_free(&m);
    return on;
}

static void test_output(const scenario *s, const kt_edits_plan *p, const kt_mesh *final)
{
    kt_err e = {0};
    double *full[NSTEPS + 1] = {0};
    int nn[NSTEPS + 1];
    CHECK(run(s, p, final, KT_AUG_PLANNED, "", full, nn, &e) == KT_OK, "planned: %s", e.msg);
    const char *sets[] = {"", "ymax", "top"};
    for (int m = 0; m < 5; m++)
        for (int q = 0; q < 3; q++) {
            double *u[NSTEPS + 1] = {0};
            int nm[NSTEPS + 1];
            e = (kt_err){0};
            const char *name = kt_aug_method_name(METHOD[m]);
            if (run(s, p, final, METHOD[m], sets[q], u, nm, &e)) {
                CHECK(0, "%s --output '%s': %s", name, sets[q], e.msg);
                continue;
            }
            double tol = METHOD[m] == KT_AUG_CG || METHOD[m] == KT_AUG_PCG_JACOBI ? 1e-6 : 1e-10;
            for (int k = 0; k <= p->nsteps; k++) {
                unsigned char *on = sets[q][0] ? set_on(s, p, k, sets[q]) : NULL;
                int bad_mask = 0, in = 0;
                double d = 0, mx = 0;
                for (int a = 0; a < nm[k]; a++) {
                    int want = !on || on[a];
                    in += want;
                    for (int c = 0; c < 3; c++) {
                        double x = u[k][3 * a + c], r = full[k][3 * a + c];
                        if (!want) {
                            bad_mask += !isnan(x);
                            continue;
                        }
                        bad_mask += isnan(x);
                        d = fmax(d, fabs(x - r));
                        mx = fmax(mx, fabs(r));
                    }
                }
                CHECK(nm[k] == nn[k] && bad_mask == 0 && in > 0 && in <= nm[k],
                      "%s --output '%s' step %d: %d values off the mask (%d of %d nodes in)",
                      name, sets[q], k, bad_mask, in, nm[k]);
                CHECK(in < nm[k] || !on, "%s --output '%s' step %d: the set is everything", name,
                      sets[q], k);
                CHECK(d <= tol * mx, "%s --output '%s' step %d: %.3g of %.3g from planned",
                      name, sets[q], k, d, mx);
                free(on);
                free(u[k]);
            }
        }
    for (int k = 0; k <= p->nsteps; k++) free(full[k]);
}

static void test_unknown_set(const scenario *s, const kt_edits_plan *p, const kt_mesh *final)
{
    for (int m = 0; m < 5; m++) {
        kt_err e = {0};
        kt_solver_opts o = opts(METHOD[m], "nosuchset");
        kt_solver *sv = NULL;
        CHECK(kt_solver_create(&sv, &s->prob, p, final, &o, &e) == KT_EINPUT &&
                  strstr(e.msg, "nosuchset") && !sv,
              "%s: unknown set: %d %s", kt_aug_method_name(METHOD[m]), e.code, e.msg);
        kt_solver_free(sv);
    }
}

/* Every step of the plan through the front door with --method newton on problem q, output
 * set out (""); gap[k] := max |u - planned| / max |planned| over the set (planned: full[k]);
 * *masked: values off the mask (NaN expected) or NaN on it. */
static int run_newton(const scenario *s, const kt_aug_problem *q, const kt_edits_plan *p,
                      const kt_mesh *final, const char *out, double *const *full, double *gap,
                      int *masked, kt_err *e)
{
    kt_solver_opts o = opts(KT_AUG_NEWTON, out);
    o.aug.verify = 0;
    kt_solver *sv = NULL;
    *masked = 0;
    if (kt_solver_create(&sv, q, p, final, &o, e)) return e->code;
    for (int k = 0; k <= p->nsteps && !e->code; k++) {
        int solved = 1;
        if (k > 0 && kt_solver_step(sv, &solved, e)) break;
        CHECK(solved && kt_solver_at(sv) == k, "newton: step %d not solved", k);
        const kt_aug_row *w = kt_solver_row(sv);
        CHECK(w->step == k && (k == 0 || w->iters >= 1) && w->rel_residual <= 1e-10,
              "newton step %d: %d iterations, residual %g", k, w->iters, w->rel_residual);
        unsigned char *on = out[0] ? set_on(s, p, k, out) : NULL;
        const double *u = kt_solver_u(sv);
        double d = 0, mx = 0;
        for (int i = 0; i < 3 * kt_solver_mesh(sv)->nn; i++) {
            if (on && !on[i / 3]) {
                *masked += !isnan(u[i]);
                continue;
            }
            *masked += isnan(u[i]);
            d = kt_nanmax(d, fabs(u[i] - full[k][i]));
            mx = fmax(mx, fabs(full[k][i]));
        }
        gap[k] = d / mx;
        free(on);
    }
    kt_solver_free(sv);
    return e->code;
}

/* --method newton behind the front door: with the moduli 1000 times stiffer (strains 1000
 * times smaller) every step equals the planned method's to 1e-3 relative (the gap is first
 * order in the load: about 2e-4 here); at the scenario's own load (strains of some percent,
 * no prestress) it differs by 100 times that at least (about 0.2), with --output its mask is
 * the set's; --verify is refused (KT_EINPUT: a linear fresh factorization is not its
 * reference). */
static void test_newton(const scenario *s, const kt_edits_plan *p, const kt_mesh *final)
{
    double gap[2][NSTEPS + 1];
    for (int stiff = 0; stiff < 2; stiff++) {
        kt_material mat[3];
        for (int i = 0; i < s->mats.nmat && i < 3; i++) {
            mat[i] = s->mats.mat[i];
            mat[i].E *= stiff ? 1000 : 1;
        }
        kt_materials mats = s->mats;
        mats.mat = mat;
        kt_aug_problem q = s->prob;
        q.mats = &mats;
        kt_err e = {0};
        double *full[NSTEPS + 1] = {0};
        kt_solver_opts o = opts(KT_AUG_PLANNED, "");
        kt_solver *sv = NULL;
        CHECK(kt_solver_create(&sv, &q, p, final, &o, &e) == KT_OK, "planned: %s", e.msg);
        for (int k = 0; sv && k <= p->nsteps && !e.code; k++) {
            int solved = 1;
            if (k > 0) kt_solver_step(sv, &solved, &e);
            size_t n = 3 * (size_t)kt_solver_mesh(sv)->nn;
            if ((full[k] = malloc(n * sizeof(double)))) memcpy(full[k], kt_solver_u(sv), n * sizeof(double));
        }
        kt_solver_free(sv);
        CHECK(!e.code, "planned: %s", e.msg);
        int masked = 0;
        const char *out = stiff ? "" : "ymax";
        if (!e.code && run_newton(s, &q, p, final, out, full, gap[stiff], &masked, &e))
            CHECK(0, "newton: %s", e.msg);
        CHECK(masked == 0, "newton --output '%s': %d values off the mask", out, masked);
        for (int k = 0; k <= p->nsteps; k++) free(full[k]);
    }
    for (int k = 0; k <= p->nsteps; k++) {
        printf("test_solver: newton step %d: %.3g from planned at the load, %.3g with 1000x the "
               "moduli\n", k, gap[0][k], gap[1][k]);
        CHECK(gap[1][k] <= 1e-3, "newton step %d, small load: %g from planned", k, gap[1][k]);
        CHECK(gap[0][k] >= 1e-4 && gap[0][k] >= 100 * gap[1][k],
              "newton step %d: %g from planned at the load, %g at 1/1000 of it", k, gap[0][k],
              gap[1][k]);
    }
    kt_err e = {0};
    kt_solver_opts o = opts(KT_AUG_NEWTON, "");
    kt_solver *sv = NULL;
    CHECK(kt_solver_create(&sv, &s->prob, p, final, &o, &e) == KT_EINPUT && !sv &&
              strstr(e.msg, "--verify"),
          "newton --verify: %d %s", e.code, e.msg);
    kt_solver_free(sv);
}

int main(void)
{
    kt_err e = {0};
    scenario beam;
    CHECK(scenario_box(&beam, 5, 4, 10, 1.0, 0.0, &e) == 0, "%s", e.msg);
    /* a region of its own, material 2, over the top three layers */
    kt_material mat[3] = {beam.mat[0], beam.mat[1], {2.0, 0.35}};
    beam.mats.mat = mat;
    beam.mats.nmat = 3;
    CHECK(kt_mesh_add_group(&beam.mesh, 3, 2, "top", &e) == KT_OK, "%s", e.msg);
    for (int t = 0; t < beam.mesh.ne; t++)
        if (tet_cx(&beam.mesh, t, 2) > beam.h * (beam.nz - 4)) beam.mesh.tet_tag[t] = 2;
    kt_edits_plan p;
    kt_mesh final = {0};
    CHECK(make_plan(&beam, &p, &final, &e) == KT_OK && p.usable && p.nsteps == NSTEPS,
          "plan: %s %s", e.msg, p.why);
    if (!e.code) {
        test_output(&beam, &p, &final);
        test_unknown_set(&beam, &p, &final);
        test_newton(&beam, &p, &final);
    }
    kt_edits_plan_free(&p);
    kt_mesh_free(&final);
    scenario_free(&beam);
    return kt_test_done("test_solver");
}
