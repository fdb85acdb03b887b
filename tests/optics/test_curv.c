/* test_curv.c: keratometry of synthetic corneal surfaces (node clouds, no solver), Alpins vector
 * analysis against a hand-worked example, and surface extraction from a cut tet mesh.
 *
 * `test_curv --make-run DIR` instead writes a synthetic run folder (MSH mesh, step VTKs, run.yaml,
 * plan) for tests/curvature_pipeline.sh; see make_run below. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "curv.h"
#include "grid.h"
#include "kt_test.h"
#include "msh.h"
#include "vtk.h"

#define DEG KT_CURV_DEG

/* A deterministic jitter in [-0.5, 0.5) (LCG; no library rand so results are reproducible). */
static double jitter(unsigned *s)
{
    *s = *s * 1664525u + 1013904223u;
    return (double)(*s >> 8) / 16777216.0 - 0.5;
}

/* Surfaces z(x, y) with apex at (x0, y0, z0). */
typedef struct surf_def {
    int kind;            /* 0 sphere, 1 torus, 2 biconic (conic 0) */
    double rs, rf;       /* steep and flat radius, mm */
    double axis;         /* steep meridian, deg */
    double x0, y0, z0;
} surf_def;

/* Torus: the generating circle of radius rs lies in the steep meridian's plane, revolved about
 * an axis along that meridian rf below the apex, so the two principal sections through the
 * apex are circles of radii rs and rf. */
static double surf_z(const surf_def *d, double x, double y)
{
    double dx = x - d->x0, dy = y - d->y0;
    double c = cos(d->axis * DEG), s = sin(d->axis * DEG);
    double xs = dx * c + dy * s, yf = -dx * s + dy * c; /* along steep, along flat */
    if (d->kind == 0) return d->z0 - d->rs + sqrt(d->rs * d->rs - dx * dx - dy * dy);
    if (d->kind == 1) {
        double rho = d->rf - d->rs + sqrt(d->rs * d->rs - xs * xs);
        return d->z0 - d->rf + sqrt(rho * rho - yf * yf);
    }
    double cs = 1 / d->rs, cf = 1 / d->rf, q1 = cs * xs * xs + cf * yf * yf;
    return d->z0 - q1 / (1 + sqrt(1 - cs * cs * xs * xs - cf * cf * yf * yf));
}

/* A jittered triangular lattice of spacing h over the disk of radius rmax around the apex. */
static double *cloud(const surf_def *d, double h, double rmax, int *n)
{
    int cap = (int)(4 * rmax * rmax / (h * h) * 1.3) + 16, k = 0;
    double *xyz = malloc(sizeof(double) * 3 * cap);
    unsigned seed = 12345;
    for (int j = -(int)(rmax / h) - 1; j <= (int)(rmax / h) + 1; j++)
        for (int i = -(int)(rmax / h) - 2; i <= (int)(rmax / h) + 2; i++) {
            double x = (i + 0.5 * (j & 1) + 0.3 * jitter(&seed)) * h;
            double y = (j * 0.8660254 + 0.3 * jitter(&seed)) * h;
            if (x * x + y * y > rmax * rmax || k == cap) continue;
            xyz[3 * k] = d->x0 + x, xyz[3 * k + 1] = d->y0 + y;
            xyz[3 * k + 2] = surf_z(d, d->x0 + x, d->y0 + y);
            k++;
        }
    *n = k;
    return xyz;
}

/* Angle difference modulo 180, in (-90, 90]. */
static double axis_diff(double a, double b)
{
    double d = fmod(a - b, 180);
    if (d > 90) d -= 180;
    if (d <= -90) d += 180;
    return d;
}

/* Worst errors by fit (index KT_FIT_ZERNIKE or KT_FIT_TORIC), for the report. */
static double worst_dk[3], worst_cyl_sphere[3], worst_daxis[3], worst_dk_toric[3];

