/* lp.h: the LRI planner (lri-plan(1), keratome-patient(5)): one patient in, the limbal relaxing
 * incisions that minimize the predicted residual astigmatism out, composed in memory from the
 * layers below: the patient becomes a scene (model), a mesh (model's builder and ordering
 * set), families of plans (model/plan.h structs), edits (cut), solved runs (solve/solver.h,
 * one factorization per family, the families sharing the physics), readings per step (optics)
 * and a choice. No file passes between its stages; the caller writes what it wants from the
 * answer and from the steps the planner shows it (kt_lp_opts.sink).
 *
 * Outputs: kt_lp_plan fills a kt_lp_answer. Its parts are written by the stages in order, each
 * stage writing only its own part (and reading the parts before it):
 *   eye     lp_patient.c  the patient as loaded, its Pentacam fits, halves, blade depth
 *   scene   lp_scene.c    the patient's eye scene with its measured surfaces, the main
 *                         incision's tunnel
 *   mesh    lp_mesh.c     the intact mesh (owned: kt_lp_answer_free), its hash and size
 *   fam     lp_family.c   the candidate families (single, paired, unequal) and their arcs
 *   trim    lp_trim.c     what the clearance from the wounds leaves of each family (its arcs'
 *                         steps and centre: the candidates' centres downstream are the trim's)
 *   run     lp_run.c      each family's readings per step, its tunnel steps, its fallback
 *   choice  lp_choose.c   the predictions, each family's best step, the chosen family
 *   band    lp_band.c     the 2-D band of the chosen prediction (lri-plan(1), BAND)
 * The arrays of a family are indexed by arc step k = 0..nstep (k = 0: no arc, the eye after
 * the main incision's tunnel when it is simulated); the run's own steps are k + run.skip. */
#ifndef KT_LP_H
#define KT_LP_H

#include <stdint.h>

#include "aug.h"
#include "curv.h"
#include "patient.h"
#include "physics.h"
#include "plan.h"
#include "sens.h"
#include "surffit.h"

#define KT_LP_MAXSTEP 64 /* arc steps of a family */
#define KT_LP_MAXQ 16    /* band quantities */
#define KT_LP_NFAM 3
enum { KT_LP_SINGLE = 0, KT_LP_PAIRED, KT_LP_UNEQUAL };

/* A 2x2 covariance in double-angle space, D^2 (x: cos 2a, y: sin 2a components). */
typedef struct kt_lp_cov {
    double xx, xy, yy;
} kt_lp_cov;

/* What the planner shows of each solved step (kt_lp_opts.sink): valid during the call. */
typedef struct kt_lp_step {
    int family;                 /* index into kt_lp_answer.fam.f */
    int step, nsteps;           /* the run's step (0: intact; then the tunnel's, then the arcs') */
    int skip;                   /* the run's steps of the main incision's tunnel */
    const kt_mesh *mesh;        /* the cut mesh after this step */
    const double *u;            /* 3 nn, mm */
    const int *origin;          /* nn: the intact node each node descends from (0-based) */
    int nd;                     /* derivative fields (0 without the band) */
    const double *dudp[KT_UQ_N];/* du/dq of sens->d[k].q, 3 nn, mm per unit of q */
    const kt_fem_sens *sens;    /* the band's quantities (NULL without it) */
    const kt_physics *ph;       /* the per-tet inputs (step 0's cell fields) */
    const struct kt_wound *wound; /* a healed wound's bridge on the intact mesh (NULL: the
                                   immediate wound; lib/fem/wound.h) */
    const kt_aug_row *row;      /* the solver's row of the step */
    int method;                 /* KT_AUG_* that ran */
    const char *fallback;       /* NULL, or why the planned method fell back */
} kt_lp_step;
typedef int (*kt_lp_sink)(void *ctx, const kt_lp_step *s, kt_err *e);

/* The clearance of a candidate's arcs from the wounds (the main incision, the side port;
 * keratome-patient(5), CLEARANCE): 1 when the arcs of plan p (its incisions at their extent)
 * come within the clearance, with the reason in why; 0 when they clear. The planner leaves out
 * or trims what does not clear (lp_trim.c) before anything is meshed. */
typedef int (*kt_lp_clear)(void *ctx, const kt_plan *p, char *why, size_t n);

