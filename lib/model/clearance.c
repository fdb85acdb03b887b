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

/* The zone's radius in the meridian th (deg). */
static double rho(kt_zone z, double th)
{
    double c = cos(th * RAD), s = sin(th * RAD);
    return z.rx * z.ry / hypot(z.ry * c, z.rx * s);
}

/* Distance (mm) from the zone's point at meridian th (deg) to the footprint. */
static double dist(const kt_footprint *w, double th, kt_zone z)
{
    double R = rho(z, th), a = (th - w->meridian) * RAD, u = R * cos(a), v = R * sin(a);
    double du = fmax(fmax(w->r_in - u, u - w->r_out), 0), dv = fmax(fabs(v) - 0.5 * w->width, 0);
    return hypot(du, dv);
}

static int bad(const kt_footprint *w, double centre, double arc, kt_zone z)
{
    return !(z.rx > 0 && z.ry > 0 && arc >= 0 && isfinite(arc) && isfinite(centre) && w->width > 0 &&
             w->r_in < w->r_out && isfinite(w->meridian));
}

double kt_clearance(const kt_footprint *w, double centre, double arc, kt_zone z)
{
    if (bad(w, centre, arc, z)) return NAN;
    int n = (int)ceil(arc / SAMPLE);
    double h = n > 0 ? arc / n : 0, dmin = HUGE_VAL, rmin = z.rx, inside = 0;
    for (int i = 0; i <= n; i++) {
        double th = centre - 0.5 * arc + i * h, d = dist(w, th, z);
        if (d < dmin) dmin = d, rmin = rho(z, th);
        /* each sample stands for h degrees of arc (half at the ends) */
        if (d <= 0) inside += (i == 0 || i == n) ? 0.5 * h : h;
    }
    if (dmin > 0) return dmin / rmin / RAD;
    return n > 0 ? -inside : 0;
}

/* Is the zone's point at meridian th closer than lim deg (at the zone's radius there) to a wound
 * (or in it)? The wound's index or -1. */
static int near(const kt_footprint *w, int nw, double th, kt_zone z, double lim)
{
    double mm = rho(z, th) * lim * RAD;
    for (int k = 0; k < nw; k++) {
        double d = dist(&w[k], th, z);
        if (d <= 0 || d < mm) return k;
    }
    return -1;
}

double kt_clear_arc(const kt_footprint *w, int nw, double centre, double max, kt_zone z, double min, int *which)
{
    *which = -1;
    for (int k = 0; k < nw; k++)
        if (bad(&w[k], centre, max, z) || !(min >= 0)) return NAN;
    if ((*which = near(w, nw, centre, z, min)) >= 0) return 0;
    double half = 0.5 * max;
    for (double d = SAMPLE; d < half + SAMPLE; d += SAMPLE) {
        double dd = fmin(d, half);
        int k = near(w, nw, centre - dd, z, min);
        if (k < 0) k = near(w, nw, centre + dd, z, min);
        if (k < 0) continue;
        double lo = dd - SAMPLE, hi = dd; /* lo is clear, hi is not */
        for (int it = 0; it < 40; it++) {
            double mid = 0.5 * (lo + hi);
            if (near(w, nw, centre - mid, z, min) >= 0 || near(w, nw, centre + mid, z, min) >= 0) hi = mid;
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

void kt_clear_family(const kt_footprint *w, int nw, double centre, int paired, double ratio, double max, kt_zone z,
                     double min, kt_clear_result *r)
{
    memset(r, 0, sizeof *r);
    int k1, k2 = -1;
    double l1 = kt_clear_arc(w, nw, centre, max, z, min, &k1), l2 = HUGE_VAL;
    r->at_max = HUGE_VAL;
    for (int k = 0; k < nw; k++) r->at_max = fmin(r->at_max, kt_clearance(&w[k], centre, max, z));
    if (paired && ratio > 0) {
        double opp = wrap(centre + 180), a2 = kt_clear_arc(w, nw, opp, ratio * max, z, min, &k2);
        l2 = a2 >= ratio * max ? max : a2 / ratio; /* untrimmed: max exactly, not max to an ulp */
        for (int k = 0; k < nw; k++) r->at_max = fmin(r->at_max, kt_clearance(&w[k], opp, ratio * max, z));
    }
    if (nw == 0) r->at_max = NAN;
    r->opposite = l2 < l1;
    r->arc = fmin(l1, l2);
    r->wound = r->opposite ? k2 : k1;
    r->trimmed = r->arc < max;
    if (!r->trimmed || r->wound < 0) return;
    const kt_footprint *lw = &w[r->wound];
    snprintf(r->reason, sizeof r->reason, "the arc at %.0f deg would come within %g deg of %s at %.0f deg (%.1f mm zone)",
             wrap(round(r->opposite ? centre + 180 : centre)), min, lw->name ? lw->name : "a wound",
             wrap(round(lw->meridian)), 2 * z.rx);
}
