/* curvature: simulated keratometry of every step of an augsolve run (see curvature(1)). */
#define _POSIX_C_SOURCE 200809L
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "curvature_run.h"

static const char usage[] =
    "usage: curvature [options] RUN_DIR\n"
    "       curvature [options] --mesh MESH.msh STEP.vtk...\n"
    "       curvature --compare RUN_A RUN_B [-o OUTDIR]\n"
    "Simulated keratometry of the deformed anterior cornea at every step: K steep/flat, axis,\n"
    "cylinder, flattening of the incised meridian, steepening of the orthogonal one, coupling\n"
    "ratio, Alpins vector analysis, posterior and total corneal power, and with RUN_DIR/uncertainty.tsv\n"
    "(augsolve --uncertainty) each reading's first-order 90% band; writes curvature.tsv,\n"
    "meridians.tsv, surface-NNNN.vtk, axial-NNNN.png, report.html and (RUN_DIR) steps.pvd, and\n"
    "prints a summary.\n"
    "  --zone MM          keratometry zone diameter, mm (3, 5 or 7; default 3)\n"
    "  --fit KIND         toric (default: biconic with free apex) or zernike\n"
    "  --order N          Zernike order of the zone fit (2..12, default 6)\n"
    "  --map-zone MM      diameter of the axial power map, mm (default 8)\n"
    "  --map-order N      Zernike order of the map fit (2..12, default 8)\n"
    "  --meridian DEG     incised meridian, 0 to 360 (default: the plan's first incision, else the\n"
    "                     steep meridian of step 0)\n"
    "  --plan PLAN.yaml   plan for the incised meridian and target (default: run.yaml's plan)\n"
    "  --mesh MESH.msh    input mesh (with the 'anterior' surface group) of the step files\n"
    "  --png / --no-png   write the axial power maps (default on)\n"
    "  --no-vtk           do not write the surface VTKs\n"
    "  --scale TSV|auto   colour scale of the maps (default share/colour/axial.tsv, absolute);\n"
    "                     auto: relative, 0.25-3 D bins over this run's powers\n"
    "  --step N           report step N only (against step 0)\n"
    "  --arc DEG          report the step with DEG of arc opened per incision only\n"
    "  --compare A B      a page comparing two runs read by curvature: OUTDIR/compare.html\n"
    "  --eye OD|OS        the eye the report draws (nasal side; default OD, a right eye)\n"
    "  --no-report        do not write report.html\n"
    "  --json             print the summary as JSON (one object) instead of text\n"
    "  --sens FILE        finite-difference derivatives of the run's fd quantities (param, reading,\n"
    "                     dR_dp [, step]) for the uncertainty bands\n"
    "  --no-uncertainty   no bands, even when RUN_DIR has uncertainty.tsv\n"
    "  -o OUTDIR          output folder (default RUN_DIR, or . with --mesh)\n"
    "  -q                 no progress on stderr\n"
    "  -h, --help         this help\n"
    "      --version      the version (the CMake project version)\n"
    "Exit status: 0 ok, 1 run-time failure, 2 bad usage or input. See curvature(1).\n";

static int bad(const char *fmt, const char *arg)
{
    fprintf(stderr, "curvature: ");
    fprintf(stderr, fmt, arg);
    fprintf(stderr, " (see curvature --help)\n");
    return KT_EINPUT;
}

