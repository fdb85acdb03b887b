/* test_wound.c: the healed wound's bridge (lib/fem/wound.h) on a clamped box cut through by a
 * plane layer by layer (keratome's stream of dups), with a second split of some new nodes (chains
 * of two increments):
 *   - the face pairs found on every step's cut mesh are exactly the faces of the cut plane
 *     that hold a split node (counted geometrically against the plan);
 *   - the face mass matrix integrates exactly (P1 and P2: sum = area, the P2 entries), and the
 *     bridge's energy of a rigid opening d of the cut is k |d|^2 A exactly;
 *   - the final mesh's bridge in the planned method's variables, restricted to step k's (the
 *     unreleased increments zero), is step k's own bridge, and it holds no intact variable;
 *   - planned, augmented, refactor and CG equal a fresh factorization of the bridged cut mesh at
 *     every step (1e-10; CG to its tolerance); k = 0 is bitwise the unbridged answer;
 *   - k -> infinity gives back the uncut body: the final mesh's field at k = 1e2, 1e4, 1e6
 *     against the intact one, the error O(1/k) (a penalty);
 *   - the nonlinear residual and tangent (augsolve --method newton) hold the bridge. */
#include <stdio.h>

#include "aug_plan.h"
#include "kt_test.h"
#include "test_aug_scenario.h"
#include "topology.h"
#include "wound.h"

/* Split again the nodes [first, last) of m: each moves its tets with centroid y > y0. */
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

/* The stream: the plane x = xi h cut from the top layer down to zmin (forces on every third
 * step), then (again = 1) a step that splits the last layer's new nodes again at y0. */
static FILE *make_stream(const scenario *s, int again, int *nsteps, kt_err *e)
{
    FILE *f = tmpfile();
    kt_mesh cur;
    if (kt_mesh_copy(&cur, &s->mesh, e)) return f;
    kt_edits_header h = {.nn = s->mesh.nn, .ne = s->mesh.ne};
    snprintf(h.scene, sizeof h.scene, "box");
    snprintf(h.mesh, sizeof h.mesh, "box.msh");
    kt_edits_write_header(f, &h, e);
    kt_step st = {0};
    int k = 0, prev = cur.nn;
    for (int layer = s->nz - 1; layer >= 0 && !e->code; layer--) {
        kt_step_clear(&st);
        st.index = ++k;
        prev = cur.nn;
        cut_layer(s, &cur, &st, s->nx / 2, layer, k % 3 == 0 ? 0.002 : 0.0, e);
        int *touched = NULL, nt = 0;
        if (!e->code) kt_cut_apply(&cur, &st, &touched, &nt, e);
        free(touched);
        if (!e->code) kt_edits_write_step(f, &st, e);
    }
    if (again && !e->code) {
        kt_step_clear(&st);
        st.index = ++k;
        split_again(&cur, &st, prev, cur.nn, 0.5 * s->h * (s->ny - 1), e);
        if (!e->code) kt_edits_write_step(f, &st, e);
    }
    if (!e->code) kt_edits_write_done(f, k, e);
    *nsteps = k;
    kt_step_free(&st);
    kt_mesh_free(&cur);
    rewind(f);
    return f;
}

static int read_plan(FILE *f, kt_edits_plan *p, kt_err *e)
{
    rewind(f);
    kt_edits_reader r;
    memset(p, 0, sizeof *p);
    if (kt_edits_open(&r, f, "stream", e)) return e->code;
    return kt_edits_plan_read(p, &r, e);
}

/* ------------------------------------------------------------------ face mass */

