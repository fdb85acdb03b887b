/* lriplan_int.h: what lri-plan's files share (private to lib/app/lriplan_*.c). */
#ifndef KT_LRIPLAN_INT_H
#define KT_LRIPLAN_INT_H

#include <stdint.h>

#include "clearance.h"
#include "curv.h"
#include "lriplan_run.h"
#include "patient.h"
#include "surffit.h"

#define KT_LRIPLAN_MAXSTEP 64
/* --fast's incision-floor size, mm (lri-plan(1), --fast; a mesh setting, not a physical
 * number): measured on plans/patients/wtr-od.yaml, the --fast mesh's best arcs were 85 / 2 x 55
 * deg without a floor refinement, 75 / 2 x 50 with 0.1 mm and 0.08 mm, 70 / 2 x 50 with
 * 0.06 mm, against the default mesh's (floor 42 um) 70 / 2 x 50; 0.1 mm is the coarsest of
 * these within one 5 deg step of the default, at about 1.7x the CPU of no refinement. */
#define KT_LRIPLAN_FAST_FLOOR 0.1
/* Unequal paired arcs (keratome-patient(5), UNEQUAL PAIRED ARCS; the project's rule, not a
 * publication's): run when the two halves' astigmatism differ by more than 10% (their ratio
 * below 0.9); the opposite arc's ratio is never below 0.2 (shorter, a single arc does it). */
#define KT_LRIPLAN_SYMMETRIC 0.9
#define KT_LRIPLAN_RATIO_MIN 0.2

/* The band's data of a family's run (lriplan_band.c): augsolve --uncertainty's derivative
 * quantities, their sd, and each step's derivative of the keratometric SIA's double-angle vector
 * (curvature's derivatives.tsv: sia_x_D, sia_y_D). */
#define KT_LRIPLAN_MAXQ 16
typedef struct kt_lri_bdata {
    int on;                           /* the run has derivatives.tsv */
    int nq;
    char q[KT_LRIPLAN_MAXQ][32];      /* the quantities with a derivative (used) */
    double sd[KT_LRIPLAN_MAXQ];       /* their sd, in their unit */
    double dsia[KT_LRIPLAN_MAXSTEP + 1][KT_LRIPLAN_MAXQ][2]; /* d(sia_x, sia_y)/dq, D per unit */
    char left[256];                   /* quantities left out (fd, no derivative), ", "-separated */
} kt_lri_bdata;

/* A band: sd and 90% interval of a magnitude, D (NAN: no band). */
typedef struct kt_lri_band {
    double sd, lo, hi;
} kt_lri_band;

/* One family's run: the predicted astigmatism after each step (step 0: no arc). */
typedef struct kt_lri_family {
    int paired;
    int unequal;                      /* a pair of unequal arcs (the opposite one ratio x arc) */
    double meridian;                  /* the (longer) arc's centre, deg [0, 360) */
    double ratio;                     /* the opposite arc over this one (1 for an equal pair) */
    char name[16];                    /* single, paired, unequal: the files' names */
    int nstep;                        /* steps run, arcs step * o->step deg */
    double arc[KT_LRIPLAN_MAXSTEP + 1], arc_opp[KT_LRIPLAN_MAXSTEP + 1]; /* deg (arc_opp: 0 single) */
    kt_astig kerato[KT_LRIPLAN_MAXSTEP + 1], total[KT_LRIPLAN_MAXSTEP + 1]; /* simulated */
    kt_astig pred[KT_LRIPLAN_MAXSTEP + 1]; /* predicted post-operative, the target's kind */
    kt_astig kerato_intact, total_intact; /* simulated before any cut (the run's step 0; the same
                                       as step 0 above unless the main incision is simulated) */
    int best;                         /* step of the least predicted residual */
    kt_lri_bdata band;                /* the first-order band's derivatives (lriplan_band.c) */
} kt_lri_family;

/* Everything the answer reports. */
typedef struct kt_lri_answer {
    kt_patient p;
    int fitted;                       /* the cornea came from a Pentacam export */
    kt_surffit fit_ant, fit_post;
    int fit_post_ok, fit_pachy_ok;
    kt_pachyfit fit_pachy;
    kt_halfmer halves;                /* the half-meridian powers (Pentacam front) */
    int halves_ok;
    double half_a, half_b;            /* half-meridian astigmatism at axis and axis + 180, D */
    double ratio;                     /* the shorter arc over the longer (1: symmetric) */
    double steep_half;                /* meridian of the steeper half, deg [0, 360) */
    double t_zone;                    /* pachymetry at the zone used, mm */
    double blade;                     /* blade depth, mm */
    kt_astig pre_kerato, pre_total;   /* pre-operative (measured; total with the posterior) */
    kt_astig main_vec;                /* the main incision's SIA added (0 when none / simulated) */
    int main_steps;                   /* the run's steps of the simulated main incision (0: none) */
    kt_astig main_sia_kerato, main_sia_total; /* its simulated SIA (lriplan_main.c) */
    int nfam;
    kt_lri_family fam[3];
    char clear_note[3][320];          /* why a family (single, paired, unequal) was trimmed or left
                                       out to keep clear of the wounds ("": neither) */
    int chosen;                       /* family index of the answer */
    double mesh_seconds, solve_seconds;
    int nodes;                        /* of the mesh */
    uint64_t mesh_hash;               /* kt_mesh_hash of the mesh */
} kt_lri_answer;

