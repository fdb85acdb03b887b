/* eye_geom.c: analytic geometry of the parametric eye: profile, toric surface, thickness,
 * warp weights and incision-ring placement (see eye_geom.h for the picture). */
#include "eye_geom.h"

#include <math.h>
#include <string.h>

#define DEG (KT_PI / 180.0)
#define RING_EPS 0.01 /* mm: a ring this close to the corneal or limbal border is rejected */

static double sq(double a) { return a * a; }
static double clamp01(double a) { return a < 0 ? 0 : (a > 1 ? 1 : a); }

double kt_eye_geom_sphere_z(const kt_eye_geom *g, double rho)
{
    return g->z_ca + sqrt(sq(g->Ra) - sq(rho));
}

double kt_eye_geom_globe_z(const kt_eye_geom *g, double rho)
{
    return sqrt(sq(g->Rg) - sq(rho));
}

/* Posterior conic rho^2 = 2 Rp s - k s^2, s = z_pv - z, near branch. */
double kt_eye_geom_post_z(const kt_eye_geom *g, double rho)
{
    return g->z_pv - (g->Rp - sqrt(sq(g->Rp) - g->k * sq(rho))) / g->k;
}

/* Sag of a conic of apical curvature c and k = 1 + Q at radial distance rho; NAN past its rim. */
static double conic_sag(double c, double k, double rho)
{
    double q = 1.0 - k * sq(c * rho);
    if (q < 0) return NAN;
    return c * rho * rho / (1.0 + sqrt(q));
}

static double post_taper(const kt_eye_geom *g, double rho)
{
    if (rho <= g->taper_in) return 1;
    if (rho >= g->taper_out) return 0;
    return 0.5 * (1 + cos(KT_PI * (rho - g->taper_in) / (g->taper_out - g->taper_in)));
}

double kt_eye_geom_post_delta(const kt_eye_geom *g, double x, double y)
{
    double rho = hypot(x, y);
    if (g->cp_half == 0 || rho <= 0 || rho >= g->taper_out) return 0;
    double u = x * g->cos_pax + y * g->sin_pax, v = -x * g->sin_pax + y * g->cos_pax;
    double c = 1.0 / g->Rp + g->cp_half * (u * u - v * v) / (rho * rho);
    return -post_taper(g, rho) * (conic_sag(c, g->k, rho) - conic_sag(1.0 / g->Rp, g->k, rho));
}

/* Biconic with zero conic constants: exact circles of radius 1/cs and 1/cf in the principal
 * meridians, apical curvature cs cos^2 + cf sin^2 in between. */
double kt_eye_geom_toric_z(const kt_eye_geom *g, double x, double y)
{
    double u = x * g->cos_ax + y * g->sin_ax, v = -x * g->sin_ax + y * g->cos_ax;
    double q = 1.0 - sq(g->cs * u) - sq(g->cf * v);
    if (q < 0) return NAN;
    return g->z_apex - (g->cs * u * u + g->cf * v * v) / (1.0 + sqrt(q));
}

/* Distance from Ca to the posterior conic along the ray at angle phi from the axis. */
static double post_t(const kt_eye_geom *g, double phi)
{
    double s = sin(phi), c = cos(phi), D = g->z_pv - g->z_ca, k = g->k, R = g->Rp;
    double A = s * s + k * c * c, B = 2 * c * (R - k * D), C = k * D * D - 2 * R * D;
    double disc = B * B - 4 * A * C;
    if (disc < 0) return NAN;
    return (-B + sqrt(disc)) / (2 * A);
}

/* Distance from the origin, along the ray at polar angle alpha, to the line Pp-Li. */
static double limbus_inner_t(const kt_eye_geom *g, double alpha)
{
    double d[2] = {sin(alpha), cos(alpha)}, l[2] = {g->Li[0] - g->Pp[0], g->Li[1] - g->Pp[1]};
    double det = d[0] * (-l[1]) - d[1] * (-l[0]);
    if (fabs(det) < 1e-300) return NAN;
    /* t d - v l = Pp */
    return (g->Pp[0] * (-l[1]) - g->Pp[1] * (-l[0])) / det;
}