static void check_face_mass(void)
{
    double x3[9] = {0, 0, 0, 2, 0, 0, 0, 1, 0}, M[36], sum = 0; /* area 1 */
    kt_wound_face_mass(1, x3, M);
    for (int i = 0; i < 9; i++) sum += M[i];
    CHECK_NEAR(sum, 1.0, 1e-15, "P1 face mass: sum = area");
    CHECK_NEAR(M[0], 2.0 / 12, 1e-15, "P1 face mass: M_00 = A/6");
    /* tri6 in gmsh order, straight: the P2 mass A/180 [6 -1 -1 0 -4 0; ...; 32 16 16 ...] */
    double x6[18] = {0, 0, 0, 2, 0, 0, 0, 1, 0, 1, 0, 0, 1, 0.5, 0, 0, 0.5, 0};
    kt_wound_face_mass(2, x6, M);
    sum = 0;
    for (int i = 0; i < 36; i++) sum += M[i];
    CHECK_NEAR(sum, 1.0, 1e-14, "P2 face mass: sum = area");
    CHECK_NEAR(M[0], 6.0 / 180, 1e-14, "P2 face mass: corner diagonal");
    CHECK_NEAR(M[1], -1.0 / 180, 1e-14, "P2 face mass: corner-corner");
    CHECK_NEAR(M[6 * 0 + 4], -4.0 / 180, 1e-14, "P2 face mass: corner - opposite edge");
    CHECK_NEAR(M[6 * 3 + 3], 32.0 / 180, 1e-14, "P2 face mass: edge diagonal");
    CHECK_NEAR(M[6 * 3 + 4], 16.0 / 180, 1e-14, "P2 face mass: edge-edge");
}

/* ------------------------------------------------------------------ pairs */

/* Faces of the intact mesh on the plane x = x0 with a corner split in mesh m (by origin). */
static int plane_faces_split(const scenario *s, const kt_mesh *m, const int *parent, double x0)
{
    int n = 0;
    for (int t = 0; t < s->mesh.ne; t++)
        for (int f = 0; f < 4; f++) {
            int on = 1, split = 0;
            for (int q = 0; q < 3; q++) {
                int loc = kt_tet_face[f][q], a = s->mesh.tet[4 * t + loc];
                on &= fabs(s->mesh.xyz[3 * a] - x0) < 1e-12;
                /* the corner's intact node has a child in m */
                for (int b = s->mesh.nn; b < m->nn; b++) {
                    int r = b;
                    while (parent[r] >= 0) r = parent[r];
                    split |= r == a;
                }
            }
            n += on && split;
        }
    return n / 2; /* each face from both of its tets */
}

typedef struct dense {
    int n;
    double *A;
} dense;

static void dense_put(void *ctx, int v, int w, double x)
{
    dense *d = ctx;
    d->A[(size_t)v * d->n + w] += x;
}

