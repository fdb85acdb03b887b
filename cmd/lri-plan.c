/* lri-plan: one patient in, a plan of limbal relaxing incisions out (see lri-plan(1)). */
#define _POSIX_C_SOURCE 200809L
#include <getopt.h>
#include <stdio.h>

#include "lriplan_run.h"

static const char usage[] =
    "usage: lri-plan [options] PATIENT.yaml -o PLAN_DIR\n"
    "Simulates the patient's eye (keratome-patient(5)) and answers which limbal relaxing\n"
    "incisions minimize the residual astigmatism: PLAN_DIR/plan.json and a summary on stdout.\n"
    "  -o, --output DIR    the plan folder (required; made if missing)\n"
    "      --base SCENE    the base eye scene (default: the repository's plans/eye.yaml)\n"
    "      --fast          a coarse mesh, the incision floor refined at 0.1 mm\n"
    "      --step DEG      arc opened per step, deg (default 5)\n"
    "      --no-uncertainty  no first-order band on the predicted residual (augsolve without\n"
    "                      --uncertainty: the runs cost up to a quarter less)\n"
    "  -q, --quiet         no progress on stderr\n"
    "  -h, --help          this help\n"
    "      --version       the version\n"
    "Exit status: 0 success, 1 run-time failure, 2 bad usage or input.\n";

static int tool_main(int argc, char **argv)
{
    enum { O_BASE = 256, O_FAST, O_STEP, O_VERSION, O_NOBAND };
    static const struct option lo[] = {{"output", required_argument, 0, 'o'}, {"base", required_argument, 0, O_BASE},
                                       {"fast", no_argument, 0, O_FAST},      {"step", required_argument, 0, O_STEP},
                                       {"quiet", no_argument, 0, 'q'},        {"help", no_argument, 0, 'h'},
                                       {"version", no_argument, 0, O_VERSION}, {"no-uncertainty", no_argument, 0, O_NOBAND},
                                       {0, 0, 0, 0}};
    kt_lriplan_opts o;
    kt_lriplan_opts_default(&o);
    int c;
    while ((c = getopt_long(argc, argv, "o:qh", lo, NULL)) != -1) {
        switch (c) {
        case 'o': o.outdir = optarg; break;
        case O_BASE: o.base = optarg; break;
        case O_FAST: o.fast = 1; break;
        case O_NOBAND: o.no_band = 1; break;
        case O_STEP:
            if (kt_parse_number(optarg, &o.step) || !(o.step > 0 && o.step <= 90)) {
                fprintf(stderr, "lri-plan: --step %s: expected an angle in (0, 90] deg\n", optarg);
                return KT_EINPUT;
            }
            break;
        case 'q': o.quiet = 1; break;
        case 'h': fputs(usage, stdout); return kt_stdout_done("lri-plan");
        case O_VERSION: puts("lri-plan (keratome) " KT_VERSION); return kt_stdout_done("lri-plan");
        default: return KT_EINPUT; /* getopt named the option on stderr */
        }
    }
    if (optind != argc - 1) {
        fprintf(stderr, "lri-plan: expected one PATIENT.yaml, got %d arguments\n%s", argc - optind, usage);
        return KT_EINPUT;
    }
    if (!o.outdir) {
        fprintf(stderr, "lri-plan: -o PLAN_DIR: expected the plan folder\n");
        return KT_EINPUT;
    }
    o.patient = argv[optind];
    kt_err e = {0};
    int rc = kt_lriplan_run(&o, stdout, &e);
    if (rc != KT_OK) {
        fprintf(stderr, "lri-plan: %s\n", e.msg);
        return rc;
    }
    return kt_stdout_done("lri-plan");
}

int main(int argc, char **argv)
{
    kt_tool_start();
    kt_exit(tool_main(argc, argv));
}
