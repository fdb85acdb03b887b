/* test_measured_eye.c: the patient's own cornea in the mesh, on plans/patients/asym-od.yaml (its
 * Pentacam export: plans/patients/pentacam-asym-front.csv, -back.csv, -pachy.csv). The maps are
 * fitted as lri-plan fits them (kt_surffit_elevation, _pachymetry), the patient's scene made from
 * plans/eye.yaml (coarse sizes), the measured surfaces put in (kt_surffit_measured_eye) and the
 * eye meshed at order 2 (every curved tet's Jacobian positive: kt_eye_check_curved). Then, inside
 * the 8 mm zone:
 *  - the mesh's anterior nodes against the map (the map's height at a node: a local cubic
 *    least-squares fit of the measured cells within 0.35 mm), up to a plane (the map's
 *    decentration, left out of the mesh): within the departure fit's largest residual plus
 *    0.02 um (the interpolation);
 *  - keratometry as curvature(1) reads it (the toric fit over the 3 mm zone, kt_curv_simk) on the
 *    mesh's anterior nodes against the same on the map less that plane sampled at the nodes:
 *    within 0.005 D and 0.1 deg (the map on its own grid, as measured, and the toric mesh of
 *    before printed beside);
 *  - the half-meridians (kt_surffit_halves) of the mesh's anterior surface and of the map less
 *    its plane, both sampled on the device's grid by a local quadratic fit within 0.5 mm: each
 *    half's astigmatism within 0.05 D; the halves differ by more than 0.5 D, where the toric
 *    mesh of before (the same nodes on the fitted toric) had them within 0.1 D.
 * The figures are printed (keratome-patient(5), THE FIT). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "eye.h"
#include "kt_test.h"
#include "scene.h"
#include "surffit.h"

#include "kt_test_gmsh.h"

/* Solve the n x n normal equations A x = b (Cholesky; n <= 10); -1 when not positive. */
static int chol_solve(int n, double A[10][10], double b[10], double x[10])
{
    for (int j = 0; j < n; j++) {
        for (int k = 0; k < j; k++) A[j][j] -= A[j][k] * A[j][k];
        if (!(A[j][j] > 0)) return -1;
        A[j][j] = sqrt(A[j][j]);
        for (int i = j + 1; i < n; i++) {
            for (int k = 0; k < j; k++) A[i][j] -= A[i][k] * A[j][k];
            A[i][j] /= A[j][j];
        }
    }
    for (int i = 0; i < n; i++) {
        double s = b[i];
        for (int k = 0; k < i; k++) s -= A[i][k] * x[k];
        x[i] = s / A[i][i];
    }
    for (int i = n - 1; i >= 0; i--) {
        double s = x[i];
        for (int k = i + 1; k < n; k++) s -= A[k][i] * x[k];
        x[i] = s / A[i][i];
    }
    return 0;
}

/* The value at (x0, y0) of the least-squares polynomial of degree deg (2 or 3) in (x - x0, y -
 * y0) through the points p[3 i] within radius r; NAN when too few. */
static double local_fit(const double *p, int n, double x0, double y0, double r, int deg)
{
    int nb = deg == 3 ? 10 : 6, used = 0;
    double A[10][10] = {{0}}, b[10] = {0}, c[10];
    for (int i = 0; i < n; i++) {
        double dx = p[3 * i] - x0, dy = p[3 * i + 1] - y0;
        if (dx * dx + dy * dy > r * r) continue;
        double f[10] = {1, dx, dy, dx * dx, dx * dy, dy * dy, dx * dx * dx, dx * dx * dy, dx * dy * dy, dy * dy * dy};
        for (int a = 0; a < nb; a++) {
            b[a] += f[a] * p[3 * i + 2];
            for (int k = 0; k <= a; k++) A[a][k] += f[a] * f[k];
        }
        used++;
    }
    if (used < nb + 4 || chol_solve(nb, A, b, c) != 0) return NAN;
    return c[0];
}

/* The map's measured cells as (x, y, value) within radius rmax of the centre. */
static int map_cells(const kt_pentacam_map *m, double rmax, double *p)
{
    int k = 0;
    for (int j = 0; j < m->n; j++)
        for (int i = 0; i < m->n; i++) {
            double v = m->v[j * m->n + i], x = kt_pentacam_coord(i), y = kt_pentacam_coord(j);
            if (isnan(v) || hypot(x, y) > rmax) continue;
            p[3 * k] = x, p[3 * k + 1] = y, p[3 * k + 2] = v;
            k++;
        }
    return k;
}