/* The pairs, the bridge's energy and the restriction property on every step of the plan. */
static void check_pairs(scenario *s, const kt_edits_plan *p, const kt_mesh *final, kt_wound *w)
{
    kt_err e = {0};
    kt_mesh cur;
    CHECK(kt_mesh_copy(&cur, &s->mesh, &e) == KT_OK, "copy: %s", e.msg);
    int N = 3 * p->nn, x0i = s->nx / 2;
    dense Bf = {N, calloc((size_t)N * N, sizeof(double))};
    CHECK(kt_wound_assemble(w, final, p->parent, 1.0, dense_put, &Bf, &e) == KT_OK, "final: %s", e.msg);
    for (int v = 0; v < 3 * p->nn0; v++)
        for (int u = 0; u < N; u++)
            CHECK(Bf.A[(size_t)v * N + u] == 0 && Bf.A[(size_t)u * N + v] == 0,
                  "bridge entry at intact variable %d", v);
    for (int k = 0; k <= p->nsteps; k++) {
        if (k > 0) {
            int *touched = NULL, nt = 0;
            kt_cut_apply(&cur, &p->step[k - 1], &touched, &nt, &e);
            free(touched);
        }
        int *slots, np;
        CHECK(kt_wound_pairs(w, &cur, &slots, &np, &e) == KT_OK, "pairs: %s", e.msg);
        int plane = plane_faces_split(s, &cur, p->parent, x0i * s->h);
        if (k <= s->nz) /* the layer cuts: every pair on the plane, one per split plane face */
            CHECK(np == plane && np == 2 * (s->ny - 1) * (k < s->nz - 1 ? k : s->nz - 1),
                  "step %d: %d pairs, %d faces of the plane hold a split node", k, np, plane);
        else /* the second split adds the faces at y0 on the + side of the last cells */
            CHECK(np > plane, "step %d: %d pairs with the second split (plane %d)", k, np, plane);
        free(slots);
        /* step k's bridge in the variables = the final one restricted to step k's */
        int Nk = 3 * cur.nn;
        dense Bk = {N, calloc((size_t)N * N, sizeof(double))};
        CHECK(kt_wound_assemble(w, &cur, p->parent, 1.0, dense_put, &Bk, &e) == KT_OK, "%s", e.msg);
        double worst = 0, scale = 0;
        for (int v = 0; v < N; v++)
            for (int u = 0; u < N; u++) {
                double f = v < Nk && u < Nk ? Bf.A[(size_t)v * N + u] : 0;
                worst = fmax(worst, fabs(Bk.A[(size_t)v * N + u] - f));
                scale = fmax(scale, fabs(Bf.A[(size_t)v * N + u]));
            }
        CHECK(worst <= 1e-14 * scale, "step %d: final bridge restricted vs the step's: %.3g of %.3g",
              k, worst, scale);
        free(Bk.A);
        if (k == s->nz) { /* the plane cut through: a rigid opening d of the + side */
            double d[3] = {0.3, -0.2, 0.1}, A = s->h * (s->ny - 1) * s->h * (s->nz - 1);
            double *u = calloc(3 * (size_t)cur.nn, sizeof(double)), *y = calloc(3 * (size_t)cur.nn, sizeof(double));
            for (int t = 0; t < cur.ne; t++)
                if (tet_cx(&cur, t, 0) > x0i * s->h)
                    for (int l = 0; l < 4; l++) memcpy(u + 3 * cur.tet[4 * t + l], d, sizeof d);
            kt_wound_apply(w, &cur, u, 1.0, y, &e);
            double E = 0;
            for (int i = 0; i < 3 * cur.nn; i++) E += u[i] * y[i];
            CHECK_NEAR(E, w->k * (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) * A, 1e-13,
                       "u^T B u of a rigid opening = k |d|^2 A");
            free(u);
            free(y);
        }
    }
    free(Bf.A);
    kt_mesh_free(&cur);
}

/* ------------------------------------------------------------------ every method */

static double diff(const double *u, const double *r, int n)
{
    return max_rel_diff(u, r, (size_t)n);
}

/* Planned, augmented, refactor and CG against the fresh reference at every step; the planned
 * fields into up (steps + 1 of 3 nn final each) when not NULL. */