static void check_surface(const surf_def *d, int fit, int order, double zone, const char *what)
{
    kt_err e = {0};
    int n;
    double *xyz = cloud(d, 0.12, zone / 2 + 1.0, &n);
    kt_fit f;
    kt_kerato k;
    /* start the fit off-centre: the apex search must find (x0, y0) */
    int rc = kt_curv_fit(xyz, n, fit, order, zone, d->x0 + 0.2, d->y0 - 0.15, &f, NULL, 0, &e);
    CHECK(rc == KT_OK, "%s: %s", what, e.msg);
    if (rc != KT_OK) {
        free(xyz);
        return;
    }
    kt_curv_simk(&f, &k);
    double ks = KT_CURV_N_KERATO / d->rs, kf = KT_CURV_N_KERATO / d->rf;
    CHECK(hypot(f.ax - d->x0, f.ay - d->y0) < 1e-3, "%s: apex (%g, %g) vs (%g, %g)", what, f.ax,
          f.ay, d->x0, d->y0);
    if (d->kind == 0) {
        CHECK(fabs(k.k_steep - ks) < 0.01 && fabs(k.k_flat - ks) < 0.01,
              "%s: K %.5f / %.5f vs %.5f", what, k.k_steep, k.k_flat, ks);
        CHECK(fabs(k.cyl) < 0.01, "%s: cylinder %.5f", what, k.cyl);
        worst_dk[fit] = fmax(worst_dk[fit], fmax(fabs(k.k_steep - ks), fabs(k.k_flat - ks)));
        worst_cyl_sphere[fit] = fmax(worst_cyl_sphere[fit], fabs(k.cyl));
    } else {
        CHECK(fabs(k.k_steep - ks) < 0.02 && fabs(k.k_flat - kf) < 0.02,
              "%s: K %.5f / %.5f vs %.5f / %.5f", what, k.k_steep, k.k_flat, ks, kf);
        CHECK(fabs(k.cyl - (ks - kf)) < 0.02, "%s: cyl %.5f vs %.5f", what, k.cyl, ks - kf);
        CHECK(fabs(axis_diff(k.axis_steep, d->axis)) < 1.0, "%s: axis %.4f vs %.4f", what,
              k.axis_steep, d->axis);
        CHECK(k.axis_steep >= 0 && k.axis_steep < 180, "%s: axis %.4f outside [0, 180)", what,
              k.axis_steep);
        worst_dk_toric[fit] = fmax(worst_dk_toric[fit], fmax(fabs(k.k_steep - ks), fabs(k.k_flat - kf)));
        worst_daxis[fit] = fmax(worst_daxis[fit], fabs(axis_diff(k.axis_steep, d->axis)));
    }
    free(xyz);
}

