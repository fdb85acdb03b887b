/* augsolve: apply an edits stream step by step: the planned method (one factorization for
 * every step) by default, the augmented-matrix method and the baselines on request. */
#include <getopt.h>
#include <stdio.h>
#include <string.h>

#include "augsolve_run.h"
#include "util.h"

static const char *USAGE =
    "usage: augsolve MESH.msh EDITS -o RUN_DIR [options]\n"
    "Apply the edits stream (keratome-edits(5); - reads stdin) to the mesh step by step and solve\n"
    "the linear elastic response under the scene's loads. Step 0 is the intact scene. Writes\n"
    "RUN_DIR/step-NNNN.vtk, steps.tsv, run.yaml. Every method first reads the whole stream and\n"
    "checks it (and every option) before anything is solved; the default method (planned) then\n"
    "factors the final cut mesh's augmented matrix once and solves every step exactly from it.\n"
    "  -o RUN_DIR            the run folder (created if needed; required)\n"
    "  --scene PATH          scene YAML (default: the one the edits header names)\n"
    "  --method M            planned (default), augmented (the paper's method on the\n"
    "                        append-only form: step after step), refactor, cg,\n"
    "                        pcg-jacobi, newton (the geometrically nonlinear reference:\n"
    "                        each step from the intact state, Newton with a factorization\n"
    "                        per iteration; no --verify)\n"
    "  --steps LIST          write only these steps (e.g. 3,6,10-12; step 0 always); the\n"
    "                        planned method solves only these, all from one factorization\n"
    "  --tol T               planned, augmented: largest backward error of the system solved\n"
    "                        (one step of iterative refinement first; default 1e-10); CG: the\n"
    "                        relative residual of K u = f to stop at\n"
    "  --maxit N             CG iteration cap (default 20000)\n"
    "  --ordering O          natural, amd, metis (default metis for planned and augmented,\n"
    "                        where it orders the intact block; natural (the mesh's order) for\n"
    "                        the others)\n"
    "  --factor F            supernodal (default) or simplicial (planned, refactor; the\n"
    "                        augmented method's factor is supernodal)\n"
    "  --output all|SET      displacements everywhere (default) or only on the nodes of the\n"
    "                        named surface or region (NaN elsewhere, every method; planned:\n"
    "                        restricted back substitution)\n"
    "  --plan-max-ratio R    planned: fall back to refactor with METIS when its factor's\n"
    "                        predicted nonzeros exceed R times METIS's on the intact block\n"
    "                        (default 4; 0: never) or its flops would take longer\n"
    "                        than a fresh factorization at every step\n"
    "  --plan-panel N        planned: store the increments' block in panels of N columns\n"
    "                        (default 256; 0: CHOLMOD's own supernodes, one square)\n"
    "  --uncertainty         also the derivative of every written step's displacement with\n"
    "                        respect to each uncertain quantity of the scene (its\n"
    "                        uncertainty section): fields dudp_<q> in the step VTKs and\n"
    "                        RUN_DIR/uncertainty.tsv (not with --method newton)\n"
    "  --verify              also factor K from scratch each step and compare\n"
    "  --verify-tol T        largest accepted relative difference (default 1e-8)\n"
    "  --no-vtk              write no step VTKs (benchmarks)\n"
    "  --binary              binary legacy VTK\n"
    "  -q, --quiet           no progress on stderr\n"
    "  -h, --help            this text\n"
    "      --version         the version (the CMake project version)\n"
    "Exit status: 0 ok, 1 numerical failure (a backward error above --tol, CG missing --tol, a\n"
    "factor that is not positive definite, a --verify difference above --verify-tol), 2 bad\n"
    "usage or input (also the removed GMRES options --restart, --precond, --refactor,\n"
    "--refactor-sync).\n"
    "See augsolve(1) and keratome-edits(5).\n";

static int usage_error(const char *msg, const char *arg)
{
    fprintf(stderr, "augsolve: %s%s%s (see augsolve --help)\n", msg, arg ? ": " : "",
            arg ? arg : "");
    return KT_EINPUT;
}

enum { O_SCENE = 256, O_METHOD, O_TOL, O_RESTART, O_MAXIT, O_PRECOND, O_ORDERING, O_FACTOR,
       O_REFACTOR, O_SYNC, O_OUTPUT, O_VERIFY, O_VTOL, O_NOVTK, O_BINARY, O_STEPS,
       O_MAXRATIO, O_PANEL, O_UNC };

