/* test_eye_oval.c: the oval cornea (eye_geom.h, kt_eye_warp_oval; keratome-scene(5), THE OVAL
 * CORNEA): the warp against its closed forms (the corneal edge on the white-to-white ellipse, a
 * ring at the same distance inside it in every meridian, nothing moved in the optical zone, a
 * round posterior boundary, monotone along every meridian), the arcs' chords, the refusals;
 * and on a coarse P2 mesh: the edge and ring nodes on their ellipses, the central cornea the
 * same bytes as the round eye's, vertical = horizontal the round eye exactly, and the fibres'
 * limbal weight following the oval. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "eye.h"
#include "kt_test.h"
#include "plan.h"

#include "kt_test_gmsh.h"

#define DEG (KT_PI / 180.0)

/* A coarse eye with literature dimensions (the default eye's), 1.5 D of cylinder at an oblique
 * 30 deg, one ring at 10.2 mm; oval 11.7 x 10.6 mm. */
static void coarse_eye(kt_eye *e)
{
    memset(e, 0, sizeof *e);
    double K = 337.5 / 7.8;
    e->r_ant_steep = 337.5 / (K + 0.75);
    e->r_ant_flat = 337.5 / (K - 0.75);
    e->steep_axis = 30;
    e->r_post = e->r_post_steep = e->r_post_flat = 6.7;
    e->t_central = 0.54;
    e->t_peripheral = 0.67;
    e->wtw = 11.7;
    e->wtw_v = 10.6;
    e->limbus_width = 1.0;
    e->sclera_thickness = 0.53;
    e->globe_radius = 12;
    e->extent = 50;
    e->optical_zone = 7;
    e->fibre_band = 1.5;
    e->fibre_density = 1.91;
    e->h_optical = 0.6;
    e->h_incision = 0.4;
    e->h_cornea = 0.6;
    e->h_sclera = 2.0;
    e->nring = 1;
    strcpy(e->ring[0].name, "incision-ring-1");
    e->ring[0].diameter = 10.2;
    e->ring[0].depth_fraction = 0.9;
}

static double ellipse(double a, double b, double t) { return a * b / hypot(b * cos(t), a * sin(t)); }

/* The warp's closed forms, without a mesh. */
static void check_closed_forms(void)
{
    kt_eye eye, round;
    coarse_eye(&eye);
    round = eye;
    round.wtw_v = 0;
    kt_eye_geom g;
    kt_err e = {0};
    CHECK(kt_eye_geom_init(&eye, &g, &e) == KT_OK && g.oval, "oval geometry: %s", e.msg);
    double d = 0.5 * (eye.wtw - eye.wtw_v);
    for (int k = 0; k <= 12; k++) {
        double t = 15 * k;
        /* the corneal edge on the white-to-white ellipse; a ring of zone Z on the ellipse of
         * semi-axes Z/2 and Z/2 - d: the same distance inside the edge at 0 and 90 deg */
        CHECK_NEAR(kt_eye_oval_radius(&eye, eye.wtw, t), ellipse(5.85, 5.3, t * DEG), 1e-13, "corneal edge");
        CHECK_NEAR(kt_eye_oval_radius(&eye, 10.2, t), ellipse(5.1, 5.1 - d, t * DEG), 1e-13, "ring");
        CHECK(kt_eye_oval_radius(&round, 10.2, t) == 5.1, "round: exactly the circle");
        /* nothing moves in the optical zone */
        CHECK(kt_eye_oval_radius(&eye, eye.optical_zone, t) == 0.5 * eye.optical_zone, "optical zone untouched");
        double c = cos(t * DEG), s = sin(t * DEG);
        /* the posterior boundary of the cornea (h = 0 at the edge) and the limbus's outer edge stay */
        CHECK(kt_eye_geom_oval_shift(&g, g.rc, 0, c, s) == 0, "posterior corneal boundary round");
        CHECK(kt_eye_geom_oval_shift(&g, g.rL, 1, c, s) == 0, "limbus outer edge round");
        /* monotone along the meridian at every height: no element squeezed below KT_EYE_OVAL_KEEP */
        for (int hk = 0; hk <= 4; hk++) {
            double h = hk / 4.0, prev = -1, slope = INFINITY;
            for (int i = 0; i <= 1400; i++) {
                double xi = g.rL * i / 1400, x = xi + kt_eye_geom_oval_shift(&g, xi, h, c, s);
                if (i) slope = fmin(slope, (x - prev) / (g.rL / 1400));
                prev = x;
            }
            CHECK(slope >= KT_EYE_OVAL_KEEP - 1e-9, "meridian %g deg, height %g: slope %g", t, h, slope);
        }
    }
    CHECK_NEAR(kt_eye_oval_radius(&eye, 10.2, 90), 5.1 - d, 1e-13, "ring's vertical radius Z/2 - (wtw - wtw_v)/2");
    /* chords and arc lengths: round against the circle's, oval between its ellipse's axes */
    CHECK_NEAR(kt_eye_arc_chord(&round, 10.5, 60, 120), 10.5 * sin(30 * DEG), 1e-12, "round chord");
    CHECK_NEAR(kt_eye_arc_length(&round, 10.5, 60, 120), 5.25 * 60 * DEG, 1e-12, "round arc length");
    double r60 = ellipse(5.1, 5.1 - d, 60 * DEG);
    CHECK_NEAR(kt_eye_arc_chord(&eye, 10.2, 60, 120), 2 * r60 * cos(60 * DEG), 1e-12, "oval chord");
    double len = kt_eye_arc_length(&eye, 10.2, 60, 120);
    CHECK(len > (5.1 - d) * 60 * DEG && len < r60 * 60 * DEG, "oval arc length %g", len);
    /* refusals */
    kt_eye bad = eye;
    bad.wtw_v = 11.8;
    CHECK(kt_eye_geom_init(&bad, &g, &e) == KT_EINPUT && strstr(e.msg, "at most the horizontal"), "%s", e.msg);
    double vmin = kt_eye_wtw_v_min(&eye);
    CHECK_NEAR(vmin, 11.7 - 1.6 * (11.7 - 1.0 - 7) / 2, 1e-12, "least vertical white-to-white");
    bad.wtw_v = vmin - 0.01;
    e = (kt_err){0};
    CHECK(kt_eye_geom_init(&bad, &g, &e) == KT_EINPUT && strstr(e.msg, "expected at least"), "%s", e.msg);
    bad.wtw_v = vmin + 0.01;
    e = (kt_err){0};
    CHECK(kt_eye_geom_init(&bad, &g, &e) == KT_OK, "just above the least: %s", e.msg);
    /* an optical zone inside the rings' ellipses' reach (xi <= d: a negative semi-axis) */
    bad = eye;
    bad.optical_zone = 1.0; /* d = 0.55 mm */
    e = (kt_err){0};
    CHECK(kt_eye_geom_init(&bad, &g, &e) == KT_EINPUT && strstr(e.msg, "eye.optical_zone"), "%s", e.msg);
    bad.optical_zone = 3.0, bad.wtw_v = 8.0; /* d = 1.85 mm, a vertical the least allows */
    e = (kt_err){0};
    CHECK(kt_eye_geom_init(&bad, &g, &e) == KT_EINPUT && strstr(e.msg, "eye.optical_zone"), "%s", e.msg);
    /* a ring past the clear cornea (white_to_white - limbus_width) on an oval cornea */
    bad = eye;
    bad.ring[0].diameter = 10.9;
    double top[2], dir[2], depth;
    e = (kt_err){0};
    CHECK(kt_eye_geom_init(&bad, &g, &e) == KT_OK &&
              kt_eye_geom_ring(&g, &bad, 0, top, dir, &depth, &e) == KT_EINPUT && strstr(e.msg, "oval cornea"),
          "%s", e.msg);
}

