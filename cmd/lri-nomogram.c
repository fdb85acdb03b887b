/* lri-nomogram: inverse planning from a simulated nomogram (see lri-nomogram(1)). */
#define _POSIX_C_SOURCE 200809L
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "nomo.h"
#include "nomo_out.h"

static const char usage[] =
    "usage: lri-nomogram --k-steep D --k-flat D --axis DEG --age YEARS [options] [NOMOGRAM.tsv]\n"
    "The limbal relaxing incisions (one arc, and a pair) centred on the steep axis that the\n"
    "simulated nomogram (nomogram.tsv of plans/studies/nomogram) says correct the cylinder,\n"
    "with the predicted residual cylinder. Without NOMOGRAM.tsv, the table shipped in\n"
    "share/nomogram/nomogram.tsv (the quick study's: one eye, paired arcs).\n"
    "  --k-steep D, --k-flat D  keratometry, D (required)\n"
    "  --axis DEG               steep axis, deg, [0, 180], 180 read as 0 (required)\n"
    "  --age YEARS              the patient's age, [18, 110] (required)\n"
    "  --sia D --sia-axis DEG   the main incision's SIA vector (the surgeon's own; the axis of\n"
    "                           the induced steepening, as lri-plan's sia), added to the\n"
    "                           keratometric astigmatism by double-angle sum (default none)\n"
    "  --target D               the cylinder to correct (default: of the sum above)\n"
    "  --depth F                incision depth fraction (default: the table's deepest)\n"
    "  --diameter MM            incision diameter (default: the table's most frequent)\n"
    "      --json               the answer as one JSON object instead of the table\n"
    "  -h, --help               this help\n"
    "      --version            the version\n"
    "Exit status: 0 success, 1 run-time failure, 2 bad usage or input.\n";

static int bad(const char *opt, const char *arg, const char *what)
{
    fprintf(stderr, "lri-nomogram: %s %s: expected %s\n", opt, arg, what);
    return KT_EINPUT;
}

