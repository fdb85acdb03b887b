/* curv_report.h: the teaching report of a curvature run (RUN/report.html): one self-contained
 * HTML page (maps as PNG data URIs, plots as inline SVG, inline CSS, no script) with the plan
 * on a frontal eye diagram, the axial maps before and after on one absolute scale, the
 * tangential and difference maps, flattening / steepening / SIA against step, the
 * double-angle plot with the Alpins indices, a meridional section through an incision with
 * the wound opening, and the run's provenance. Also the meridional section itself. */
#ifndef KT_CURV_REPORT_H
#define KT_CURV_REPORT_H

#include "curv_total.h"
#include "plan.h"
#include "axialmap.h"

/* ---- meridional section (curv_section.c) ---- */

/* The cut of a step's tets by the half-plane through the eye axis at meridian t: polygons in
 * (r, z), r the distance along the meridian (cos t, sin t), of the tets whose centroid lies
 * within rc +- w along it and at most 1.6 w below the highest point there (the anterior
 * surface: the window holds the cornea around an incision at rc, not the globe behind). The
 * geometry drawn is the pre-operative shape (reference + step-0 displacement); def holds the
 * displacement since step 0, so base + F def shows the surgery's change exaggerated F times. */
typedef struct kt_section {
    double meridian, r0, r1;
    int n;              /* polygons (3 or 4 corners) */
    int *nv;            /* corners of each */
    double *base;       /* 8 n: (r, z) of each corner (4 slots per polygon), mm */
    double *def;        /* 8 n: (dr, dz) displacement since step 0, mm */
    double max_disp;    /* largest |displacement since step 0| of a corner drawn, mm */
    double gape;        /* largest separation of two points split from one input node (the
                         * wound's faces) within 0.5 mm of the section, mm; 0: none */
    double gape_all;    /* the same over the whole step mesh (every incision), mm */
} kt_section;

/* u0 (may be NULL: zero) is step 0's displacement by input-mesh node (3 per node, 0-based). */
int kt_curv_section(const kt_vtk *v, const double *u0, int mesh_nn, double meridian, double rc, double w,
                    kt_section *s, kt_err *e);
void kt_section_free(kt_section *s);

/* ---- the report (curv_report.c) ---- */

/* One step's figures (against step 0). */
typedef struct kt_report_step {
    kt_kerato k;
    double k_inc, k_ort, flat, steep; /* D */
    kt_alpins va;
    kt_total tot;
    double arc;                       /* degrees of arc opened per incision (NaN: unknown) */
} kt_report_step;

/* The patient's main cataract incision as the report shows it (lri-plan's chosen run): drawn at
 * the limbus; when it is not simulated, the surgeon's SIA vector that the prediction adds to
 * the simulated eye (the report then states both the simulated post-operative astigmatism and
 * the prediction with it). */
typedef struct kt_report_main {
    int present;
    double meridian, width;           /* deg TABO, mm */
    int simulated;                    /* cut in the run (its tunnel's steps before the arcs) */
    kt_astig sia;                     /* the surgeon's SIA added (mag 0: none) */
} kt_report_main;

typedef struct kt_report {
    const char *version, *run_dir, *mesh, *plan_path, *run_yaml; /* run_yaml: its text, or NULL */
    const char *scene_path;     /* the scene as the provenance names it (NULL: the plan's) */
    const kt_plan *plan;              /* NULL: no plan */
    int mesh_nn, mesh_ne, mesh_order;
    int nstep;
    const kt_report_step *step;       /* nstep */
    double meridian;                  /* incised meridian, deg */
    int has_target;
    kt_astig tia;
    const kt_fit *map_pre, *map_post; /* the map fits of step 0 and the last step */
    double rad_pre, rad_post;         /* their radii, mm */
    double zone;                      /* keratometry zone diameter, mm */
    const char *fit_name;
    const kt_topo_scale *scale, *diff_scale; /* absolute axial scale; post - pre scale */
    const kt_section *section;        /* NULL: none */
    double solver_ms;                 /* sum of steps.tsv's t_total_ms (NaN: unknown) */
    double curv_s;                    /* curvature's own time so far, s */
    const kt_cornea_n *n;
    const int *num;                   /* nstep: each step's number in its run */
    const char *verdict;              /* over-/under-correction and axis flip (NULL: none) */
    const char *axis_note;            /* why the steep axis swings (NULL: it does not) */
    const kt_topo_scale *rel_scale;   /* relative scale over the run's powers (NULL: none) */
    int scale_auto;                   /* the maps' scale is the relative one (--scale auto) */
    const kt_fit *const *maps;        /* nstep map fits (the strip of every step's map) */
    const double *map_rad;            /* nstep their radii, mm */
    double apex_z;                    /* step 0's fitted apex height, mm (eye frame) */
    int eye_os;                       /* 1: a left eye (OS), 0: right (OD) */
    const kt_report_main *main;       /* NULL: no main incision to show */
    const double *sia_lo, *sia_hi;   /* nstep: the SIA's 90% band (NULL: no bands) */
    int ntorn;                        /* quantities in the tornado chart (0: none) */
    const char *const *torn_name;     /* ntorn, largest first */
    const double *torn_val;           /* their contributions to the SIA's sd at the last step, D */
    double sia_sd;                    /* the SIA's sd at the last step, D */
    int nprov;                        /* provenance rows from run.yaml: key, value pairs */
    const char *const *prov;
} kt_report;

/* The display factor of the section: 1, 2 or 5 times a power of ten bringing the largest
 * displacement to about `target` mm on the drawing (1 when nothing moves). */
double kt_report_exaggeration(double max_disp, double target);

/* The headline: over-correction (correction index > 1.1), under-correction (< 0.9) or on target
 * against the plan's target (else the induced astigmatism alone), then the cylinder before and
 * after, said to flip when its steep axis moved by more than 45 deg and 0.25 D or more remain. */
void kt_report_verdict(kt_astig pre, kt_astig post, const kt_alpins *va, int has_target, char *buf, size_t size);

/* Write the page to `path` atomically. */
int kt_curv_report_write(const char *path, const kt_report *r, kt_err *e);

#endif