/* The main incision's tunnel enters on the oval corneal edge (keratome-plan(5), TUNNELS). */
static void check_tunnel(void)
{
    kt_eye eye;
    coarse_eye(&eye);
    for (int k = 0; k < 4; k++) {
        kt_tunnel t = {0};
        t.meridian = 45 * k, t.width = 2.4, t.length = 2.0, t.entry_diameter = eye.wtw, t.steps = 4;
        const char *field = "";
        char msg[400] = "";
        int rc = kt_tunnel_derive(&eye, &t, &field, msg, sizeof msg);
        CHECK(rc == KT_OK, "tunnel at %g deg: %s: %s", t.meridian, field, msg);
        CHECK_NEAR(hypot(t.entry[0], t.entry[1]), ellipse(5.85, 5.3, t.meridian * DEG), 1e-12, "entry on the oval edge");
        CHECK_NEAR(atan2(t.entry[1], t.entry[0]), t.meridian * DEG, 1e-12, "entry in its meridian");
    }
}

/* Nodes of a surface group, as a 0/1 mark per node. */
static char *group_mark(const kt_mesh *m, const char *name)
{
    const kt_group *g = kt_mesh_find_group(m, 2, name);
    char *mark = calloc((size_t)m->nn, 1);
    int fv = kt_tri_nv(m->order);
    for (int i = 0; g && mark && i < m->nf; i++)
        if (m->tri_tag[i] == g->tag)
            for (int j = 0; j < fv; j++) mark[m->tri[(size_t)i * fv + j]] = 1;
    return mark;
}

