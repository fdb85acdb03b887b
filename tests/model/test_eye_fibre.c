/* test_eye_fibre.c: the lamellar frames of the eye (kt_eye_fibre_frames) on known points,
 * against what keratome-scene(5) (eye.fibres) states:
 *  - n is the unit vector from the anterior sphere's centre (cornea) or the globe's (limbus);
 *  - before the turn a1 is x projected onto the plane normal to n, a2 = n x a1; c is
 *    (-y, x, 0)/rho projected onto that plane;
 *  - w is 0 inside rc - limbal_band, the smoothstep of (rho - (rc - band)) / band across the
 *    band, 1 in the limbus;
 *  - the pair turns about n from a1 towards a2 (counter-clockwise seen from the front) by
 *    w delta, delta the tangent-plane angle from a1 to the radial direction c x n reduced to
 *    [-45, 45] deg: a positive azimuth in (0, 45) deg turns a1 towards +y, one in (45, 90)
 *    turns it back towards -y (the sign the page's former wording had reversed);
 *  - at w = 1 the pair lies along the radial and circumferential directions exactly, also
 *    where n is tilted (the limbus, about 32 deg from the axis);
 *  - on an oval cornea (plans/eye.yaml: white_to_white 11.7 x 10.6 mm) c is the tangent
 *    (-y a^2, x b^2, 0) of the ellipse of the white-to-white's semi-axes a, b through the point,
 *    projected, and rc in w the edge's radius a b / hypot(b cos t, a sin t) in its meridian t.
 * Both eyes: plans/eye.yaml as it is (oval) and made round (vertical = horizontal).
 * Each point is the centroid of a small regular tet of the region (the frames are evaluated at
 * tet centroids). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "eye.h"
#include "kt_test.h"
#include "scene.h"

#define DEG (KT_PI / 180.0)

static void unit(double *v)
{
    double n = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    for (int k = 0; k < 3; k++) v[k] /= n;
}

static double dot(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

static void cross(const double *u, const double *v, double *w)
{
    w[0] = u[1] * v[2] - u[2] * v[1];
    w[1] = u[2] * v[0] - u[0] * v[2];
    w[2] = u[0] * v[1] - u[1] * v[0];
}

/* v minus its component along n, normalized */
static void tangent(const double *v, const double *n, double *t)
{
    double d = dot(v, n);
    for (int k = 0; k < 3; k++) t[k] = v[k] - d * n[k];
    unit(t);
}

typedef struct {
    double rho, phi_deg; /* the centroid's place: radius from the axis, azimuth */
    int limbus;          /* 0: cornea, 1: limbus */
} place;

/* One tet per place, centroid on the outer surface's height less 0.2 mm (cornea: on the
 * anterior sphere of radius ra about (0, 0, zc); limbus: on the globe of radius rg). */
static int build(const place *pl, int n, double ra, double zc, double rg, kt_mesh *m, kt_err *e)
{
    static const double D[4][3] = {{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}};
    memset(m, 0, sizeof *m);
    m->order = 1, m->nn = 4 * n, m->ne = n;
    m->xyz = malloc(sizeof(double) * 12 * (size_t)n);
    m->tet = malloc(sizeof(int) * 4 * (size_t)n);
    m->tet_tag = malloc(sizeof(int) * (size_t)n);
    if (!m->xyz || !m->tet || !m->tet_tag) return kt_fail(e, KT_ERUN, "test mesh: out of memory");
    for (int t = 0; t < n; t++) {
        double r = pl[t].rho, f = pl[t].phi_deg * DEG;
        double z = pl[t].limbus ? sqrt(rg * rg - r * r) - 0.2 : zc + sqrt(ra * ra - r * r) - 0.2;
        double c[3] = {r * cos(f), r * sin(f), z};
        for (int a = 0; a < 4; a++) {
            for (int k = 0; k < 3; k++) m->xyz[12 * t + 3 * a + k] = c[k] + 0.01 * D[a][k];
            m->tet[4 * t + a] = 4 * t + a;
        }
        m->tet_tag[t] = pl[t].limbus ? 2 : 1;
    }
    if (kt_mesh_add_group(m, 3, 1, "cornea", e) || kt_mesh_add_group(m, 3, 2, "limbus", e)) return e->code;
    return KT_OK;
}