/* One option; returns 0, or the exit code of a usage error. */
static int option(int c, const char *arg, kt_aug_run_opts *o)
{
    kt_aug_opts *a = &o->aug;
    int n;
    switch (c) {
    case 'o': o->run_dir = arg; return 0;
    case 'q': a->quiet = 1; return 0;
    case O_SCENE: o->scene = arg; return 0;
    case O_METHOD: return kt_aug_parse_method(arg, &a->method) ? usage_error("bad --method", arg) : 0;
    case O_TOL:
        return kt_parse_number(arg, &a->tol) || !(a->tol > 0 && a->tol < 1)
                   ? usage_error("--tol expects a number in (0, 1)", arg) : 0;
    case O_RESTART: case O_PRECOND: case O_REFACTOR: case O_SYNC:
        return usage_error("--restart, --precond, --refactor and --refactor-sync were removed "
                           "with GMRES: --method augmented is a direct "
                           "bordered solve (one intact factor, a dense Schur factor grown by "
                           "each step); see augsolve(1)", NULL);
    case O_MAXIT:
        return kt_parse_int(arg, &a->maxit) || a->maxit < 1
                   ? usage_error("--maxit expects a positive integer", arg) : 0;
    case O_ORDERING:
        return kt_aug_parse_ordering(arg, &a->ordering) ? usage_error("bad --ordering", arg) : 0;
    case O_FACTOR:
        return kt_aug_parse_factor(arg, &a->factor) ? usage_error("bad --factor", arg) : 0;
    case O_OUTPUT:
        n = (int)strlen(arg);
        if (n == 0 || n >= KT_NAME_MAX) return usage_error("bad --output", arg);
        if (strcmp(arg, "all") != 0) strcpy(a->output, arg);
        return 0;
    case O_VERIFY: a->verify = 1; return 0;
    case O_UNC: o->uncertainty = 1; return 0;
    case O_VTOL:
        return kt_parse_number(arg, &a->verify_tol) || !(a->verify_tol > 0)
                   ? usage_error("--verify-tol expects a positive number", arg) : 0;
    case O_NOVTK: o->vtk = 0; return 0;
    case O_BINARY: o->binary = 1; return 0;
    case O_STEPS: o->steps = arg; return 0;
    case O_MAXRATIO:
        return kt_parse_number(arg, &o->plan_max_ratio) || !(o->plan_max_ratio >= 0)
                   ? usage_error("--plan-max-ratio expects a number >= 0", arg) : 0;
    case O_PANEL:
        return kt_parse_int(arg, &a->plan_panel) || a->plan_panel < 0
                   ? usage_error("--plan-panel expects an integer >= 0", arg) : 0;
    }
    return usage_error("unknown or incomplete option", arg);
}

static int tool_main(int argc, char **argv)
{
    static const struct option LONG[] = {
        {"scene", required_argument, NULL, O_SCENE}, {"method", required_argument, NULL, O_METHOD},
        {"tol", required_argument, NULL, O_TOL}, {"restart", required_argument, NULL, O_RESTART},
        {"maxit", required_argument, NULL, O_MAXIT}, {"precond", required_argument, NULL, O_PRECOND},
        {"ordering", required_argument, NULL, O_ORDERING},
        {"factor", required_argument, NULL, O_FACTOR},
        {"refactor", required_argument, NULL, O_REFACTOR},
        {"refactor-sync", no_argument, NULL, O_SYNC}, {"output", required_argument, NULL, O_OUTPUT},
        {"verify", no_argument, NULL, O_VERIFY}, {"verify-tol", required_argument, NULL, O_VTOL},
        {"no-vtk", no_argument, NULL, O_NOVTK}, {"binary", no_argument, NULL, O_BINARY},
        {"steps", required_argument, NULL, O_STEPS},
        {"plan-max-ratio", required_argument, NULL, O_MAXRATIO},
        {"plan-panel", required_argument, NULL, O_PANEL},
        {"uncertainty", no_argument, NULL, O_UNC},
        {"quiet", no_argument, NULL, 'q'}, {"help", no_argument, NULL, 'h'},
        {"version", no_argument, NULL, 'V'}, {NULL, 0, NULL, 0}};
    kt_aug_run_opts o;
    kt_aug_run_opts_default(&o);
    int c, rc;
    opterr = 0;
    while ((c = getopt_long(argc, argv, "o:qh", LONG, NULL)) != -1) {
        if (c == 'h') {
            fputs(USAGE, stdout);
            return kt_stdout_done("augsolve");
        }
        if (c == 'V') {
            puts("augsolve (keratome) " KT_VERSION);
            return kt_stdout_done("augsolve");
        }
        if (c == '?' || c == ':') return usage_error("unknown or incomplete option", argv[optind - 1]);
        if ((rc = option(c, optarg, &o))) return rc;
    }
    if (optind != argc - 2) return usage_error("expected a mesh and an edits stream", NULL);
    if (!o.run_dir) return usage_error("expected -o RUN_DIR", NULL);
    o.mesh = argv[optind];
    o.edits = argv[optind + 1];
    kt_err e = {0};
    if (kt_aug_run(&o, &e)) {
        fprintf(stderr, "augsolve: %s\n", e.msg);
        return e.code;
    }
    return kt_stdout_done("augsolve");
}

int main(int argc, char **argv)
{
    kt_tool_start();
    kt_exit(tool_main(argc, argv));
}