static int tool_main(int argc, char **argv)
{
    enum { O_ZONE = 256, O_FIT, O_ORDER, O_MAPZONE, O_MAPORDER, O_MERIDIAN, O_PLAN, O_MESH, O_PNG,
           O_NOPNG, O_NOVTK, O_SCALE, O_NOREPORT, O_JSON, O_VERSION, O_STEP, O_ARC, O_COMPARE, O_EYE,
           O_SENS, O_NOUQ };
    static const struct option lo[] = {
        {"zone", required_argument, 0, O_ZONE},         {"fit", required_argument, 0, O_FIT},
        {"order", required_argument, 0, O_ORDER},       {"map-zone", required_argument, 0, O_MAPZONE},
        {"map-order", required_argument, 0, O_MAPORDER}, {"meridian", required_argument, 0, O_MERIDIAN},
        {"plan", required_argument, 0, O_PLAN},         {"mesh", required_argument, 0, O_MESH},
        {"png", no_argument, 0, O_PNG},                 {"no-png", no_argument, 0, O_NOPNG},
        {"no-vtk", no_argument, 0, O_NOVTK},            {"scale", required_argument, 0, O_SCALE},
        {"no-report", no_argument, 0, O_NOREPORT},      {"json", no_argument, 0, O_JSON},
        {"version", no_argument, 0, O_VERSION},         {"help", no_argument, 0, 'h'},
        {"step", required_argument, 0, O_STEP},         {"arc", required_argument, 0, O_ARC},
        {"compare", no_argument, 0, O_COMPARE},         {"eye", required_argument, 0, O_EYE},
        {"sens", required_argument, 0, O_SENS},         {"no-uncertainty", no_argument, 0, O_NOUQ},
        {0, 0, 0, 0}};
    kt_curv_opts o;
    kt_curv_opts_default(&o);
    int c, compare = 0;
    opterr = 0;
    while ((c = getopt_long(argc, argv, "o:qh", lo, NULL)) != -1) {
        switch (c) {
        case O_ZONE:
            if (kt_parse_number(optarg, &o.zone) || !(o.zone >= 1 && o.zone <= 10))
                return bad("--zone %s: expected a diameter in mm, 1 to 10 (3, 5 or 7 usual)", optarg);
            break;
        case O_FIT:
            if (strcmp(optarg, "zernike") == 0) o.fit = KT_FIT_ZERNIKE;
            else if (strcmp(optarg, "toric") == 0) o.fit = KT_FIT_TORIC;
            else return bad("--fit %s: expected zernike or toric", optarg);
            break;
        case O_ORDER:
            if (kt_parse_int(optarg, &o.order) || o.order < 2 || o.order > KT_ZERN_ORDER_MAX)
                return bad("--order %s: expected an integer 2..12", optarg);
            break;
        case O_MAPZONE:
            if (kt_parse_number(optarg, &o.map_zone) || !(o.map_zone >= 1 && o.map_zone <= 14))
                return bad("--map-zone %s: expected a diameter in mm, 1 to 14", optarg);
            break;
        case O_MAPORDER:
            if (kt_parse_int(optarg, &o.map_order) || o.map_order < 2 || o.map_order > KT_ZERN_ORDER_MAX)
                return bad("--map-order %s: expected an integer 2..12", optarg);
            break;
        case O_MERIDIAN:
            if (kt_parse_number(optarg, &o.meridian) || !(o.meridian >= 0 && o.meridian < 360))
                return bad("--meridian %s: expected an angle in [0, 360) deg (as a plan's meridian)", optarg);
            break;
        case O_PLAN: o.plan = optarg; break;
        case O_MESH: o.mesh = optarg; break;
        case O_PNG: o.png = 1; break;
        case O_NOPNG: o.png = 0; break;
        case O_NOVTK: o.vtk_out = 0; break;
        case O_SCALE:
            o.scale = optarg;
            o.scale_auto = strcmp(optarg, "auto") == 0;
            break;
        case O_STEP:
            if (kt_parse_int(optarg, &o.step_sel) || o.step_sel < 1)
                return bad("--step %s: expected a step number, 1 or more", optarg);
            break;
        case O_ARC:
            if (kt_parse_double(optarg, &o.arc_sel) || !(o.arc_sel > 0 && o.arc_sel <= 360))
                return bad("--arc %s: expected degrees of arc, more than 0 and at most 360", optarg);
            break;
        case O_COMPARE: compare = 1; break;
        case O_EYE:
            if (strcmp(optarg, "OD") == 0 || strcmp(optarg, "od") == 0) o.eye_os = 0;
            else if (strcmp(optarg, "OS") == 0 || strcmp(optarg, "os") == 0) o.eye_os = 1;
            else return bad("--eye %s: expected OD (right eye) or OS (left eye)", optarg);
            break;
        case O_SENS: o.sens = optarg; break;
        case O_NOUQ: o.no_bands = 1; break;
        case 'o': o.outdir = optarg; break;
        case 'q': o.quiet = 1; break;
        case O_NOREPORT: o.report = 0; break;
        case O_JSON: o.json = 1; break;
        case O_VERSION: puts("curvature (keratome) " KT_VERSION); return kt_stdout_done("curvature");
        case 'h': fputs(usage, stdout); return kt_stdout_done("curvature");
        default: return bad("unknown or incomplete option: %s", argv[optind - 1]);
        }
    }
    if (o.step_sel >= 0 && isfinite(o.arc_sel)) return bad("%s", "--step and --arc: expected one of them");
    if (compare) {
        if (argc - optind != 2) return bad("%s", "--compare: expected two run folders, RUN_A RUN_B");
        kt_err e = {0};
        if (kt_curv_compare(argv[optind], argv[optind + 1], o.outdir ? o.outdir : ".", &e) != KT_OK) {
            fprintf(stderr, "curvature: %s\n", e.msg);
            return e.code;
        }
        return 0;
    }
    if (o.mesh) {
        o.vtk = (const char *const *)(argv + optind);
        o.nvtk = argc - optind;
        if (o.nvtk < 1) return bad("%s: expected at least one step VTK after --mesh", o.mesh);
    } else {
        if (argc - optind != 1) return bad("%s", "expected one RUN_DIR, or --mesh MESH.msh STEP.vtk...");
        o.run_dir = argv[optind];
    }
    kt_err e = {0};
    if (kt_curv_run(&o, stdout, &e) != KT_OK) {
        fprintf(stderr, "curvature: %s\n", e.msg);
        return e.code;
    }
    return kt_stdout_done("curvature");
}

int main(int argc, char **argv)
{
    kt_tool_start();
    kt_exit(tool_main(argc, argv));
}