/* One arc of the answer as the surgeon marks it. */
typedef struct kt_lri_arc {
    double centre, arc;               /* deg TABO [0, 360), deg */
    double from, to;                  /* end points, deg [0, 360): from centre - arc/2 to centre + arc/2 */
    char from_clock[8], to_clock[8];  /* "h:mm" */
    double chord;                     /* mm at the zone */
} kt_lri_arc;

/* The chosen answer's arcs (0 when no arc, 1 single, 2 a pair); post-operative astigmatism. */
int kt_lri_arcs(const kt_lri_answer *a, kt_lri_arc arcs[2]);
void kt_lri_post(const kt_lri_answer *a, kt_astig *kerato, kt_astig *total);
/* The clock hour of a meridian as the surgeon reads the eye (12 superior, 3 at the
 * examiner's right), "h:mm". */
void kt_lri_clock(double deg, char out[8]);

/* plan.html (lriplan_html.c); report: the chosen run's report.html relative to PLAN_DIR, or
 * NULL. */
int kt_lri_write_html(const kt_lri_answer *a, const kt_lriplan_opts *o, const char *report, const char *path, kt_err *e);
/* The simulated keratometric SIA of step k of a family, D (double-angle difference from step 0). */
double kt_lri_sia(const kt_lri_family *c, int k);
/* The simulated main incision (lriplan_main.c): the steps its tunnel takes in every family's
 * run (0 when it is not simulated); its `tunnels` block into a family's plan; its simulated SIA
 * from the first family's run (after the tunnel against before it). */
int kt_lri_main_steps(const kt_patient *p);
/* The tunnel checked against the patient's eye before any meshing (KT_EINPUT); the scene's
 * mesh refinement set to follow its site (eye.mesh_size.site). */
int kt_lri_main_check(const kt_patient *p, kt_scene *s, kt_err *e);
int kt_lri_main_plan(FILE *f, const kt_patient *p, const kt_scene *s);
void kt_lri_main_sia(kt_lri_answer *a);
/* How many steps of a family's edits the tunnel took (a portion of the blade's advance that
 * splits no node merges into the next one, so it may be fewer than planned). */
int kt_lri_main_count(const char *edits, int *n, kt_err *e);
/* The wounds the arcs keep clear of (keratome-patient(5), CLEARANCE): the main incision's tunnel
 * (simulated or not) and the side port; *nw of them (at most 2). KT_EINPUT as kt_lri_main_check. */
int kt_lri_wounds(const kt_patient *p, const kt_scene *s, kt_wound w[2], int *nw, kt_err *e);

/* The first-order band (lriplan_band.c; lri-plan(1), BAND): read RUN/derivatives.tsv of a
 * family's run into f->band (the first `skip` steps after step 0 are the main incision's); the
 * band of the magnitude of an astigmatism v predicted at step k of f (v = pre-op + main
 * incision + the arcs' simulated SIA, so dv/dq = dSIA/dq); plan.json's "band" member (written
 * after "plan"), the summary's and plan.html's lines. */
int kt_lri_band_read(const char *run, kt_lri_family *f, int skip, kt_err *e);
void kt_lri_band_of(const kt_lri_family *f, int k, kt_astig v, kt_lri_band *b);
void kt_lri_band_json(const kt_lri_answer *a, FILE *j);
void kt_lri_band_summary(const kt_lri_answer *a, FILE *s);
void kt_lri_band_html(const kt_lri_answer *a, FILE *f);

/* Fill the answer's prediction per step and choose (lriplan_out.c). */
void kt_lri_choose(kt_lri_answer *a);
/* plan.json into the folder and the summary text. */
int kt_lri_write_json(const kt_lri_answer *a, const kt_lriplan_opts *o, const char *report, const char *path, kt_err *e);
void kt_lri_summary(const kt_lri_answer *a, const kt_lriplan_opts *o, FILE *f);

#endif
