/* test_aug.c: the augmented method against a fresh direct solve (kt_fem_solve) on beam and brick
 * meshes under progressive cuts, progressive nonzero Dirichlet constraints and both, nodes split
 * twice (with constraints on them), in three orderings; equilibrium of reactions and loads; the
 * baselines. */
#include <stdio.h>

#include "test_aug_scenario.h"
#include "kt_test.h"

enum { CUTS = 1, FIXES = 2, BOTH = 3, TWICE = 4 };

/* What the test itself knows of the constraints and forces (independent of the solver). */
typedef struct tracked {
    unsigned char *fixed;
    double *g, *force;
    int nn;
} tracked;

static void tracked_grow(tracked *t, int nn)
{
    if (nn <= t->nn) return;
    size_t o = 3 * (size_t)t->nn, n = 3 * (size_t)nn;
    t->fixed = realloc(t->fixed, n);
    t->g = realloc(t->g, n * sizeof(double));
    t->force = realloc(t->force, n * sizeof(double));
    memset(t->fixed + o, 0, n - o);
    memset(t->g + o, 0, (n - o) * sizeof(double));
    memset(t->force + o, 0, (n - o) * sizeof(double));
    t->nn = nn;
}

static void tracked_apply(tracked *t, const kt_step *st)
{
    for (int i = 0; i < st->n; i++) {
        const kt_edit *ed = &st->edit[i];
        if (ed->kind == KT_EDIT_FIX) {
            for (int c = 0; c < 3; c++)
                if (ed->mask & (1u << c)) {
                    t->fixed[3 * ed->node + c] = 1;
                    t->g[3 * ed->node + c] = ed->v[c];
                }
        } else if (ed->kind == KT_EDIT_FORCE) {
            memcpy(t->force + 3 * ed->node, ed->v, sizeof ed->v);
        }
    }
}

/* New nodes on a zmin triangle are clamped like zmin (the scene's fixation surface). */
static void tracked_autofix(tracked *t, const scenario *s, const kt_mesh *m, int nn_before)
{
    for (int k = 0; k < m->nf; k++) {
        if (m->tri_tag[k] != s->fix[0].tag) continue;
        for (int l = 0; l < 3; l++) {
            int a = m->tri[3 * k + l];
            if (a < nn_before) continue;
            for (int c = 0; c < 3; c++) {
                t->fixed[3 * a + c] = 1;
                t->g[3 * a + c] = s->fix[0].v[c];
            }
        }
    }
}

/* Step st of a scenario kind: cuts advance from the free end (layer nz-1) towards zmin; fixes
 * clamp zmax nodes with nonzero values, re-prescribe earlier ones, and move a zmin node. */
static void make_step(const scenario *s, const kt_mesh *m, int kind, int step, kt_step *st,
                      kt_err *e)
{
    kt_step_clear(st);
    st->index = step;
    if (kind == TWICE) {
        if (step % 2 == 1) { /* a layer cut on x = nx/2 (forces every third step) */
            int k = s->nz - 1 - (step - 1) / 2;
            if (k >= 0) cut_layer(s, m, st, s->nx / 2, k, step % 3 == 0 ? 0.002 : 0.0, e);
            return;
        }
        /* the interior nodes the last cut made are split again, on their own y */
        int first = m->nn - s->ny;
        for (int j = 1; j < s->ny - 1; j++) {
            int a = first + j;
            add_dup_axis(m, st, a, m->nn + j - 1, 1, m->xyz[3 * a + 1], e);
        }
        if (step % 4 == 0) { /* constrain a node split twice and one split once */
            add_fix(st, m->nn, 7u, 1e-3, -5e-4, 2e-3, e);
            add_fix(st, first + 1, 2u, 0, 1e-3 * step, 0, e);
        }
        return;
    }
    int cut = kind == CUTS || (kind == BOTH && step % 2 == 1);
    if (cut) {
        int k = s->nz - 1 - (kind == BOTH ? (step - 1) / 2 : step - 1);
        if (k >= 0) cut_layer(s, m, st, s->nx / 2, k, step % 3 == 0 ? 0.002 : 0.0, e);
    } else {
        int q = kind == BOTH ? step / 2 - 1 : step - 1;
        int i = q % s->nx, j = (q / s->nx) % s->ny;
        int node = grid_node(s, i, j, s->nz - 1);
        add_fix(st, node, q % 3 == 0 ? 7u : q % 3 == 1 ? 2u : 5u, 1e-3 * (q + 1), -2e-3, 5e-4 * q,
                e);
        if (q == 3) add_fix(st, grid_node(s, 0, 0, s->nz - 1), 1u, -4e-3, 0, 0, e);
        if (q == 5) add_fix(st, grid_node(s, 1, 1, 0), 4u, 3e-3, 0, 0, e);
    }
}

static void check_equilibrium(kt_aug *A, const char *name)
{
    kt_err e = {0};
    const double *r = kt_aug_reaction(A, &e);
    const double *f = kt_aug_load(A);
    CHECK(r != NULL, "%s: reactions: %s", name, e.msg);
    if (!r) return;
    int n = 3 * kt_aug_mesh(A)->nn;
    for (int c = 0; c < 3; c++) {
        double s = 0, scale = 0;
        for (int i = c; i < n; i += 3) {
            s += r[i] + f[i];
            scale += fabs(r[i]) + fabs(f[i]);
        }
        CHECK(fabs(s) <= 1e-9 * scale, "%s: equilibrium in %c: sum %.3g of scale %.3g", name,
              "xyz"[c], s, scale);
    }
}

