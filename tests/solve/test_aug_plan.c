/* test_aug_plan.c: the planned method (aug_plan.h) on a clamped box with nonzero Dirichlet
 * values and pressures, cut layer by layer down to the clamped face (new nodes there are
 * fixed) with forces on some steps and nodes split twice: every step against a fresh
 * factorization of the cut mesh (kt_fem_solve), equilibrium of its reactions and loads; the
 * whole-stream validation (a bad tet is reported as stream:line:col before any factoring);
 * a stream with a fix edit is refused with its line (the caller falls back). */
#include <stdio.h>

#include "aug_plan.h"
#include "test_aug_scenario.h"
#include "kt_test.h"

/* Split again the nodes the last step created: each moves its tets with centroid y > y0. */
static int split_again(const kt_mesh *m, kt_step *st, int first, int last, double y0, kt_err *e)
{
    int next = m->nn;
    for (int i = 0; i < st->n; i++) next += st->edit[i].kind == KT_EDIT_DUP;
    for (int a = first; a < last; a++) {
        int el[64], nel = 0, tot = 0;
        for (int t = 0; t < m->ne; t++)
            for (int l = 0; l < 4; l++)
                if (m->tet[4 * t + l] == a) {
                    tot++;
                    if (tet_cx(m, t, 1) > y0 && nel < 64) el[nel++] = t;
                    break;
                }
        if (nel == 0 || nel == tot) continue;
        kt_edit ed = {.kind = KT_EDIT_DUP, .node = a, .new_node = next++, .nel = nel, .el = el};
        if (kt_step_add(st, &ed, e)) return e->code;
    }
    return KT_OK;
}

/* The stream: cuts from the top layer to zmin, forces on every third, and after step 2 a
 * second split of step 2's new nodes. Written to f as a keratome-edits stream. */
static int write_stream(const scenario *s, FILE *f, int *nsteps, kt_err *e)
{
    kt_mesh cur;
    if (kt_mesh_copy(&cur, &s->mesh, e)) return e->code;
    kt_edits_header h = {.nn = s->mesh.nn, .ne = s->mesh.ne};
    snprintf(h.scene, sizeof h.scene, "box");
    snprintf(h.mesh, sizeof h.mesh, "box.msh");
    kt_edits_write_header(f, &h, e);
    kt_step st = {0};
    int k = 0, prev_nn = cur.nn;
    for (int layer = s->nz - 1; layer >= 0 && !e->code; layer--) {
        kt_step_clear(&st);
        st.index = ++k;
        int nn0 = cur.nn;
        cut_layer(s, &cur, &st, s->nx / 2, layer, k % 3 == 0 ? 0.002 : 0.0, e);
        if (k == 3) split_again(&cur, &st, prev_nn, nn0, 0.5 * s->h * (s->ny - 1), e);
        int *touched = NULL, nt = 0;
        if (!e->code) kt_cut_apply(&cur, &st, &touched, &nt, e);
        free(touched);
        if (!e->code) kt_edits_write_step(f, &st, e);
        prev_nn = nn0;
    }
    /* a step that only splits the previous step's nodes again */
    kt_step_clear(&st);
    st.index = ++k;
    split_again(&cur, &st, prev_nn, cur.nn, 0.5 * s->h * (s->ny - 1), e);
    if (!e->code && st.n) kt_edits_write_step(f, &st, e);
    else k--;
    if (!e->code) kt_edits_write_done(f, k, e);
    *nsteps = k;
    kt_step_free(&st);
    kt_mesh_free(&cur);
    return e->code;
}

static int read_plan(FILE *f, kt_edits_plan *p, kt_err *e)
{
    rewind(f);
    kt_edits_reader r;
    memset(p, 0, sizeof *p);
    if (kt_edits_open(&r, f, "stream", e)) return e->code;
    return kt_edits_plan_read(p, &r, e);
}

static void check_equilibrium(const kt_plan_state *S, int k)
{
    int n = 3 * S->mesh.nn;
    for (int c = 0; c < 3; c++) {
        double sum = 0, scale = 0;
        for (int i = c; i < n; i += 3) {
            sum += S->react[i] + S->f[i];
            scale += fabs(S->react[i]) + fabs(S->f[i]);
        }
        CHECK(fabs(sum) <= 1e-9 * scale, "step %d: equilibrium in %c: %.3g of %.3g", k, "xyz"[c],
              sum, scale);
    }
}

