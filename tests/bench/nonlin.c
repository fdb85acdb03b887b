/* nonlin.c (bench_nonlin): what linearizing costs on an eye (issue 22, part 3). The plan's
 * edits (all steps) on MESH with SCENE's physics (kt_physics_problem, as augsolve builds it),
 * solved twice through the same total Lagrangian assembly (kt_newton_plan):
 *   linear     one full step from the prestressed state, K_T(0) u = -R(0): the answer of
 *              augsolve's constant-tangent methods (planned, refactor) to their tolerance;
 *   newton     the geometrically nonlinear reference: the cut released in load increments,
 *              Newton to ||R|| <= 1e-10 ||f_int|| (newton.h).
 * For each: seconds, iterations, and simulated keratometry of the anterior surface (toric fit
 * over the central 3 mm zone, as curvature(1) by default) before and after: SIA (Alpins: the
 * double-angle difference of the cylinders), flattening = -dK at the meridian 90 deg from the
 * SIA's axis, steepening = dK at the SIA's axis (K from the zone-averaged meridional powers),
 * coupling ratio = flattening / steepening, the mean K change; then the relative difference
 * of the two displacement fields. One TSV row per method on stdout.
 * --linear skips the reference. --field PREFIX writes each field, one node a line (PREFIX-linear.txt, PREFIX-newton.txt).
 *   bench_nonlin MESH SCENE EDITS [--increments N] [--zone MM] [--log] [--linear]
 *                [--field PREFIX] */
#include <time.h>

#include "bench.h"
#include "curv.h"
#include "edits.h"
#include "newton.h"

/* PREFIX-NAME.txt := u, one node a line (written atomically). */
static int write_field(const char *prefix, const char *name, const double *u, int nn, kt_err *e)
{
    char path[4096];
    if (snprintf(path, sizeof path, "%s-%s.txt", prefix, name) >= (int)sizeof path)
        return kt_fail(e, KT_EINPUT, "--field %s: path too long", prefix);
    kt_out out;
    if (kt_out_open(&out, path, e)) return e->code;
    for (int i = 0; i < nn; i++)
        fprintf(out.f, "%.17g %.17g %.17g\n", u[3 * i], u[3 * i + 1], u[3 * i + 2]);
    return kt_out_commit(&out, e);
}

typedef struct ksum {
    kt_kerato k;
    kt_astig astig;
} ksum;

/* Keratometry of the anterior nodes (mask over the intact nodes, origin maps a node of m to
 * its intact node) displaced by u (NULL: none). */
static int kerato(const kt_mesh *m, const unsigned char *mask, const int *origin, const double *u,
                  double zone, ksum *k, kt_err *e)
{
    int n = 0;
    double *xyz = kt_calloc(3 * (size_t)m->nn, sizeof(double), e);
    if (!xyz) return e->code;
    for (int i = 0; i < m->nn; i++) {
        if (!mask[origin[i]]) continue;
        for (int c = 0; c < 3; c++)
            xyz[3 * n + c] = m->xyz[3 * (size_t)i + c] + (u ? u[3 * (size_t)i + c] : 0);
        n++;
    }
    kt_fit f;
    int rc = kt_curv_fit(xyz, n, KT_FIT_TORIC, 4, zone, 0, 0, &f, NULL, 0, e);
    free(xyz);
    if (rc) return rc;
    kt_curv_simk(&f, &k->k);
    k->astig = (kt_astig){k->k.cyl, k->k.axis_steep};
    return KT_OK;
}

static int read_steps(const char *path, kt_step **steps, int *nsteps, kt_err *e)
{
    FILE *f = fopen(path, "r");
    if (!f) return kt_fail(e, KT_EINPUT, "%s: cannot open", path);
    kt_edits_reader r;
    int rc = kt_edits_open(&r, f, path, e), cap = 0;
    *steps = NULL;
    *nsteps = 0;
    while (rc == KT_OK) {
        if (*nsteps == cap) {
            cap = cap ? 2 * cap : 16;
            kt_step *s = kt_realloc(*steps, cap, sizeof **steps, e);
            if (!s) break;
            *steps = s;
        }
        memset(&(*steps)[*nsteps], 0, sizeof **steps);
        int got = kt_edits_next(&r, &(*steps)[*nsteps], e);
        if (got <= 0) {
            kt_step_free(&(*steps)[*nsteps]);
            break;
        }
        (*nsteps)++;
    }
    fclose(f);
    return e->code;
}