static void check_mesh(void)
{
    kt_eye oval, round, same;
    coarse_eye(&oval);
    round = same = oval;
    round.wtw_v = 0;
    same.wtw_v = same.wtw;
    kt_mesh mo, mr, ms;
    kt_err e = {0};
    int ok = kt_eye_mesh(&oval, 2, 1, &mo, &e) == KT_OK;
    CHECK(ok, "oval mesh: %s", e.msg);
    ok &= kt_eye_mesh(&round, 2, 1, &mr, &e) == KT_OK;
    CHECK(ok, "round mesh: %s", e.msg);
    ok &= kt_eye_mesh(&same, 2, 1, &ms, &e) == KT_OK;
    CHECK(ok, "vertical = horizontal: %s", e.msg);
    if (!ok) return;
    /* vertical = horizontal: the round eye, to the byte */
    CHECK(ms.nn == mr.nn && ms.ne == mr.ne && ms.nf == mr.nf, "same counts");
    CHECK(ms.nn == mr.nn && memcmp(ms.xyz, mr.xyz, 3 * sizeof(double) * (size_t)mr.nn) == 0, "same coordinates");
    CHECK(ms.ne == mr.ne && memcmp(ms.tet, mr.tet, 10 * sizeof(int) * (size_t)mr.ne) == 0, "same tets");
    /* the oval moves nodes only: the same tets, the same node order */
    CHECK(mo.nn == mr.nn && mo.ne == mr.ne && memcmp(mo.tet, mr.tet, 10 * sizeof(int) * (size_t)mr.ne) == 0,
          "the oval warp keeps the connectivity");
    if (mo.nn != mr.nn) return;
    char *ant = group_mark(&mo, "anterior"), *out = group_mark(&mo, "outer"), *ring = group_mark(&mo, "incision-ring-1");
    double d = 0.5 * (oval.wtw - oval.wtw_v), worst_edge = 0, worst_ring = 0, r0 = 0.5 * oval.optical_zone;
    int nedge = 0, nring = 0, moved = 0, central = 0, central_same = 1, vtop = 0;
    for (int i = 0; i < mo.nn; i++) {
        const double *p = mo.xyz + 3 * (size_t)i, *q = mr.xyz + 3 * (size_t)i;
        double rho = hypot(p[0], p[1]), t = atan2(p[1], p[0]), rq = hypot(q[0], q[1]);
        moved += memcmp(p, q, 3 * sizeof(double)) != 0;
        if ((ant[i] && rq <= r0) || rq < 0.9 * r0) {
            central++;
            central_same &= memcmp(p, q, 3 * sizeof(double)) == 0;
        }
        if (ant[i] && out[i]) nedge++, worst_edge = fmax(worst_edge, fabs(rho - ellipse(5.85, 5.3, t)));
        if (ant[i] && ring[i]) {
            nring++, worst_ring = fmax(worst_ring, fabs(rho - ellipse(5.1, 5.1 - d, t)));
            vtop |= fabs(fabs(t) - 90 * DEG) < 5 * DEG && rho < 5.1 - 0.9 * d;
        }
    }
    CHECK(nedge > 20 && worst_edge < 1e-9, "corneal edge: %d nodes, %g mm off the white-to-white ellipse", nedge, worst_edge);
    CHECK(nring > 20 && worst_ring < 1e-9, "ring top: %d nodes, %g mm off its ellipse", nring, worst_ring);
    CHECK(vtop, "the ring is oval: its top near 90 deg lies inside Z/2 - 0.9 (wtw - wtw_v)/2");
    CHECK(central > 50 && central_same, "the central cornea (%d nodes) the same bytes as the round eye's", central);
    CHECK(moved > 100, "the oval warp moved %d nodes", moved);
    /* every anterior node still on the toric surface */
    double worst_ant = 0;
    for (int i = 0; i < mo.nn; i++)
        if (ant[i]) {
            const double *p = mo.xyz + 3 * (size_t)i;
            worst_ant = fmax(worst_ant, fabs(p[2] - kt_eye_anterior_z(&oval, p[0], p[1])));
        }
    CHECK(worst_ant < 1e-9, "anterior nodes on the toric surface within %g mm", worst_ant);
    /* the limbal weight follows the oval: near the vertical edge the lamellae have turned more
     * than at the same distance from the axis horizontally */
    double *F = malloc(13 * sizeof(double) * (size_t)mo.ne);
    const kt_group *gc = kt_mesh_find_group(&mo, 3, "cornea");
    if (F && gc && kt_eye_fibre_frames(&oval, &mo, F, &e) == KT_OK) {
        double wv = INFINITY, wh = -INFINITY;
        for (int t = 0; t < mo.ne; t++) {
            if (mo.tet_tag[t] != gc->tag) continue;
            double c[3] = {0, 0, 0};
            for (int a = 0; a < 4; a++)
                for (int k = 0; k < 3; k++) c[k] += 0.25 * mo.xyz[3 * (size_t)mo.tet[10 * (size_t)t + a] + k];
            double rho = hypot(c[0], c[1]), th = fabs(atan2(c[1], c[0])) / DEG;
            if (rho < 4.9 || rho > 5.25) continue;
            if (fabs(th - 90) < 10) wv = fmin(wv, F[13 * (size_t)t + 12]);
            if (th < 10 || th > 170) wh = fmax(wh, F[13 * (size_t)t + 12]);
        }
        CHECK(isfinite(wv) && isfinite(wh) && wv > wh, "limbal weight vertical %g > horizontal %g at 4.9-5.25 mm", wv, wh);
    } else {
        CHECK(0, "fibre frames: %s", e.msg);
    }
    free(F);
    free(ant);
    free(out);
    free(ring);
    kt_mesh_free(&mo);
    kt_mesh_free(&mr);
    kt_mesh_free(&ms);
}

int main(void)
{
    check_closed_forms();
    check_tunnel();
    check_mesh();
    return kt_test_done("test_eye_oval");
}
