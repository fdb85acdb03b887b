/* lp_trim.h: the planner's fifth stage (writes kt_lp_answer.trim): every candidate's arcs kept
 * clear of the wounds (the main incision's tunnel, simulated or not, and the side port) before
 * anything is meshed (lri-plan(1), CLEARANCE; keratome-patient(5), CLEARANCE). The clearance
 * itself is the model's geometry (lib/model/clearance.h: kt_clearance of each arc from each
 * wound's footprint, at least constraints.clearance deg at the zone), or the caller's function
 * (kt_lp_opts.clear); the decision below takes its answers as data. */
#ifndef KT_LP_TRIM_H
#define KT_LP_TRIM_H

#include "clearance.h"
#include "lp.h"

/* The decision for family f cut in steps of `step` deg: clash[k] (k = 1..f->nstep) is 1 when
 * its arcs at k steps come within the clearance, reason[k] why (may be NULL). The arcs grow
 * centre-out, so the first step that clashes ends them: t->nstep := the steps before it (all
 * when none clashes; 0: the family is left out, its first step already clashes), t->meridian
 * := f->meridian, and t->why says which and why ("" when nothing is trimmed):
 * "<name> arcs left out: <reason>" or "<name> arcs at most <deg> deg: <reason>". */
void kt_lp_trim_decide(const kt_lp_family *f, double step, const unsigned char *clash, const char *const *reason,
                       kt_lp_trim *t);

/* trims := the decision for every family of fam, the clearance function (o->clear, else the
 * model's on the patient's wounds) asked about each family's plan at each extent. A single arc
 * that would be trimmed on the steeper half goes on the other half when more of its steps clear
 * there (t->moved; why says both). KT_EINPUT when a wound's tunnel does not fit the eye (named
 * at the patient's field). */
int kt_lp_trims_make(const kt_lp_opts *o, const kt_lp_eye *eye, const kt_lp_scene *sc, const kt_lp_families *fam,
                     kt_lp_trims *trims, kt_err *e);

/* Family i of a as cut: fam.f[i] with the trim's centre (every stage after this one reads the
 * candidates' centres from here or from trim.t[i].meridian). */
kt_lp_family kt_lp_family_cut(const kt_lp_answer *a, int i);

/* The model's clearance (kt_lp_clear) on `nw` wounds: plan p's arcs (each incision's, and the
 * opposite one of a pair at its own extent) clash when kt_clearance of one from a wound is not
 * at least min deg at the zone (its ellipse on an oval cornea); why: "the arc at C deg would come
 * within MIN deg of <wound> at M deg (Z mm zone)". */
typedef struct kt_lp_wounds {
    int nw;
    kt_footprint w[2];          /* the main incision, the side port */
    kt_zone zone;               /* the arcs' ring: its semi-axes at 0 and 90 deg after the oval warp, mm */
    double min;                 /* deg at the zone */
} kt_lp_wounds;
int kt_lp_wounds_of(const kt_lp_eye *eye, const kt_lp_scene *sc, kt_lp_wounds *w, kt_err *e);
int kt_lp_clear_model(void *ctx, const kt_plan *p, char *why, size_t n);

#endif
