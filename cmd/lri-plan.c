/* lri-plan: one patient in, a plan of limbal relaxing incisions out (see lri-plan(1)). */
#define _POSIX_C_SOURCE 200809L
#include <getopt.h>
#include <stdio.h>
#include <string.h>

#include "lriplan_eye.h"
#include "lriplan_run.h"

static const char usage[] =
    "usage: lri-plan [options] PATIENT.yaml -o PLAN_DIR\n"
    "Simulates the patient's eye (keratome-patient(5)) and answers which limbal relaxing\n"
    "incisions minimize the residual astigmatism: PLAN_DIR/plan.json and a summary on stdout.\n"
    "  -o, --output DIR    the plan folder (required; made if missing)\n"
    "      --base SCENE    the base eye scene (default: the repository's plans/eye.yaml)\n"
    "      --fast          a coarse mesh, the incision floor refined at 0.1 mm\n"
    "      --step DEG      arc opened per step, deg (default 5)\n"
    "      --state S       the wound the plan is made for: healed (default: the outcome months\n"
    "                      later, the identified scar) or immediate (the instant of cutting)\n"
    "      --view V        how plan.html draws the eye: temporal (default: the surgeon seated\n"
    "                      temporal), superior (seated at the head) or examiner (facing the\n"
    "                      patient, superior up)\n"
    "      --no-uncertainty  no band on the predicted residual (no derivatives: the runs cost\n"
    "                      up to a quarter less)\n"
    "      --plan-max-ratio R  the planned method's factor limit (augsolve(1)); beyond it a\n"
    "                      family falls back to refactor, said on stderr and in plan.json\n"
    "  -j, --jobs N        families solved at once, each on a core (default: 2 when the load\n"
    "                      leaves two cores free and the memory holds two runs; the answer\n"
    "                      is the same to the bit)\n"
    "  -q, --quiet         no progress on stderr\n"
    "  -h, --help          this help\n"
    "      --version       the version\n"
    "Exit status: 0 success, 1 run-time failure, 2 bad usage or input.\n";

static int tool_main(int argc, char **argv)
{
    enum { O_BASE = 256, O_FAST, O_STEP, O_VERSION, O_NOBAND, O_MAXRATIO, O_STATE, O_VIEW };
    double jobs;
    static const struct option lo[] = {{"output", required_argument, 0, 'o'}, {"base", required_argument, 0, O_BASE},
                                       {"fast", no_argument, 0, O_FAST},      {"step", required_argument, 0, O_STEP},
                                       {"quiet", no_argument, 0, 'q'},        {"help", no_argument, 0, 'h'},
                                       {"version", no_argument, 0, O_VERSION}, {"no-uncertainty", no_argument, 0, O_NOBAND},
                                       {"plan-max-ratio", required_argument, 0, O_MAXRATIO},
                                       {"state", required_argument, 0, O_STATE},
                                       {"view", required_argument, 0, O_VIEW}, {"jobs", required_argument, 0, 'j'},
                                       {0, 0, 0, 0}};
    kt_lriplan_opts o;
    kt_lriplan_opts_default(&o);
    int c;
    while ((c = getopt_long(argc, argv, "o:j:qh", lo, NULL)) != -1) {
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
        case O_MAXRATIO:
            if (kt_parse_number(optarg, &o.plan_max_ratio) || !(o.plan_max_ratio >= 0)) {
                fprintf(stderr, "lri-plan: --plan-max-ratio %s: expected a number >= 0\n", optarg);
                return KT_EINPUT;
            }
            break;
        case O_STATE:
            if ((o.state = kt_lriplan_state(optarg)) < 0) {
                fprintf(stderr, "lri-plan: --state %s: expected healed or immediate\n", optarg);
                return KT_EINPUT;
            }
            break;
        case O_VIEW:
            if (strcmp(optarg, "temporal") == 0) o.view = KT_LRI_VIEW_TEMPORAL;
            else if (strcmp(optarg, "superior") == 0) o.view = KT_LRI_VIEW_SUPERIOR;
            else if (strcmp(optarg, "examiner") == 0) o.view = KT_LRI_VIEW_EXAMINER;
            else {
                fprintf(stderr, "lri-plan: --view %s: expected temporal, superior or examiner\n", optarg);
                return KT_EINPUT;
            }
            break;
        case 'j':
            if (kt_parse_number(optarg, &jobs) || !(jobs >= 1 && jobs <= KT_LP_NFAM) || jobs != (int)jobs) {
                fprintf(stderr, "lri-plan: --jobs %s: expected a whole number from 1 to %d (the families)\n", optarg,
                        KT_LP_NFAM);
                return KT_EINPUT;
            }
            o.jobs = (int)jobs;
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
