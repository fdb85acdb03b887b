/* eye_budget.c: how many tets the eye's size fields ask for, estimated before gmsh runs, so
 * that a scene whose mesh_size would take hours (or all memory) is refused before any meshing.
 *
 * Each region's volume is divided by the volume gmsh's Delaunay mesher spends per tet of size
 * h, h^3 / KT_EYE_TETS_PER_H3 (measured on the eye, see below), at the region's size:
 *   cornea and limbus (profile quadrature of the thickness)  at h_cornea,
 *     the part inside the optical zone                       at h_optical instead,
 *   sclera (spherical shell from the limbus to `extent`)     at h_sclera,
 *   each incision ring: a band on both sides of the ring surface (2 pi rho x depth) whose size
 *     grows linearly from h_incision at h_incision/2 to h_cornea over 2 h_cornea (eye.c's
 *     graded threshold), integrated in closed form,
 *   each ring's floor (eye.mesh_size.incision_floor): half a tube about the floor's arcs in
 *     the sector (the posterior surface, 65 um under a 90% floor, clips the rest), whose size
 *     grows from h_floor at h_floor/2 by floor_grading per unit distance to
 *     min(h_incision, h_cornea), integrated numerically (measured on plans/eye.yaml's ring at
 *     60/42/30/21 um: 0.92/0.92/0.88/0.84 of the tets the floor field added).
 * The sizes are the mesher's (kt_eye_sizes caps them by the thickness rule). Grading zones
 * between the regions are left out, so the estimate is low rather than high; a bound on it
 * refuses only what certainly exceeds the bound (measured: 0.79 and 0.99 of the tets gmsh made). */
#include <math.h>

#include "eye.h"


/* Tets per h^3 of gmsh's meshes of the eye, from the regions' volumes as summed here: 7.6 on
 * plans/eye.yaml (22,549 tets, P2) and 6.0 with every size about halved (optical zone 0.25,
 * incision 0.1, cornea 0.3, sclera 0.8 mm: 75,563 tets); a regular tet of edge h gives 8.5.
 * The smaller figure keeps the estimate low. */
#define KT_EYE_TETS_PER_H3 6.0

static double per_h3(double volume, double h) { return volume * KT_EYE_TETS_PER_H3 / (h * h * h); }

/* Volume of cornea and limbus with radial distance in [r0, r1): int 2 pi r t(r) dr, midpoint
 * rule on 400 intervals (t is smooth; the estimate needs 1%). */
static double shell_volume(const kt_eye_geom *g, double r0, double r1)
{
    const int n = 400;
    double dr = (r1 - r0) / n, v = 0;
    for (int i = 0; i < n; i++) {
        double r = r0 + (i + 0.5) * dr, t = kt_eye_geom_thickness(g, r);
        if (t > 0) v += 2 * KT_PI * r * t * dr;
    }
    return v;
}

/* Tets in a band of area A on both sides of a surface where the size grows linearly from h0
 * (within d0 of it) to h1 over the distance len: 2 A (d0 / h0^3 + int_0^len dx / h(x)^3). */
static double band_tets(double area, double h0, double d0, double h1, double len)
{
    if (!(h0 < h1)) return 0; /* no refinement: the region's own size covers it */
    double slope = (h1 - h0) / len;
    double graded = (1 / (h0 * h0) - 1 / (h1 * h1)) / (2 * slope);
    return 2 * area * KT_EYE_TETS_PER_H3 * (d0 / (h0 * h0 * h0) + graded);
}

/* Tets in half a tube of length len about a curve where the size grows linearly from h0
 * (within d0 of it) by `slope` per unit distance up to h1:
 * len (pi d0^2 / h0^3 + int 2 pi r dr / h(r)^3) / 2, midpoint rule on 200 intervals. */
static double tube_tets(double len, double h0, double d0, double h1, double slope)
{
    if (!(h0 < h1)) return 0;
    const int n = 200;
    double span = (h1 - h0) / slope, dx = span / n, v = KT_PI * d0 * d0 / (h0 * h0 * h0);
    for (int i = 0; i < n; i++) {
        double x = (i + 0.5) * dx, h = h0 + slope * x;
        v += 2 * KT_PI * (d0 + x) * dx / (h * h * h);
    }
    return 0.5 * len * KT_EYE_TETS_PER_H3 * v;
}

int kt_eye_estimate_tets(const kt_eye *eye, int order, double *tets, kt_err *e)
{
    kt_eye_geom g;
    if (kt_eye_geom_init(eye, &g, e)) return e->code;
    double hc, ho;
    kt_eye_sizes(eye, order, &hc, &ho);
    double r_oz = fmin(0.5 * eye->optical_zone, g.rL);
    double n = per_h3(shell_volume(&g, 0, r_oz), ho) + per_h3(shell_volume(&g, r_oz, g.rL), hc);
    double sclera = 2 * KT_PI / 3 * (pow(g.Rg, 3) - pow(g.Ri, 3)) * (cos(g.alphaL) - cos(g.alphaX));
    n += per_h3(fmax(sclera, 0), eye->h_sclera);
    for (int i = 0; i < eye->nring; i++) {
        double top[2], dir[2], depth;
        if (kt_eye_geom_ring(&g, eye, i, top, dir, &depth, e)) return e->code;
        double area = 2 * KT_PI * top[0] * depth;
        n += band_tets(area, eye->h_incision, 0.5 * eye->h_incision, hc, 2 * hc);
        if (eye->h_floor > 0) {
            double rho = top[0] + depth * dir[0];
            double sector = eye->floor_sector > 0 && eye->floor_sector < 90 ? eye->floor_sector : 90;
            n += tube_tets(4 * sector * KT_PI / 180 * rho, eye->h_floor, 0.5 * eye->h_floor,
                           fmin(eye->h_incision, hc), kt_eye_floor_slope(eye));
        }
    }
    *tets = n;
    return KT_OK;
}