/* Nodes of surface group name on mesh m (calloc'd). */
static unsigned char *surface_nodes(const kt_mesh *m, const char *name)
{
    unsigned char *on = calloc((size_t)m->nn, 1);
    const kt_group *g = kt_mesh_find_group(m, 2, name);
    for (int t = 0; t < m->nf; t++)
        if (m->tri_tag[t] == g->tag)
            for (int a = 0; a < 3; a++) on[m->tri[3 * t + a]] = 1;
    return on;
}

/* Largest relative difference on the marked nodes (NULL: all). */
static double diff_on(const double *u, const double *ref, const unsigned char *on, int nn)
{
    double d = 0, m = 0;
    for (int i = 0; i < 3 * nn; i++) {
        if (on && !on[i / 3]) continue;
        d = fmax(d, fabs(u[i] - ref[i]));
        m = fmax(m, fabs(ref[i]));
    }
    return m > 0 ? d / m : d;
}

/* ||A_k||_F of every step from A's lower triangle, against F->fro_at (the backward error's). */
static void check_frobenius(const kt_plan_factor *F, int nsteps, const char *name)
{
    const int *Ap = F->A->p, *Ai = F->A->i;
    const double *Ax = F->A->x;
    for (int k = 0; k <= nsteps; k++) {
        double ss = 0;
        int N = F->nfree_at[k];
        for (int j = 0; j < N; j++)
            for (int q = Ap[j]; q < Ap[j + 1]; q++)
                if (Ai[q] < N) ss += (Ai[q] == j ? 1 : 2) * Ax[q] * Ax[q];
        CHECK_NEAR(F->fro_at[k], sqrt(ss), 1e-12 * sqrt(ss), name);
    }
}

/* Every step of the plan against a fresh factorization (only on the surface group "only" when
 * given: the restricted back substitution; perm0: the intact block in that given order,
 * kt_plan_factor_build_with); returns the steps checked. */