static void test_keratometry(void)
{
    static const double zones[] = {3, 5, 7};
    static const double axes[] = {0, 0.4, 30, 45, 90, 91, 135, 179.6};
    char what[160];
    for (int fit = KT_FIT_ZERNIKE; fit <= KT_FIT_TORIC; fit++)
        for (int z = 0; z < 3; z++) {
            const char *fn = fit == KT_FIT_ZERNIKE ? "zernike" : "toric";
            surf_def sph = {0, 7.8, 7.8, 0, 0.11, -0.07, 0.6};
            snprintf(what, sizeof what, "sphere R 7.8, %s, zone %g", fn, zones[z]);
            check_surface(&sph, fit, 6, zones[z], what);
            for (int a = 0; a < 8; a++) {
                surf_def tor = {1, 7.6, 7.9, axes[a], -0.05, 0.08, 0.55};
                snprintf(what, sizeof what, "torus 7.6/7.9 @ %g, %s, zone %g", axes[a], fn, zones[z]);
                check_surface(&tor, fit, 6, zones[z], what);
            }
            surf_def bic = {2, 7.5, 8.0, 120, 0, 0, 0.5};
            snprintf(what, sizeof what, "biconic 7.5/8.0 @ 120, %s, zone %g", fn, zones[z]);
            check_surface(&bic, fit, 6, zones[z], what);
        }
    for (int fit = KT_FIT_ZERNIKE; fit <= KT_FIT_TORIC; fit++)
        printf("%s fit, zones 3/5/7 mm: sphere worst |K - 337.5/R| %.1e D, |cyl| %.1e D; torus and "
               "biconic worst |K - 337.5/R| %.1e D, axis %.1e deg\n",
               fit == KT_FIT_ZERNIKE ? "Zernike order 6" : "toric", worst_dk[fit], worst_cyl_sphere[fit],
               worst_dk_toric[fit], worst_daxis[fit]);

    /* Axial power of a sphere is 337.5/R everywhere (the normal passes through the centre). */
    surf_def sph = {0, 8.0, 8.0, 0, 0, 0, 0};
    int n;
    double *xyz = cloud(&sph, 0.12, 4.5, &n);
    kt_err e = {0};
    kt_fit f;
    CHECK(kt_curv_fit(xyz, n, KT_FIT_ZERNIKE, 8, 8.0, 0, 0, &f, NULL, 0, &e) == KT_OK, "%s", e.msg);
    double worst = 0;
    for (int i = 0; i <= 20; i++) {
        double r = 3.8 * i / 20, t = 37 * i;
        worst = fmax(worst, fabs(kt_fit_axial_power(&f, r * cos(t * DEG), r * sin(t * DEG)) - 337.5 / 8.0));
    }
    CHECK(worst < 0.01, "sphere axial power off by %g D", worst);
    printf("sphere R 8, 8 mm map fit (order 8): worst axial power error %.2e D, fit rms %.2e um\n",
           worst, 1000 * f.rms);

    /* Best-fit sphere of a spherical cap. */
    double c[3], R;
    CHECK(kt_curv_sphere_fit(xyz, n, c, &R, &e) == KT_OK, "%s", e.msg);
    CHECK_NEAR(R, 8.0, 1e-9, "best-fit sphere radius");
    CHECK(fabs(c[2] + 8.0) < 1e-9, "best-fit sphere centre z %g", c[2]);
    free(xyz);

    /* Too few points in the zone: a run-time error, not a silent answer. */
    double few[3 * 5] = {0, 0, 0, 0.1, 0, 0, 0, 0.1, 0, -0.1, 0, 0, 0, -0.1, 0};
    kt_err e2 = {0};
    CHECK(kt_curv_fit(few, 5, KT_FIT_ZERNIKE, 6, 3, 0, 0, &f, NULL, 0, &e2) == KT_ERUN, "few points");
}

/* Finite element surfaces are rough: the demo eye's 3 mm zone fits leave about 0.9 um RMS.
 * With that much white noise on a 0.25 mm lattice (about 90 nodes in the zone) the toric fit,
 * the default, must scatter less than a Zernike order-6 fit, which follows the noise. */
static double gauss(unsigned *s)
{
    double u1 = jitter(s) + 0.5 + 1e-9, u2 = jitter(s) + 0.5;
    return sqrt(-2 * log(u1)) * cos(2 * KT_CURV_PI * u2);
}

static void test_noise(void)
{
    const int kinds[2] = {KT_FIT_TORIC, KT_FIT_ZERNIKE};
    double cyl_rms[2] = {0, 0}, ntrial = 20;
    surf_def d = {1, 7.6, 7.9, 90, 0, 0, 0};
    double cyl = KT_CURV_N_KERATO / d.rs - KT_CURV_N_KERATO / d.rf;
    for (int f = 0; f < 2; f++)
        for (int t = 0; t < ntrial; t++) {
            int n;
            double *xyz = cloud(&d, 0.25, 2.5, &n);
            unsigned seed = 99 + 31 * t;
            for (int i = 0; i < n; i++) xyz[3 * i + 2] += 0.0009 * gauss(&seed);
            kt_fit fit;
            kt_kerato k;
            kt_err e = {0};
            CHECK(kt_curv_fit(xyz, n, kinds[f], 6, 3.0, 0, 0, &fit, NULL, 0, &e) == KT_OK, "%s", e.msg);
            kt_curv_simk(&fit, &k);
            cyl_rms[f] += (k.cyl - cyl) * (k.cyl - cyl) / ntrial;
            free(xyz);
        }
    cyl_rms[0] = sqrt(cyl_rms[0]), cyl_rms[1] = sqrt(cyl_rms[1]);
    printf("0.9 um noise, 3 mm zone: cylinder RMS error toric %.3f D, Zernike order 6 %.3f D\n",
           cyl_rms[0], cyl_rms[1]);
    CHECK(cyl_rms[0] < 0.2 && cyl_rms[0] < 0.6 * cyl_rms[1], "toric %.3f vs zernike %.3f", cyl_rms[0],
          cyl_rms[1]);
}