static void check_methods(scenario *s, FILE *f, const char *name, double *up)
{
    kt_err e = {0};
    kt_edits_plan p;
    kt_mesh final = {0};
    kt_plan_factor F = {0};
    kt_plan_state S = {0};
    CHECK(read_plan(f, &p, &e) == KT_OK && kt_edits_plan_check(&p, "stream", &s->prob, &final, &e) == KT_OK &&
              p.usable,
          "%s: plan: %s %s", name, e.msg, p.why);
    CHECK(kt_plan_factor_build(&F, &p, &final, &s->mats, KT_AUG_ORDER_METIS, KT_AUG_FACTOR_SUPERNODAL, 0,
                               KT_PLAN_MAX_RATIO, &e) == KT_OK && !F.refused,
          "%s: factor: %s %s", name, e.msg, F.why);
    CHECK(kt_plan_state_init(&S, &p, &F, &s->prob, &e) == KT_OK, "%s: state: %s", name, e.msg);
    kt_aug *A[3] = {NULL, NULL, NULL};
    const int methods[3] = {KT_AUG_AUGMENTED, KT_AUG_REFACTOR, KT_AUG_CG};
    for (int q = 0; q < 3; q++) {
        kt_aug_opts o;
        kt_aug_opts_default(&o);
        o.method = methods[q];
        o.ordering = q == 0 ? KT_AUG_ORDER_METIS : KT_AUG_ORDER_NATURAL;
        o.tol = q == 2 ? 1e-12 : 1e-10;
        CHECK(kt_aug_create(&A[q], &s->prob, &o, &e) == KT_OK, "%s: create %d: %s", name, q, e.msg);
    }
    double *ref = calloc(3 * (size_t)p.nn, sizeof(double)), *ra = calloc(3 * (size_t)p.nn, sizeof(double));
    double worst[4] = {0};
    for (int k = 0; k <= p.nsteps && !e.code; k++) {
        if (k > 0) {
            if (kt_plan_advance(&S, &p, &e)) break;
            for (int q = 0; q < 3; q++)
                if (A[q] && kt_aug_step(A[q], &p.step[k - 1], &e)) break;
        }
        if (kt_plan_solve(&S, &p, &F, &s->prob, 1e-12, &e) ||
            kt_plan_fresh(&S, &p, &s->prob, ref, &(double){0}, &e))
            break;
        int n = 3 * S.mesh.nn;
        worst[0] = fmax(worst[0], diff(S.u, ref, n));
        for (int q = 0; q < 3; q++) {
            if (!A[q]) continue;
            CHECK(kt_aug_fresh(A[q], ra, &(double){0}, &e) == KT_OK, "%s: fresh %d: %s", name, q, e.msg);
            double dq = diff(kt_aug_displacement(A[q]), ref, n), df = diff(ra, ref, n);
            CHECK(df <= 1e-12, "%s: step %d: the stream's fresh reference vs the plan's %.3g", name, k, df);
            worst[1 + q] = fmax(worst[1 + q], dq);
        }
        if (up) memcpy(up + (size_t)k * 3 * p.nn, S.u, (size_t)n * sizeof(double));
    }
    CHECK(e.code == KT_OK, "%s: %s", name, e.msg);
    CHECK(worst[0] <= 1e-10 && worst[1] <= 1e-10 && worst[2] <= 1e-10 && worst[3] <= 1e-8,
          "%s: vs fresh: planned %.3g augmented %.3g refactor %.3g cg %.3g", name, worst[0],
          worst[1], worst[2], worst[3]);
    printf("%s: %d steps vs fresh: planned %.3g, augmented %.3g, refactor %.3g, cg %.3g\n", name,
           p.nsteps, worst[0], worst[1], worst[2], worst[3]);
    for (int q = 0; q < 3; q++) kt_aug_free(A[q]);
    free(ref);
    free(ra);
    kt_plan_state_free(&S);
    kt_plan_factor_free(&F);
    kt_mesh_free(&final);
    kt_edits_plan_free(&p);
}

/* ------------------------------------------------------------------ the uncut limit */

/* Largest difference of the final mesh's field (bridge k, no forces) from the intact one at
 * each node's origin, relative to the intact field's largest. */
static double uncut_error(scenario *s, FILE *f, kt_wound *w, double k, const double *u0)
{
    kt_err e = {0};
    kt_edits_plan p;
    kt_mesh final = {0};
    read_plan(f, &p, &e);
    kt_edits_plan_check(&p, "stream", &s->prob, &final, &e);
    w->k = k;
    size_t n = 3 * (size_t)final.nn;
    double *fl = calloc(n, sizeof(double)), *u = calloc(n, sizeof(double));
    for (int q = 0; q < 2; q++) kt_fem_pressure(&final, s->press[q].tag, s->press[q].p, fl, &e);
    cholmod_common c;
    cholmod_start(&c);
    kt_fem_solve(&final, &s->mats, p.fixed, p.g, fl, u, &c, &e);
    cholmod_finish(&c);
    double d = 0, m = 0;
    for (int a = 0; a < final.nn; a++) {
        int o = a;
        while (p.parent[o] >= 0) o = p.parent[o];
        for (int c2 = 0; c2 < 3; c2++) {
            d = fmax(d, fabs(u[3 * a + c2] - u0[3 * o + c2]));
            m = fmax(m, fabs(u0[3 * o + c2]));
        }
    }
    CHECK(e.code == KT_OK, "uncut limit k %g: %s", k, e.msg);
    free(fl);
    free(u);
    kt_mesh_free(&final);
    kt_edits_plan_free(&p);
    return d / m;
}

