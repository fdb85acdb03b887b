/* test_clearance.c: an arc's clearance from a wound against the closed forms of a footprint that
 * spans the zone circle (the distance from the circle's point at angle D from the wound's
 * meridian to the footprint's long side is R sin D - width / 2; the circle runs inside it over
 * 2 asin(width / 2R)), the longest clear arcs of single and paired families, and the main
 * incision of issue 34's ATR eye (OD, temporal 2.2 mm) against arcs on its own meridian. */
#include <math.h>
#include <string.h>

#include "clearance.h"
#include "kt_test.h"
#include "scene.h"

#define R 5.25  /* the default zone, 10.5 mm */
#define HW 1.2  /* half a 2.4 mm incision */
#define ZONE ((kt_zone){R, R}) /* the zone as a circle */
#define DEG (180 / KT_PI)

static kt_footprint strip(double meridian)
{
    kt_footprint w = {meridian, 2 * HW, 0.1 * R, 2 * R, "the main incision"};
    return w;
}

/* The closed form: the clearance of an arc whose nearer end is D deg from the wound. */
static double apart(double D) { return (R * sin(D / DEG) - HW) / R * DEG; }

static void test_clearance(void)
{
    kt_footprint w = strip(0);
    CHECK_NEAR(kt_clearance(&w, 90, 90, ZONE), apart(45), 0.02, "90 deg arc at 90: ends 45 deg from the wound");
    CHECK_NEAR(kt_clearance(&w, 120, 60, ZONE), apart(90), 0.02, "60 deg arc at 120: end at 90 deg");
    double in = 2 * asin(HW / R) * DEG;
    CHECK_NEAR(kt_clearance(&w, 0, 60, ZONE), -in, 0.02, "an arc across the wound: minus the degrees inside");
    CHECK_NEAR(kt_clearance(&w, 20, 30, ZONE), -(asin(HW / R) * DEG - 5), 0.02, "an arc into the wound's side");
    kt_footprint w2 = strip(350);
    CHECK_NEAR(kt_clearance(&w2, 10, 20, ZONE), -(asin(HW / R) * DEG - 10), 0.02, "wraps through 0 deg");
    (void)in;
    CHECK(isnan(kt_clearance(&w, 0, 60, (kt_zone){0, 0})), "a zero radius is NaN");
    CHECK(isnan(kt_clearance(&w, NAN, 60, ZONE)), "a NaN centre is NaN");
    /* a footprint short of the zone: the distance to its inner end */
    kt_footprint s = {0, 2 * HW, R + 0.5, R + 1.5, "a side port"};
    CHECK_NEAR(kt_clearance(&s, 90, 60, ZONE), hypot(R + 0.5 - R * cos(60 / DEG), R * sin(60 / DEG) - HW) / R * DEG, 0.02,
               "footprint outside the zone circle");
}

static void test_clear_arc(void)
{
    kt_footprint w = strip(0);
    int k;
    double b = asin((HW + R * 15 / DEG) / R) * DEG; /* 15 deg clear of the wound */
    CHECK_NEAR(kt_clear_arc(&w, 1, 60, 120, ZONE, 15, &k), 2 * (60 - b), 1e-3, "trimmed at 15 deg clearance");
    CHECK(k == 0, "limited by wound 0, got %d", k);
    CHECK_NEAR(kt_clearance(&w, 60, 2 * (60 - b), ZONE), 15, 0.02, "the trimmed arc keeps exactly 15 deg");
    CHECK(kt_clear_arc(&w, 1, 90, 90, ZONE, 15, &k) == 90 && k == -1, "a clear arc keeps max");
    CHECK(kt_clear_arc(&w, 1, 5, 90, ZONE, 15, &k) == 0 && k == 0, "a centre within the clearance: none");
    CHECK(isnan(kt_clear_arc(&w, 1, 5, 90, ZONE, -1, &k)), "a negative clearance is NaN");
    kt_footprint two[2] = {strip(0), strip(150)};
    two[1].name = "the side port";
    double b2 = asin((HW + R * 15 / DEG) / R) * DEG;
    CHECK_NEAR(kt_clear_arc(two, 2, 90, 120, ZONE, 15, &k), 2 * (60 - b2), 1e-3, "the nearer of two wounds limits");
    CHECK(k == 1, "the side port at 150 limits, got %d", k);
}