static int run_plan(scenario *s, FILE *f, int ordering, const int *perm0, int factor, int panel,
                    const char *only, int unsorted, const char *name)
{
    kt_err e = {0};
    kt_edits_plan p;
    kt_mesh final = {0};
    kt_plan_factor F = {0};
    kt_plan_state S = {0};
    int checked = 0, splits2 = 0;
    CHECK(read_plan(f, &p, &e) == KT_OK, "%s: read: %s", name, e.msg);
    CHECK(kt_edits_plan_check(&p, "stream", &s->prob, &final, &e) == KT_OK, "%s: check: %s", name,
          e.msg);
    CHECK(p.usable, "%s: plan refused: %s", name, p.why);
    for (int a = p.nn0; a < p.nn; a++) splits2 += p.parent[a] >= p.nn0;
    CHECK(splits2 > 0, "%s: the stream splits no node twice", name);
    CHECK(kt_plan_factor_build_with(&F, &p, &final, &s->mats, ordering, perm0, factor, panel,
                                    KT_PLAN_MAX_RATIO, &e) == KT_OK && !F.refused,
          "%s: factor: %s %s", name, e.msg, F.why);
    CHECK(F.reused_order == (perm0 != NULL), "%s: the given order %s", name,
          perm0 ? "was not used" : "used without one");
    if (F.L->is_super && panel > 0) { /* the increments' block is stored in panels */
        const int *Sup = F.L->super;
        int wide = 0;
        for (size_t q = 0; q < F.L->nsuper; q++)
            if (Sup[q + 1] > F.nK && Sup[q + 1] - Sup[q] > panel) wide++;
        CHECK(wide == 0 && F.x_S < (double)(F.nfree - F.nK) * (F.nfree - F.nK + panel),
              "%s: %d supernodes with increments wider than %d; their values %g", name, wide,
              panel, F.x_S);
    }
    if (unsorted) F.rows_sorted = 0; /* the substitutions' path for unsorted row lists */
    CHECK(kt_plan_state_init(&S, &p, &F, &s->prob, &e) == KT_OK, "%s: state: %s", name, e.msg);
    check_frobenius(&F, p.nsteps, name);
    if (only) {
        unsigned char *on = surface_nodes(&final, only);
        CHECK(kt_plan_state_restrict(&S, &p, &F, on, &e) == KT_OK, "%s: restrict: %s", name, e.msg);
        CHECK(S.want && S.want_cols < F.nfree, "%s: no restriction (%d of %d columns)", name,
              S.want_cols, F.nfree);
        free(on);
    }
    double *ref = calloc(3 * (size_t)p.nn, sizeof(double));
    for (int k = 0; k <= p.nsteps && !e.code; k++) {
        if (k > 0 && kt_plan_advance(&S, &p, &e)) break;
        if (kt_plan_solve(&S, &p, &F, &s->prob, 1e-12, &e) ||
            kt_plan_fresh(&S, &p, &s->prob, ref, &(double){0}, &e))
            break;
        unsigned char *on = only ? surface_nodes(&S.mesh, only) : NULL;
        double d = diff_on(S.u, ref, on, S.mesh.nn);
        free(on);
        CHECK(d <= 1e-10, "%s: step %d: planned vs fresh %.3g", name, k, d);
        /* the loads from the pressure tets' view are bitwise those of the whole cut mesh */
        double *fw = calloc(3 * (size_t)S.mesh.nn, sizeof(double));
        for (int q = 0; q < s->prob.npress; q++)
            kt_fem_pressure(&S.mesh, s->prob.press[q].tag, s->prob.press[q].p, fw, &e);
        int same = 1;
        for (int i = 0; i < 3 * S.mesh.nn; i++) same &= fw[i] + S.force[i] == S.f[i];
        CHECK(same && s->prob.npress > 0 && S.npown < S.mesh.ne,
              "%s: step %d: loads differ from the whole mesh's (%d of %d tets)", name, k, S.npown,
              S.mesh.ne);
        free(fw);
        CHECK(S.row.m == F.nfree_at[k] - F.nK, "%s: step %d: m", name, k);
        if (!only) check_equilibrium(&S, k);
        checked++;
    }
    CHECK(e.code == KT_OK, "%s: %s", name, e.msg);
    CHECK(S.mesh.nn == p.nn, "%s: the last step reaches the final mesh", name);
    /* the stream's loads move with the tets (its forces land on new nodes): every later step
     * continues step 0's forward substitution */
    CHECK(S.ncont == p.nsteps, "%s: %d of %d steps continued the forward substitution", name,
          S.ncont, p.nsteps);
    if (!e.code) { /* a load on rows it already consumed: it starts over, and stays exact */
        int a = 0, nc = S.ncont;
        while (a < p.nn0 && p.fixed[3 * a]) a++;
        double fmax = 0;
        for (int i = 0; i < 3 * S.mesh.nn; i++) {
            double v = S.f[i] < 0 ? -S.f[i] : S.f[i];
            if (v > fmax) fmax = v;
        }
        S.force[3 * a] += fmax;
        CHECK(kt_plan_solve(&S, &p, &F, &s->prob, 1e-12, &e) == KT_OK &&
                  kt_plan_fresh(&S, &p, &s->prob, ref, &(double){0}, &e) == KT_OK,
              "%s: extra load: %s", name, e.msg);
        unsigned char *on = only ? surface_nodes(&S.mesh, only) : NULL;
        double d = diff_on(S.u, ref, on, S.mesh.nn);
        free(on);
        CHECK(S.ncont == nc && d <= 1e-10, "%s: extra load at node %d: continued %d -> %d, "
              "planned vs fresh %.3g", name, a + 1, nc, S.ncont, d);
        CHECK(kt_plan_solve(&S, &p, &F, &s->prob, 1e-12, &e) == KT_OK && S.ncont == nc + 1,
              "%s: the same right-hand side again does not continue (%d)", name, S.ncont);
    }
    if (!only) { /* a tolerance no rounding meets: one refinement step, then a loud failure */
        kt_err e2 = {0};
        CHECK(kt_plan_solve(&S, &p, &F, &s->prob, 1e-300, &e2) == KT_ERUN && S.row.iters == 1 &&
                  strstr(e2.msg, "after a step of iterative refinement"),
              "%s: tol 1e-300: rc %d iters %d '%s'", name, e2.code, S.row.iters, e2.msg);
    }
    free(ref);
    kt_plan_state_free(&S);
    kt_plan_factor_free(&F);
    kt_mesh_free(&final);
    kt_edits_plan_free(&p);
    return checked;
}

/* A stream from text: header for the box, then body. */
static FILE *text_stream(const scenario *s, const char *body)
{
    FILE *f = tmpfile();
    fprintf(f, "keratome-edits 1\nscene box\nmesh box.msh %d %d\n%s", s->mesh.nn, s->mesh.ne, body);
    return f;
}

/* The first tet that holds node a, and one that does not. */
static void tets_of(const kt_mesh *m, int a, int *with, int *without)
{
    *with = *without = -1;
    for (int t = 0; t < m->ne; t++) {
        int has = 0;
        for (int l = 0; l < 4; l++) has |= m->tet[4 * t + l] == a;
        if (has && *with < 0) *with = t;
        if (!has && *without < 0) *without = t;
    }
}

