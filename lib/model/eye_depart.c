/* eye_depart.c: the measured corneal surfaces in the eye's mesh: the departures' evaluation,
 * their check against the geometry, and the warp that applies them after the toric one
 * (eye_depart.h). */
#include "eye_depart.h"

#include <math.h>
#include <stdlib.h>

#include "eye_geom.h"

#define NP KT_ZERN_NP

void kt_eye_departure_poly(const kt_eye_departure *d, double poly[NP * NP])
{
    kt_zern_poly(d->coef, d->order > 0 ? kt_zern_nterms(d->order) : 0, poly);
}

double kt_eye_departure_at(const kt_eye_departure *d, const double *poly, double x, double y)
{
    double rho = hypot(x, y), a = d->radius, b = d->taper;
    if (d->order <= 0 || !(rho < b)) return 0;
    if (rho <= a) return kt_zern_poly_value(poly, d->order, x / a, y / a);
    /* Beyond the zone: the expansion's second-order Taylor polynomial along the radius from the
     * rim, times the quintic step that takes value, slope and curvature to 0 at b. */
    double c = x / rho, s = y / rho, q[6];
    kt_zern_poly_eval(poly, d->order, c, s, q);
    double dr = (q[1] * c + q[2] * s) / a, drr = (q[3] * c * c + 2 * q[4] * c * s + q[5] * s * s) / (a * a);
    double u = rho - a, t = u / (b - a), step = 1 - t * t * t * (10 - 15 * t + 6 * t * t);
    return (q[0] + u * dr + 0.5 * u * u * drr) * step;
}

/* The sag of the biconic with the eye's radii and axis and conic constant Q at (x, y); NAN past
 * its rim. */
static double biconic_sag(const kt_eye_geom *g, double Q, double x, double y)
{
    double u = x * g->cos_ax + y * g->sin_ax, v = -x * g->sin_ax + y * g->cos_ax;
    double q1 = g->cs * u * u + g->cf * v * v, q2 = g->cs * g->cs * u * u + g->cf * g->cf * v * v;
    double w = 1 - (1 + Q) * q2;
    return w >= 0 ? q1 / (1 + sqrt(w)) : NAN;
}

/* dQ: the aspheric base's height over the toric at (x, y), mm. */
static double q_delta(const kt_eye_geom *g, double Q, double x, double y)
{
    return Q == 0 ? 0 : biconic_sag(g, 0, x, y) - biconic_sag(g, Q, x, y);
}

/* c0: dQ at the corneal edge of the conic of the mean apical curvature (cs + cf) / 2. */
static double q_edge(const kt_eye_geom *g, double Q)
{
    double c = 0.5 * (g->cs + g->cf), r2 = g->rc * g->rc;
    return Q == 0 ? 0 : c * r2 / (1 + sqrt(1 - c * c * r2)) - c * r2 / (1 + sqrt(1 - (1 + Q) * c * c * r2));
}

/* The aspheric base's move before its weight: dQ - c0 within the corneal edge's radius, the
 * edge's value in the node's meridian beyond it. */
static double q_field(const kt_eye_geom *g, double Q, double x, double y)
{
    double rho = hypot(x, y), f = rho > g->rc ? g->rc / rho : 1;
    return q_delta(g, Q, f * x, f * y) - q_edge(g, Q);
}

/* wQ at the polar angle alpha (about the globe centre) of a point of the mesh of revolution. */
static double q_weight(const kt_eye_geom *g, double alpha)
{
    double a0 = asin(g->rc / g->Rg), t = (alpha - a0) / (g->alphaL - a0);
    if (t <= 0) return 1;
    if (t >= 1) return 0;
    return 1 - t * t * t * (10 - 15 * t + 6 * t * t);
}

double kt_eye_base_apex(const kt_eye_geom *g, const kt_eye *eye) { return g->z_apex - q_edge(g, eye->dep_ant.conic); }

double kt_eye_base_sag(const kt_eye_geom *g, const kt_eye *eye, int posterior, double x, double y)
{
    double Q = eye->dep_ant.conic;
    if (!posterior) return biconic_sag(g, Q, x, y);
    double rho = hypot(x, y);
    return g->z_pv - (kt_eye_geom_post_z(g, rho) + kt_eye_geom_post_delta(g, x, y)) - q_delta(g, Q, x, y);
}