/* Keratometry over the 3 mm zone of points (x, y, height). */
static int kerato(const double *xyz, int n, kt_kerato *k)
{
    kt_fit f;
    kt_err e = {0};
    if (kt_curv_fit(xyz, n, KT_FIT_TORIC, 2, 3.0, 0, 0, &f, NULL, 0, &e) != KT_OK) return -1;
    kt_curv_simk(&f, k);
    return 0;
}

/* The half-meridians of a surface given as sags at points (x, y, sag): sampled on the device's
 * grid within 4.5 mm, fitted as lri-plan fits a map. */
static int halves_of(const double *sag, int n, kt_halfmer *h)
{
    kt_pentacam_map m;
    memset(&m, 0, sizeof m);
    m.kind = KT_PENTACAM_ELEVATION, m.n = KT_PENTACAM_N;
    kt_err e = {0};
    m.v = malloc(sizeof(double) * KT_PENTACAM_N * KT_PENTACAM_N);
    if (!m.v) return -1;
    for (int j = 0; j < m.n; j++)
        for (int i = 0; i < m.n; i++) {
            double x = kt_pentacam_coord(i), y = kt_pentacam_coord(j);
            double v = hypot(x, y) <= 4.5 ? local_fit(sag, n, x, y, 0.5, 2) : NAN;
            m.v[j * m.n + i] = v;
            m.nvalid += !isnan(v);
        }
    kt_surffit f;
    int rc = kt_surffit_elevation(&m, KT_SURFFIT_ZONE, &f, &e) || kt_surffit_halves(&m, &f, h, &e);
    if (rc) fprintf(stderr, "halves: %s\n", e.msg);
    free(m.v);
    return rc;
}

/* The patient's fits as lri-plan makes them (lib/planner/lp_patient.c, fit_pentacam). */
static int fit_patient(kt_patient *p, kt_surffit *fa, kt_surffit *fp, kt_pentacam_map *front, kt_err *e)
{
    kt_pentacam_map m;
    if (kt_pentacam_read(p->pentacam_front, KT_PENTACAM_ELEVATION, front, e) ||
        kt_surffit_elevation(front, KT_SURFFIT_ZONE, fa, e))
        return e->code;
    p->ant.r_steep = fa->r_steep, p->ant.r_flat = fa->r_flat, p->ant.axis = fa->axis, p->ant.conic = fa->conic;
    if (kt_pentacam_read(p->pentacam_back, KT_PENTACAM_ELEVATION, &m, e)) return e->code;
    int rc = kt_surffit_elevation(&m, KT_SURFFIT_ZONE, fp, e);
    kt_pentacam_free(&m);
    if (rc) return rc;
    p->post.r_steep = fp->r_steep, p->post.r_flat = fp->r_flat, p->post.axis = fp->axis, p->post.conic = fp->conic;
    kt_pachyfit pf;
    if (kt_pentacam_read(p->pentacam_pachy, KT_PENTACAM_PACHYMETRY, &m, e)) return e->code;
    rc = kt_surffit_pachymetry(&m, fa->ax, fa->ay, p->zone / 2 + 0.5, &pf, e);
    kt_pentacam_free(&m);
    p->t_central = pf.t0, p->t_zone = kt_pachyfit_at(&pf, p->zone / 2);
    return rc;
}

