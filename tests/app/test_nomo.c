/* test_nomo.c: inverse planning against closed forms. A synthetic nomogram.tsv where the SIA is
 * linear in arc and in age, SIA = g(age) * arc, g(age) = 0.02 + 0.0002 (age - 60) D/deg for a pair
 * and half of it for one incision; the arc that meets a target is then target / g(age) exactly,
 * between any two simulated arcs and ages, and the residual cylinder is the double-angle sum of
 * the pre-operative cylinder and the SIA. Bad tables are refused with file:line:col. */
#define _XOPEN_SOURCE 700
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "kt_test.h"
#include "lp_choose.h"
#include "nomo.h"

static char dir[64];

static double g(double age, int n) { return (0.02 + 0.0002 * (age - 60)) * (n == 2 ? 1 : 0.5); }

/* The synthetic table: ages 45, 60, 75; a 1.5 D and a 3 D eye at 60 (the 3 D one induces 10%
 * more, so picking the wrong eye shows); arcs 15..90; SIA axis 0 (orthogonal to the 90 axis). */
static const char *write_table(void)
{
    static char path[128];
    snprintf(path, sizeof path, "%s/nomogram.tsv", dir);
    FILE *f = fopen(path, "w");
    fprintf(f, "eye\tage_y\tstiffness\tk_steep_D\tk_flat_D\tcyl_pre_D\taxis_deg\tincisions\tarc_deg"
               "\tdepth\tdiameter_mm\tsia_D\tsia_axis_deg\n");
    const char *eyes[] = {"y45", "y60", "cyl3", "y75"};
    const double ages[] = {45, 60, 60, 75}, cyl[] = {1.5, 1.5, 3, 1.5};
    for (int e = 0; e < 4; e++)
        for (int n = 1; n <= 2; n++)
            for (int arc = 15; arc <= 90; arc += 15)
                fprintf(f, "%s\t%g\t1\t44\t42.5\t%.2f\t90\t%d\t%d\t0.9\t10.5\t%.6f\t0\n", eyes[e],
                        ages[e], cyl[e], n, arc, g(ages[e], n) * arc * (e == 2 ? 1.1 : 1));
    /* a shallower pair on the 60 eye, which the default (deepest) selection must ignore */
    for (int arc = 15; arc <= 90; arc += 15)
        fprintf(f, "y60\t60\t1\t44\t42.5\t1.50\t90\t2\t%d\t0.6\t10.5\t%.6f\t0\n", arc, 0.001 * arc);
    fclose(f);
    return path;
}