int kt_eye_departure_check(const kt_eye_geom *g, const kt_eye *eye, kt_err *e)
{
    const kt_eye_departure *da = &eye->dep_ant, *dp = &eye->dep_post;
    if (!(da->conic == 0 || (da->conic > -1 && isfinite(q_delta(g, da->conic, g->rc * g->cos_ax, g->rc * g->sin_ax)))))
        return kt_fail(e, KT_EINPUT, "eye.anterior_departure.asphericity: Q %g: expected a conic constant in (-1, 1] "
                       "whose surface reaches the corneal edge (%g mm from the axis)", da->conic, g->rc);
    if (da->order > 0 && !(da->taper <= g->rc))
        return kt_fail(e, KT_EINPUT, "eye.anterior_departure.taper: expected at most the corneal edge's radius "
                       "(white_to_white / 2 = %g mm), got %g mm", g->rc, da->taper);
    if (dp->order > 0 && !(dp->taper <= g->Pp[0]))
        return kt_fail(e, KT_EINPUT, "eye.posterior_departure.taper: expected at most %g mm, where the posterior "
                       "cornea meets the limbus, got %g mm", g->Pp[0], dp->taper);
    double pa[NP * NP], pp[NP * NP];
    kt_eye_departure_poly(da, pa);
    kt_eye_departure_poly(dp, pp);
    double rmax = fmax(da->order > 0 ? da->taper : 0, dp->order > 0 ? dp->taper : 0);
    for (double rho = 0; rho < rmax; rho += 0.05)
        for (int k = 0; k < 180; k++) {
            double x = rho * cos(k * KT_PI / 90), y = rho * sin(k * KT_PI / 90);
            double d = fabs(kt_eye_departure_at(da, pa, x, y) - kt_eye_departure_at(dp, pp, x, y));
            double t = kt_eye_geom_thickness(g, rho);
            if (!(d < 0.5 * t))
                return kt_fail(e, KT_EINPUT, "eye.%s: the measured surfaces change the cornea's thickness by %g mm "
                               "at %g mm from the axis (meridian %d deg), more than half its thickness %g mm",
                               da->order > 0 && dp->order > 0 ? "anterior_departure and posterior_departure"
                               : da->order > 0 ? "anterior_departure" : "posterior_departure", d, rho, 2 * k, t);
        }
    return KT_OK;
}

/* dz[i]: the departures' move of node i of the mesh of revolution (eye_depart.h). */
static int departure_moves(const kt_eye_geom *g, const kt_eye *eye, const kt_mesh *m, double *dz, kt_err *e)
{
    const kt_eye_departure *da = &eye->dep_ant, *dp = &eye->dep_post;
    const kt_group *ga = kt_mesh_find_tag(m, 2, KT_EYE_SURF_ANTERIOR);
    int *nodes = NULL, count = 0;
    char *ant = kt_calloc((size_t)m->nn, 1, e);
    if (!ant || (ga && kt_mesh_group_nodes(m, ga, &nodes, &count, e))) {
        free(ant);
        return e->code;
    }
    for (int k = 0; k < count; k++) ant[nodes[k]] = 1;
    free(nodes);
    double pa[NP * NP], pp[NP * NP];
    kt_eye_departure_poly(da, pa);
    kt_eye_departure_poly(dp, pp);
    for (int i = 0; i < m->nn; i++) {
        const double *p = m->xyz + 3 * (size_t)i;
        double rho = hypot(p[0], p[1]);
        double wq = da->conic != 0 ? q_weight(g, atan2(rho, p[2])) : 0;
        if (wq > 0) dz[i] += wq * q_field(g, da->conic, p[0], p[1]);
        if (da->order > 0 && rho < da->taper) {
            double w = ant[i] ? 1 : kt_eye_geom_weight(g, rho, p[2]);
            if (w > 0) dz[i] += w * kt_eye_departure_at(da, pa, p[0], p[1]);
        }
        if (dp->order > 0 && !ant[i] && rho < dp->taper) {
            double h = kt_eye_geom_height(g, rho, p[2]);
            if (isfinite(h)) dz[i] += (1 - h) * kt_eye_departure_at(dp, pp, p[0], p[1]);
        }
    }
    free(ant);
    return KT_OK;
}

int kt_eye_warp_measured(const kt_eye_geom *g, const kt_eye *eye, kt_mesh *m, kt_err *e)
{
    if (eye->dep_ant.order <= 0 && eye->dep_post.order <= 0 && eye->dep_ant.conic == 0) return kt_eye_warp_toric(g, m, e);
    if (kt_eye_departure_check(g, eye, e)) return e->code;
    double *dz = kt_calloc((size_t)m->nn, sizeof(double), e);
    if (!dz) return e->code;
    int rc = departure_moves(g, eye, m, dz, e);
    if (rc == KT_OK) rc = kt_eye_warp_toric(g, m, e);
    for (int i = 0; i < m->nn && rc == KT_OK; i++) {
        m->xyz[3 * (size_t)i + 2] += dz[i];
        if (!isfinite(m->xyz[3 * (size_t)i + 2]))
            rc = kt_fail(e, KT_ERUN, "eye: node %d left the measured surfaces' domain", i + 1);
    }
    free(dz);
    return rc;
}