/* Alpins vector analysis, worked by hand on the double-angle plane (method: Alpins NA, "A new
 * method of analyzing vectors for changes in astigmatism", J Cataract Refract Surg 1993;
 * 19:524-533, and Alpins & Goggin, Surv Ophthalmol 2004;49:109-122; the numbers are ours):
 *   pre    2.00 D @ 90  -> double angle 180 deg -> (-2.00, 0.00)
 *   post   1.00 D @ 45  -> double angle  90 deg -> ( 0.00, 1.00)
 *   SIA = post - pre = (2.00, 1.00): |SIA| = sqrt 5 = 2.2361 D,
 *         double angle atan(1/2) = 26.565 deg -> axis 13.2825 deg
 *   TIA (target: 0.50 D @ 90, i.e. induce (-0.50, 0) - (-2.00, 0) = (1.50, 0)) = 1.50 D @ 0
 *   DV = TIA - SIA = (-0.50, -1.00): |DV| = sqrt 1.25 = 1.1180 D,
 *         double angle 180 + 63.435 = 243.435 deg -> axis 121.7175 deg
 *   CI = 2.2361 / 1.50 = 1.4907; AE = 13.2825 - 0 = +13.2825 deg (counter-clockwise);
 *   ME = 2.2361 - 1.50 = 0.7361 D; IOS = 1.1180 / 1.50 = 0.7454. */
static void test_alpins(void)
{
    kt_astig pre = {2.0, 90}, post = {1.0, 45}, tia = {1.5, 0};
    kt_alpins a;
    kt_curv_alpins(pre, post, &tia, &a);
    CHECK_NEAR(a.sia.mag, 2.2360680, 1e-6, "SIA magnitude");
    CHECK_NEAR(a.sia.axis, 13.2825256, 1e-6, "SIA axis");
    CHECK_NEAR(a.dv.mag, 1.1180340, 1e-6, "DV magnitude");
    CHECK_NEAR(a.dv.axis, 121.7174744, 1e-6, "DV axis");
    CHECK_NEAR(a.ci, 1.4907120, 1e-6, "correction index");
    CHECK_NEAR(a.ae, 13.2825256, 1e-6, "angle of error");
    CHECK_NEAR(a.me, 0.7360680, 1e-6, "magnitude of error");
    CHECK_NEAR(a.ios, 0.7453560, 1e-6, "index of success");

    /* An on-axis LRI on 1.50 D @ 90 that leaves 0.25 D @ 90: SIA 1.25 D @ 180 (0 here). */
    kt_astig p0 = {1.5, 90}, p1 = {0.25, 90};
    kt_curv_alpins(p0, p1, NULL, &a);
    CHECK_NEAR(a.sia.mag, 1.25, 1e-12, "on-axis SIA");
    CHECK(fabs(axis_diff(a.sia.axis, 0)) < 1e-9, "on-axis SIA axis %g", a.sia.axis);
    CHECK(isnan(a.ci) && isnan(a.tia.mag), "no target: NaN indices");

    /* Axes wrap: 179 and 1 deg are 2 deg apart; their double-angle difference is small. */
    kt_astig q0 = {1.0, 179}, q1 = {1.0, 1};
    kt_curv_alpins(q0, q1, NULL, &a);
    CHECK_NEAR(a.sia.mag, 2 * sin(2 * DEG), 1e-12, "wrap SIA magnitude");
    CHECK(fabs(axis_diff(a.sia.axis, 45)) < 1e-9, "wrap SIA axis %g", a.sia.axis);
}

