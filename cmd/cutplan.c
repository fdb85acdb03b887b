/* cutplan: an incision plan (YAML) and a mesh become a stream of node-duplication edits. */
#include <getopt.h>
#include <stdio.h>
#include <string.h>

#include "cutplan_run.h"

static const char *USAGE =
    "usage: cutplan PLAN.yaml MESH.msh -o EDITS [--mesh-out SNAPPED.msh [--binary]] [-q]\n"
    "Turn the plan's incisions (arcs on the eye's incision-ready surfaces), planar cuts and\n"
    "deformation steps into the edits stream augsolve applies step by step (keratome-edits(5)).\n"
    "Steps are written and flushed one at a time, so -o - can feed augsolve through a pipe.\n"
    "  -o, --output PATH     edits file, or - for stdout (required)\n"
    "  --mesh-out PATH       write the mesh the edits apply to; required when a cut without an\n"
    "                        incision-ready surface snaps nodes onto the cutting surface\n"
    "  --binary              binary MSH for --mesh-out\n"
    "  -q, --quiet           no progress or summary on stderr\n"
    "  -h, --help            this text\n"
    "      --version         the version (the CMake project version)\n"
    "Exit status: 0 ok, 1 run-time failure (e.g. snapping would invert an element), 2 bad\n"
    "usage or input. See cutplan(1) and keratome-plan(5).\n";

static int usage_error(const char *msg, const char *arg)
{
    fprintf(stderr, "cutplan: %s%s%s (see cutplan --help)\n", msg, arg ? ": " : "", arg ? arg : "");
    return KT_EINPUT;
}

static int tool_main(int argc, char **argv)
{
    static const struct option LONG[] = {{"output", required_argument, NULL, 'o'},
                                         {"mesh-out", required_argument, NULL, 'm'},
                                         {"binary", no_argument, NULL, 'b'},
                                         {"quiet", no_argument, NULL, 'q'},
                                         {"help", no_argument, NULL, 'h'},
                                         {"version", no_argument, NULL, 'V'},
                                         {NULL, 0, NULL, 0}};
    kt_cutplan_opts o = {0};
    int c;
    opterr = 0;
    while ((c = getopt_long(argc, argv, "o:qh", LONG, NULL)) != -1) {
        switch (c) {
        case 'o': o.out = optarg; break;
        case 'm': o.mesh_out = optarg; break;
        case 'b': o.binary = 1; break;
        case 'q': o.quiet = 1; break;
        case 'h': fputs(USAGE, stdout); return kt_stdout_done("cutplan");
        case 'V': puts("cutplan (keratome) " KT_VERSION); return kt_stdout_done("cutplan");
        default: return usage_error("unknown or incomplete option", argv[optind - 1]);
        }
    }
    if (optind != argc - 2) return usage_error("expected a plan and a mesh", NULL);
    if (!o.out) return usage_error("expected -o EDITS", NULL);
    o.plan = argv[optind];
    o.mesh = argv[optind + 1];
    if (strcmp(o.plan, "-") == 0 && strcmp(o.mesh, "-") == 0)
        return usage_error("the plan and the mesh cannot both be stdin", NULL);
    kt_err e = {0};
    if (kt_cutplan_run(&o, &e)) {
        fprintf(stderr, "cutplan: %s\n", e.msg);
        return e.code;
    }
    return kt_stdout_done("cutplan");
}

int main(int argc, char **argv)
{
    kt_tool_start();
    kt_exit(tool_main(argc, argv));
}