double kt_eye_geom_thickness(const kt_eye_geom *g, double r)
{
    if (!(r >= 0)) return NAN;
    if (r <= g->rc) return g->Ra - post_t(g, asin(r / g->Ra));
    if (r < g->rL) return g->Rg - limbus_inner_t(g, asin(r / g->Rg));
    if (r <= g->Rg) return g->Rg - g->Ri;
    return NAN;
}

/* Bilinear coordinates (u, s) of X in the limbus quad: u = 0 on E-Pp (cornea side), u = 1 on
 * Lo-Li (sclera side), s = 0 on the inner side, 1 on the outer. Newton from the centre. */
static void limbus_coords(const kt_eye_geom *g, const double X[2], double *u, double *s)
{
    double U = 0.5, S = 0.5;
    for (int it = 0; it < 30; it++) {
        double P[2], Pu[2], Ps[2];
        for (int c = 0; c < 2; c++) {
            P[c] = (1 - U) * ((1 - S) * g->Pp[c] + S * g->E[c]) +
                   U * ((1 - S) * g->Li[c] + S * g->Lo[c]) - X[c];
            Pu[c] = (1 - S) * (g->Li[c] - g->Pp[c]) + S * (g->Lo[c] - g->E[c]);
            Ps[c] = (1 - U) * (g->E[c] - g->Pp[c]) + U * (g->Lo[c] - g->Li[c]);
        }
        double det = Pu[0] * Ps[1] - Pu[1] * Ps[0];
        if (fabs(det) < 1e-300) break;
        double dU = (P[0] * Ps[1] - P[1] * Ps[0]) / det, dS = (Pu[0] * P[1] - Pu[1] * P[0]) / det;
        U -= dU;
        S -= dS;
        if (fabs(dU) + fabs(dS) < 1e-15) break;
    }
    *u = U;
    *s = S;
}

double kt_eye_geom_weight(const kt_eye_geom *g, double rho, double z)
{
    if (atan2(rho, z) >= g->alphaL) return 0;
    double phi = atan2(rho, z - g->z_ca);
    if (phi <= g->phic) {
        double d = hypot(rho, z - g->z_ca), t = post_t(g, phi);
        return clamp01((d - t) / (g->Ra - t));
    }
    double X[2] = {rho, z}, u, s;
    limbus_coords(g, X, &u, &s);
    return clamp01(s) * (1 - clamp01(u));
}

double kt_eye_geom_height(const kt_eye_geom *g, double rho, double z)
{
    if (atan2(rho, z) >= g->alphaL) return NAN;
    double phi = atan2(rho, z - g->z_ca);
    if (phi <= g->phic) return kt_eye_geom_weight(g, rho, z);
    double X[2] = {rho, z}, u, s;
    limbus_coords(g, X, &u, &s);
    return clamp01(s);
}

double kt_eye_geom_outer_z(const kt_eye_geom *g, double x, double y)
{
    double rho = hypot(x, y);
    if (rho <= g->rc) return kt_eye_geom_toric_z(g, x, y);
    if (rho > g->Rg) return NAN;
    double zg = kt_eye_geom_globe_z(g, rho);
    if (rho >= g->rL) return zg;
    double delta = kt_eye_geom_toric_z(g, x, y) - kt_eye_geom_sphere_z(g, rho);
    return zg + delta * kt_eye_geom_weight(g, rho, zg);
}