/* ---------------------------------------------------------------- synthetic run folder */

/* The synthetic eye of the pipeline test: a 0.5 mm shell over [-4, 4]^2 whose top (group
 * "anterior") is the torus of step k: steep radius 7.6 + 0.05 k at 90 deg (the incised
 * meridian flattens), flat radius 7.9 - 0.03 k at 0 deg (the orthogonal one steepens). */
static surf_def run_surface(int k)
{
    surf_def d = {1, 7.6 + 0.05 * k, 7.9 - 0.03 * k, 90, 0, 0, 0};
    return d;
}

/* Step k's mesh: from step 1 on, a crack in the plane y = 3 for -1 < x < 1 through the whole
 * thickness: its nodes are duplicated for the tets on the y > 3 side (as cutplan does), so
 * the step mesh has more nodes than the input mesh and boundary faces inside the volume. */
static int crack_mesh(const kt_mesh *m, int k, kt_mesh *mk, double **origin, kt_err *e)
{
    if (kt_mesh_copy(mk, m, e)) return e->code;
    int nv = kt_tet_nv(m->order), *dup = calloc(m->nn, sizeof(int)), nn = m->nn;
    for (int i = 0; k > 0 && i < m->nn; i++) {
        const double *q = m->xyz + 3 * i;
        if (fabs(q[1] - 3.0) < 1e-9 && q[0] > -1 + 1e-9 && q[0] < 1 - 1e-9) dup[i] = ++nn;
    }
    mk->xyz = realloc(mk->xyz, sizeof(double) * 3 * nn);
    *origin = malloc(sizeof(double) * nn);
    for (int i = 0; i < m->nn; i++) {
        (*origin)[i] = i + 1;
        if (dup[i]) {
            memcpy(mk->xyz + 3 * (dup[i] - 1), m->xyz + 3 * i, 3 * sizeof(double));
            (*origin)[dup[i] - 1] = i + 1;
        }
    }
    for (int t = 0; t < m->ne; t++) {
        int *tn = mk->tet + (size_t)nv * t;
        double cy = 0;
        for (int j = 0; j < 4; j++) cy += m->xyz[3 * tn[j] + 1] / 4;
        if (cy <= 3.0) continue;
        for (int j = 0; j < nv; j++)
            if (dup[tn[j]]) tn[j] = dup[tn[j]] - 1;
    }
    mk->nn = nn;
    free(dup);
    return KT_OK;
}

