/* test_choose.c: the planner's choice (lib/planner/lp_choose.h) on synthetic per-step readings
 * (no mesh, no solve): each family's best step is its least predicted residual (the first of
 * equal ones); the least residual wins, fewer incisions within 0.01 D (families are tried single
 * first); a family that did not run is never chosen; the prediction adds the surgeon's SIA
 * vector and reads the target's kind; the simulated main incision's SIA is the step after its
 * tunnel against the intact eye; the chosen arcs as the surgeon marks them. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "kt_test.h"
#include "lp_choose.h"

/* A family's residuals falling linearly to `low` at step `at`, rising after. */
static void curve(kt_astig *p, int n, double low, int at)
{
    for (int k = 0; k <= n; k++) p[k].mag = low + 0.05 * fabs((double)(k - at)), p[k].axis = 90;
}

static void decision(void)
{
    static kt_astig pred[KT_LP_NFAM][KT_LP_MAXSTEP + 1];
    int ran[3] = {1, 1, 1}, nstep[3] = {18, 18, 18}, best[3];
    curve(pred[0], 18, 0.30, 12), curve(pred[1], 18, 0.295, 8), curve(pred[2], 18, 0.5, 5);
    int c = kt_lp_choose_best(3, ran, nstep, (const kt_astig(*)[KT_LP_MAXSTEP + 1])pred, best);
    CHECK(best[0] == 12 && best[1] == 8 && best[2] == 5, "best steps %d %d %d", best[0], best[1], best[2]);
    CHECK(c == 0, "0.295 D paired against 0.300 D single: within 0.01 D, the single arc (%d)", c);
    curve(pred[1], 18, 0.28, 8);
    c = kt_lp_choose_best(3, ran, nstep, (const kt_astig(*)[KT_LP_MAXSTEP + 1])pred, best);
    CHECK(c == 1, "0.28 D paired against 0.30 D single: the pair (%d)", c);
    curve(pred[2], 18, 0.275, 5);
    c = kt_lp_choose_best(3, ran, nstep, (const kt_astig(*)[KT_LP_MAXSTEP + 1])pred, best);
    CHECK(c == 1, "0.275 D unequal against 0.28 D paired: within 0.01 D, the equal pair (%d)", c);
    curve(pred[2], 18, 0.2, 5);
    c = kt_lp_choose_best(3, ran, nstep, (const kt_astig(*)[KT_LP_MAXSTEP + 1])pred, best);
    CHECK(c == 2, "0.20 D unequal: chosen (%d)", c);
    ran[2] = 0;
    c = kt_lp_choose_best(3, ran, nstep, (const kt_astig(*)[KT_LP_MAXSTEP + 1])pred, best);
    CHECK(c == 1, "a family that did not run (trimmed out) is never chosen (%d)", c);
    ran[0] = ran[1] = 0;
    CHECK(kt_lp_choose_best(3, ran, nstep, (const kt_astig(*)[KT_LP_MAXSTEP + 1])pred, best) == -1, "none ran: none");
    /* equal residuals: the first step; a lower one by 1e-12 D is no lower */
    ran[0] = 1;
    for (int k = 0; k <= 18; k++) pred[0][k].mag = k < 4 ? 1 - 0.2 * k : 0.4 - 1e-12 * k;
    kt_lp_choose_best(1, ran, nstep, (const kt_astig(*)[KT_LP_MAXSTEP + 1])pred, best);
    CHECK(best[0] == 3, "the first of equal residuals (%d)", best[0]);
    /* NaN readings: never the best step, never the chosen family; none finite: none */
    ran[0] = ran[1] = 1, ran[2] = 0;
    curve(pred[0], 18, 0.30, 12), curve(pred[1], 18, 0.2, 8);
    pred[0][0].mag = NAN, pred[1][8].mag = NAN;
    c = kt_lp_choose_best(2, ran, nstep, (const kt_astig(*)[KT_LP_MAXSTEP + 1])pred, best);
    CHECK(best[0] == 12 && best[1] == 7, "a NaN at step 0 or at the minimum is passed over (%d %d)", best[0], best[1]);
    CHECK(c == 1, "and the family with the least finite residual chosen (%d)", c);
    for (int k = 0; k <= 18; k++) pred[1][k].mag = NAN;
    c = kt_lp_choose_best(2, ran, nstep, (const kt_astig(*)[KT_LP_MAXSTEP + 1])pred, best);
    CHECK(c == 0, "a family with no finite residual does not compete (%d)", c);
    for (int k = 0; k <= 18; k++) pred[0][k].mag = NAN;
    CHECK(kt_lp_choose_best(2, ran, nstep, (const kt_astig(*)[KT_LP_MAXSTEP + 1])pred, best) == -1, "no finite residual: none");
}