static void check_uncut_limit(scenario *s, FILE *f, kt_wound *w)
{
    kt_err e = {0};
    size_t n = 3 * (size_t)s->mesh.nn;
    double *u0 = calloc(n, sizeof(double)), *fl = calloc(n, sizeof(double));
    for (int q = 0; q < 2; q++) kt_fem_pressure(&s->mesh, s->press[q].tag, s->press[q].p, fl, &e);
    cholmod_common c;
    cholmod_start(&c);
    kt_fem_solve(&s->mesh, &s->mats, s->fixed, s->g, fl, u0, &c, &e);
    cholmod_finish(&c);
    double k0 = w->k, err[3];
    for (int i = 0; i < 3; i++) err[i] = uncut_error(s, f, w, pow(10, 2 + 2 * i), u0);
    w->k = k0;
    printf("uncut limit: relative error %.3g, %.3g, %.3g at k = 1e2, 1e4, 1e6 MPa/mm\n", err[0],
           err[1], err[2]);
    /* a penalty: the error falls as 1/k (a factor 100 per step, within 20%) */
    CHECK(err[0] > 1e-6 && err[1] / err[0] < 0.015 && err[1] / err[0] > 0.005 &&
              err[2] / err[1] < 0.015 && err[2] / err[1] > 0.005,
          "uncut limit not O(1/k): %.3g %.3g %.3g", err[0], err[1], err[2]);
    free(u0);
    free(fl);
}

/* ------------------------------------------------------------------ nonlinear */

static void check_nonlinear(scenario *s, FILE *f)
{
    kt_err e = {0};
    kt_edits_plan p;
    kt_mesh final = {0};
    read_plan(f, &p, &e);
    kt_edits_plan_check(&p, "stream", &s->prob, &final, &e);
    size_t n = 3 * (size_t)final.nn;
    double *u = calloc(n, sizeof(double)), *r0 = calloc(n, sizeof(double)), *r1 = calloc(n, sizeof(double));
    double *r2 = calloc(n, sizeof(double)), *ku = calloc(n, sizeof(double));
    for (size_t i = 0; i < n; i++) u[i] = 1e-7 * sin(0.37 * (double)i + 0.1 * (double)(i % 7));
    cholmod_common c;
    cholmod_start(&c);
    cholmod_sparse *K = kt_fem_assemble(&final, &s->mats, NULL, &c, &e);
    cholmod_sparse *Kn = kt_fem_nl_assemble(&final, &s->mats, u, 1.0, NULL, r2, &c, &e);
    kt_fem_nl_residual(&final, &s->mats, u, 1.0, r1, NULL, &e);
    double *z = calloc(n, sizeof(double));
    kt_fem_nl_residual(&final, &s->mats, z, 1.0, r0, NULL, &e);
    double one[2] = {1, 0}, zero[2] = {0, 0};
    cholmod_dense U = {n, 1, n, n, u, NULL, CHOLMOD_REAL, CHOLMOD_DOUBLE}, Y = {n, 1, n, n, ku, NULL, CHOLMOD_REAL, CHOLMOD_DOUBLE};
    if (K) cholmod_sdmult(K, 0, one, zero, &U, &Y, &c);
    double d = 0, m = 0, dr = 0;
    for (size_t i = 0; i < n; i++) {
        d = fmax(d, fabs(r1[i] - r0[i] - ku[i]));
        m = fmax(m, fabs(ku[i]));
        dr = fmax(dr, fabs(r2[i] - r1[i]));
    }
    CHECK(e.code == KT_OK && K && Kn && d <= 1e-5 * m && dr <= 1e-14 * m,
          "nonlinear residual with the bridge: r(u) - r(0) vs K u %.3g of %.3g; assembled vs residual %.3g: %s",
          d, m, dr, e.msg);
    cholmod_free_sparse(&K, &c);
    cholmod_free_sparse(&Kn, &c);
    cholmod_finish(&c);
    free(u), free(r0), free(r1), free(r2), free(ku), free(z);
    kt_mesh_free(&final);
    kt_edits_plan_free(&p);
}