static int make_run(const char *dir, int order, const char *drop, int no_anterior, int nsteps)
{
    kt_err e = {0};
    kt_mesh m;
    char path[4096];
    if (kt_mkdir_p(dir, &e) || kt_grid_box(&m, 41, 41, 3, 8.0, 8.0, 0.5, &e)) goto fail;
    for (int i = 0; i < m.ng; i++)
        if (m.group[i].dim == 2 && strcmp(m.group[i].name, "zmax") == 0)
            strcpy(m.group[i].name, no_anterior ? "front" : "anterior");
    if (order == 2 && kt_mesh_elevate(&m, &e)) goto fail;
    surf_def d0 = run_surface(0);
    for (int i = 0; i < m.nn; i++) {
        double *q = m.xyz + 3 * i;
        q[0] -= 4, q[1] -= 4;
        q[2] = surf_z(&d0, q[0], q[1]) - 0.5 + q[2];
    }
    snprintf(path, sizeof path, "%s/eye.msh", dir);
    if (kt_msh_write(path, &m, 0, &e)) goto fail;
    kt_mesh back; /* the hash of the mesh as curvature reads it */
    if (kt_msh_read(path, &back, &e)) goto fail;
    unsigned long long hash = kt_mesh_hash(&back);
    kt_mesh_free(&back);
    FILE *f;
    snprintf(path, sizeof path, "%s/run.yaml", dir);
    f = fopen(path, "w");
    fprintf(f, "mesh: %s/eye.msh\nmethod: augmented\norder: %d\nsteps: %d\nmesh_hash: \"%016llx\"\n",
            dir, order, nsteps, hash);
    fclose(f);
    snprintf(path, sizeof path, "%s/steps.tsv", dir);
    f = fopen(path, "w");
    fprintf(f, "step\tn_dofs\n");
    for (int k = 0; k <= nsteps; k++) fprintf(f, "%d\t%d\n", k, 3 * m.nn);
    fclose(f);
    /* Analytic truth: principal sections are circles, K = 337.5 / R exactly. */
    snprintf(path, sizeof path, "%s/expected.tsv", dir);
    f = fopen(path, "w");
    fprintf(f, "step\tk_steep_D\tk_flat_D\taxis_steep_deg\tcyl_D\tflattening_D\tsteepening_D\tcoupling_ratio\tsia_D\tsia_axis_deg\n");
    for (int k = 0; k <= nsteps; k++) {
        surf_def dk = run_surface(k);
        double ks = 337.5 / dk.rs, kf = 337.5 / dk.rf, fl = 337.5 / d0.rs - ks, st = kf - 337.5 / d0.rf;
        double cyl0 = 337.5 / d0.rs - 337.5 / d0.rf;
        /* pre cyl0 @ 90 and post (ks - kf) @ 90 lie on the negative x axis of the double-angle
         * plane: SIA = (cyl0 - (ks - kf), 0), i.e. that magnitude at 0 deg */
        fprintf(f, "%d\t%.6f\t%.6f\t90\t%.6f\t%.6f\t%.6f\t%.6f\t%.6f\t0\n", k, ks, kf, ks - kf, fl, st,
                k ? fl / st : NAN, cyl0 - (ks - kf));
    }
    fclose(f);
    for (int k = 0; k <= nsteps; k++) {
        kt_mesh mk;
        double *origin = NULL;
        if (crack_mesh(&m, k, &mk, &origin, &e)) goto fail;
        surf_def dk = run_surface(k);
        double *u = calloc((size_t)3 * mk.nn, sizeof(double));
        for (int i = 0; i < mk.nn; i++) {
            const double *q = mk.xyz + 3 * i;
            u[3 * i + 2] = surf_z(&dk, q[0], q[1]) - surf_z(&d0, q[0], q[1]);
        }
        kt_vtk_field fl[2];
        memset(fl, 0, sizeof fl);
        strcpy(fl[0].name, "displacement"), fl[0].ncomp = 3, fl[0].v = u;
        strcpy(fl[1].name, "origin"), fl[1].ncomp = 1, fl[1].is_int = 1, fl[1].v = origin;
        int skip = k == 1 && drop ? (strcmp(drop, "displacement") == 0 ? 0 : 1) : -1;
        kt_vtk_field keep[2];
        int nf = 0;
        for (int j = 0; j < 2; j++)
            if (j != skip) keep[nf++] = fl[j];
        snprintf(path, sizeof path, "%s/step-%04d.vtk", dir, k);
        int rc = kt_vtk_write_tets(path, &mk, keep, nf, k % 2, &e); /* binary and ASCII */
        free(u), free(origin);
        kt_mesh_free(&mk);
        if (rc) goto fail;
    }
    kt_mesh_free(&m);
    return 0;
fail:
    fprintf(stderr, "test_curv --make-run: %s\n", e.msg);
    return 1;
}

int main(int argc, char **argv)
{
    if (argc >= 3 && strcmp(argv[1], "--make-run") == 0) {
        int order = 1, no_ant = 0, nsteps = 3;
        const char *drop = NULL;
        for (int i = 3; i < argc; i++) {
            if (strcmp(argv[i], "--order2") == 0) order = 2;
            else if (strcmp(argv[i], "--no-anterior") == 0) no_ant = 1;
            else if (strcmp(argv[i], "--drop") == 0 && i + 1 < argc) drop = argv[++i];
            else return fprintf(stderr, "test_curv --make-run DIR [--order2] [--no-anterior] [--drop FIELD]\n"), 2;
        }
        return make_run(argv[2], order, drop, no_ant, nsteps);
    }
    test_keratometry();
    test_noise();
    test_alpins();
    return kt_test_done("test_curv");
}