static double cross2(const double *a, const double *b, const double *c)
{
    return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

static int check_sizes(const kt_eye *eye, kt_err *e)
{
    const struct { const char *name; double v; } pos[] = {
        {"r_ant_steep", eye->r_ant_steep}, {"r_ant_flat", eye->r_ant_flat},
        {"r_post", eye->r_post}, {"t_central", eye->t_central},
        {"t_peripheral", eye->t_peripheral}, {"wtw", eye->wtw},
        {"limbus_width", eye->limbus_width}, {"sclera_thickness", eye->sclera_thickness},
        {"globe_radius", eye->globe_radius}, {"optical_zone", eye->optical_zone},
        {"h_optical", eye->h_optical}, {"h_incision", eye->h_incision},
        {"h_cornea", eye->h_cornea}, {"h_sclera", eye->h_sclera}};
    for (size_t i = 0; i < sizeof pos / sizeof pos[0]; i++)
        if (!(pos[i].v > 0) || !isfinite(pos[i].v))
            return kt_fail(e, KT_EINPUT, "eye.%s: expected a positive length, got %g mm",
                           pos[i].name, pos[i].v);
    if (!(eye->extent > 0 && eye->extent <= 180))
        return kt_fail(e, KT_EINPUT, "eye.extent: expected an angle in (0, 180] deg, got %g",
                       eye->extent);
    if (!isfinite(eye->steep_axis))
        return kt_fail(e, KT_EINPUT, "eye.steep_axis: expected an angle in deg");
    if (eye->r_ant_steep > eye->r_ant_flat)
        return kt_fail(e, KT_EINPUT,
                       "eye.r_ant_steep: expected at most r_ant_flat (%g mm), got %g mm",
                       eye->r_ant_flat, eye->r_ant_steep);
    return KT_OK;
}

/* Anterior sphere, corneal edge and limbus on the globe. */
static int init_outer(const kt_eye *eye, kt_eye_geom *g, kt_err *e)
{
    g->cs = 1.0 / eye->r_ant_steep;
    g->cf = 1.0 / eye->r_ant_flat;
    g->cos_ax = cos(eye->steep_axis * DEG);
    g->sin_ax = sin(eye->steep_axis * DEG);
    g->Ra = 2.0 / (g->cs + g->cf);
    g->rc = 0.5 * eye->wtw;
    g->rL = g->rc + eye->limbus_width;
    g->Rg = eye->globe_radius;
    g->Ri = g->Rg - eye->sclera_thickness;
    if (g->Ri <= 0)
        return kt_fail(e, KT_EINPUT, "eye.sclera_thickness: expected less than globe_radius "
                       "(%g mm), got %g mm", g->Rg, eye->sclera_thickness);
    if (g->Ra >= g->Rg)
        return kt_fail(e, KT_EINPUT, "eye.globe_radius: expected more than the mean anterior "
                       "corneal radius %g mm, got %g mm", g->Ra, g->Rg);
    if (g->rL >= 0.999 * eye->r_ant_steep)
        return kt_fail(e, KT_EINPUT, "eye.limbus_width: the limbus (out to %g mm from the axis) "
                       "must stay inside r_ant_steep (%g mm)", g->rL, eye->r_ant_steep);
    if (g->rL >= g->Ri)
        return kt_fail(e, KT_EINPUT, "eye.wtw: corneal and limbal radius %g mm must be less "
                       "than the inner scleral radius %g mm", g->rL, g->Ri);
    g->E[0] = g->rc;
    g->E[1] = kt_eye_geom_globe_z(g, g->rc);
    g->z_ca = g->E[1] - sqrt(sq(g->Ra) - sq(g->rc));
    g->z_apex = g->z_ca + g->Ra;
    g->phic = asin(g->rc / g->Ra);
    g->alphaL = asin(g->rL / g->Rg);
    g->whole = eye->extent >= 180;
    g->alphaX = eye->extent * DEG;
    if (g->alphaX <= g->alphaL + 1e-3)
        return kt_fail(e, KT_EINPUT, "eye.extent: expected more than the limbus edge at %g deg, "
                       "got %g deg", g->alphaL / DEG, eye->extent);
    double sL = sin(g->alphaL), cL = cos(g->alphaL), sX = sin(g->alphaX), cX = cos(g->alphaX);
    if (g->whole) sX = 0, cX = -1;
    g->Lo[0] = g->Rg * sL, g->Lo[1] = g->Rg * cL;
    g->Li[0] = g->Ri * sL, g->Li[1] = g->Ri * cL;
    g->So[0] = g->Rg * sX, g->So[1] = g->Rg * cX;
    g->Si[0] = g->Ri * sX, g->Si[1] = g->Ri * cX;
    return KT_OK;
}

/* The toric posterior (eye.posterior_radius_steep/flat, posterior_steep_axis): half the
 * apical curvature difference and the taper; its steepest meridian's conic must reach the
 * taper's end and the warp must leave at least half the thickness (keratome-scene(5)). */
static int init_post_toric(const kt_eye *eye, kt_eye_geom *g, kt_err *e)
{
    g->taper_out = g->Pp[0];
    g->taper_in = 0.5 * g->Pp[0];
    g->cos_pax = cos(eye->post_axis * DEG);
    g->sin_pax = sin(eye->post_axis * DEG);
    if (!(eye->r_post_steep > 0) || !(eye->r_post_flat > 0) || eye->r_post_steep == eye->r_post_flat) return KT_OK;
    g->cp_half = 0.5 * (1.0 / eye->r_post_steep - 1.0 / eye->r_post_flat);
    if (!(fabs(g->cp_half) < 0.25 / g->Rp))
        return kt_fail(e, KT_EINPUT, "eye.posterior_radius_steep: %g mm against flat %g mm: expected posterior "
                       "curvatures (1/radius) differing by less than half their mean", eye->r_post_steep, eye->r_post_flat);
    for (int i = 0; i <= 64; i++) {
        double rho = g->taper_out * i / 64.0, c = 1.0 / g->Rp + fabs(g->cp_half);
        double d = post_taper(g, rho) * fabs(conic_sag(c, g->k, rho) - conic_sag(1.0 / g->Rp, g->k, rho));
        double t = kt_eye_geom_thickness(g, rho);
        if (!(d < 0.5 * t))
            return kt_fail(e, KT_EINPUT, "eye.posterior_radius_steep: the toric posterior (radii %g/%g mm) moves "
                           "the posterior cornea %g mm at %g mm from the axis, more than half its thickness %g mm",
                           eye->r_post_steep, eye->r_post_flat, d, rho, t);
    }
    return KT_OK;
}

/* Posterior conic through the vertex (apex - t_central) and the point Pp at t_peripheral
 * along the anterior normal at the corneal edge: apical radius r_post, k = 1 + Q solved. */
static int init_posterior(const kt_eye *eye, kt_eye_geom *g, kt_err *e)
{
    double n[2] = {sin(g->phic), cos(g->phic)};
    g->Pp[0] = g->E[0] - eye->t_peripheral * n[0];
    g->Pp[1] = g->E[1] - eye->t_peripheral * n[1];
    g->z_pv = g->z_apex - eye->t_central;
    g->Rp = eye->r_post;
    double sp = g->z_pv - g->Pp[1], rp = g->Pp[0];
    if (!(sp > 0) || !(rp > 0))
        return kt_fail(e, KT_EINPUT, "eye.t_peripheral: %g mm does not fit a cornea of central "
                       "thickness %g mm and diameter %g mm", eye->t_peripheral, eye->t_central,
                       eye->wtw);
    g->k = (2 * g->Rp * sp - rp * rp) / (sp * sp);
    if (!(g->k > 0.05) || sp > g->Rp / g->k)
        return kt_fail(e, KT_EINPUT, "eye.r_post: no posterior ellipse of apical radius %g mm "
                       "gives thicknesses %g mm (centre) and %g mm (edge); asphericity Q = %.3g",
                       g->Rp, eye->t_central, eye->t_peripheral, g->k - 1);
    for (int i = 0; i <= 64; i++) {
        double t = g->Ra - post_t(g, g->phic * i / 64.0);
        if (!(t > 0))
            return kt_fail(e, KT_EINPUT, "eye.r_post: the posterior cornea (radius %g mm) "
                           "crosses the anterior surface", g->Rp);
    }
    return init_post_toric(eye, g, e);
}

static int init_limbus(const kt_eye *eye, kt_eye_geom *g, kt_err *e)
{
    const double *q[4] = {g->Pp, g->E, g->Lo, g->Li};
    double s0 = 0;
    for (int i = 0; i < 4; i++) {
        double c = cross2(q[i], q[(i + 1) % 4], q[(i + 2) % 4]);
        if (i == 0) s0 = c;
        if (!(c * s0 > 0))
            return kt_fail(e, KT_EINPUT, "eye.limbus_width: the limbus section (width %g mm, "
                           "thicknesses %g/%g mm) is not convex", eye->limbus_width,
                           eye->t_peripheral, eye->sclera_thickness);
    }
    if (!(eye->optical_zone < eye->wtw))
        return kt_fail(e, KT_EINPUT, "eye.optical_zone: expected less than wtw (%g mm), got %g mm",
                       eye->wtw, eye->optical_zone);
    return KT_OK;
}

int kt_eye_geom_init(const kt_eye *eye, kt_eye_geom *g, kt_err *e)
{
    memset(g, 0, sizeof *g);
    if (check_sizes(eye, e) || init_outer(eye, g, e) || init_posterior(eye, g, e) ||
        init_limbus(eye, g, e))
        return e->code;
    return KT_OK;
}

int kt_eye_geom_ring(const kt_eye_geom *g, const kt_eye *eye, int i, double top[2],
                     double dir[2], double *depth, kt_err *e)
{
    const kt_ring *r = &eye->ring[i];
    double rho = 0.5 * r->diameter;
    if (!(rho > 0.5 * eye->optical_zone))
        return kt_fail(e, KT_EINPUT, "eye.rings[%d] '%s': diameter %g mm lies inside the optical "
                       "zone (%g mm)", i, r->name, r->diameter, eye->optical_zone);
    if (!(rho < g->rL - RING_EPS))
        return kt_fail(e, KT_EINPUT, "eye.rings[%d] '%s': diameter %g mm lies outside the cornea "
                       "and limbus (expected less than %g mm)", i, r->name, r->diameter,
                       2 * (g->rL - RING_EPS));
    if (fabs(rho - g->rc) < RING_EPS)
        return kt_fail(e, KT_EINPUT, "eye.rings[%d] '%s': diameter %g mm lies on the corneal edge "
                       "(wtw %g mm); move it at least %g mm inside or outside", i, r->name,
                       r->diameter, eye->wtw, 2 * RING_EPS);
    for (int j = 0; j < i; j++)
        if (fabs(eye->ring[j].diameter - r->diameter) < 2 * RING_EPS)
            return kt_fail(e, KT_EINPUT, "eye.rings[%d] '%s': diameter %g mm coincides with ring "
                           "'%s'", i, r->name, r->diameter, eye->ring[j].name);
    if (rho < g->rc) {
        top[0] = rho, top[1] = kt_eye_geom_sphere_z(g, rho);
        dir[0] = -rho / g->Ra, dir[1] = -(top[1] - g->z_ca) / g->Ra;
    } else {
        top[0] = rho, top[1] = kt_eye_geom_globe_z(g, rho);
        dir[0] = -top[0] / g->Rg, dir[1] = -top[1] / g->Rg;
    }
    double t = kt_eye_geom_thickness(g, rho);
    if (r->depth_fraction != 0 && !(r->depth_fraction > 0 && r->depth_fraction < 1))
        return kt_fail(e, KT_EINPUT, "eye.rings[%d] '%s': depth_fraction %g: expected a value in "
                       "(0, 1)", i, r->name, r->depth_fraction);
    *depth = r->depth_fraction > 0 ? r->depth_fraction * t : r->depth;
    if (!(*depth > 0) || !(*depth < t))
        return kt_fail(e, KT_EINPUT, "eye.rings[%d] '%s': depth %g mm: expected more than 0 and "
                       "less than the local thickness %g mm", i, r->name, *depth, t);
    return KT_OK;
}

double kt_eye_anterior_z(const kt_eye *eye, double x, double y)
{
    kt_eye_geom g;
    kt_err e = {0};
    if (kt_eye_geom_init(eye, &g, &e)) return NAN;
    return kt_eye_geom_outer_z(&g, x, y);
}

double kt_eye_thickness(const kt_eye *eye, double r)
{
    kt_eye_geom g;
    kt_err e = {0};
    if (kt_eye_geom_init(eye, &g, &e)) return NAN;
    return kt_eye_geom_thickness(&g, r);
}