static void check_eye(const kt_eye *eye)
{
    kt_err e = {0};
    int rc;
    /* the mean anterior sphere through the corneal edge on the globe (keratome-scene(5)) */
    double ra = 2 / (1 / eye->r_ant_steep + 1 / eye->r_ant_flat), rcorn = eye->wtw / 2, rg = eye->globe_radius;
    double a = rcorn, b = 0.5 * (eye->wtw_v > 0 ? eye->wtw_v : eye->wtw); /* the white-to-white's semi-axes */
    double zc = sqrt(rg * rg - rcorn * rcorn) - sqrt(ra * ra - rcorn * rcorn), band = eye->fibre_band;
    CHECK(band == 1.5, "plans/eye.yaml's limbal band %g mm (the places below assume 1.5 mm)", band);
    const place pl[] = {
        {2.0, 30, 0},                    /* w = 0: no turn */
        {rcorn - 0.75, 30, 0},           /* mid-band, w = 0.5: a1 towards +y */
        {rcorn - 0.75, 60, 0},           /* mid-band past 45 deg: a1 towards -y */
        {rcorn - 0.75, 120, 0},          /* delta +30 about the 90 deg multiple */
        {rcorn - 0.3, -20, 0},           /* s = 0.8 */
        {rcorn - 0.3, 200, 0},           /* s = 0.8, third quadrant */
        {rcorn + 0.5, 30, 1},            /* limbus, w = 1: a1' radial */
        {rcorn + 0.5, 60, 1},            /* limbus, w = 1: a2' radial */
        {rcorn + 0.5, 137, 1},           /* limbus, w = 1 */
    };
    int n = (int)(sizeof pl / sizeof pl[0]);
    kt_mesh m;
    double F[13 * 9];
    rc = build(pl, n, ra, zc, rg, &m, &e);
    if (rc == KT_OK) rc = kt_eye_fibre_frames(eye, &m, F, &e);
    CHECK(rc == KT_OK, "frames: %s", e.msg);
    for (int t = 0; t < n && rc == KT_OK; t++) {
        const double *f = F + 13 * t, *a1 = f, *a2 = f + 3, *nn = f + 6, *c = f + 9, w = f[12];
        double r = pl[t].rho, ph = pl[t].phi_deg * DEG, p[3] = {0, 0, 0};
        for (int a = 0; a < 4; a++)
            for (int k = 0; k < 3; k++) p[k] += 0.25 * m.xyz[12 * t + 3 * a + k];
        /* n, c and the untouched pair */
        double n0[3] = {p[0], p[1], p[2] - (pl[t].limbus ? 0 : zc)}, x[3] = {1, 0, 0}, b1[3], b2[3], c0[3], cz[3];
        unit(n0);
        tangent(x, n0, b1);
        cross(n0, b1, b2);
        cz[0] = -sin(ph) * a * a, cz[1] = cos(ph) * b * b, cz[2] = 0;
        tangent(cz, n0, c0);
        double edge = a * b / hypot(b * cos(ph), a * sin(ph));
        double dn = 0, dc = 0;
        for (int k = 0; k < 3; k++) dn = fmax(dn, fabs(nn[k] - n0[k])), dc = fmax(dc, fabs(c[k] - c0[k]));
        CHECK(dn < 1e-12 && dc < 1e-12, "place %d: n and c as stated (%.2e, %.2e)", t, dn, dc);
        /* w */
        double sw = pl[t].limbus ? 1 : fmin(1, fmax(0, (r - (edge - band)) / band)), want_w = sw * sw * (3 - 2 * sw);
        CHECK(fabs(w - want_w) < 1e-12, "place %d: w %.15g, expected %.15g", t, w, want_w);
        /* the turn: the angle of a1 from b1 about n, positive from b1 towards b2 */
        double th = atan2(dot(a1, b2), dot(a1, b1));
        double rad[3];
        cross(c0, n0, rad);
        double psi = atan2(dot(rad, b2), dot(rad, b1)), delta = psi - 0.5 * KT_PI * round(psi / (0.5 * KT_PI));
        CHECK(fabs(th - w * delta) < 1e-12, "place %d: a1 turned %.6f deg, expected w delta = %.6f deg", t, th / DEG,
              w * delta / DEG);
        double a2w[3];
        cross(nn, a1, a2w);
        CHECK(fabs(a2w[0] - a2[0]) + fabs(a2w[1] - a2[1]) + fabs(a2w[2] - a2[2]) < 1e-12, "place %d: a2 = n x a1", t);
        /* the page's signs: azimuth 30 deg mid-band turns a1 towards +y (counter-clockwise),
         * azimuth 60 deg towards -y; where n is nearly the axis delta is about the azimuth's
         * distance to the nearest multiple of 90 deg */
        if (t == 1) CHECK(th > 5 * DEG && a1[1] > b1[1], "azimuth 30 deg, w 0.5: a1 turned counter-clockwise (%.2f deg)", th / DEG);
        if (t == 2) CHECK(th < -5 * DEG && a1[1] < b1[1], "azimuth 60 deg, w 0.5: a1 turned clockwise (%.2f deg)", th / DEG);
        if (t == 0) CHECK(fabs(th) < 1e-12, "w = 0: no turn");
        /* at w = 1 the pair is radial / circumferential exactly */
        if (pl[t].limbus) {
            double along_r = fmax(fabs(dot(a1, rad)), fabs(dot(a2, rad))), along_c = fmax(fabs(dot(a1, c0)), fabs(dot(a2, c0)));
            CHECK(along_r > 1 - 1e-12 && along_c > 1 - 1e-12, "place %d (limbus, n %.1f deg from the axis): the pair "
                  "along r and c (%.3g, %.3g)", t, acos(n0[2]) / DEG, 1 - along_r, 1 - along_c);
            if (pl[t].phi_deg == 30) CHECK(dot(a1, rad) > 1 - 1e-12, "azimuth 30 deg, w 1: a1 radial");
            if (pl[t].phi_deg == 60) CHECK(fabs(dot(a2, rad)) > 1 - 1e-12, "azimuth 60 deg, w 1: a2 radial");
        }
    }
    kt_mesh_free(&m);
}

int main(void)
{
    kt_scene s;
    kt_err e = {0};
    int rc = kt_scene_load("plans/eye.yaml", &s, &e);
    CHECK(rc == KT_OK, "plans/eye.yaml: %s", e.msg);
    if (rc != KT_OK) return kt_test_done("test_eye_fibre");
    CHECK(s.eye.wtw_v < s.eye.wtw, "plans/eye.yaml's cornea is oval (%g x %g mm)", s.eye.wtw, s.eye.wtw_v);
    check_eye(&s.eye);
    s.eye.wtw_v = s.eye.wtw;
    check_eye(&s.eye);
    return kt_test_done("test_eye_fibre");
}