typedef struct kt_lp_opts {
    const char *patient;        /* PATIENT.yaml */
    const char *base;           /* base eye scene; NULL: the repository's plans/eye.yaml */
    double step;                /* arc added per step, deg (5) */
    int fast;                   /* coarse mesh, the floor refinement at KT_LP_FAST_FLOOR */
    int no_band;                /* no derivatives, no band */
    int quiet;
    double plan_max_ratio;      /* the planned factor's limit (aug_plan.h, KT_PLAN_MAX_RATIO):
                                   beyond it a family falls back to refactor, loudly */
    int state;                  /* the wound planned for: KT_WOUND_HEALED (the default: the
                                   base scene's scar, its bridge_stiffness, age_rate and months)
                                   or KT_WOUND_IMMEDIATE; overrides the base's wound.state */
    kt_lp_cov band_extra;       /* a covariance added to the prediction's (non-tissue terms:
                                   healing, blade depth, keratometry), D^2; zero: none */
    int jobs;                   /* families run side by side, each on a thread of its own: 1
                                   one at a time, 2 or more at most that many at once; 0 (the
                                   default) decides (lp_run.h). The answer is the same to the
                                   bit whatever it is. */
    kt_lp_sink sink;            /* NULL, or called with every solved step of every family;
                                   with jobs > 1 from the families' threads, one family's steps
                                   from one thread, in order */
    void *sink_ctx;
    kt_lp_clear clear;          /* NULL: the model's clearance (lib/model/clearance.h) from the
                                   patient's wounds and constraints.clearance (lp_trim.c); else
                                   this function (tests) */
    void *clear_ctx;
} kt_lp_opts;

void kt_lp_opts_default(kt_lp_opts *o);

/* ---- the answer's parts, one writer each (see the top) ---- */

typedef struct kt_lp_eye {
    kt_patient p;               /* as loaded, the Pentacam fit's radii and thickness put in */
    int fitted;                 /* the cornea came from a Pentacam export */
    kt_surffit fit_ant, fit_post;
    int fit_post_ok, fit_pachy_ok;
    kt_pachyfit fit_pachy;
    kt_halfmer halves;          /* the half-meridian powers (Pentacam front) */
    int halves_ok;
    double half_a, half_b;      /* half-meridian astigmatism at axis and axis + 180, D */
    double ratio;               /* the shorter arc over the longer (1: symmetric) */
    double steep_half;          /* meridian of the steeper half, deg [0, 360) */
    double t_zone;              /* pachymetry at the zone used, mm */
    double blade;               /* blade depth, mm */
} kt_lp_eye;

typedef struct kt_lp_scene {
    kt_scene s;                 /* the patient's eye scene (path: the base's) */
    char base[1024];            /* the base scene file */
    int main_sim;               /* the main incision is simulated: main holds its tunnel */
    kt_tunnel main;             /* its tunnel, derived */
    int measured;               /* a Pentacam patient: s.eye carries the measured surfaces
                                   (s.eye.dep_ant, dep_post; keratome-patient(5), THE FIT) */
    kt_surffit mesh_ant, mesh_post; /* the eye's fits (kt_lp_eye.fit_ant, fit_post) with the
                                   mesh's surfaces' residuals against the maps (dep_*; dep_order
                                   0: none, mesh_post's without a back map) */
} kt_lp_scene;

typedef struct kt_lp_mesh {
    kt_mesh m;                  /* the intact mesh, nodes in elimination order (owned) */
    uint64_t hash;              /* kt_mesh_hash */
    double seconds, cpu;        /* wall and CPU seconds to make it */
} kt_lp_mesh;

typedef struct kt_lp_family {
    int kind;                   /* KT_LP_* */
    int paired, unequal;
    double meridian;            /* the (longer) arc's centre, deg [0, 360) */
    double ratio;               /* the opposite arc over this one (1 for an equal pair) */
    char name[16];              /* single, paired, unequal */
    int nstep;                  /* arc steps to max_arc */
} kt_lp_family;
typedef struct kt_lp_families {
    int n;
    kt_lp_family f[KT_LP_NFAM];
} kt_lp_families;

typedef struct kt_lp_trim {
    int nstep;                  /* arc steps kept (<= the family's; 0: left out) */
    double meridian;            /* the (longer) arc's centre as cut, deg [0, 360): the family's,
                                   or for a single arc the other half's when it keeps clear
                                   longer there (moved) */
    int moved;
    char why[640];              /* "" when nothing was trimmed or moved */
} kt_lp_trim;
typedef struct kt_lp_trims {
    kt_lp_trim t[KT_LP_NFAM];
} kt_lp_trims;

