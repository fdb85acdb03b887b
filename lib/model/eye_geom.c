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
    if (!(eye->floor_grading == 0 || (eye->floor_grading >= 0.1 && eye->floor_grading <= 2)))
        return kt_fail(e, KT_EINPUT, "eye.mesh_size.floor_grading: expected 0 (the default) or a number in [0.1, 2], got %g",
                       eye->floor_grading);
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

/* The oval cornea: the white-to-white ellipse and the warp's ramp (eye_geom.h). */
static int init_oval(const kt_eye *eye, kt_eye_geom *g, kt_err *e)
{
    double v = eye->wtw_v == 0 ? eye->wtw : eye->wtw_v;
    if (!(v > 0) || !(v <= eye->wtw))
        return kt_fail(e, KT_EINPUT, "eye.white_to_white.vertical: expected a positive diameter at most the "
                       "horizontal white_to_white (%g mm), got %g mm", eye->wtw, v);
    g->rv = 0.5 * v;
    g->oval = g->rv < g->rc;
    if (!g->oval) return KT_OK;
    double d = g->rc - g->rv;
    g->ov_r0 = 0.5 * eye->optical_zone;
    g->ov_xb = g->rc - 0.5 * eye->limbus_width;
    g->ov_r1 = fmin(g->ov_r0 + KT_EYE_OVAL_RAMP * d, g->ov_xb);
    if (!(g->ov_r0 > d)) /* the rings' ellipses (xi, xi - d) need xi > d from the optical zone out */
        return kt_fail(e, KT_EINPUT, "eye.optical_zone: expected more than %g mm with an oval cornea (twice the "
                       "horizontal white_to_white %g mm less the vertical %g mm), got %g mm",
                       2 * d, eye->wtw, v, eye->optical_zone);
    if (!(d <= (1 - KT_EYE_OVAL_KEEP) * (g->ov_r1 - g->ov_r0)))
        return kt_fail(e, KT_EINPUT, "eye.white_to_white.vertical: expected at least %g mm (the horizontal %g mm less "
                       "what the cornea between the optical zone and the outermost ring can take), got %g mm",
                       eye->wtw - 2 * (1 - KT_EYE_OVAL_KEEP) * (g->ov_xb - g->ov_r0), eye->wtw, v);
    return KT_OK;
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
        init_limbus(eye, g, e) || init_oval(eye, g, e))
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
    if (g->oval && rho > g->ov_xb)
        return kt_fail(e, KT_EINPUT, "eye.rings[%d] '%s': diameter %g mm: on an oval cornea a ring lies in clear cornea, "
                       "at most white_to_white - limbus_width (%g mm)", i, r->name, r->diameter, 2 * g->ov_xb);
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

/* ---- the oval cornea ------------------------------------------------------------------- */

/* Radius in the meridian (c, s) of the ellipse of semi-axes a (along x) and b (along y). */
static double ellipse_rho(double a, double b, double c, double s)
{
    return a * b / hypot(b * c, a * s);
}

double kt_eye_geom_edge_rho(const kt_eye_geom *g, double c, double s)
{
    return g->oval ? ellipse_rho(g->rc, g->rv, c, s) : g->rc;
}

static double ramp(double x, double x0, double x1) { return clamp01((x - x0) / (x1 - x0)); }

double kt_eye_geom_oval_shift(const kt_eye_geom *g, double xi, double h, double c, double s)
{
    if (!g->oval || !(xi > g->ov_r0) || !(xi < g->rL)) return 0;
    double d = g->rc - g->rv;
    if (xi <= g->rc) {
        double T = ramp(xi, g->ov_r0, g->ov_r1), W = 1 - ramp(xi, g->ov_xb, g->rc) * (1 - h);
        return (ellipse_rho(xi, xi - d, c, s) - xi) * T * W;
    }
    return (ellipse_rho(g->rc, g->rv, c, s) - g->rc) * (1 - ramp(xi, g->rc, g->rL)) * h;
}

double kt_eye_geom_oval_rho(const kt_eye_geom *g, double xi, double c, double s)
{
    return xi + kt_eye_geom_oval_shift(g, xi, 1, c, s);
}

/* The limbus quad with its outer side on the globe: P(u, s) = (1 - s) I(u) + s O(u), I(u) on
 * the line Pp-Li, O(u) on the globe arc E-Lo at the polar angle from E's to Lo's. */
static void limbus_arc_point(const kt_eye_geom *g, double u, double s, double P[2], double Pu[2], double Ps[2])
{
    double aE = asin(g->rc / g->Rg), a = aE + u * (g->alphaL - aE);
    double O[2] = {g->Rg * sin(a), g->Rg * cos(a)}, Ou[2] = {g->Rg * cos(a) * (g->alphaL - aE), -O[0] * (g->alphaL - aE)};
    for (int k = 0; k < 2; k++) {
        double I = g->Pp[k] + u * (g->Li[k] - g->Pp[k]);
        P[k] = (1 - s) * I + s * O[k];
        Pu[k] = (1 - s) * (g->Li[k] - g->Pp[k]) + s * Ou[k];
        Ps[k] = O[k] - I;
    }
}