static void check_validation(scenario *s)
{
    int a = grid_node(s, 1, 1, s->nz - 1), with, without;
    tets_of(&s->mesh, a, &with, &without);
    char body[512];
    /* step 2 moves a tet that does not hold the node: found before any factoring */
    snprintf(body, sizeof body, "step 1\ndup %d %d 1 %d\nend\nstep 2\ndup %d %d 2 %d %d\nend\ndone 2\n",
             a + 1, s->mesh.nn + 1, with + 1, a + 1, s->mesh.nn + 2, with + 1, without + 1);
    FILE *f = text_stream(s, body);
    kt_err e = {0};
    kt_edits_plan p;
    kt_mesh final = {0};
    CHECK(read_plan(f, &p, &e) == KT_OK, "bad tet: read: %s", e.msg);
    CHECK(kt_edits_plan_check(&p, "stream", &s->prob, &final, &e) == KT_EINPUT,
          "bad tet: not refused");
    char want[64];
    snprintf(want, sizeof want, "stream:8:");
    CHECK(strncmp(e.msg, want, strlen(want)) == 0 && strstr(e.msg, "does not hold"),
          "bad tet: message '%s'", e.msg);
    kt_mesh_free(&final);
    kt_edits_plan_free(&p);
    fclose(f);
    /* a dup that moves every tet of its node leaves a node in no tet (issue 26, item 12):
     * refused before any factoring, naming the line and the step */
    int n = snprintf(body, sizeof body, "step 1\ndup %d %d 1 %d\nend\nstep 2\ndup %d %d ", a + 1,
                     s->mesh.nn + 1, with + 1, a + 1, s->mesh.nn + 2);
    int cnt = 0, list[64];
    for (int t = 0; t < s->mesh.ne && cnt < 64; t++)
        for (int l = 0; l < 4; l++)
            if (s->mesh.tet[4 * t + l] == a && t != with) list[cnt++] = t + 1;
    n += snprintf(body + n, sizeof body - n, "%d", cnt);
    for (int i = 0; i < cnt; i++) n += snprintf(body + n, sizeof body - n, " %d", list[i]);
    snprintf(body + n, sizeof body - n, "\nend\ndone 2\n");
    f = text_stream(s, body);
    e = (kt_err){0};
    CHECK(read_plan(f, &p, &e) == KT_OK, "orphan: read: %s", e.msg);
    CHECK(kt_edits_plan_check(&p, "stream", &s->prob, &final, &e) == KT_EINPUT &&
              strncmp(e.msg, "stream:8: step 2:", 17) == 0 && strstr(e.msg, "at least one tetrahedron"),
          "orphan: not refused: '%s'", e.msg);
    kt_mesh_free(&final);
    kt_edits_plan_free(&p);
    fclose(f);
    /* a fix edit changes the intact block: usable = 0, with its line */
    snprintf(body, sizeof body, "step 1\ndup %d %d 1 %d\nend\nstep 2\nfix %d x 0.001\nend\ndone 2\n",
             a + 1, s->mesh.nn + 1, with + 1, a + 1);
    f = text_stream(s, body);
    e = (kt_err){0};
    CHECK(read_plan(f, &p, &e) == KT_OK, "fix: read: %s", e.msg);
    CHECK(kt_edits_plan_check(&p, "stream", &s->prob, &final, &e) == KT_OK, "fix: check: %s",
          e.msg);
    CHECK(!p.usable && strncmp(p.why, "stream:8:", 9) == 0 && strstr(p.why, "fixes node"),
          "fix: usable %d why '%s'", p.usable, p.why);
    kt_mesh_free(&final);
    kt_edits_plan_free(&p);
    fclose(f);
}

/* The size check: the planned factor of the box's plan against METIS on its intact block
 * (the analysis predicts the factor's nonzeros exactly); refused (nothing factored, the reason
 * given) just below its own nonzero ratio, built just above (its flops ratio is below the
 * plan's nsteps + 1 fresh factorizations). */
