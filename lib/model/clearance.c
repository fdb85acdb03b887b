/* clearance.c: an arc's clearance from the eye's through-incisions, and the longest arcs that
 * keep it (clearance.h). The arc is sampled every 0.01 deg (SAMPLE): the clearance is exact to
 * about that, and the longest arc is found by stepping out from its centre at that resolution
 * and bisecting the first step that comes too close. */
#include "clearance.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#define SAMPLE 0.01 /* deg */
#define RAD (KT_PI / 180)

void kt_footprint_of_tunnel(const kt_tunnel *t, const char *name, kt_footprint *w)
{
    w->meridian = t->meridian, w->width = t->width, w->name = name;
    double ri = hypot(t->exit[0], t->exit[1]), re = hypot(t->entry[0], t->entry[1]);
    w->r_in = fmin(ri, re), w->r_out = fmax(ri, re);
}

/* Distance (mm) from the point of the circle of radius R at angle th (deg) to the footprint. */
static double dist(const kt_footprint *w, double th, double R)
{
    double a = (th - w->meridian) * RAD, u = R * cos(a), v = R * sin(a);
    double du = fmax(fmax(w->r_in - u, u - w->r_out), 0), dv = fmax(fabs(v) - 0.5 * w->width, 0);
    return hypot(du, dv);
}

static int bad(const kt_footprint *w, double centre, double arc, double radius)
{
    return !(radius > 0 && arc >= 0 && isfinite(centre) && w->width > 0 && w->r_in < w->r_out &&
             isfinite(w->meridian));
}

double kt_clearance(const kt_footprint *w, double centre, double arc, double radius)
{
    if (bad(w, centre, arc, radius)) return NAN;
    int n = (int)ceil(arc / SAMPLE);
    double h = n > 0 ? arc / n : 0, dmin = HUGE_VAL, inside = 0;
    for (int i = 0; i <= n; i++) {
        double d = dist(w, centre - 0.5 * arc + i * h, radius);
        dmin = fmin(dmin, d);
        /* each sample stands for h degrees of arc (half at the ends) */
        if (d <= 0) inside += (i == 0 || i == n) ? 0.5 * h : h;
    }
    if (dmin > 0) return dmin / radius / RAD;
    return n > 0 ? -inside : 0;
}

/* Is the point at angle th closer than lim (mm) to a wound (or in it)? The wound's index or -1. */
static int near(const kt_footprint *w, int nw, double th, double R, double lim)
{
    for (int k = 0; k < nw; k++) {
        double d = dist(&w[k], th, R);
        if (d <= 0 || d < lim) return k;
    }
    return -1;
}

double kt_clear_arc(const kt_footprint *w, int nw, double centre, double max, double radius, double min, int *which)
{
    *which = -1;
    for (int k = 0; k < nw; k++)
        if (bad(&w[k], centre, max, radius) || !(min >= 0)) return NAN;
    double lim = radius * min * RAD;
    if ((*which = near(w, nw, centre, radius, lim)) >= 0) return 0;
    double half = 0.5 * max;
    for (double d = SAMPLE; d < half + SAMPLE; d += SAMPLE) {
        double dd = fmin(d, half);
        int k = near(w, nw, centre - dd, radius, lim);
        if (k < 0) k = near(w, nw, centre + dd, radius, lim);
        if (k < 0) continue;
        double lo = dd - SAMPLE, hi = dd; /* lo is clear, hi is not */
        for (int it = 0; it < 40; it++) {
            double mid = 0.5 * (lo + hi);
            if (near(w, nw, centre - mid, radius, lim) >= 0 || near(w, nw, centre + mid, radius, lim) >= 0) hi = mid;
            else lo = mid;
        }
        *which = k;
        return 2 * lo;
    }
    return max;
}

static double wrap(double a)
{
    a = fmod(a, 360);
    return a < 0 ? a + 360 : a;
}

void kt_clear_family(const kt_footprint *w, int nw, double centre, int paired, double ratio, double max, double radius,
                     double min, kt_clear_result *r)
{
    memset(r, 0, sizeof *r);
    int k1, k2 = -1;
    double l1 = kt_clear_arc(w, nw, centre, max, radius, min, &k1), l2 = HUGE_VAL;
    r->at_max = HUGE_VAL;
    for (int k = 0; k < nw; k++) r->at_max = fmin(r->at_max, kt_clearance(&w[k], centre, max, radius));
    if (paired && ratio > 0) {
        double opp = wrap(centre + 180);
        l2 = kt_clear_arc(w, nw, opp, ratio * max, radius, min, &k2) / ratio;
        for (int k = 0; k < nw; k++) r->at_max = fmin(r->at_max, kt_clearance(&w[k], opp, ratio * max, radius));
    }
    if (nw == 0) r->at_max = NAN;
    r->opposite = l2 < l1;
    r->arc = fmin(l1, l2);
    r->wound = r->opposite ? k2 : k1;
    r->trimmed = r->arc < max;
    if (!r->trimmed || r->wound < 0) return;
    const kt_footprint *lw = &w[r->wound];
    snprintf(r->reason, sizeof r->reason, "the arc at %.0f deg would come within %g deg of %s at %.0f deg (%.1f mm zone)",
             r->opposite ? wrap(centre + 180) : wrap(centre), min, lw->name ? lw->name : "a wound", lw->meridian,
             2 * radius);
}