static void test_asym(void)
{
    kt_patient p;
    kt_scene *base = calloc(1, sizeof *base), *s = calloc(1, sizeof *s);
    kt_surffit fa, fp;
    kt_pentacam_map front;
    kt_mesh m;
    kt_err e = {0};
    int rc = base && s ? kt_patient_load("plans/patients/asym-od.yaml", &p, &e) : KT_ERUN;
    if (rc == KT_OK) rc = fit_patient(&p, &fa, &fp, &front, &e);
    if (rc == KT_OK) rc = kt_scene_load("plans/eye.yaml", base, &e);
    if (rc == KT_OK) rc = kt_patient_scene(&p, base, s, &e);
    if (rc == KT_OK) {
        s->eye.h_optical = 0.5, s->eye.h_incision = 0.6, s->eye.h_cornea = 0.8, s->eye.h_sclera = 3, s->eye.h_floor = 0;
        rc = kt_surffit_measured_eye(&p, &s->eye, &fa, &fp, &e);
    }
    if (rc == KT_OK) rc = kt_eye_mesh(&s->eye, 2, 1, &m, &e);
    CHECK(rc == KT_OK, "asym-od meshed with its measured surfaces (curved tets valid): %s", e.msg);
    if (rc) return;
    printf("asym-od: departure order %d, anterior residual rms %.4f um, max %.4f um (%d cells); posterior %.4f / "
           "%.4f um\n", fa.dep_order, 1000 * fa.dep_rms, 1000 * fa.dep_max, fa.dep_npts, 1000 * fp.dep_rms,
           1000 * fp.dep_max);
    for (int k = 0; k < 2; k++) {
        const kt_eye_departure *dd = k ? &s->eye.dep_post : &s->eye.dep_ant;
        double poly[KT_ZERN_NP * KT_ZERN_NP], din = 0, dout = 0;
        kt_eye_departure_poly(dd, poly);
        for (double r = 0; r < dd->taper; r += 0.05)
            for (int t = 0; t < 180; t++) {
                double v = fabs(kt_eye_departure_at(dd, poly, r * cos(t * KT_PI / 90), r * sin(t * KT_PI / 90)));
                if (r <= dd->radius) din = fmax(din, v);
                else dout = fmax(dout, v);
            }
        printf("asym-od: %s departure: largest %.2f um in the zone, %.2f um in the taper (%.2f ... %.2f mm); base Q %.4f\n",
               k ? "posterior" : "anterior", 1000 * din, 1000 * dout, dd->radius, dd->taper, dd->conic);
    }
    kt_eye_geom g;
    kt_eye_geom_init(&s->eye, &g, &e);
    int *an = NULL, na = 0;
    kt_mesh_group_nodes(&m, kt_mesh_find_group(&m, 2, "anterior"), &an, &na, &e);
    double *cells = malloc(sizeof(double) * 3 * KT_PENTACAM_N * KT_PENTACAM_N), *node = malloc(sizeof(double) * 3 * na);
    double *sag = malloc(sizeof(double) * 3 * na), *toric = malloc(sizeof(double) * 3 * na);
    int nc = map_cells(&front, 6.5, cells), nn = 0;
    /* Nodes within 5.5 mm: (x, y, z) as the mesh has them, their sags, the toric mesh's sags. */
    for (int k = 0; k < na; k++) {
        const double *q = m.xyz + 3 * (size_t)an[k];
        if (hypot(q[0], q[1]) > 5.5) continue;
        memcpy(node + 3 * nn, q, 3 * sizeof(double));
        sag[3 * nn] = toric[3 * nn] = q[0], sag[3 * nn + 1] = toric[3 * nn + 1] = q[1];
        sag[3 * nn + 2] = kt_eye_base_apex(&g, &s->eye) - q[2];
        toric[3 * nn + 2] = g.z_apex - kt_eye_geom_toric_z(&g, q[0], q[1]);
        nn++;
    }
    /* The nodes against the map, up to a plane: least squares d = p0 + p1 x + p2 y. */
    double A[10][10] = {{0}}, b[10] = {0}, pl[10] = {0}, *d = malloc(sizeof(double) * nn);
    int nz = 0;
    for (int k = 0; k < nn; k++) {
        double x = node[3 * k], y = node[3 * k + 1];
        d[k] = NAN;
        if (hypot(x, y) > 0.5 * KT_SURFFIT_ZONE - 0.1) continue;
        double v = local_fit(cells, nc, x, y, 0.35, 3);
        if (isnan(v)) continue;
        d[k] = sag[3 * k + 2] - v;
        double f[3] = {1, x, y};
        for (int i = 0; i < 3; i++) {
            b[i] += f[i] * d[k];
            for (int j = 0; j <= i; j++) A[i][j] += f[i] * f[j];
        }
        nz++;
    }
    chol_solve(3, A, b, pl);
    double ss = 0, mx = 0;
    for (int k = 0; k < nn; k++) {
        if (isnan(d[k])) continue;
        double r = d[k] - pl[0] - pl[1] * node[3 * k] - pl[2] * node[3 * k + 1];
        ss += r * r, mx = fmax(mx, fabs(r));
    }
    printf("asym-od: %d anterior nodes in the zone against the map: rms %.4f um, max %.4f um (the plane left out: "
           "%.2f um, tilt %.3f / %.3f mrad)\n", nz, 1000 * sqrt(ss / nz), 1000 * mx, 1000 * pl[0], 1000 * pl[1], 1000 * pl[2]);
    CHECK(nz > 300 && mx < fa.dep_max + 2e-5, "the mesh's anterior surface matches the map: max %.4f um (fit's %.4f um)",
          1000 * mx, 1000 * fa.dep_max);
    /* The map as the mesh carries it: less its decentration (the plane): sag + plane. */
    double *flat = malloc(sizeof(double) * 3 * nc), *neg = malloc(sizeof(double) * 3 * nc);
    for (int k = 0; k < nc; k++) {
        double x = cells[3 * k], y = cells[3 * k + 1];
        flat[3 * k] = neg[3 * k] = x, flat[3 * k + 1] = neg[3 * k + 1] = y;
        flat[3 * k + 2] = cells[3 * k + 2] + pl[0] + pl[1] * x + pl[2] * y;
        neg[3 * k + 2] = -flat[3 * k + 2];
    }
    /* Keratometry on the mesh against the map's own, sampled at the same points: the map less
     * its plane at the nodes within 2.5 mm (a toric fit to a surface that is not toric depends on
     * where it is sampled: the map's grid gives its figures too). */
    kt_kerato km, kmap, kgrid, kraw, kold;
    double *at = malloc(sizeof(double) * 3 * nn);
    int nat = 0;
    for (int k = 0; k < nn; k++) {
        double x = node[3 * k], y = node[3 * k + 1];
        if (hypot(x, y) > 2.5) continue;
        at[3 * nat] = x, at[3 * nat + 1] = y, at[3 * nat + 2] = -local_fit(flat, nc, x, y, 0.35, 3);
        nat++;
    }
    for (int k = 0; k < nn; k++) toric[3 * k + 2] = -toric[3 * k + 2];
    CHECK(kerato(node, nn, &km) == 0 && kerato(at, nat, &kmap) == 0 && kerato(neg, nc, &kgrid) == 0 &&
          kerato(toric, nn, &kold) == 0, "keratometry");
    free(at);
    for (int k = 0; k < nn; k++) toric[3 * k + 2] = -toric[3 * k + 2];
    for (int k = 0; k < nc; k++) neg[3 * k + 2] = -cells[3 * k + 2];
    kerato(neg, nc, &kraw);
    printf("asym-od: K over 3 mm (toric fit): mesh %.3f / %.3f D @ %.2f, map less its tilt at the nodes %.3f / %.3f D "
           "@ %.2f, on its grid %.3f / %.3f D @ %.2f, map as measured (grid) %.3f / %.3f D @ %.2f, toric mesh %.3f / %.3f D "
           "@ %.2f; the 8 mm fit's apex K %.3f / %.3f D @ %.2f\n", km.k_steep, km.k_flat, km.axis_steep, kmap.k_steep,
           kmap.k_flat, kmap.axis_steep, kgrid.k_steep, kgrid.k_flat, kgrid.axis_steep, kraw.k_steep, kraw.k_flat,
           kraw.axis_steep, kold.k_steep, kold.k_flat, kold.axis_steep, 337.5 / fa.r_steep, 337.5 / fa.r_flat, fa.axis);
    CHECK(fabs(km.k_steep - kmap.k_steep) < 0.005 && fabs(km.k_flat - kmap.k_flat) < 0.005 &&
          fabs(km.axis_steep - kmap.axis_steep) < 0.1, "the mesh's K is the map's");
    /* The half-meridians, both surfaces sampled the same way. */
    kt_halfmer hmap, hmesh, hold;
    CHECK(halves_of(flat, nc, &hmap) == 0 && halves_of(sag, nn, &hmesh) == 0 && halves_of(toric, nn, &hold) == 0,
          "half-meridians");
    printf("asym-od: half-meridian astigmatism (axis / axis + 180): map less its tilt %.3f / %.3f D, mesh %.3f / %.3f D, "
           "toric mesh %.3f / %.3f D\n", hmap.k_a - hmap.k_flat, hmap.k_b - hmap.k_flat, hmesh.k_a - hmesh.k_flat,
           hmesh.k_b - hmesh.k_flat, hold.k_a - hold.k_flat, hold.k_b - hold.k_flat);
    CHECK(fabs((hmesh.k_a - hmesh.k_flat) - (hmap.k_a - hmap.k_flat)) < 0.05 &&
          fabs((hmesh.k_b - hmesh.k_flat) - (hmap.k_b - hmap.k_flat)) < 0.05, "the mesh carries the map's halves");
    CHECK(hmesh.k_b - hmesh.k_a > 0.5 && fabs(hold.k_a - hold.k_b) < 0.1, "the halves differ by %.3f D (the toric mesh: %.3f D)",
          hmesh.k_b - hmesh.k_a, hold.k_b - hold.k_a);
    free(an), free(cells), free(node), free(sag), free(toric), free(d), free(neg), free(flat);
    kt_mesh_free(&m);
    kt_pentacam_free(&front);
    free(base), free(s);
}

int main(void)
{
    test_asym();
    return kt_test_done("test_measured_eye");
}