static void check_size_refusal(scenario *s, FILE *f)
{
    kt_err e = {0};
    kt_edits_plan p;
    kt_mesh final = {0};
    kt_plan_factor F = {0};
    CHECK(read_plan(f, &p, &e) == KT_OK &&
              kt_edits_plan_check(&p, "stream", &s->prob, &final, &e) == KT_OK,
          "size: %s", e.msg);
    CHECK(kt_plan_factor_build(&F, &p, &final, &s->mats, KT_AUG_ORDER_METIS,
                               KT_AUG_FACTOR_SUPERNODAL, KT_AUG_PLAN_PANEL, 0, &e) == KT_OK &&
              !F.refused,
          "size: no check: %s", e.msg);
    double r = F.lnz_plan / F.lnz_ref, rf = F.fl_plan / F.fl_ref;
    CHECK(r > 1 && rf > 1 && rf <= p.nsteps + 1 && F.lnz_plan >= F.nnzL * 0.999 &&
              F.lnz_plan <= F.nnzL * 1.001,
          "size: predicted %g (factor %g) vs METIS %g; flops %g vs %g", F.lnz_plan, F.nnzL,
          F.lnz_ref, F.fl_plan, F.fl_ref);
    kt_plan_factor_free(&F);
    CHECK(kt_plan_factor_build(&F, &p, &final, &s->mats, KT_AUG_ORDER_METIS,
                               KT_AUG_FACTOR_SUPERNODAL, KT_AUG_PLAN_PANEL, 0.99 * r, &e) == KT_OK,
          "size: refusal is no error: %s", e.msg);
    CHECK(F.refused && F.nnzL == 0 && strstr(F.why, "--plan-max-ratio"),
          "size: ratio %g not refused at %g (why '%s')", r, 0.99 * r, F.why);
    kt_plan_factor_free(&F);
    CHECK(kt_plan_factor_build(&F, &p, &final, &s->mats, KT_AUG_ORDER_METIS,
                               KT_AUG_FACTOR_SUPERNODAL, KT_AUG_PLAN_PANEL, 1.01 * r, &e) == KT_OK &&
              !F.refused && F.nnzL > 0,
          "size: ratio %g refused at %g", r, 1.01 * r);
    kt_plan_factor_free(&F);
    kt_mesh_free(&final);
    kt_edits_plan_free(&p);
}

int main(void)
{
    kt_err e = {0};
    scenario s;
    CHECK(scenario_box(&s, 5, 4, 6, 1.0, 1e-3, &e) == 0, "box: %s", e.msg);
    FILE *f = tmpfile();
    int nsteps = 0;
    CHECK(write_stream(&s, f, &nsteps, &e) == KT_OK, "stream: %s", e.msg);
    CHECK(nsteps == s.nz + 1, "stream: %d steps", nsteps);
    CHECK(run_plan(&s, f, KT_AUG_ORDER_METIS, NULL, KT_AUG_FACTOR_SUPERNODAL, 0, NULL, 0,
                   "metis supernodal") ==
              nsteps + 1, "metis supernodal: not every step checked");
    CHECK(run_plan(&s, f, KT_AUG_ORDER_NATURAL, NULL, KT_AUG_FACTOR_SIMPLICIAL, KT_AUG_PLAN_PANEL, NULL, 0,
                   "natural simplicial") == nsteps + 1, "natural simplicial: not every step checked");
    CHECK(run_plan(&s, f, KT_AUG_ORDER_AMD, NULL, KT_AUG_FACTOR_SUPERNODAL, 3, NULL, 0,
                   "amd supernodal, panels of 3") ==
              nsteps + 1, "amd supernodal: not every step checked");
    CHECK(run_plan(&s, f, KT_AUG_ORDER_METIS, NULL, KT_AUG_FACTOR_SUPERNODAL, KT_AUG_PLAN_PANEL, NULL, 1,
                   "metis supernodal, rows read unsorted") == nsteps + 1,
          "metis supernodal, rows read unsorted: not every step checked");
    CHECK(run_plan(&s, f, KT_AUG_ORDER_METIS, NULL, KT_AUG_FACTOR_SUPERNODAL, 5, "zmax", 0,
                   "zmax only, panels of 5") ==
              nsteps + 1, "zmax only: not every step checked");
    /* the intact block in the order of a direct solve of the intact problem (3 nn DOFs, the
     * constrained ones among them), as augsolve reuses its prestress solve's */
    {
        size_t n = 3 * (size_t)s.mesh.nn;
        double *f0 = calloc(n, sizeof(double)), *u0 = calloc(n, sizeof(double));
        int *perm = NULL;
        cholmod_common c;
        cholmod_start(&c);
        CHECK(f0 && u0 && kt_fem_solve_order(&s.mesh, &s.mats, s.prob.fixed, s.prob.g, f0, u0,
                                             &perm, &c, &e) == KT_OK && perm,
              "the direct solve's order: %s", e.msg);
        cholmod_finish(&c);
        CHECK(run_plan(&s, f, KT_AUG_ORDER_METIS, perm, KT_AUG_FACTOR_SUPERNODAL,
                       KT_AUG_PLAN_PANEL, NULL, 0, "a direct solve's order reused") == nsteps + 1,
              "a direct solve's order reused: not every step checked");
        free(perm);
        free(f0);
        free(u0);
    }
    check_size_refusal(&s, f);
    fclose(f);
    check_validation(&s);
    scenario_free(&s);
    return kt_test_done("test_aug_plan");
}