static void test_closed_forms(const char *path)
{
    kt_err e = {0};
    kt_nomo t;
    CHECK(kt_nomo_read(&t, path, &e) == KT_OK, "%s", e.msg);
    CHECK(t.n == 4 * 2 * 6 + 6, "%d cases", t.n);
    kt_nomo_answer a[2];
    /* age 66: between 60 and 75, weight 0.4; SIA linear in age, so the interpolation is exact */
    kt_nomo_query q = {44.0, 42.5, 90, 66, 1.5, 0, 0, 0, 0};
    CHECK(kt_nomo_plan(&t, &q, a, &e) == KT_OK, "%s", e.msg);
    double g2 = 0.6 * g(60, 2) + 0.4 * g(75, 2);
    CHECK(a[1].incisions == 2 && a[1].reached, "pair reached");
    CHECK_NEAR(a[1].arc, 1.5 / g2, 1e-9, "pair arc = target / g(age)");
    CHECK_NEAR(a[1].sia, 1.5, 1e-12, "pair SIA = target");
    CHECK_NEAR(a[1].residual, 0, 1e-9, "pair residual: the whole cylinder corrected");
    CHECK(a[1].age_lo == 60 && a[1].age_hi == 75, "ages %g-%g", a[1].age_lo, a[1].age_hi);
    CHECK(a[1].depth == 0.9 && a[1].diameter == 10.5, "deepest depth, most frequent diameter");
    /* one incision: g1 * 90 = 0.8 D < 1.5 D, not reached; residual 1.5 - SIA(90) */
    double g1 = 0.6 * g(60, 1) + 0.4 * g(75, 1);
    CHECK(a[0].incisions == 1 && !a[0].reached, "single not reached");
    CHECK_NEAR(a[0].arc, 90, 1e-12, "single: the longest arc");
    CHECK_NEAR(a[0].sia, g1 * 90, 1e-9, "single: its SIA");
    CHECK_NEAR(a[0].residual, 1.5 - g1 * 90, 1e-9, "single: residual |pre + SIA|");
    CHECK_NEAR(a[0].residual_axis, 90, 1e-9, "single: residual stays at the steep axis");

    /* a 3 D eye at 60 y: the 3 D simulated eye is the one used (10% more SIA) */
    kt_nomo_query q3 = {45.0, 42.0, 90, 60, 1.2, 0, 0, 0, 0};
    CHECK(kt_nomo_plan(&t, &q3, a, &e) == KT_OK, "%s", e.msg);
    CHECK_NEAR(a[1].arc, 1.2 / (1.1 * g(60, 2)), 1e-9, "3 D: the 3 D eye's curve");
    CHECK(a[1].age_lo == 60 && a[1].age_hi == 60, "one age");

    /* an oblique eye (axis 30) with a partial target: the SIA axis turns with the incisions
     * (0 - 90 + 30 = 120 deg); residual = 2 D @ 30 + 1 D @ 120 = 1 D @ 30 */
    kt_nomo_query qo = {44.0, 42.0, 30, 60, 1.0, 0, 0, 0, 0};
    CHECK(kt_nomo_plan(&t, &qo, a, &e) == KT_OK, "%s", e.msg);
    CHECK_NEAR(a[1].arc, 1.0 / g(60, 2), 1e-9, "oblique: arc");
    CHECK_NEAR(a[1].residual, 1.0, 1e-9, "oblique: residual magnitude");
    CHECK_NEAR(a[1].residual_axis, 30, 1e-6, "oblique: residual axis");

    /* depth 0.6: only the 60 y eye has it, so age 30 clamps to 60 y */
    kt_nomo_query qy = {44.0, 43.0, 90, 30, 0.05, 0.6, 0, 0, 0};
    CHECK(kt_nomo_plan(&t, &qy, a, &e) == KT_OK, "%s", e.msg);
    CHECK(a[1].age_lo == 60 && a[1].age_hi == 60, "clamped to 60");
    CHECK(a[0].incisions == 0, "no single at depth 0.6");
    CHECK_NEAR(a[1].arc, 50, 1e-9, "depth 0.6: 0.05 D / 0.001 D/deg");
    CHECK(a[1].arc_lo == 45 && a[1].arc_hi == 60, "between 45 and 60");

    /* below the table's ages: clamped to 45 y */
    kt_nomo_query qc = {44.0, 42.5, 90, 30, 1.0, 0, 0, 0, 0};
    CHECK(kt_nomo_plan(&t, &qc, a, &e) == KT_OK, "%s", e.msg);
    CHECK(a[1].age_lo == 45 && a[1].age_hi == 45, "clamped to 45");
    CHECK_NEAR(a[1].arc, 1.0 / g(45, 2), 1e-9, "45 y arc");

    /* bad queries */
    kt_nomo_query qb = {42.0, 44.0, 90, 60, 1, 0, 0, 0, 0};
    CHECK(kt_nomo_plan(&t, &qb, a, &e) == KT_EINPUT, "steep < flat refused");
    kt_nomo_query qd = {44.0, 42.5, 90, 60, 1, 0.3, 0, 0, 0};
    e.code = 0;
    CHECK(kt_nomo_plan(&t, &qd, a, &e) == KT_EINPUT && strstr(e.msg, "no case"), "%s", e.msg);
    kt_nomo_free(&t);
}

static void expect_refused(const char *body, const char *where)
{
    char path[128];
    snprintf(path, sizeof path, "%s/bad.tsv", dir);
    FILE *f = fopen(path, "w");
    fputs(body, f);
    fclose(f);
    kt_err e = {0};
    kt_nomo t;
    CHECK(kt_nomo_read(&t, path, &e) == KT_EINPUT && strstr(e.msg, where), "%s: %s", where, e.msg);
    CHECK(t.c == NULL && t.n == 0, "nothing kept");
}

static void test_bad_tables(void)
{
    const char *h = "eye\tage_y\tcyl_pre_D\taxis_deg\tincisions\tarc_deg\tdepth\tdiameter_mm\tsia_D"
                    "\tsia_axis_deg\n";
    char b[1024];
    expect_refused("eye\tage_y\n", "bad.tsv:1:1: expected a header with column cyl_pre_D");
    snprintf(b, sizeof b, "%sa\t60\t1.5\t90\t3\t60\t0.9\t10.5\t1\t0\n", h);
    expect_refused(b, "bad.tsv:2:13: expected incisions 1 or 2");
    snprintf(b, sizeof b, "%sa\t60\t1.5\t90\t2\t60\t0.9\t10.5\tx\t0\n", h);
    expect_refused(b, "bad.tsv:2:27: expected a number in column sia_D");
    snprintf(b, sizeof b, "%sa\t60\t1.5\t90\t2\n", h);
    expect_refused(b, "bad.tsv:2:");
    expect_refused(h, "bad.tsv:2:1: expected a case");
}

