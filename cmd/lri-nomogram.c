/* lri-nomogram: inverse planning from a simulated nomogram (see lri-nomogram(1)). */
#define _POSIX_C_SOURCE 200809L
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "nomo.h"

static const char usage[] =
    "usage: lri-nomogram --k-steep D --k-flat D --axis DEG --age YEARS [options] NOMOGRAM.tsv\n"
    "The limbal relaxing incisions (one arc, and a pair) centred on the steep axis that the\n"
    "simulated nomogram (nomogram.tsv of plans/studies/nomogram) says correct the cylinder,\n"
    "with the predicted residual cylinder.\n"
    "  --k-steep D, --k-flat D  keratometry, D (required)\n"
    "  --axis DEG               steep axis, deg, [0, 180) (required)\n"
    "  --age YEARS              the patient's age (required)\n"
    "  --target D               the cylinder to correct (default K steep - K flat)\n"
    "  --depth F                incision depth fraction (default: the table's deepest)\n"
    "  --diameter MM            incision diameter (default: the table's most frequent)\n"
    "  -h, --help               this help\n";

static int bad(const char *opt, const char *arg, const char *what)
{
    fprintf(stderr, "lri-nomogram: %s %s: expected %s\n", opt, arg, what);
    return KT_EINPUT;
}

static void print_answer(const kt_nomo_answer *a)
{
    printf("%d\t%.1f\t%.2f\t%.2f\t%.0f\t%g-%g\t%g-%g\t%s\n", a->incisions, a->arc, a->sia,
           a->residual, a->residual_axis, a->arc_lo, a->arc_hi, a->age_lo, a->age_hi,
           a->reached ? (a->arc_lo == a->arc_hi ? "simulated arc" : "interpolated")
                      : "under-corrects: the longest simulated arc");
}

static int tool_main(int argc, char **argv)
{
    enum { O_KS = 256, O_KF, O_AXIS, O_AGE, O_TARGET, O_DEPTH, O_DIAM };
    static const struct option lo[] = {
        {"k-steep", required_argument, 0, O_KS}, {"k-flat", required_argument, 0, O_KF},
        {"axis", required_argument, 0, O_AXIS},  {"age", required_argument, 0, O_AGE},
        {"target", required_argument, 0, O_TARGET}, {"depth", required_argument, 0, O_DEPTH},
        {"diameter", required_argument, 0, O_DIAM}, {"help", no_argument, 0, 'h'},
        {0, 0, 0, 0}};
    kt_nomo_query q = {NAN, NAN, NAN, NAN, NAN, 0, 0};
    int c;
    while ((c = getopt_long(argc, argv, "h", lo, NULL)) != -1) {
        double v;
        if (c == 'h') { fputs(usage, stdout); return kt_stdout_done("lri-nomogram"); }
        if (c == '?') { fputs(usage, stderr); return KT_EINPUT; }
        if (kt_parse_number(optarg, &v) || !isfinite(v))
            return bad(argv[optind - 2], optarg, "a number");
        switch (c) {
        case O_KS:
        case O_KF:
            if (!(v >= KT_NOMO_K_MIN && v <= KT_NOMO_K_MAX))
                return bad(c == O_KS ? "--k-steep" : "--k-flat", optarg,
                           "a keratometry reading in [30, 70] D");
            if (c == O_KS) q.k_steep = v;
            else q.k_flat = v;
            break;
        case O_AXIS:
            if (!(v >= 0 && v < 180)) return bad("--axis", optarg, "an axis in [0, 180) deg");
            q.axis = v;
            break;
        case O_AGE:
            if (!(v > 0 && v < 150)) return bad("--age", optarg, "an age in years");
            q.age = v;
            break;
        case O_TARGET:
            if (!(v > 0 && v <= KT_NOMO_CYL_MAX))
                return bad("--target", optarg, "a cylinder to correct in (0, 10] D");
            q.target = v;
            break;
        case O_DEPTH:
            if (!(v > 0 && v <= 1)) return bad("--depth", optarg, "a fraction in (0, 1]");
            q.depth = v;
            break;
        case O_DIAM:
            if (!(v > 0 && v <= 14)) return bad("--diameter", optarg, "a diameter in (0, 14] mm");
            q.diameter = v;
            break;
        }
    }
    if (optind != argc - 1 || isnan(q.k_steep) || isnan(q.k_flat) || isnan(q.axis) ||
        isnan(q.age)) {
        fputs(usage, stderr);
        return KT_EINPUT;
    }
    if (!(q.k_steep >= q.k_flat)) {
        fprintf(stderr, "lri-nomogram: --k-steep %g --k-flat %g: expected K steep >= K flat\n",
                q.k_steep, q.k_flat);
        return KT_EINPUT;
    }
    if (isnan(q.target) && !(q.k_steep - q.k_flat > 0 && q.k_steep - q.k_flat <= KT_NOMO_CYL_MAX)) {
        fprintf(stderr, "lri-nomogram: --k-steep %g --k-flat %g: expected a cylinder K steep - "
                "K flat in (0, 10] D to correct (or --target)\n", q.k_steep, q.k_flat);
        return KT_EINPUT;
    }
    if (isnan(q.target)) q.target = q.k_steep - q.k_flat;
    kt_err e = {0};
    kt_nomo t;
    if (kt_nomo_read(&t, argv[optind], &e)) {
        fprintf(stderr, "lri-nomogram: %s\n", e.msg);
        return e.code;
    }
    kt_nomo_answer ans[2];
    int rc = kt_nomo_plan(&t, &q, ans, &e);
    kt_nomo_free(&t);
    if (rc) {
        fprintf(stderr, "lri-nomogram: %s\n", e.msg);
        return rc;
    }
    const kt_nomo_answer *any = ans[0].incisions ? &ans[0] : &ans[1];
    printf("# pre-op %.2f D @ %g deg, age %g y, target %.2f D; incisions centred on %g deg, "
           "depth %g, diameter %g mm\n",
           q.k_steep - q.k_flat, q.axis, q.age, q.target, q.axis, any->depth, any->diameter);
    printf("incisions\tarc_deg\tsia_D\tresidual_D\tresidual_axis_deg\tbetween_arcs_deg"
           "\tages_y\tnote\n");
    for (int i = 0; i < 2; i++)
        if (ans[i].incisions) print_answer(&ans[i]);
    return kt_stdout_done("lri-nomogram");
}

int main(int argc, char **argv)
{
    kt_tool_start();
    kt_exit(tool_main(argc, argv));
}
