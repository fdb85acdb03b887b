/* test_incise.c: exact predicates against an integer oracle, and cuts checked by applying every
 * step with kt_cut_apply: the two sides separate, element count and volume are unchanged, each
 * step touches only its portion, counts match an independent count on the incision surface,
 * paired arcs are symmetric, overlaps are skipped, planar cuts, snapping and deformation. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "apply.h"
#include "eye.h"
#include "grid.h"
#include "incise.h"
#include "kt_test.h"
#include "predicates.h"

#include "kt_test_gmsh.h"

/* ---- predicates against __int128 on dyadic coordinates ---- */

static uint64_t rng_state = 88172645463325252ull;
static uint64_t rng(void)
{
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 7;
    rng_state ^= rng_state << 17;
    return rng_state;
}
static long long rnd(long long range) { return (long long)(rng() % (2 * (uint64_t)range + 1)) - range; }
static int sgn128(__int128 v) { return (v > 0) - (v < 0); }

static const double SCALE = 1.0 / 1048576.0; /* 2^-20: integer * SCALE is exact */

static void test_orient3d(void)
{
    int wrong_naive = 0, bad = 0, zeros = 0;
    kt_pred_stats st = {0, 0};
    for (int it = 0; it < 200000; it++) {
        long long A[3], B[3], C[3], D[3];
        for (int k = 0; k < 3; k++) {
            A[k] = rnd(1LL << 26);
            B[k] = rnd(1LL << 26);
            C[k] = rnd(1LL << 26);
        }
        /* D near the plane ABC: an affine combination, rounded, plus a tiny offset */
        double s = (double)(rng() % 1000) / 500.0 - 0.5, t = (double)(rng() % 1000) / 500.0 - 0.5;
        for (int k = 0; k < 3; k++)
            D[k] = A[k] + llround(s * (double)(B[k] - A[k])) + llround(t * (double)(C[k] - A[k])) +
                   (it % 3 == 0 ? 0 : rnd(1));
        if (it % 7 == 0) /* exactly coplanar: D = A + (B - A) + (C - A) */
            for (int k = 0; k < 3; k++) D[k] = B[k] + C[k] - A[k];
        __int128 u[3], v[3], w[3];
        double a[3], b[3], c[3], d[3];
        for (int k = 0; k < 3; k++) {
            u[k] = B[k] - A[k], v[k] = C[k] - A[k], w[k] = D[k] - A[k];
            a[k] = A[k] * SCALE, b[k] = B[k] * SCALE, c[k] = C[k] * SCALE, d[k] = D[k] * SCALE;
        }
        __int128 det = u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) +
                       u[2] * (v[0] * w[1] - v[1] * w[0]);
        int want = sgn128(det);
        int got = kt_pred_orient3d_counted(a, b, c, d, &st);
        bad += got != want;
        zeros += want == 0;
        double vol = kt_tet_volume(a, b, c, d);
        wrong_naive += ((vol > 0) - (vol < 0)) != want;
    }
    CHECK(bad == 0, "orient3d disagrees with the exact integer sign in %d of 200000 cases", bad);
    CHECK(zeros > 20000, "too few exactly coplanar cases (%d) to exercise the exact path", zeros);
    CHECK(st.exact > 0, "no case needed the exact path");
    printf("orient3d: %ld calls, %ld exact fallbacks, naive double sign wrong in %d cases\n",
           st.calls, st.exact, wrong_naive);
    CHECK(wrong_naive > 0, "the test set should include cases plain doubles get wrong");
}

static void test_plane_cylinder(void)
{
    int bad_p = 0, bad_c = 0, zp = 0, zc = 0;
    for (int it = 0; it < 100000; it++) {
        long long X[4][3], P[3], N[3];
        for (int k = 0; k < 3; k++) {
            P[k] = rnd(1LL << 24);
            N[k] = rnd(1LL << 20);
        }
        /* points scattered about the plane, their centroid close to it */
        for (int j = 0; j < 4; j++)
            for (int k = 0; k < 3; k++) X[j][k] = P[k] + rnd(1LL << 22);
        __int128 val = 0;
        for (int k = 0; k < 3; k++) {
            __int128 s = -4 * (__int128)P[k];
            for (int j = 0; j < 4; j++) s += X[j][k];
            val += s * N[k];
        }
        /* nudge the last point along a coordinate to bring the value to about zero */
        int kk = N[0] ? 0 : N[1] ? 1 : 2;
        if (N[kk] != 0) {
            long long shift = (long long)(val / N[kk]);
            X[3][kk] -= shift;
            val -= (__int128)shift * N[kk];
        }
        double x[4][3], p[3], n[3];
        const double *xp[4];
        for (int k = 0; k < 3; k++) {
            p[k] = P[k] * SCALE;
            n[k] = (double)N[k];
            for (int j = 0; j < 4; j++) x[j][k] = X[j][k] * SCALE;
        }
        for (int j = 0; j < 4; j++) xp[j] = x[j];
        int want = sgn128(val);
        zp += want == 0;
        bad_p += kt_pred_plane_side(p, n, xp, 4) != want;

        /* cylinder: r integer, centroid radius near r */
        long long R = (1LL << 22) + rnd(1LL << 20), sx = 0, sy = 0;
        for (int j = 0; j < 4; j++) sx += X[j][0], sy += X[j][1];
        __int128 cv = (__int128)sx * sx + (__int128)sy * sy - (__int128)(4 * R) * (4 * R);
        if (it % 2 == 0) { /* Pythagorean centroid exactly on the cylinder: 3-4-5 */
            long long m = 1LL << 20;
            X[0][0] = 3 * m, X[0][1] = 4 * m, X[1][0] = 3 * m, X[1][1] = 4 * m;
            X[2][0] = 3 * m + 7, X[2][1] = 4 * m - 5, X[3][0] = 3 * m - 7, X[3][1] = 4 * m + 5;
            R = 5 * m;
            sx = 12 * m, sy = 16 * m;
            cv = (__int128)sx * sx + (__int128)sy * sy - (__int128)(4 * R) * (4 * R);
            for (int j = 0; j < 4; j++) x[j][0] = X[j][0] * SCALE, x[j][1] = X[j][1] * SCALE;
        }
        int wc = sgn128(cv);
        zc += wc == 0;
        bad_c += kt_pred_cylinder_side(R * SCALE, xp, 4) != wc;
    }
    CHECK(bad_p == 0, "plane side wrong in %d cases", bad_p);
    CHECK(bad_c == 0, "cylinder side wrong in %d cases", bad_c);
    CHECK(zp > 0 && zc > 0, "degenerate cases exercised: plane %d cylinder %d", zp, zc);
}