typedef struct kt_lp_run {
    int ran;                    /* the family was run */
    int skip;                   /* the run's steps of the main incision's tunnel */
    int nstep;                  /* arc steps run */
    double arc[KT_LP_MAXSTEP + 1], arc_opp[KT_LP_MAXSTEP + 1]; /* deg (arc_opp 0: single) */
    kt_astig kerato[KT_LP_MAXSTEP + 1], total[KT_LP_MAXSTEP + 1]; /* simulated */
    kt_astig kerato_intact, total_intact; /* the run's step 0 (before any cut) */
    double dsia[KT_LP_MAXSTEP + 1][KT_LP_MAXQ][2]; /* d(SIA_x, SIA_y)/dq from step 0, D per unit */
    char fallback[300];         /* "" or why the planned method fell back */
    int method;                 /* KT_AUG_* that ran */
    double cpu_cut, cpu_solve, cpu_read, cpu_sink; /* CPU seconds: edits, solves, readings, the
                                   caller's sink (the process's when the families run one at a
                                   time, the family's threads' when side by side) */
} kt_lp_run;
typedef struct kt_lp_runs {
    kt_lp_run r[KT_LP_NFAM];
    int nq;                     /* the band's quantities (derivative), KT_UQ_* in q */
    int q[KT_LP_MAXQ];
    double sd[KT_LP_MAXQ];      /* their sd, in their unit */
    char left[256];             /* quantities with a spread and no derivative, ", "-separated */
    double cpu_physics;         /* the shared physics, CPU seconds */
    double solve_seconds;       /* wall seconds of the families' runs: cuts, the shared
                                   physics, the solves */
    int jobs;                   /* how many families ran at once (1: one at a time) */
} kt_lp_runs;

typedef struct kt_lp_choice {
    kt_astig main_vec;          /* the surgeon's SIA added (0 when none or simulated) */
    kt_astig pre_kerato, pre_total; /* pre-operative (intact, with main_vec) */
    kt_astig main_sia_kerato, main_sia_total; /* the simulated main incision's SIA (0: none) */
    kt_astig bare_kerato, bare_total; /* pre-operative without the main incision (intact) */
    kt_astig with_kerato, with_total; /* with it: the simulated tunnel's eye, or the intact eye
                                   plus the surgeon's vector (= bare without a main incision) */
    kt_astig sia_kerato, sia_total; /* the main incision's SIA used: with - bare (0: none) */
    kt_astig pred[KT_LP_NFAM][KT_LP_MAXSTEP + 1]; /* predicted post-operative, the target's kind */
    int best[KT_LP_NFAM];       /* arc step of the least predicted residual */
    int chosen;                 /* family index; -1: none ran */
} kt_lp_choice;

/* A prediction's band: the double-angle vector v ~ N(mean, cov); its magnitude's distribution,
 * its mean, sd and 5% / 95% quantiles (lo, hi), computed from that 2-D normal distribution. */
typedef struct kt_lp_band {
    double mean[2];             /* the prediction, D */
    kt_lp_cov cov;              /* D^2 */
    double mag;                 /* |mean|, D */
    double sd, lo, hi;          /* of |v|, D (NAN: no band) */
} kt_lp_band;
typedef struct kt_lp_bands {
    int on;
    kt_lp_band residual, post_kerato, post_total; /* the chosen plan's */
    kt_lp_band best[KT_LP_NFAM];/* each family's best residual */
    double sia_sd;              /* the SIA's sd at the chosen step (its projection on itself), D:
                                   the tissue quantities' and the non-tissue term's */
    double sia_sd_tissue;       /* the tissue quantities' part alone, D */
} kt_lp_bands;

typedef struct kt_lp_answer {
    kt_lp_eye eye;
    kt_lp_scene scene;
    kt_lp_mesh mesh;
    kt_lp_families fam;
    kt_lp_trims trim;
    kt_lp_runs run;
    kt_lp_choice choice;
    kt_lp_bands band;
} kt_lp_answer;

/* Plan o->patient into *a (zeroed first): every stage in order. Bad input is KT_EINPUT before
 * anything is meshed; a run-time failure KT_ERUN. Progress on stderr unless quiet; a planned
 * solve that falls back says so on stderr whatever quiet says. */
int kt_lp_plan(const kt_lp_opts *o, kt_lp_answer *a, kt_err *e);
void kt_lp_answer_free(kt_lp_answer *a);

/* A meridian as the surgeon marks it on a degree gauge: whole degrees (halves away from zero),
 * in [0, 360). Every page and message prints an arc's centre and end points through it. */
double kt_lp_deg_mark(double deg);

/* The decimals (2 to 4) that print a residual of r D beside a target of t D (both with them) so
 * that the two figures do not read as equal when r misses t by 0.00005 D or more: 0.503 against
 * 0.50, not 0.50 against 0.50. */
int kt_lp_res_digits(double r, double t);

#endif