/* The main incision's SIA vector: 1.5 D @ 90 plus 0.5 D @ 0 is 1.0 D @ 90, so the answer is
 * the one for a 1.0 D eye at 90 without it; an oblique SIA turns the axis the arcs are centred
 * on (1.5 @ 90 + 1.5 @ 45: 2.12 D @ 67.5). */
static void test_main_sia(const char *path)
{
    kt_err e = {0};
    kt_nomo t;
    CHECK(kt_nomo_read(&t, path, &e) == KT_OK, "%s", e.msg);
    kt_nomo_query qs = {44.0, 42.5, 90, 66, 1.0, 0, 0, 0.5, 0}, q1 = {43.5, 42.5, 90, 66, 1.0, 0, 0, 0, 0};
    double ax, pre = kt_nomo_pre(&qs, &ax);
    CHECK(fabs(pre - 1.0) < 1e-12 && fabs(ax - 90) < 1e-9, "1.5 @ 90 + 0.5 @ 0 = %.15g @ %.15g", pre, ax);
    kt_nomo_answer a[2], b[2];
    CHECK(kt_nomo_plan(&t, &qs, a, &e) == KT_OK && kt_nomo_plan(&t, &q1, b, &e) == KT_OK, "%s", e.msg);
    for (int n = 0; n < 2; n++)
        CHECK(fabs(a[n].arc - b[n].arc) < 1e-9 && fabs(a[n].residual - b[n].residual) < 1e-9,
              "%d incisions: with the SIA vector %.4f deg / %.4f D, as the 1.0 D eye %.4f deg / %.4f D", n + 1, a[n].arc,
              a[n].residual, b[n].arc, b[n].residual);
    kt_nomo_query qo = {44.0, 42.5, 90, 66, 0, 0, 0, 1.5, 45};
    pre = kt_nomo_pre(&qo, &ax);
    CHECK(fabs(pre - 1.5 * sqrt(2)) < 1e-12 && fabs(ax - 67.5) < 1e-9, "1.5 @ 90 + 1.5 @ 45 = %.15g @ %.15g", pre, ax);
    double lo, hi;
    kt_nomo_ages(&t, &lo, &hi);
    CHECK(lo == 45 && hi == 75, "the table's ages %g-%g", lo, hi);
    kt_nomo_free(&t);
}

/* The surgeon's SIA means the same in lri-nomogram and lri-plan (keratome-patient(5), sia): a
 * steepening at its axis, added by double-angle sum. kt_nomo_pre against the planner's sum
 * (lp_choose's kt_lp_astig_add, which lri-plan adds the patient's sia with), axes 0 and 180 the
 * same. */
static void test_sia_as_lri_plan(void)
{
    static const double v[][4] = {/* K cylinder D, its axis, SIA D, its axis */
                                  {1.5, 90, 0.5, 0},  {1.5, 90, 0.5, 180}, {1.5, 0, 0.3, 90}, {1.5, 180, 0.3, 90},
                                  {1.0, 30, 0.4, 120}, {1.0, 30, 1.0, 120}, {2.0, 178, 0.3, 2}, {0.8, 45, 0.6, 135},
                                  {1.2, 10, 0.5, 60}};
    for (size_t i = 0; i < sizeof v / sizeof v[0]; i++) {
        kt_nomo_query q = {44.0 + v[i][0], 44.0, v[i][1], 66, NAN, 0, 0, v[i][2], v[i][3]};
        double ax, pre = kt_nomo_pre(&q, &ax);
        kt_astig s = kt_lp_astig_add((kt_astig){v[i][0], v[i][1]}, (kt_astig){v[i][2], v[i][3]});
        double d = fmod(fabs(ax - s.axis), 180);
        d = fmin(d, 180 - d);
        CHECK(fabs(pre - s.mag) < 1e-12 && (s.mag < 1e-9 || d < 1e-9),
              "%g @ %g + SIA %g @ %g: lri-nomogram %.12g @ %.9g, lri-plan %.12g @ %.9g", v[i][0], v[i][1], v[i][2],
              v[i][3], pre, ax, s.mag, s.axis);
    }
}

int main(void)
{
    snprintf(dir, sizeof dir, "/tmp/kt_nomo_XXXXXX");
    if (!mkdtemp(dir)) return 1;
    test_closed_forms(write_table());
    test_main_sia(write_table());
    test_bad_tables();
    test_sia_as_lri_plan();
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
    if (system(cmd) != 0) return 1;
    return kt_test_done("test_nomo");
}
