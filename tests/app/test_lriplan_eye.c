/* test_lriplan_eye.c: plan.html's eye drawing (lib/app/lriplan_eye.h). For every eye, view,
 * main incision site and arc plan on a grid (single, paired and unequal arcs centred every 15 deg,
 * 10 to 90 deg long, kept 15 deg clear of the main incision as the planner keeps them), no two
 * labels' text boxes meet and every box lies inside the drawing; each end point's label is
 * written, "from" before "to". The views turn, never mirror: the side the surgeon sits on is at
 * the bottom. The box estimate is checked against DejaVu Sans's advance widths. */
#define _XOPEN_SOURCE 700
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "kt_test.h"
#include "lriplan_eye.h"

static kt_lp_arc arc_at(double centre, double arc)
{
    kt_lp_arc q;
    memset(&q, 0, sizeof q);
    q.centre = fmod(centre + 360, 360), q.arc = arc;
    q.from = fmod(centre + arc / 2 + 360, 360), q.to = fmod(centre - arc / 2 + 360, 360);
    kt_lp_clock(q.from, q.from_clock), kt_lp_clock(q.to, q.to_clock);
    return q;
}

/* The least angle between meridian m and the arc q, deg (0 when m is on it). */
static double gap(const kt_lp_arc *q, double m)
{
    double d = fabs(fmod(m - q->centre + 540, 360) - 180);
    return d <= q->arc / 2 ? 0 : d - q->arc / 2;
}

static int n_draw, n_meet, n_out, n_order;

static void draw(const kt_patient *p, const kt_lp_arc *arcs, int narc, int view)
{
    kt_lri_labels lab;
    FILE *f = fopen("/dev/null", "w");
    kt_lri_eye_svg(f, p, arcs, narc, view, &lab);
    fclose(f);
    n_draw++;
    for (int i = 0; i < lab.n; i++) {
        const kt_lri_box *b = &lab.b[i];
        if (b->x0 < 0 || b->y0 < 0 || b->x1 > 520 || b->y1 > 520) {
            if (n_out++ < 3) fprintf(stderr, "outside: '%s'\n", lab.text[i]);
        }
        for (int j = i + 1; j < lab.n; j++)
            if (kt_lri_box_meet(b, &lab.b[j]) && n_meet++ < 3)
                fprintf(stderr, "meet: '%s' and '%s' (eye %d view %d, arc %g at %g, %d arcs)\n", lab.text[i], lab.text[j],
                        p->eye, view, arcs[0].arc, arcs[0].centre, narc);
    }
    int from = 0, to = 0;
    for (int i = 0; i < lab.n; i++) {
        if (strstr(lab.text[i], "from ")) from++;
        if (strstr(lab.text[i], "to ") && from > to) to++;
    }
    if (from != narc || to != narc) n_order++;
}

static void test_grid(void)
{
    static const char *sites[] = {"temporal", "superotemporal", "superior"};
    kt_patient p;
    memset(&p, 0, sizeof p);
    p.wtw = 11.7, p.wtw_v = 10.6, p.zone = 10.5, p.ant.axis = 95;
    for (int eye = 0; eye < 2; eye++)
        for (int site = 0; site < 4; site++) {
            p.eye = eye, p.main_present = site < 3, p.main_width = 2.4;
            p.main_meridian = site < 3 ? kt_patient_site(eye, sites[site]) : 0;
            double half = 0.5 * p.main_width / (0.5 * p.wtw - 0.3) * 180 / M_PI;
            for (int view = 0; view < 3; view++)
                for (double c = 0; c < 360; c += 15)
                    for (double arc = 10; arc <= 90; arc += 20)
                        for (int kind = 0; kind < 3; kind++) {
                            kt_lp_arc q[2] = {arc_at(c, arc), arc_at(c + 180, kind == 2 ? 0.6 * arc : arc)};
                            int n = kind ? 2 : 1, clear = 1;
                            for (int i = 0; i < n && p.main_present; i++) clear &= gap(&q[i], p.main_meridian) >= 15 + half;
                            if (clear) draw(&p, q, n, view);
                        }
        }
    CHECK(n_draw > 3000, "%d drawings", n_draw);
    CHECK(n_meet == 0, "%d pairs of labels meet", n_meet);
    CHECK(n_out == 0, "%d labels outside the drawing", n_out);
    CHECK(n_order == 0, "%d drawings without one 'from' then one 'to' per arc", n_order);
}

static void test_view(void)
{
    /* the side the surgeon sits on goes to the bottom (screen 270 deg) */
    CHECK_NEAR(fmod(kt_patient_site(KT_EYE_OD, "temporal") + kt_lri_view_turn(KT_LRI_VIEW_TEMPORAL, KT_EYE_OD), 360), 270, 0,
               "OD temporal at the bottom");
    CHECK_NEAR(fmod(kt_patient_site(KT_EYE_OS, "temporal") + kt_lri_view_turn(KT_LRI_VIEW_TEMPORAL, KT_EYE_OS), 360), 270, 0,
               "OS temporal at the bottom");
    CHECK_NEAR(fmod(90 + kt_lri_view_turn(KT_LRI_VIEW_SUPERIOR, KT_EYE_OD), 360), 270, 0, "superior at the bottom");
    CHECK_NEAR(kt_lri_view_turn(KT_LRI_VIEW_EXAMINER, KT_EYE_OS), 0, 0, "the examiner's: TABO as it is");
    CHECK(KT_LRI_VIEW_DEFAULT == KT_LRI_VIEW_TEMPORAL && strcmp(kt_lri_view_name(KT_LRI_VIEW_DEFAULT), "temporal") == 0,
          "the default view is temporal");
}

static void test_box(void)
{
    /* "120°" at 12 px: three digits of 0.636 em and the degree sign's 0.5 em (DejaVu Sans) are
     * 32.3 px; the estimate is at least that, and not 20% over */
    kt_lri_box b = kt_lri_text_box("120\xC2\xB0", 12, 0, 100, 50, 'm');
    double w = b.x1 - b.x0, real = 12 * (3 * 0.636 + 0.5);
    CHECK(w >= real && w <= 1.2 * real, "width %g against %g px", w, real);
    CHECK_NEAR(0.5 * (b.x0 + b.x1), 100, 1e-12, "middle anchor");
    CHECK(b.y0 < 50 - 0.9 * 12 && b.y1 > 50 + 0.2 * 12, "ascent and descent");
    kt_lri_box c = b;
    c.x0 = b.x1, c.x1 = b.x1 + 10;
    CHECK(!kt_lri_box_meet(&b, &c) && kt_lri_box_meet(&b, &b), "touching is not meeting");
}

int main(void)
{
    test_box();
    test_view();
    test_grid();
    return kt_test_done("test_lriplan_eye");
}
