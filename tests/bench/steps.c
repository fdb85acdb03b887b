/* bench_steps: run an edits stream with one of augsolve's methods through the library calls
 * augsolve makes (kt_aug_create / kt_aug_step), writing the steps.tsv columns plus what the
 * benchmark needs and the tool does not print:
 *   - status per step: ok, or fail (the step's solve missed its tolerance) and the run goes on
 *     (--keep-going; augsolve rightly stops at the first failure, but the paper's CG curves
 *     show the steps after one that failed);
 *   - t_factor_ms: the time of the factorization in use (augmented), and the wall budget
 *     (--budget SECONDS): steps after it is spent are not run (status "budget").
 * The problem is augsolve's (kt_physics_problem: the fibre matrices and, for a prestressed
 * scene, the prestress of the measured geometry). --field PREFIX writes each completed step's
 * displacement to PREFIX-NNNN.txt (NNNN the step): one line per node of its cut mesh,
 * "ux uy uz" in mm (%.17g), in the node order of augsolve's step VTK files.
 *
 *   bench_steps MESH EDITS [--scene S] [--method M] [--tol T] [--maxit N] [--verify]
 *               [--keep-going] [--field PREFIX]
 *               [--budget S] [--max-steps N] [--tag NAME]
 * stdout: TSV with a header line. Exit 1 if a step failed (even with --keep-going). */
#define _POSIX_C_SOURCE 200809L
#include "aug.h"
#include "bench.h"

typedef struct opts {
    const char *mesh, *edits, *scene, *tag, *field;
    kt_aug_opts aug;
    int keep_going, max_steps;
    double budget;
} opts;

static int parse(int argc, char **argv, opts *o)
{
    memset(o, 0, sizeof *o);
    kt_aug_opts_default(&o->aug);
    o->aug.quiet = 1;
    o->aug.verify_tol = 1e300; /* record the difference; the suite judges it */
    o->tag = "-";
    o->budget = INFINITY;
    o->max_steps = 1 << 30;
    int pos = 0;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : "";
        int bad = 0, arg = 1;
        if (!strcmp(a, "--scene")) o->scene = v;
        else if (!strcmp(a, "--tag")) o->tag = v;
        else if (!strcmp(a, "--field")) o->field = v;
        else if (!strcmp(a, "--method")) bad = kt_aug_parse_method(v, &o->aug.method);
        else if (!strcmp(a, "--tol")) bad = kt_parse_double(v, &o->aug.tol);
        else if (!strcmp(a, "--maxit")) bad = kt_parse_int(v, &o->aug.maxit);
        else if (!strcmp(a, "--budget")) bad = kt_parse_double(v, &o->budget);
        else if (!strcmp(a, "--max-steps")) bad = kt_parse_int(v, &o->max_steps);
        else {
            arg = 0;
            if (!strcmp(a, "--verify")) o->aug.verify = 1;
            else if (!strcmp(a, "--keep-going")) o->keep_going = 1;
            else if (a[0] != '-' && pos == 0) o->mesh = a, pos++;
            else if (a[0] != '-' && pos == 1) o->edits = a, pos++;
            else bad = 1;
        }
        if (bad || (arg && i + 1 >= argc)) return -1;
        i += arg;
    }
    return o->mesh && o->edits ? 0 : -1;
}

/* --field: the current step's displacement, one node a line (written atomically). */
static int write_field(const char *prefix, const kt_aug *A, kt_err *e)
{
    char path[4096];
    if (snprintf(path, sizeof path, "%s-%04d.txt", prefix, kt_aug_last(A)->step) >= (int)sizeof path)
        return kt_fail(e, KT_EINPUT, "--field %s: path too long", prefix);
    kt_out out;
    if (kt_out_open(&out, path, e)) return e->code;
    const double *u = kt_aug_displacement(A);
    for (int i = 0; i < kt_aug_mesh(A)->nn; i++)
        fprintf(out.f, "%.17g %.17g %.17g\n", u[3 * i], u[3 * i + 1], u[3 * i + 2]);
    return kt_out_commit(&out, e);
}

static void num(double v, const char *fmt)
{
    if (isnan(v)) fputs("\tNaN", stdout);
    else printf(fmt, v);
}