/* Run nsteps of a kind; every step must match the reference to tol. Returns the solver. */
static kt_aug *run_case(const char *name, scenario *s, const kt_aug_opts *o, int kind, int nsteps,
                        double tol, int keep)
{
    kt_err e = {0};
    kt_aug *A = NULL;
    CHECK(kt_aug_create(&A, &s->prob, o, &e) == KT_OK, "%s: create: %s", name, e.msg);
    if (!A) return NULL;
    tracked t = {0};
    tracked_grow(&t, s->mesh.nn);
    memcpy(t.fixed, s->fixed, 3 * (size_t)s->mesh.nn);
    memcpy(t.g, s->g, 3 * (size_t)s->mesh.nn * sizeof(double));
    kt_step st = {0};
    double worst = 0;
    for (int step = 0; step <= nsteps; step++) {
        int nn_before = kt_aug_mesh(A)->nn;
        if (step > 0) {
            make_step(s, kt_aug_mesh(A), kind, step, &st, &e);
            tracked_grow(&t, nn_before + st.n);
            tracked_apply(&t, &st);
            if (kt_aug_step(A, &st, &e) != KT_OK) {
                CHECK(0, "%s: step %d: %s", name, step, e.msg);
                break;
            }
        }
        const kt_mesh *m = kt_aug_mesh(A);
        tracked_grow(&t, m->nn);
        tracked_autofix(&t, s, m, nn_before);
        double *ref = calloc(3 * (size_t)m->nn, sizeof(double));
        CHECK(reference_solve(s, m, t.fixed, t.g, t.force, ref, &e) == KT_OK, "%s: reference: %s",
              name, e.msg);
        double d = max_rel_diff(kt_aug_displacement(A), ref, 3 * (size_t)m->nn);
        worst = fmax(worst, d);
        CHECK(d <= tol, "%s: step %d: relative difference %.3g (m = %d)", name, step, d,
              kt_aug_last(A)->m);
        free(ref);
    }
    printf("%s: %d steps, worst relative difference %.3g, final m %d, n %d\n", name, nsteps,
           worst, kt_aug_last(A)->m, kt_aug_last(A)->n_dofs);
    check_equilibrium(A, name);
    kt_step_free(&st);
    free(t.fixed);
    free(t.g);
    free(t.force);
    if (!keep) {
        kt_aug_free(A);
        A = NULL;
    }
    return A;
}

int main(void)
{
    kt_err e = {0};
    scenario beam, brick;
    CHECK(scenario_box(&beam, 5, 5, 16, 1.0, 0.0, &e) == 0, "%s", e.msg);
    CHECK(scenario_box(&brick, 5, 5, 9, 0.25, 1e-3, &e) == 0, "%s", e.msg);
    kt_aug_opts o;
    kt_aug_opts_default(&o);
    o.quiet = 1;
    o.tol = 1e-14; /* backward error of the bordered solve: a direct solve's, not a loose one */
    run_case("beam cuts", &beam, &o, CUTS, 14, 1e-10, 0);
    run_case("beam fixes", &beam, &o, FIXES, 12, 1e-10, 0);
    run_case("beam both", &beam, &o, BOTH, 24, 1e-10, 0);
    run_case("brick cuts through the clamped face", &brick, &o, CUTS, 9, 1e-10, 0);
    run_case("brick both", &brick, &o, BOTH, 18, 1e-10, 0);

    run_case("beam split twice", &beam, &o, TWICE, 16, 1e-10, 0);
    run_case("brick split twice through the clamped face", &brick, &o, TWICE, 18, 1e-10, 0);

    kt_aug_opts p = o;
    p.ordering = KT_AUG_ORDER_AMD;
    run_case("brick both, amd", &brick, &p, BOTH, 12, 1e-10, 0);
    run_case("beam split twice, amd", &beam, &p, TWICE, 12, 1e-10, 0);
    p.ordering = KT_AUG_ORDER_METIS;
    run_case("beam cuts, metis", &beam, &p, CUTS, 8, 1e-10, 0);
    run_case("beam both, metis", &beam, &p, BOTH, 16, 1e-10, 0);
    run_case("brick split twice, metis", &brick, &p, TWICE, 12, 1e-10, 0);

    kt_aug_opts b = o;
    b.method = KT_AUG_REFACTOR;
    run_case("brick both, refactor baseline", &brick, &b, BOTH, 8, 1e-10, 0);
    b.method = KT_AUG_PCG_JACOBI;
    b.tol = 1e-12;
    run_case("brick both, pcg-jacobi baseline", &brick, &b, BOTH, 6, 1e-8, 0);
    b.method = KT_AUG_CG;
    run_case("brick cuts, cg baseline", &brick, &b, CUTS, 4, 1e-8, 0);

    scenario_free(&beam);
    scenario_free(&brick);
    return kt_test_done("test_aug");
}