/* The whole stage on synthetic runs: a surgeon's vector, both target kinds, the main incision. */
static void stage(void)
{
    static kt_lp_eye eye;
    static kt_lp_families fam;
    static kt_lp_runs runs;
    static kt_lp_choice ch;
    memset(&eye, 0, sizeof eye), memset(&fam, 0, sizeof fam), memset(&runs, 0, sizeof runs);
    eye.p.main_present = 1, eye.p.main_simulate = 0, eye.p.main_sia = 0.4, eye.p.main_sia_axis = 0;
    eye.p.target_kind = KT_TARGET_KERATOMETRIC;
    fam.n = 1;
    kt_lp_run *r = &runs.r[0];
    r->ran = 1, r->nstep = 4;
    r->kerato_intact = (kt_astig){1.0, 90};
    for (int k = 0; k <= 4; k++) r->kerato[k] = (kt_astig){1.0 - 0.3 * k, 90}, r->total[k] = (kt_astig){0.9 - 0.3 * k, 90};
    kt_lp_choose(&eye, &fam, &runs, &ch);
    /* 1.0 - 0.3 k D at 90 plus 0.4 D at 0 (opposite in double angle): 0.6 - 0.3 k */
    CHECK(ch.chosen == 0 && ch.best[0] == 2, "with the surgeon's 0.4 D at 0 deg, 0.4 D of arcs' share is left: step %d", ch.best[0]);
    CHECK_NEAR(ch.pred[0][2].mag, 0.0, 1e-12, "its residual");
    CHECK_NEAR(ch.pre_kerato.mag, 0.6, 1e-12, "pre-op keratometric with the surgeon's SIA");
    eye.p.target_kind = KT_TARGET_TOTAL;
    kt_lp_choose(&eye, &fam, &runs, &ch);
    CHECK(ch.best[0] == 2 && fabs(ch.pred[0][2].mag - 0.1) < 1e-12, "total target: 0.5 - 0.3 k -> step 2, 0.1 D");
    /* a simulated main incision: no vector added; its SIA from the tunnel's steps */
    eye.p.main_simulate = 1, r->skip = 4, r->kerato_intact = (kt_astig){1.2, 90};
    kt_lp_choose(&eye, &fam, &runs, &ch);
    CHECK(ch.main_vec.mag == 0, "simulated: nothing added");
    CHECK_NEAR(ch.main_sia_kerato.mag, 0.2, 1e-12, "the simulated SIA: arc step 0 against the intact eye");
}

static void marks(void)
{
    static kt_lp_answer a;
    memset(&a, 0, sizeof a);
    a.eye.p.zone = 10.5;
    a.eye.p.wtw = a.eye.p.wtw_v = 11.7; /* round: the chord is the circle's */
    a.eye.p.ant.source = KT_SOURCE_KERATOMETRY, a.eye.p.ant.r_steep = a.eye.p.ant.r_flat = 7.7;
    a.eye.p.post.r_steep = a.eye.p.post.r_flat = 6.5, a.eye.p.t_central = 0.55;
    a.fam.n = 1, a.fam.f[0].paired = 1, a.fam.f[0].meridian = 95, a.fam.f[0].ratio = 1;
    a.trim.t[0].meridian = 95, a.trim.t[0].nstep = 10; /* the centre as cut is the trim's */
    a.run.r[0].ran = 1, a.run.r[0].nstep = 10;
    for (int k = 0; k <= 10; k++) a.run.r[0].arc[k] = a.run.r[0].arc_opp[k] = 5 * k;
    a.choice.chosen = 0, a.choice.best[0] = 10;
    kt_lp_arc arcs[2];
    int n = kt_lp_arcs(&a, arcs);
    CHECK(n == 2, "a pair: two arcs");
    CHECK(arcs[0].from == 120 && arcs[0].to == 70 && arcs[1].from == 300 && arcs[1].to == 250, "end points, clockwise");
    CHECK(strcmp(arcs[0].from_clock, "11:00") == 0 && strcmp(arcs[0].to_clock, "12:40") == 0, "clock %s to %s (clockwise)",
          arcs[0].from_clock, arcs[0].to_clock);
    CHECK_NEAR(arcs[0].chord, 10.5 * sin(25 * M_PI / 180), 1e-9, "chord at the zone (round)");
    a.eye.p.wtw_v = 10.6; /* oval: the zone follows the cornea, narrower across the vertical meridian */
    kt_lp_arcs(&a, arcs);
    CHECK(arcs[0].chord < 10.5 * sin(25 * M_PI / 180) - 1e-3, "chord at 95 deg on the oval zone %g below the circle's",
          arcs[0].chord);
    a.eye.p.wtw_v = 11.7;
    a.trim.t[0].meridian = 275, a.trim.t[0].moved = 1; /* on the other half: the arcs follow the trim */
    kt_lp_arcs(&a, arcs);
    CHECK(arcs[0].centre == 275 && arcs[0].from == 300 && arcs[1].centre == 95, "the trim's centre: %g, %g", arcs[0].centre,
          arcs[1].centre);
    a.choice.best[0] = 0;
    CHECK(kt_lp_arcs(&a, arcs) == 0, "no arc at step 0");
}

/* A residual that misses the target never prints as equal to it. */
static void digits(void)
{
    char r[32], t[32];
    const double cases[][3] = {{0.503, 0.5, 3}, {0.5004, 0.5, 4}, {0.5, 0.5, 2}, {0.49, 0.5, 2}, {0.4996, 0.5, 2},
                               {0.62, 0.5, 2}, {0.25001, 0.25, 4}};
    for (int i = 0; i < (int)(sizeof cases / sizeof cases[0]); i++) {
        int d = kt_lp_res_digits(cases[i][0], cases[i][1]);
        CHECK(d == (int)cases[i][2], "%g against %g: %d decimals, expected %g", cases[i][0], cases[i][1], d, cases[i][2]);
        snprintf(r, sizeof r, "%.*f", d, cases[i][0]), snprintf(t, sizeof t, "%.*f", d, cases[i][1]);
        if (cases[i][0] > cases[i][1] && d < 4)
            CHECK(strcmp(r, t) != 0, "a miss printed as the target: %s against %s", r, t);
    }
}

int main(void)
{
    decision();
    stage();
    marks();
    digits();
    return kt_test_done("test_choose");
}