/* ---- a cylindrical slab with an embedded ring ---- */

#define RING_TAG 10
static const double H = 0.8, R_RING = 5.25;

/* A kt_grid_box in (r, theta, z) wrapped around the z axis: r in [4.5, 6], theta in nth steps
 * over 360 deg, z in [0, H] (nz nodes). The layer r = R_RING becomes "incision-ring-1" (when
 * with_ring), zmax becomes "anterior". */
static int ring_mesh(kt_mesh *m, int nth, int nz, int with_ring, int order, kt_err *e)
{
    const int nr = 7;
    kt_mesh b;
    if (kt_grid_box(&b, nr, nth + 1, nz, 1.5, 360.0, H, e)) return e->code;
    int *map = calloc((size_t)b.nn, sizeof(int));
    memset(m, 0, sizeof *m);
    m->order = 1;
    m->nn = nr * nth * nz;
    m->xyz = calloc(3 * (size_t)m->nn, sizeof(double));
    for (int k = 0; k < nz; k++)
        for (int j = 0; j <= nth; j++)
            for (int i = 0; i < nr; i++) {
                int old = i + nr * (j + (nth + 1) * k), nw = i + nr * ((j % nth) + nth * k);
                map[old] = nw;
                double r = 4.5 + 0.25 * i, th = (j % nth) * (2 * M_PI / nth);
                m->xyz[3 * nw] = r * cos(th);
                m->xyz[3 * nw + 1] = r * sin(th);
                m->xyz[3 * nw + 2] = b.xyz[3 * old + 2];
            }
    m->ne = b.ne;
    m->tet = malloc(4 * sizeof(int) * (size_t)m->ne);
    m->tet_tag = malloc(sizeof(int) * (size_t)m->ne);
    for (int t = 0; t < m->ne; t++) {
        for (int k = 0; k < 4; k++) m->tet[4 * t + k] = map[b.tet[4 * t + k]];
        m->tet_tag[t] = 1;
    }
    /* surfaces: anterior from zmax (tag 6), ring from tet faces on the layer i = 3 */
    m->tri = malloc(sizeof(int) * 3 * (size_t)(b.nf + 4 * b.ne));
    m->tri_tag = malloc(sizeof(int) * (size_t)(b.nf + 4 * b.ne));
    for (int f = 0; f < b.nf; f++)
        if (b.tri_tag[f] == 6) {
            for (int k = 0; k < 3; k++) m->tri[3 * m->nf + k] = map[b.tri[3 * f + k]];
            m->tri_tag[m->nf++] = 1;
        }
    static const int FV[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
    for (int t = 0; with_ring && t < m->ne; t++)
        for (int j = 0; j < 4; j++) {
            int v[3], on = 1;
            for (int k = 0; k < 3; k++) {
                v[k] = m->tet[4 * t + FV[j][k]];
                on &= v[k] % nr == 3;
            }
            /* take each face once: from the tet on the inner side (opposite vertex at i = 2) */
            if (!on || m->tet[4 * t + j] % nr != 2) continue;
            for (int k = 0; k < 3; k++) m->tri[3 * m->nf + k] = v[k];
            m->tri_tag[m->nf++] = RING_TAG;
        }
    kt_mesh_add_group(m, 3, 1, "body", e);
    kt_mesh_add_group(m, 2, 1, "anterior", e);
    if (with_ring) kt_mesh_add_group(m, 2, RING_TAG, "incision-ring-1", e);
    free(map);
    kt_mesh_free(&b);
    if (!e->code && kt_mesh_check(m, "ring mesh", e)) return e->code;
    if (order == 2 && kt_mesh_elevate(m, e)) return e->code;
    return e->code;
}

static void lri_plan(kt_plan *p, double meridian, double arc, int paired, int dir, double dps)
{
    memset(p, 0, sizeof *p);
    snprintf(p->path, sizeof p->path, "test-plan");
    p->snap.fraction = 0.25;
    p->snap.min_quality = 0.05;
    p->ninc = 1;
    kt_incision *inc = &p->inc[0];
    inc->meridian = meridian;
    inc->arc = arc;
    inc->depth = 0.6;
    inc->diameter = 2 * R_RING;
    snprintf(inc->surface, sizeof inc->surface, "incision-ring-1");
    inc->paired = paired;
    inc->direction = dir;
    inc->prog.degrees_per_step = dps;
}

/* Every step of a plan, applied to a copy of the mesh with kt_cut_apply. */
typedef struct run {
    kt_mesh cut;          /* the mesh after all steps */
    int nsteps;
    int *step_of;         /* new node -> step (nn_final) */
    int ndup;
    long skipped;
    double *step_lo, *step_hi; /* travel range of each step (deg or mm), from the label */
    kt_step *steps;
    int rc;
    char msg[1100];
} run;

static void run_free(run *r)
{
    kt_mesh_free(&r->cut);
    free(r->step_of);
    free(r->step_lo);
    free(r->step_hi);
    for (int i = 0; i < r->nsteps; i++) kt_step_free(&r->steps[i]);
    free(r->steps);
}

static int run_plan(const kt_plan *p, kt_mesh *m, run *r)
{
    memset(r, 0, sizeof *r);
    kt_err e = {0};
    kt_incise *c = NULL;
    if (kt_incise_begin(&c, p, m, 1, &e)) {
        r->rc = e.code;
        snprintf(r->msg, sizeof r->msg, "%s", e.msg);
        return r->rc;
    }
    kt_mesh_copy(&r->cut, m, &e);
    r->steps = calloc(10000, sizeof(kt_step));
    r->step_lo = calloc(10000, sizeof(double));
    r->step_hi = calloc(10000, sizeof(double));
    r->step_of = calloc(1000000, sizeof(int));
    for (;;) {
        kt_step *s = &r->steps[r->nsteps];
        int more = kt_incise_next(c, s, &e);
        if (more <= 0) {
            if (more < 0) {
                r->rc = e.code;
                snprintf(r->msg, sizeof r->msg, "%s", e.msg);
            }
            break;
        }
        CHECK(s->index == r->nsteps + 1, "step numbers in sequence");
        sscanf(s->label, "%*s %lf-%lf", &r->step_lo[r->nsteps], &r->step_hi[r->nsteps]);
        int *touched = NULL, nt = 0;
        int base = r->cut.nn;
        if (kt_cut_apply(&r->cut, s, &touched, &nt, &e)) {
            r->rc = e.code;
            snprintf(r->msg, sizeof r->msg, "kt_cut_apply: %s", e.msg);
            free(touched);
            r->nsteps++;
            break;
        }
        free(touched);
        for (int v = base; v < r->cut.nn; v++) r->step_of[v] = r->nsteps + 1;
        r->ndup += r->cut.nn - base;
        r->nsteps++;
    }
    r->skipped = kt_incise_stats_get(c)->skipped;
    kt_incise_end(c);
    return r->rc;
}

static double total_volume(const kt_mesh *m)
{
    int nv = kt_tet_nv(m->order);
    double v = 0;
    for (int i = 0; i < m->ne; i++) {
        const int *t = m->tet + (size_t)nv * i;
        v += kt_tet_volume(m->xyz + 3 * t[0], m->xyz + 3 * t[1], m->xyz + 3 * t[2], m->xyz + 3 * t[3]);
    }
    return v;
}

static void centroid(const kt_mesh *m, int t, double *c)
{
    int nv = kt_tet_nv(m->order);
    c[0] = c[1] = c[2] = 0;
    for (int k = 0; k < 4; k++)
        for (int q = 0; q < 3; q++) c[q] += 0.25 * m->xyz[3 * (size_t)m->tet[(size_t)t * nv + k] + q];
}

/* Separation: a tet holding a new node lies outside (side > 0), a tet holding a node that was
 * duplicated lies inside; side() is an independent geometric test on the tet centroid. */
typedef double (*side_fn)(const double *c);
static double radial_side(const double *c) { return hypot(c[0], c[1]) - R_RING; }

static int check_separation(const run *r, int nn0, side_fn side)
{
    const kt_mesh *m = &r->cut;
    int nv = kt_tet_nv(m->order), bad = 0;
    unsigned char *split = calloc((size_t)m->nn, 1);
    for (int s = 0; s < r->nsteps; s++)
        for (int i = 0; i < r->steps[s].n; i++)
            if (r->steps[s].edit[i].kind == KT_EDIT_DUP) split[r->steps[s].edit[i].node] = 1;
    for (int t = 0; t < m->ne; t++) {
        double c[3];
        centroid(m, t, c);
        double sd = side(c);
        for (int l = 0; l < nv; l++) {
            int v = m->tet[(size_t)t * nv + l];
            if (v >= nn0 && sd <= 0) bad++;
            if (v < nn0 && split[v] && sd >= 0) bad++;
        }
    }
    free(split);
    return bad;
}

/* Independent count of the nodes an arc must duplicate: the ring's nodes on the selected
 * faces minus those on the patch's edges inside the tissue (floor, ends; the corners where an
 * end meets the anterior surface); for P2, plus the mid-edge nodes of edges interior to the
 * patch or on its opening. Selection here: every vertex within the arc and z >= H - depth. */
static int in_arc(const double *x, double centre, double arc)
{
    double th = atan2(x[1], x[0]) * 180 / M_PI;
    double d = remainder(th - centre, 360.0);
    return fabs(d) <= arc / 2 + 1e-7;
}

static int expected_dups(const kt_mesh *m, double centre, double arc, double depth)
{
    int fv = kt_tri_nv(m->order), nsel = 0;
    int (*edge)[2] = malloc(sizeof(int[2]) * 3 * (size_t)m->nf);
    int *edge_mid = malloc(sizeof(int) * 3 * (size_t)m->nf);
    int ne = 0;
    unsigned char *in = calloc((size_t)m->nn, 1);
    for (int f = 0; f < m->nf; f++) {
        if (m->tri_tag[f] != RING_TAG) continue;
        const int *t = m->tri + (size_t)f * fv;
        int ok = 1;
        for (int k = 0; k < 3; k++) {
            const double *x = m->xyz + 3 * (size_t)t[k];
            ok &= in_arc(x, centre, arc) && x[2] >= H - depth - 1e-9;
        }
        if (!ok) continue;
        nsel++;
        for (int k = 0; k < 3; k++) {
            int a = t[k], b = t[(k + 1) % 3];
            in[a] = 1;
            edge[ne][0] = a < b ? a : b;
            edge[ne][1] = a < b ? b : a;
            edge_mid[ne++] = m->order == 2 ? t[3 + k] : -1;
        }
    }
    /* boundary edges of the patch: edges in one selected face */
    unsigned char *shared = calloc((size_t)m->nn, 1);
    int mid_dups = 0;
    for (int i = 0; i < ne; i++) {
        int cnt = 0;
        for (int j = 0; j < ne; j++) cnt += edge[j][0] == edge[i][0] && edge[j][1] == edge[i][1];
        int a = edge[i][0], b = edge[i][1];
        int top_a = m->xyz[3 * (size_t)a + 2] == H, top_b = m->xyz[3 * (size_t)b + 2] == H;
        int first = 1;
        for (int j = 0; j < i; j++) first &= !(edge[j][0] == a && edge[j][1] == b);
        if (cnt == 1 && !(top_a && top_b)) { /* floor or end edge: both ends stay shared */
            shared[a] = shared[b] = 1;
        } else if (first && m->order == 2) {
            mid_dups++; /* interior edge or on the opening */
        }
    }
    int dups = 0;
    for (int v = 0; v < m->nn; v++) dups += in[v] && !shared[v];
    free(edge);
    free(edge_mid);
    free(in);
    free(shared);
    (void)nsel;
    return dups + mid_dups;
}

static double travel_of(const double *x, double centre, double arc, int dir)
{
    double th = atan2(x[1], x[0]) * 180 / M_PI, d = remainder(th - centre, 360.0);
    if (dir == KT_BLADE_CCW) return d + arc / 2;
    if (dir == KT_BLADE_CW) return arc / 2 - d;
    return 2 * fabs(d);
}

static void test_ring(int order)
{
    kt_err e = {0};
    kt_mesh m;
    const int nth = 144; /* 2.5 deg */
    CHECK(ring_mesh(&m, nth, 9, 1, order, &e) == 0, "ring mesh: %s", e.msg);
    double vol0 = total_volume(&m);
    int nn0 = m.nn, ne0 = m.ne;

    /* one 60-degree arc at 90, clockwise, 5 degrees per step */
    kt_plan p;
    lri_plan(&p, 90, 60, 0, KT_BLADE_CW, 5);
    run r;
    CHECK(run_plan(&p, &m, &r) == 0, "run: %s", r.msg);
    int want = expected_dups(&m, 90, 60, 0.6);
    printf("ring P%d: single arc: %d steps, %d nodes duplicated (independent count %d)\n", order,
           r.nsteps, r.ndup, want);
    CHECK(r.ndup == want, "P%d: duplicated %d, expected %d", order, r.ndup, want);
    CHECK(order == 2 || want == 23 * 6, "P1 count on the 2.5-degree ring: %d", want);
    CHECK(r.nsteps == 12, "12 steps of 5 degrees, got %d", r.nsteps);
    CHECK(r.cut.ne == ne0, "tet count unchanged");
    CHECK_NEAR(total_volume(&r.cut), vol0, 1e-12, "volume unchanged");
    CHECK(check_separation(&r, nn0, radial_side) == 0, "P%d: a tet shares a duplicated node across the cut", order);
    /* each step's new nodes lie in its portion of the arc (one element of slack behind) */
    int outside = 0;
    for (int v = nn0; v < r.cut.nn; v++) {
        int s = r.step_of[v] - 1;
        double t = travel_of(r.cut.xyz + 3 * (size_t)v, 90, 60, KT_BLADE_CW);
        if (t > r.step_hi[s] + 1e-6 || t < r.step_lo[s] - 2.5 - 1e-6) outside++;
    }
    CHECK(outside == 0, "%d new nodes outside their step's portion of the arc", outside);
    for (int s = 0; s < r.nsteps; s++)
        CHECK_NEAR(r.step_hi[s] - r.step_lo[s], 5.0, 1e-9, "each step adds 5 degrees");
    int single = r.ndup;
    run_free(&r);

    /* paired, counter-clockwise: symmetric counts per step, mirrored positions */
    lri_plan(&p, 90, 60, 1, KT_BLADE_CCW, 5);
    CHECK(run_plan(&p, &m, &r) == 0, "run paired: %s", r.msg);
    CHECK(r.ndup == 2 * single, "paired: %d duplicated, twice the single arc is %d", r.ndup, 2 * single);
    CHECK(check_separation(&r, nn0, radial_side) == 0, "paired: separation");
    int asym = 0, unmatched = 0;
    for (int s = 0; s < r.nsteps; s++) {
        int n1 = 0, n2 = 0;
        for (int v = nn0; v < r.cut.nn; v++) {
            if (r.step_of[v] != s + 1) continue;
            const double *x = r.cut.xyz + 3 * (size_t)v;
            if (x[1] > 0) n1++;
            else n2++;
            int mirror = 0; /* a new node of the same step at (-x, -y, z) */
            for (int w = nn0; w < r.cut.nn && !mirror; w++) {
                const double *y = r.cut.xyz + 3 * (size_t)w;
                mirror = r.step_of[w] == s + 1 && fabs(y[0] + x[0]) < 1e-9 && fabs(y[1] + x[1]) < 1e-9 &&
                         fabs(y[2] - x[2]) < 1e-12;
            }
            unmatched += !mirror;
        }
        asym += n1 != n2;
    }
    CHECK(asym == 0, "paired: %d steps with different counts on the two arcs", asym);
    CHECK(unmatched == 0, "paired: %d new nodes without a mirror image", unmatched);
    run_free(&r);

    /* centre-out: the first step's nodes are at the centre */
    lri_plan(&p, 90, 60, 0, KT_BLADE_CENTRE_OUT, 5);
    CHECK(run_plan(&p, &m, &r) == 0, "run centre-out: %s", r.msg);
    CHECK(r.ndup == single, "centre-out cuts the same nodes: %d vs %d", r.ndup, single);
    double far = 0;
    for (int v = nn0; v < r.cut.nn; v++)
        if (r.step_of[v] == 1) far = fmax(far, fabs(travel_of(r.cut.xyz + 3 * (size_t)v, 90, 60, KT_BLADE_CENTRE_OUT)));
    CHECK(far <= 5.0 + 1e-9, "centre-out first step reaches %g deg of arc", far);
    run_free(&r);

    /* overlapping arcs: 90 +- 30 then 120 +- 30 = one wound from 60 to 150; the overlap is
     * skipped (a note on stderr), the union is cut once */
    lri_plan(&p, 90, 60, 0, KT_BLADE_CW, 5);
    p.ninc = 2;
    p.inc[1] = p.inc[0];
    p.inc[1].meridian = 120;
    CHECK(run_plan(&p, &m, &r) == 0, "run overlap: %s", r.msg);
    int want_union = expected_dups(&m, 105, 90, 0.6);
    CHECK(r.ndup == want_union, "overlap: %d duplicated, the 90-degree union needs %d", r.ndup, want_union);
    CHECK(r.skipped > 0, "overlap: skipped faces reported");
    CHECK(check_separation(&r, nn0, radial_side) == 0, "overlap: separation");
    run_free(&r);

    /* the same arc twice: the second adds nothing (no steps) */
    p.inc[1].meridian = 90;
    CHECK(run_plan(&p, &m, &r) == 0, "run twice: %s", r.msg);
    CHECK(r.ndup == single && r.nsteps == 12, "same arc twice: %d dups in %d steps", r.ndup, r.nsteps);
    run_free(&r);

    /* nodes per step */
    lri_plan(&p, 90, 60, 0, KT_BLADE_CW, 0);
    p.inc[0].prog.nodes_per_step = order == 1 ? 12 : 30;
    CHECK(run_plan(&p, &m, &r) == 0, "run nodes/step: %s", r.msg);
    CHECK(r.ndup == single, "nodes per step: %d vs %d", r.ndup, single);
    int short_steps = 0;
    for (int s = 0; s + 1 < r.nsteps; s++) {
        int n = 0;
        for (int v = nn0; v < r.cut.nn; v++) n += r.step_of[v] == s + 1;
        short_steps += n < p.inc[0].prog.nodes_per_step;
    }
    CHECK(short_steps == 0, "every step but the last duplicates at least nodes_per_step nodes");
    run_free(&r);

    /* a full circle: no ends, every ring node above the floor splits (the faces across the
     * back of the ring close it in the last step) */
    lri_plan(&p, 90, 360, 0, KT_BLADE_CCW, 30);
    CHECK(run_plan(&p, &m, &r) == 0, "run 360: %s", r.msg);
    int want360 = expected_dups(&m, 90, 360, 0.6);
    CHECK(r.ndup == want360 && (order == 2 || want360 == 144 * 6), "360: %d duplicated, expected %d",
          r.ndup, want360);
    CHECK(check_separation(&r, nn0, radial_side) == 0, "360: separation");
    run_free(&r);

    /* deeper than the ring in the mesh: refused at the plan's depth */
    lri_plan(&p, 90, 60, 0, KT_BLADE_CW, 5);
    p.inc[0].depth = 1.0;
    p.inc[0].at_depth.line = 7;
    p.inc[0].at_depth.col = 12;
    CHECK(run_plan(&p, &m, &r) == KT_EINPUT && strstr(r.msg, "test-plan:7:12:"), "too deep: %s", r.msg);
    run_free(&r);
    kt_mesh_free(&m);

    /* the same cut snapped onto the cylinder when the mesh has no ring surface */
    CHECK(ring_mesh(&m, nth, 9, 0, order, &e) == 0, "plain mesh: %s", e.msg);
    lri_plan(&p, 90, 60, 0, KT_BLADE_CW, 5);
    p.inc[0].surface[0] = '\0';
    CHECK(run_plan(&p, &m, &r) == 0, "run cylinder: %s", r.msg);
    CHECK(r.ndup == single, "cylinder cut duplicates %d, the ring cut %d", r.ndup, single);
    CHECK(check_separation(&r, nn0, radial_side) == 0, "cylinder: separation");
    run_free(&r);
    kt_mesh_free(&m);
}

/* ---- planar cuts on box grids ---- */

static double plane_side_y2(const double *c) { return c[1] - 2.0; }

static void planar_plan(kt_plan *p, double y, double length, int nps, double pull)
{
    memset(p, 0, sizeof *p);
    snprintf(p->path, sizeof p->path, "test-plan");
    p->snap.fraction = 0.25;
    p->snap.min_quality = 0.05;
    kt_planar *pl = &p->planar;
    pl->set = 1;
    pl->point[1] = y;
    pl->normal[1] = 1;
    pl->advance[2] = -1;
    pl->length = length;
    pl->nodes_per_step = nps;
    pl->pull_force = pull;
    snprintf(pl->pull_surface, sizeof pl->pull_surface, "zmax");
}

static void test_planar(int order)
{
    kt_err e = {0};
    kt_mesh m;
    CHECK(kt_grid_box(&m, 5, 5, 9, 4, 4, 8, &e) == 0, "%s", e.msg);
    if (order == 2) CHECK(kt_mesh_elevate(&m, &e) == 0, "%s", e.msg);
    int nn0 = m.nn;
    double vol0 = total_volume(&m);
    kt_plan p;
    planar_plan(&p, 2.0, 4.0, 5, 0.01);
    run r;
    CHECK(run_plan(&p, &m, &r) == 0, "planar: %s", r.msg);
    /* vertices on y = 2 with z in {5,6,7,8}: 5 x 4; the front z = 4 stays shared */
    int want_v = 20, want_mid = 0;
    if (order == 2) { /* mid-edge nodes of cut-face edges not on the front line z = 4 */
        for (int v = 0; v < m.nn; v++) {
            const double *x = m.xyz + 3 * (size_t)v;
            int is_vertex = v < 225;
            if (!is_vertex && fabs(x[1] - 2) < 1e-12 && x[2] > 4 - 1e-12 && !(fabs(x[2] - 4) < 1e-12)) want_mid++;
        }
    }
    printf("planar P%d: %d steps, %d duplicated (expected %d)\n", order, r.nsteps, r.ndup, want_v + want_mid);
    CHECK(r.ndup == want_v + want_mid, "planar P%d: %d duplicated, expected %d", order, r.ndup, want_v + want_mid);
    CHECK(order == 2 || r.nsteps == 4, "four steps of five nodes: %d", r.nsteps);
    CHECK(check_separation(&r, nn0, plane_side_y2) == 0, "planar: separation");
    CHECK_NEAR(total_volume(&r.cut), vol0, 1e-12, "planar: volume");
    /* pull forces: each side's total is the pull force along the normal, on zmax nodes */
    double fy_pos = 0, fy_neg = 0;
    int last_force_step = -1;
    for (int s = 0; s < r.nsteps; s++)
        for (int i = 0; i < r.steps[s].n; i++)
            if (r.steps[s].edit[i].kind == KT_EDIT_FORCE) last_force_step = s;
    CHECK(last_force_step >= 0, "pull forces emitted");
    for (int i = 0; last_force_step >= 0 && i < r.steps[last_force_step].n; i++) {
        const kt_edit *ed = &r.steps[last_force_step].edit[i];
        if (ed->kind != KT_EDIT_FORCE) continue;
        CHECK(fabs(r.cut.xyz[3 * (size_t)ed->node + 2] - 8) < 1e-12, "pulled node on zmax");
        if (ed->v[1] > 0) {
            fy_pos += ed->v[1];
            CHECK(ed->node >= nn0, "+ on the new node");
        } else {
            fy_neg += ed->v[1];
        }
    }
    CHECK_NEAR(fy_pos, 0.01, 1e-12, "pull force on the moving side");
    CHECK_NEAR(fy_neg, -0.01, 1e-12, "pull force on the staying side");
    run_free(&r);

    /* off the grid by 0.1 mm: the layer y = 2 snaps onto y = 2.1 */
    kt_mesh m2;
    kt_mesh_copy(&m2, &m, &e);
    planar_plan(&p, 2.1, 4.0, 5, 0);
    CHECK(run_plan(&p, &m2, &r) == 0, "snap: %s", r.msg);
    int on = 0, moved = 0;
    for (int v = 0; v < 225; v++) {
        on += fabs(m2.xyz[3 * v + 1] - 2.1) < 1e-12;
        moved += m2.xyz[3 * v + 1] != m.xyz[3 * v + 1];
    }
    CHECK(on == 25 && moved == 25, "snapped the 25 layer nodes of the cut region: on %d moved %d", on, moved);
    CHECK(r.ndup == want_v + want_mid, "snapped cut duplicates %d", r.ndup);
    CHECK(kt_mesh_check(&m2, "snapped", &e) == 0, "snapped mesh valid: %s", e.msg);
    run_free(&r);
    kt_mesh_free(&m2);

    /* a quality limit every snap would break: no node moves (each stays where it was), the cut
     * is made along the faces as meshed */
    kt_mesh_copy(&m2, &m, &e);
    planar_plan(&p, 2.2, 4.0, 5, 0);
    p.snap.min_quality = 0.99;
    CHECK(run_plan(&p, &m2, &r) == 0, "a snap that breaks the limit stays: %s", r.msg);
    int same = memcmp(m2.xyz, m.xyz, sizeof(double) * 3 * (size_t)m.nn) == 0;
    CHECK(same, "no node snapped: the mesh unchanged");
    CHECK(r.ndup > 0, "the cut is made: %d duplicated", r.ndup);
    run_free(&r);
    kt_mesh_free(&m2);
    kt_mesh_free(&m);
}

/* ---- deformation steps ---- */

static void test_deform(void)
{
    kt_err e = {0};
    kt_mesh m;
    CHECK(kt_grid_box(&m, 5, 5, 9, 4, 4, 8, &e) == 0, "%s", e.msg);
    kt_plan p;
    memset(&p, 0, sizeof p);
    snprintf(p.path, sizeof p.path, "test-plan");
    p.ndeform = 2;
    kt_deform *d = &p.deform[0];
    d->kind = KT_DEFORM_FIX;
    d->set_dim = 2;
    snprintf(d->set, sizeof d->set, "zmax");
    d->mask = 7;
    d->v[2] = -0.1;
    d->nodes_per_step = 5;
    d->order[0] = 1;
    p.deform[1] = *d;
    p.deform[1].kind = KT_DEFORM_FORCE;
    p.deform[1].nodes_per_step = 0;
    p.deform[1].steps = 4;
    p.deform[1].v[2] = -0.2;
    run r;
    CHECK(run_plan(&p, &m, &r) == 0, "deform: %s", r.msg);
    CHECK(r.nsteps == 5 + 4, "5 + 4 steps, got %d", r.nsteps);
    int fixed = 0, bad = 0;
    for (int s = 0; s < 5; s++) {
        CHECK(r.steps[s].n == 5, "five new constraints per step");
        for (int i = 0; i < r.steps[s].n; i++) {
            const kt_edit *ed = &r.steps[s].edit[i];
            fixed++;
            bad += ed->kind != KT_EDIT_FIX || ed->v[2] != -0.1 || m.xyz[3 * ed->node + 2] != 8;
            /* taken by increasing x */
            bad += m.xyz[3 * ed->node] != (double)s;
        }
    }
    CHECK(fixed == 25 && bad == 0, "constraints: %d fixed, %d wrong", fixed, bad);
    for (int s = 5; s < 9; s++) {
        double fz = 0;
        for (int i = 0; i < r.steps[s].n; i++) fz += r.steps[s].edit[i].v[2];
        CHECK_NEAR(fz, -0.2 * (s - 4) / 4.0, 1e-12, "ramped total force");
    }
    run_free(&r);
    kt_mesh_free(&m);
}


/* ---- the demo plan on a coarse eye from kt_eye_mesh ---- */

/* Outward unit normal of the selected ring faces around each node (summed face normals,
 * oriented away from the axis), for an independent side test at the cut. */
static void ring_normals(const kt_mesh *m, const unsigned char *sel, int tag, double *nrm)
{
    for (int f = 0; f < m->nf; f++) {
        if (m->tri_tag[f] != tag || !sel[f]) continue;
        const int *t = m->tri + 3 * (size_t)f;
        const double *a = m->xyz + 3 * (size_t)t[0], *b = m->xyz + 3 * (size_t)t[1], *c = m->xyz + 3 * (size_t)t[2];
        double u[3], v[3], n[3];
        for (int k = 0; k < 3; k++) u[k] = b[k] - a[k], v[k] = c[k] - a[k];
        n[0] = u[1] * v[2] - u[2] * v[1];
        n[1] = u[2] * v[0] - u[0] * v[2];
        n[2] = u[0] * v[1] - u[1] * v[0];
        double radial = n[0] * (a[0] + b[0] + c[0]) + n[1] * (a[1] + b[1] + c[1]);
        double sg = radial > 0 ? 1 : -1;
        for (int k = 0; k < 3; k++)
            for (int q = 0; q < 3; q++) nrm[3 * (size_t)t[k] + q] += sg * n[q];
    }
}

static void test_eye(void)
{
    kt_err e = {0};
    kt_plan *p = calloc(1, sizeof *p);
    CHECK(kt_plan_load("plans/lri-paired-60.yaml", p, &e) == 0, "demo plan: %s", e.msg);
    if (e.code) {
        free(p);
        return;
    }
    CHECK(p->ninc == 1 && p->inc[0].paired && p->inc[0].arc == 60 && p->inc[0].meridian == 90,
          "demo plan: paired 60-degree arcs at 90");
    CHECK(p->target.set && p->target.magnitude == 1.5 && p->target.axis == 90, "demo target");
    /* coarse sizes: the test meshes in a few seconds */
    kt_eye eye = p->scene.eye;
    eye.h_optical = 0.6, eye.h_incision = 0.3, eye.h_cornea = 0.8, eye.h_sclera = 2.5;
    kt_mesh m;
    double t0 = kt_now();
    CHECK(kt_eye_mesh(&eye, 1, 1, &m, &e) == 0, "eye mesh: %s", e.msg);
    if (e.code) {
        free(p);
        return;
    }
    double t1 = kt_now();
    run r;
    CHECK(run_plan(p, &m, &r) == 0, "demo on the eye: %s", r.msg);
    double t2 = kt_now();
    const kt_group *g = kt_mesh_find_group(&m, 2, "incision-ring-1");
    const kt_group *ga = kt_mesh_find_group(&m, 2, "anterior");
    CHECK(g && ga, "eye groups");
    if (!g || !ga) goto done;
    /* independent count: the demo's depth is the ring's full depth, so every ring triangle
     * with its vertices within either arc is cut; minus floor, ends and corners */
    unsigned char *top = calloc((size_t)m.nn, 1), *sel = calloc((size_t)m.nf, 1);
    for (int f = 0; f < m.nf; f++)
        if (m.tri_tag[f] == ga->tag)
            for (int k = 0; k < 3; k++) top[m.tri[3 * f + k]] = 1;
    int nsel = 0;
    for (int f = 0; f < m.nf; f++) {
        if (m.tri_tag[f] != g->tag) continue;
        int ok1 = 1, ok2 = 1;
        for (int k = 0; k < 3; k++) {
            const double *x = m.xyz + 3 * (size_t)m.tri[3 * f + k];
            ok1 &= in_arc(x, 90, 60);
            ok2 &= in_arc(x, 270, 60);
        }
        sel[f] = ok1 || ok2;
        nsel += sel[f];
    }
    int ne = 0, (*edge)[2] = malloc(sizeof(int[2]) * 3 * (size_t)nsel);
    unsigned char *in = calloc((size_t)m.nn, 1), *shared = calloc((size_t)m.nn, 1);
    for (int f = 0; f < m.nf; f++)
        if (m.tri_tag[f] == g->tag && sel[f])
            for (int k = 0; k < 3; k++) {
                int a = m.tri[3 * f + k], b = m.tri[3 * f + (k + 1) % 3];
                in[a] = 1;
                edge[ne][0] = a < b ? a : b;
                edge[ne++][1] = a < b ? b : a;
            }
    for (int i = 0; i < ne; i++) {
        int cnt = 0;
        for (int j = 0; j < ne; j++) cnt += edge[j][0] == edge[i][0] && edge[j][1] == edge[i][1];
        if (cnt == 1 && !(top[edge[i][0]] && top[edge[i][1]])) shared[edge[i][0]] = shared[edge[i][1]] = 1;
    }
    int want = 0;
    for (int v = 0; v < m.nn; v++) want += in[v] && !shared[v];
    printf("eye (coarse, %d nodes %d tets, meshed in %.1f s): demo plan %d steps, %d duplicated "
           "(independent count %d), cut in %.3f s\n", m.nn, m.ne, t1 - t0, r.nsteps, r.ndup, want, t2 - t1);
    CHECK(r.ndup == want, "eye: %d duplicated, independent count %d", r.ndup, want);
    /* 5 degrees per step; a portion that splits no node (the first, on a coarse ring) merges
     * into the next, so up to 12 steps ending at 60 degrees */
    CHECK(r.nsteps >= 10 && r.nsteps <= 12 && r.step_hi[r.nsteps - 1] == 60 && r.step_lo[0] == 0,
          "eye: steps of 5 degrees over 0-60: %d steps, last %g", r.nsteps, r.step_hi[r.nsteps - 1]);
    /* both arcs advance together, each step about as many nodes on either side */
    for (int s = 0; s < r.nsteps; s++) {
        int n1 = 0, n2 = 0;
        for (int v = m.nn; v < r.cut.nn; v++)
            if (r.step_of[v] == s + 1) {
                if (r.cut.xyz[3 * (size_t)v + 1] > 0) n1++;
                else n2++;
            }
        CHECK(n1 > 0 && n2 > 0 && abs(n1 - n2) <= 1 + (n1 + n2) / 4, "eye step %d: arcs %d and %d", s + 1, n1, n2);
    }
    CHECK_NEAR(total_volume(&r.cut), total_volume(&m), 1e-12, "eye volume");
    /* sides at every duplicated node: tets holding the new node lie outward of the ring,
     * tets keeping the original inward (centroid offset along the ring's outward normal) */
    double *nrm = calloc(3 * (size_t)m.nn, sizeof(double));
    ring_normals(&m, sel, g->tag, nrm);
    int wrong = 0;
    for (int s = 0; s < r.nsteps; s++)
        for (int i = 0; i < r.steps[s].n; i++) {
            const kt_edit *ed = &r.steps[s].edit[i];
            if (ed->kind != KT_EDIT_DUP) continue;
            const double *x = m.xyz + 3 * (size_t)ed->node, *n = nrm + 3 * (size_t)ed->node;
            for (int t = 0; t < r.cut.ne; t++)
                for (int k = 0; k < 4; k++) {
                    int v = r.cut.tet[4 * (size_t)t + k];
                    if (v != ed->node && v != ed->new_node) continue;
                    double c[3];
                    centroid(&r.cut, t, c);
                    double d = (c[0] - x[0]) * n[0] + (c[1] - x[1]) * n[1] + (c[2] - x[2]) * n[2];
                    wrong += (v == ed->new_node) != (d > 0);
                }
        }
    CHECK(wrong == 0, "eye: %d tets on the wrong side of a duplicated node", wrong);
    free(nrm);
    free(top);
    free(sel);
    free(edge);
    free(in);
    free(shared);
done:
    run_free(&r);
    kt_mesh_free(&m);
    free(p);
}

int main(void)
{
    double t = kt_now();
    test_orient3d();
    test_plane_cylinder();
    printf("predicates: %.1f s\n", kt_now() - t);
    t = kt_now();
    test_ring(1);
    test_ring(2);
    printf("rings: %.1f s\n", kt_now() - t);
    t = kt_now();
    test_planar(1);
    test_planar(2);
    test_deform();
    printf("planar and deform: %.1f s\n", kt_now() - t);
    test_eye();
    return kt_test_done("test_incise");
}