/* (u, s) of X in that quad, Newton from the bilinear coordinates; 0 when it does not converge. */
static int limbus_arc_coords(const kt_eye_geom *g, const double X[2], double *u, double *s)
{
    limbus_coords(g, X, u, s);
    for (int it = 0; it < 30; it++) {
        double P[2], Pu[2], Ps[2];
        limbus_arc_point(g, *u, *s, P, Pu, Ps);
        double det = Pu[0] * Ps[1] - Pu[1] * Ps[0], r[2] = {P[0] - X[0], P[1] - X[1]};
        if (!(fabs(det) > 1e-300)) return 0;
        double du = (r[0] * Ps[1] - r[1] * Ps[0]) / det, ds = (Pu[0] * r[1] - Pu[1] * r[0]) / det;
        *u -= du, *s -= ds;
        if (fabs(du) + fabs(ds) < 1e-14) return 1;
    }
    double P[2], Pu[2], Ps[2]; /* stalled at the last bits: the point itself decides */
    limbus_arc_point(g, *u, *s, P, Pu, Ps);
    return hypot(P[0] - X[0], P[1] - X[1]) < 1e-9 * g->Rg;
}

/* Shell coordinates (eye_geom.h) of a base-geometry point: 1 in cornea or limbus, 0 in the
 * sclera, -1 when the limbus quad's coordinates do not converge. */
static int shell_coords(const kt_eye_geom *g, double rho, double z, double *xi, double *h)
{
    if (atan2(rho, z) >= g->alphaL) return 0;
    double phi = atan2(rho, z - g->z_ca);
    if (phi <= g->phic) {
        double d = hypot(rho, z - g->z_ca), t = post_t(g, phi);
        *xi = g->Ra * sin(phi), *h = (d - t) / (g->Ra - t);
        return 1;
    }
    double X[2] = {rho, z}, u, s;
    if (!limbus_arc_coords(g, X, &u, &s)) return -1;
    *xi = g->rc + u * (g->rL - g->rc), *h = s;
    return 1;
}

static void shell_point(const kt_eye_geom *g, double xi, double h, double *rho, double *z)
{
    if (xi <= g->rc) {
        double phi = asin(xi / g->Ra), t = post_t(g, phi), d = t + h * (g->Ra - t);
        *rho = d * sin(phi), *z = g->z_ca + d * cos(phi);
        return;
    }
    double P[2], Pu[2], Ps[2];
    limbus_arc_point(g, (xi - g->rc) / (g->rL - g->rc), h, P, Pu, Ps);
    *rho = P[0], *z = P[1];
}

int kt_eye_warp_oval(const kt_eye_geom *g, kt_mesh *m, kt_err *e)
{
    if (!g->oval) return KT_OK;
    for (int i = 0; i < m->nn; i++) {
        double *p = m->xyz + 3 * (size_t)i, rho = hypot(p[0], p[1]), xi, h;
        if (!(rho > 0)) continue;
        int in = shell_coords(g, rho, p[2], &xi, &h);
        if (in < 0) return kt_fail(e, KT_ERUN, "eye: node %d: no limbus coordinates for the oval warp", i + 1);
        if (!in) continue;
        double c = p[0] / rho, s = p[1] / rho, shift = kt_eye_geom_oval_shift(g, xi, h, c, s), r2, z2;
        if (shift == 0) continue;
        shell_point(g, xi + shift, h, &r2, &z2);
        if (!isfinite(r2) || !isfinite(z2) || !(r2 > 0))
            return kt_fail(e, KT_ERUN, "eye: node %d left the eye under the oval warp", i + 1);
        p[0] = r2 * c, p[1] = r2 * s, p[2] = z2;
    }
    return KT_OK;
}

/* ---- the oval seen from the plan ------------------------------------------------------- */

double kt_eye_wtw_v_min(const kt_eye *eye)
{
    kt_eye round = *eye;
    round.wtw_v = 0;
    kt_eye_geom g;
    kt_err e = {0};
    if (kt_eye_geom_init(&round, &g, &e)) return NAN;
    return eye->wtw - 2 * (1 - KT_EYE_OVAL_KEEP) * (eye->wtw - eye->limbus_width - eye->optical_zone) / 2;
}

double kt_eye_oval_radius(const kt_eye *eye, double diameter, double meridian)
{
    kt_eye_geom g;
    kt_err e = {0};
    if (kt_eye_geom_init(eye, &g, &e)) return NAN;
    return kt_eye_geom_oval_rho(&g, 0.5 * diameter, cos(meridian * DEG), sin(meridian * DEG));
}

static void curve_xy(const kt_eye_geom *g, double xi, double deg, double p[2])
{
    double c = cos(deg * DEG), s = sin(deg * DEG), r = kt_eye_geom_oval_rho(g, xi, c, s);
    p[0] = r * c, p[1] = r * s;
}

double kt_eye_arc_chord(const kt_eye *eye, double diameter, double from, double to)
{
    kt_eye_geom g;
    kt_err e = {0};
    if (kt_eye_geom_init(eye, &g, &e)) return NAN;
    double a[2], b[2];
    curve_xy(&g, 0.5 * diameter, from, a);
    curve_xy(&g, 0.5 * diameter, to, b);
    return hypot(b[0] - a[0], b[1] - a[1]);
}

/* Along the curve: the polygon of 1/8 deg steps (on a circle of 5 mm it is short by 1e-7 mm). */
double kt_eye_arc_length(const kt_eye *eye, double diameter, double from, double to)
{
    kt_eye_geom g;
    kt_err e = {0};
    if (kt_eye_geom_init(eye, &g, &e)) return NAN;
    if (!g.oval) return 0.5 * diameter * (to - from) * DEG;
    int n = (int)ceil(fabs(to - from) * 8) + 1;
    double len = 0, a[2], b[2];
    curve_xy(&g, 0.5 * diameter, from, a);
    for (int i = 1; i <= n; i++) {
        curve_xy(&g, 0.5 * diameter, from + (to - from) * i / n, b);
        len += hypot(b[0] - a[0], b[1] - a[1]);
        a[0] = b[0], a[1] = b[1];
    }
    return len;
}