int main(int argc, char **argv)
{
    const char *mesh = NULL, *scene = NULL, *edits = NULL, *field = NULL;
    int increments = 5, log = 0, only_linear = 0;
    double zone = 3;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--increments") && i + 1 < argc) increments = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--zone") && i + 1 < argc) zone = atof(argv[++i]);
        else if (!strcmp(argv[i], "--log")) log = 1;
        else if (!strcmp(argv[i], "--linear")) only_linear = 1;
        else if (!strcmp(argv[i], "--field") && i + 1 < argc) field = argv[++i];
        else if (argv[i][0] != '-' && !mesh) mesh = argv[i];
        else if (argv[i][0] != '-' && !scene) scene = argv[i];
        else if (argv[i][0] != '-' && !edits) edits = argv[i];
        else {
            fprintf(stderr, "bench_nonlin: argument '%s': expected MESH SCENE EDITS [--increments N] "
                    "[--zone MM] [--log] [--linear] [--field PREFIX]\n", argv[i]);
            return 2;
        }
    }
    if (!edits || increments < 1 || !(zone > 0)) {
        fprintf(stderr, "usage: bench_nonlin MESH SCENE EDITS [--increments N >= 1] [--zone MM > 0] "
                "[--log] [--linear] [--field PREFIX]\n");
        return 2;
    }
    kt_err e = {0};
    bench_problem p;
    kt_step *steps = NULL;
    int nsteps = 0;
    unsigned char *mask = NULL;
    if (bench_problem_load(&p, mesh, scene, &e) || read_steps(edits, &steps, &nsteps, &e) ||
        kt_curv_anterior_mask(&p.mesh, mesh, &mask, &e)) {
        fprintf(stderr, "bench_nonlin: %s\n", e.msg);
        return e.code == KT_EINPUT ? 2 : 1;
    }
    /* the intact node of every node after the cut */
    int nn = p.mesh.nn;
    for (int s = 0; s < nsteps; s++)
        for (int i = 0; i < steps[s].n; i++)
            if (steps[s].edit[i].kind == KT_EDIT_DUP) nn++;
    int *origin = kt_calloc((size_t)nn, sizeof(int), &e);
    for (int i = 0; origin && i < p.mesh.nn; i++) origin[i] = i;
    for (int s = 0; origin && s < nsteps; s++)
        for (int i = 0; i < steps[s].n; i++)
            if (steps[s].edit[i].kind == KT_EDIT_DUP)
                origin[steps[s].edit[i].new_node] = origin[steps[s].edit[i].node];
    ksum pre;
    if (!origin || kerato(&p.mesh, mask, origin, NULL, zone, &pre, &e)) {
        fprintf(stderr, "bench_nonlin: %s\n", e.msg);
        return 1;
    }
    printf("# %s: %d nodes, %d tets, %d steps; pre-op K %.3f / %.3f D, cyl %.3f D at %.1f deg\n",
           mesh, p.mesh.nn, p.mesh.ne, nsteps, pre.k.k_steep, pre.k.k_flat, pre.k.cyl,
           pre.k.axis_steep);
    printf("method\tseconds\titerations\tincrements\tsia_D\tsia_axis\tflattening_D\tsteepening_D"
           "\tcoupling\tdK_mean_D\tmax_u_mm\n");
    double *u[2] = {NULL, NULL};
    int rc = 0;
    for (int lin = 1; lin >= only_linear && !rc; lin--) {
        kt_mesh m;
        if (kt_mesh_copy(&m, &p.mesh, &e)) break;
        kt_newton_opts o;
        kt_newton_defaults(&o);
        o.increments = increments;
        o.linear = lin;
        o.log = log ? stderr : NULL;
        kt_newton_stats st;
        ksum post;
        rc = kt_newton_plan(&m, &p.fem, steps, nsteps, &o, &u[lin], &st, &e) ||
             kerato(&m, mask, origin, u[lin], zone, &post, &e) ||
             (field && write_field(field, lin ? "linear" : "newton", u[lin], m.nn, &e));
        if (!rc) {
            kt_alpins a;
            kt_curv_alpins(pre.astig, post.astig, NULL, &a);
            int is = (int)lround(a.sia.axis / 2) % KT_CURV_NMERID;
            int ifl = (is + KT_CURV_NMERID / 2) % KT_CURV_NMERID;
            double steep = post.k.kmer[is] - pre.k.kmer[is];
            double flat = pre.k.kmer[ifl] - post.k.kmer[ifl], umax = 0;
            for (size_t i = 0; i < 3 * (size_t)m.nn; i++) umax = fmax(umax, fabs(u[lin][i]));
            printf("%s\t%.2f\t%d\t%d\t%.4f\t%.1f\t%.4f\t%.4f\t%.3f\t%.4f\t%.5f\n",
                   lin ? "linear" : "newton", st.t, st.iterations, st.increments, a.sia.mag,
                   a.sia.axis, flat, steep, flat / steep, post.k.k_mean - pre.k.k_mean, umax);
            fflush(stdout);
        }
        if (!lin && !rc) {
            double d = 0, s = 0;
            for (size_t i = 0; i < 3 * (size_t)m.nn; i++) {
                d += (u[0][i] - u[1][i]) * (u[0][i] - u[1][i]);
                s += u[1][i] * u[1][i];
            }
            printf("# ||u_newton - u_linear|| / ||u_linear|| = %.3e\n", sqrt(d / s));
        }
        kt_mesh_free(&m);
    }
    if (rc) fprintf(stderr, "bench_nonlin: %s\n", e.msg);
    for (int s = 0; s < nsteps; s++) kt_step_free(&steps[s]);
    free(steps);
    free(u[0]);
    free(u[1]);
    free(mask);
    free(origin);
    bench_problem_free(&p);
    return rc ? 1 : 0;
}