static void test_family(void)
{
    kt_footprint w = strip(180);
    kt_clear_result r;
    kt_clear_family(&w, 1, 90, 1, 1, 90, ZONE, 15, &r);
    CHECK(r.arc == 90 && !r.trimmed && r.reason[0] == 0, "a pair across the wound's meridian is clear");
    kt_clear_family(&w, 1, 0, 0, 1, 90, ZONE, 15, &r);
    CHECK(r.arc == 90 && !r.trimmed, "a single arc opposite the wound is clear");
    kt_clear_family(&w, 1, 0, 1, 1, 90, ZONE, 15, &r);
    CHECK(r.arc == 0 && r.opposite && r.wound == 0, "a pair whose opposite arc lies on the wound: none");
    CHECK(strstr(r.reason, "the main incision at 180 deg") != NULL, "reason: %s", r.reason);
    CHECK(r.at_max < 0, "at max the pair crosses: %g", r.at_max);
    /* an unequal pair: the opposite arc half as long, 30 deg from the wound's meridian */
    kt_footprint u = strip(270);
    double b = asin((HW + R * 15 / DEG) / R) * DEG;
    kt_clear_family(&u, 1, 60, 1, 0.5, 90, ZONE, 15, &r);
    CHECK_NEAR(r.arc, 2 * (30 - b) / 0.5, 1e-3, "the opposite arc limits an unequal pair, in its ratio");
    CHECK(r.opposite == 1 && r.trimmed == 1, "opposite %d trimmed %d", r.opposite, r.trimmed);
}

/* Issue 34's ATR eye: OD, temporal (180 deg) clear-corneal 2.2 mm, the default eye. */
static void test_atr(void)
{
    kt_scene s;
    kt_err e = {0};
    CHECK(kt_scene_load("plans/eye.yaml", &s, &e) == KT_OK, "plans/eye.yaml: %s", e.msg);
    kt_tunnel t = {0};
    t.meridian = 180, t.width = 2.2, t.length = KT_TUNNEL_LENGTH, t.entry_diameter = s.eye.wtw, t.steps = 4;
    const char *field;
    char msg[400];
    CHECK(kt_tunnel_derive(&s.eye, &t, &field, msg, sizeof msg) == KT_OK, "tunnel: %s", msg);
    kt_footprint w;
    kt_footprint_of_tunnel(&t, "the main incision", &w);
    CHECK(w.r_out > R && w.r_in < R, "the tunnel spans the 10.5 mm zone: %g-%g mm", w.r_in, w.r_out);
    kt_clear_result r;
    kt_clear_family(&w, 1, 0, 1, 1, 90, ZONE, KT_CLEARANCE_DEG, &r);
    CHECK(r.arc == 0, "the ATR pair at 0/180 is left out: %g", r.arc);
    kt_clear_family(&w, 1, 0, 0, 1, 90, ZONE, KT_CLEARANCE_DEG, &r);
    CHECK(r.arc == 90, "the single arc at 0 (nasal) keeps 90 deg: %g", r.arc);
    CHECK(kt_clearance(&w, 0, 90, ZONE) > 60, "and stays far from the wound: %g deg", kt_clearance(&w, 0, 90, ZONE));
}

/* The zone of an oval cornea: an ellipse of semi-axes 5.25 and 4.70 mm (the default eye's ring).
 * A superior wound: the longest clear arc's end keeps exactly the clearance at the ellipse's
 * radius there, and is shorter than on the circle (the ring runs 0.55 mm further in above). */
static void test_oval(void)
{
    kt_zone oval = {R, R - 0.55};
    kt_footprint w = {90, 2 * HW, 3.5, 5.3, "the main incision"};
    int k;
    double a_oval = kt_clear_arc(&w, 1, 0, 180, oval, 15, &k), a_circ = kt_clear_arc(&w, 1, 0, 180, ZONE, 15, &k);
    double th = 0.5 * a_oval / DEG, c = cos(th), s = sin(th);
    double rho = oval.rx * oval.ry / hypot(oval.ry * c, oval.rx * s), x = rho * c, y = rho * s;
    /* distance to the footprint (x across it, y along it from 3.5 to 5.3 mm) */
    double d = hypot(fmax(fabs(x) - HW, 0), fmax(fmax(3.5 - y, y - 5.3), 0));
    CHECK(fabs(d / rho * DEG - 15) < 1e-3, "the oval arc's end keeps 15 deg at its own radius (%.4f deg, %.3f mm there)",
          d / rho * DEG, rho);
    CHECK(a_oval < a_circ - 1, "shorter than on the circle: %.2f against %.2f deg", a_oval, a_circ);
    CHECK(fabs(kt_clearance(&w, 0, a_oval, oval) - 15) < 0.02, "kt_clearance agrees: %g", kt_clearance(&w, 0, a_oval, oval));
    CHECK(isnan(kt_clearance(&w, 0, INFINITY, oval)), "an infinite arc is NaN");
    /* an untrimmed opposite arc of a short ratio is max exactly, not trimmed by an ulp */
    kt_footprint far = {90, 2 * HW, 3.5, 5.3, "a wound"};
    kt_clear_result r;
    kt_clear_family(&far, 1, 0, 1, 0.05, 43, ZONE, 15, &r);
    CHECK(r.arc == 43 && !r.trimmed && r.reason[0] == 0, "ratio 0.05, max 43: untrimmed (%.17g, %d)", r.arc, r.trimmed);
}

int main(void)
{
    test_clearance();
    test_oval();
    test_clear_arc();
    test_family();
    test_atr();
    return kt_test_done("test_clearance");
}