int main(void)
{
    kt_err e = {0};
    check_face_mass();
    scenario s;
    CHECK(scenario_box(&s, 5, 3, 4, 0.25, 0.01, &e) == 0, "box: %s", e.msg);
    kt_wound w;
    CHECK(kt_wound_build(&w, &s.mesh, 0.5, &e) == KT_OK, "build: %s", e.msg);
    int nsteps = 0, nbound = 0;
    for (int q = 0; q < 4 * s.mesh.ne; q++) nbound += w.mate[q] < 0;
    CHECK(nbound == 2 * 2 * (4 * 2 + 4 * 3 + 2 * 3),
          "boundary faces of the box: %d (2 triangles per boundary square)", nbound);
    s.mats.wound = &w;
    FILE *f = make_stream(&s, 1, &nsteps, &e);
    CHECK(e.code == KT_OK && nsteps == s.nz + 1, "stream: %s (%d steps)", e.msg, nsteps);
    kt_edits_plan p;
    kt_mesh final = {0};
    CHECK(read_plan(f, &p, &e) == KT_OK && kt_edits_plan_check(&p, "stream", &s.prob, &final, &e) == KT_OK,
          "plan: %s", e.msg);
    check_pairs(&s, &p, &final, &w);
    kt_mesh_free(&final);
    kt_edits_plan_free(&p);
    size_t sz = 3 * (size_t)(s.mesh.nn + 64) * (nsteps + 1);
    double *ub = calloc(sz, sizeof(double));
    check_methods(&s, f, "k 0.5 MPa/mm", ub);
    w.k = 50;
    check_methods(&s, f, "k 50 MPa/mm", NULL);
    /* k = 0 is the unbridged answer, bitwise */
    double *u0 = calloc(sz, sizeof(double)), *un = calloc(sz, sizeof(double));
    w.k = 0;
    check_methods(&s, f, "k 0", u0);
    s.mats.wound = NULL;
    check_methods(&s, f, "no wound", un);
    CHECK(memcmp(u0, un, sz * sizeof(double)) == 0, "k = 0 differs from the unbridged answer");
    { /* the bridge closes the wound: the opening's energy measure u^T B u (k 1) of the last
       * step's field, bridged against unbridged */
        CHECK(read_plan(f, &p, &e) == KT_OK && kt_edits_plan_check(&p, "stream", &s.prob, &final, &e) == KT_OK,
              "plan: %s", e.msg);
        size_t n = 3 * (size_t)final.nn, at = (size_t)nsteps * 3 * p.nn;
        double *y0 = calloc(n, sizeof(double)), *yb = calloc(n, sizeof(double)), E0 = 0, Eb = 0;
        w.k = 1;
        kt_wound_apply(&w, &final, u0 + at, 1.0, y0, &e);
        kt_wound_apply(&w, &final, ub + at, 1.0, yb, &e);
        for (size_t i = 0; i < n; i++) E0 += u0[at + i] * y0[i], Eb += ub[at + i] * yb[i];
        printf("opening (u^T B u, k = 1): %.4g unbridged, %.4g with k = 0.5 MPa/mm\n", E0, Eb);
        CHECK(E0 > 0 && Eb < 0.9 * E0, "the bridge does not close the wound: %.4g vs %.4g", Eb, E0);
        free(y0);
        free(yb);
        kt_mesh_free(&final);
        kt_edits_plan_free(&p);
    }
    s.mats.wound = &w;
    w.k = 0.5;
    check_uncut_limit(&s, f, &w);
    check_nonlinear(&s, f);
    free(u0);
    free(un);
    free(ub);
    fclose(f);
    kt_wound_free(&w);
    scenario_free(&s);
    return kt_test_done("test_wound");
}