static int tool_main(int argc, char **argv)
{
    enum { O_KS = 256, O_KF, O_AXIS, O_AGE, O_TARGET, O_DEPTH, O_DIAM, O_SIA, O_SIAAX, O_VERSION, O_JSON };
    static const struct option lo[] = {
        {"k-steep", required_argument, 0, O_KS}, {"k-flat", required_argument, 0, O_KF},
        {"axis", required_argument, 0, O_AXIS},  {"age", required_argument, 0, O_AGE},
        {"target", required_argument, 0, O_TARGET}, {"depth", required_argument, 0, O_DEPTH},
        {"diameter", required_argument, 0, O_DIAM}, {"help", no_argument, 0, 'h'},
        {"sia", required_argument, 0, O_SIA}, {"sia-axis", required_argument, 0, O_SIAAX},
        {"version", no_argument, 0, O_VERSION}, {"json", no_argument, 0, O_JSON}, {0, 0, 0, 0}};
    kt_nomo_query q = {NAN, NAN, NAN, NAN, NAN, 0, 0, NAN, NAN};
    int c, li = -1, as_json = 0;
    opterr = 0; /* one line of our own for a bad option */
    while ((c = getopt_long(argc, argv, ":h", lo, &li)) != -1) {
        double v;
        if (c == 'h') { fputs(usage, stdout); return kt_stdout_done("lri-nomogram"); }
        if (c == O_VERSION) { puts("lri-nomogram (keratome) " KT_VERSION); return kt_stdout_done("lri-nomogram"); }
        if (c == O_JSON) { as_json = 1; continue; }
        if (c == '?' || c == ':') {
            const char *arg = argv[optind - 1];
            if (c == ':') fprintf(stderr, "lri-nomogram: %s: expected a value (lri-nomogram --help)\n", arg);
            else fprintf(stderr, "lri-nomogram: %s: unknown option (lri-nomogram --help)\n", arg);
            return KT_EINPUT;
        }
        /* the option's name as given, without "=value" */
        char name[64];
        snprintf(name, sizeof name, "%s", argv[optind - 1] == optarg ? argv[optind - 2] : argv[optind - 1]);
        char *eq = strchr(name, '=');
        if (eq) *eq = '\0';
        if (kt_parse_number(optarg, &v) || !isfinite(v)) return bad(name, optarg, "a number");
        switch (c) {
        case O_KS:
        case O_KF:
            if (!(v >= KT_NOMO_K_MIN && v <= KT_NOMO_K_MAX))
                return bad(c == O_KS ? "--k-steep" : "--k-flat", optarg,
                           "a keratometry reading in [20, 70] D");
            if (c == O_KS) q.k_steep = v;
            else q.k_flat = v;
            break;
        case O_AXIS:
            if (!(v >= 0 && v <= 180)) return bad("--axis", optarg, "an axis in [0, 180] deg");
            q.axis = v >= 180 ? 0 : v; /* 180 read as 0, as keratome-patient(5) reads it */
            break;
        case O_AGE:
            if (!(v >= KT_NOMO_AGE_MIN && v <= KT_NOMO_AGE_MAX))
                return bad("--age", optarg, "an age in [18, 110] years");
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
        case O_SIA:
            if (!(v >= 0 && v <= KT_NOMO_SIA_MAX)) return bad("--sia", optarg, "the main incision's SIA in [0, 5] D");
            q.main_sia = v;
            break;
        case O_SIAAX:
            if (!(v >= 0 && v <= 180)) return bad("--sia-axis", optarg, "an axis in [0, 180] deg");
            q.main_axis = v >= 180 ? 0 : v;
            break;
        }
    }
    static const struct { const char *opt, *what; } req[] = {
        {"--k-steep", "the steep keratometry, D"}, {"--k-flat", "the flat keratometry, D"},
        {"--axis", "the steep axis, deg"}, {"--age", "the patient's age, years"}};
    double *reqv[] = {&q.k_steep, &q.k_flat, &q.axis, &q.age};
    for (int i = 0; i < 4; i++)
        if (isnan(*reqv[i])) {
            fprintf(stderr, "lri-nomogram: %s: missing, expected %s (lri-nomogram --help)\n", req[i].opt, req[i].what);
            return KT_EINPUT;
        }
    if (isnan(q.main_sia) != isnan(q.main_axis)) {
        fprintf(stderr, "lri-nomogram: %s: missing, expected it with %s (the SIA vector: magnitude and axis)\n",
                isnan(q.main_sia) ? "--sia" : "--sia-axis", isnan(q.main_sia) ? "--sia-axis" : "--sia");
        return KT_EINPUT;
    }
    if (isnan(q.main_sia)) q.main_sia = 0, q.main_axis = 0;
    if (optind < argc - 1) {
        fprintf(stderr, "lri-nomogram: %s: expected one NOMOGRAM.tsv, got %d (lri-nomogram --help)\n", argv[optind + 1],
                argc - optind);
        return KT_EINPUT;
    }
    char deftab[1200];
    snprintf(deftab, sizeof deftab, "%s/%s", KT_SHARE_DIR, KT_NOMO_DEFAULT);
    const char *table = optind == argc - 1 ? argv[optind] : deftab;
    if (!(q.k_steep >= q.k_flat)) {
        fprintf(stderr, "lri-nomogram: --k-steep %g --k-flat %g: expected K steep >= K flat\n",
                q.k_steep, q.k_flat);
        return KT_EINPUT;
    }
    double pre_axis, pre = kt_nomo_pre(&q, &pre_axis);
    if (isnan(q.target) && !(pre > 0 && pre <= KT_NOMO_CYL_MAX)) {
        if (q.main_sia > 0)
            fprintf(stderr, "lri-nomogram: --k-steep %g --k-flat %g --sia %g: expected a cylinder to correct in (0, 10] D "
                    "(with the main incision's SIA: %.2f D), or --target\n", q.k_steep, q.k_flat, q.main_sia, pre);
        else
            fprintf(stderr, "lri-nomogram: --k-steep %g --k-flat %g: expected a cylinder K steep - "
                    "K flat in (0, 10] D to correct (or --target)\n", q.k_steep, q.k_flat);
        return KT_EINPUT;
    }
    if (isnan(q.target)) q.target = pre;
    kt_err e = {0};
    kt_nomo t;
    if (kt_nomo_read(&t, table, &e)) {
        if (table == deftab)
            fprintf(stderr, "lri-nomogram: no NOMOGRAM.tsv given and the default %s cannot be read: make one with "
                    "'make -C plans/studies/nomogram quick' and give run/nomogram/nomogram.tsv\n", deftab);
        else fprintf(stderr, "lri-nomogram: %s\n", e.msg);
        return e.code;
    }
    /* Warnings: the target outside what LRIs treat; the age outside the table's (clamped). */
    if (q.target < KT_NOMO_LRI_MIN || q.target > KT_NOMO_LRI_MAX)
        fprintf(stderr, "lri-nomogram: warning: a cylinder of %.2f D lies outside what LRIs treat (about %g-%g D, "
                "Nichamin 2006); the answer is the table's, not a recommendation\n", q.target, KT_NOMO_LRI_MIN, KT_NOMO_LRI_MAX);
    double age_lo, age_hi;
    kt_nomo_ages(&t, &age_lo, &age_hi);
    if (q.age < age_lo || q.age > age_hi)
        fprintf(stderr, "lri-nomogram: warning: --age %g lies outside the table's simulated ages %g-%g y: clamped to %g y\n",
                q.age, age_lo, age_hi, q.age < age_lo ? age_lo : age_hi);
    kt_nomo_answer ans[2];
    int rc = kt_nomo_plan(&t, &q, ans, &e);
    kt_nomo_free(&t);
    if (rc) {
        fprintf(stderr, "lri-nomogram: %s\n", e.msg);
        return rc;
    }
    if (kt_nomo_print(stdout, &q, pre, pre_axis, ans, as_json, &e)) {
        fprintf(stderr, "lri-nomogram: %s\n", e.msg);
        return e.code;
    }
    return kt_stdout_done("lri-nomogram");
}

int main(int argc, char **argv)
{
    kt_tool_start();
    kt_exit(tool_main(argc, argv));
}
