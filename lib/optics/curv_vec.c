/* curv_vec.c: astigmatism vectors on the double-angle plane and Alpins vector analysis. */
#include <math.h>

#include "curv.h"

#define DEG KT_CURV_DEG

void kt_astig_xy(kt_astig a, double xy[2])
{
    xy[0] = a.mag * cos(2 * a.axis * DEG);
    xy[1] = a.mag * sin(2 * a.axis * DEG);
}

/* Axis in [0, 180): half the double angle. */
kt_astig kt_astig_from_xy(double x, double y)
{
    kt_astig a;
    a.mag = hypot(x, y);
    a.axis = 0.5 * atan2(y, x) / DEG;
    if (a.axis < 0) a.axis += 180;
    if (a.axis >= 180 - 1e-9) a.axis = 0; /* 179.999... from round-off is 0 */
    return a;
}

void kt_curv_alpins(kt_astig pre, kt_astig post, const kt_astig *tia, kt_alpins *out)
{
    double p0[2], p1[2];
    kt_astig_xy(pre, p0);
    kt_astig_xy(post, p1);
    out->sia = kt_astig_from_xy(p1[0] - p0[0], p1[1] - p0[1]);
    if (!tia) {
        out->tia.mag = out->tia.axis = out->dv.mag = out->dv.axis = NAN;
        out->ci = out->ae = out->me = out->ios = NAN;
        return;
    }
    double t[2];
    kt_astig_xy(*tia, t);
    out->tia = kt_astig_from_xy(t[0], t[1]);
    /* DV = TIA - SIA = target - post: the change still needed to reach the target */
    out->dv = kt_astig_from_xy(t[0] - (p1[0] - p0[0]), t[1] - (p1[1] - p0[1]));
    out->ci = out->tia.mag > 0 ? out->sia.mag / out->tia.mag : NAN;
    double ae = out->sia.axis - out->tia.axis;
    while (ae > 90) ae -= 180;
    while (ae <= -90) ae += 180;
    out->ae = ae;
    out->me = out->sia.mag - out->tia.mag;
    out->ios = out->tia.mag > 0 ? out->dv.mag / out->tia.mag : NAN;
}