static void row(const opts *o, const kt_aug *A, const char *status, const kt_aug_row *w)
{
    double nnz, tf;
    kt_aug_factor_info(A, &nnz, &tf);
    if (!(nnz > 0) && w->nnz_L > 0) nnz = w->nnz_L; /* refactor: the step's fresh factor */
    /* a failed step never reached the total: add up what it measured */
    double tot = w->t_total;
    if (strcmp(status, "ok"))
        tot = w->t_update + (isnan(w->t_step1) ? 0 : w->t_step1) + w->t_step2 +
              (isnan(w->t_step3) ? 0 : w->t_step3);
    int ndofs = strcmp(status, "ok") ? 3 * kt_aug_mesh(A)->nn : w->n_dofs;
    printf("%s\t%s\t%d\t%d\t%d\t%d\t%d\t%d", o->tag, kt_aug_method_name(o->aug.method), w->step,
           ndofs, w->m, w->new_dofs, w->iters, w->closure_max);
    num(w->t_update, "\t%.4f");
    num(w->t_step1, "\t%.4f");
    num(w->t_step2, "\t%.4f");
    num(w->t_step3, "\t%.4f");
    num(tot, "\t%.4f");
    num(w->rel_residual, "\t%.3e");
    num(w->verify_rel_diff, "\t%.3e");
    printf("\t%.0f\t%.3f\t%s\n", nnz, 1e3 * tf, status);
    fflush(stdout);
}

/* The step's row, with --verify its difference from a fresh METIS factorization
 * (kt_aug_fresh: max |u - u_fresh| / max |u_fresh|, as augsolve's front door measures it). */
static kt_aug_row verified(const opts *o, kt_aug *A, kt_err *e)
{
    kt_aug_row w = *kt_aug_last(A);
    if (!o->aug.verify) return w;
    int n = 3 * kt_aug_mesh(A)->nn;
    double *ref = kt_calloc((size_t)n, sizeof(double), e), t = 0, d = 0, mx = 0;
    const double *u = kt_aug_displacement(A);
    if (ref && kt_aug_fresh(A, ref, &t, e) == KT_OK) {
        for (int i = 0; i < n; i++) {
            d = fmax(d, fabs(u[i] - ref[i]));
            mx = fmax(mx, fabs(ref[i]));
        }
        w.verify_rel_diff = mx > 0 ? d / mx : d;
        w.t_verify = 1e3 * t;
    }
    free(ref);
    return w;
}

int main(int argc, char **argv)
{
    opts o;
    if (parse(argc, argv, &o)) {
        fprintf(stderr, "usage: bench_steps MESH EDITS [--scene S] [--method M] [--tol T] "
                        "[--maxit N] [--verify] [--keep-going] [--field PREFIX] [--budget S] "
                        "[--max-steps N] [--tag NAME]\n");
        return 2;
    }
    kt_err e = {0};
    bench_problem p;
    memset(&p, 0, sizeof p);
    kt_edits_reader rd;
    kt_step st = {0};
    kt_aug *A = NULL;
    kt_aug_problem ap;
    int failed = 0;
    FILE *f = fopen(o.edits, "r");
    if (!f) {
        fprintf(stderr, "bench_steps: cannot open %s\n", o.edits);
        return 2;
    }
    if (kt_edits_open(&rd, f, o.edits, &e)) goto done;
    if (bench_problem_load(&p, o.mesh, o.scene ? o.scene : rd.h.scene, &e)) goto done;
    ap = kt_aug_problem_of(&p.mesh, &p.fem);
    printf("tag\tmethod\tstep\tn_dofs\tm\tnew_dofs\titers\tclosure_max\tt_update_ms\tt_step1_ms\t"
           "t_step2_ms\tt_step3_ms\tt_total_ms\trel_residual\tverify_rel_diff\tnnz_L\t"
           "t_factor_ms\tstatus\n");
    double t0 = kt_now();
    if (kt_aug_create(&A, &ap, &o.aug, &e)) goto done;
    kt_aug_row w = verified(&o, A, &e);
    if (e.code) goto done;
    row(&o, A, "ok", &w);
    if (o.field && write_field(o.field, A, &e)) goto done;
    int rc;
    while ((rc = kt_edits_next(&rd, &st, &e)) == 1 && st.index <= o.max_steps) {
        if (kt_now() - t0 > o.budget) {
            printf("%s\t%s\t%d\tNaN\tNaN\tNaN\tNaN\tNaN\tNaN\tNaN\tNaN\tNaN\tNaN\tNaN\tNaN\tNaN"
                   "\tNaN\tbudget\n", o.tag, kt_aug_method_name(o.aug.method), st.index);
            continue;
        }
        if (kt_aug_step(A, &st, &e) == KT_OK) {
            w = verified(&o, A, &e);
            if (e.code) goto done;
            row(&o, A, "ok", &w);
            if (o.field && write_field(o.field, A, &e)) goto done;
            continue;
        }
        failed = 1;
        fprintf(stderr, "bench_steps: %s\n", e.msg);
        row(&o, A, "fail", kt_aug_last(A));
        if (!o.keep_going || e.code != KT_ERUN) goto done;
        e = (kt_err){0};
    }
done:
    if (e.code) fprintf(stderr, "bench_steps: %s\n", e.msg);
    kt_aug_free(A);
    kt_step_free(&st);
    fclose(f);
    bench_problem_free(&p);
    return e.code ? e.code : failed;
}
