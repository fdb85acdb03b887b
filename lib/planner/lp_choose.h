/* lp_choose.h: the planner's seventh stage (writes kt_lp_answer.choice): the predicted
 * post-operative astigmatism of every step (the simulated astigmatism of the target's kind, and
 * the surgeon's SIA vector of a main incision that is not simulated, by double-angle sum),
 * each family's best step (the least predicted residual) and the chosen family: the least
 * residual, the fewer incisions when within KT_LP_TIE (families are tried single first). And
 * the chosen answer read out as the surgeon marks it. */
#ifndef KT_LP_CHOOSE_H
#define KT_LP_CHOOSE_H

#include "lp.h"

/* Two residuals within this are a tie, D (the summary's precision): the fewer incisions win. */
#define KT_LP_TIE 0.01

/* The choice from the runs' readings: choice->pred, best, chosen (-1 when no family ran),
 * the pre-operative astigmatism and the simulated main incision's SIA. */
void kt_lp_choose(const kt_lp_eye *eye, const kt_lp_families *fam, const kt_lp_runs *runs, kt_lp_choice *choice);

/* The decision alone, on n families' predictions (pred[i][0..nstep[i]], ran[i]): best[i] the
 * first step of the least magnitude (a later one must be lower by more than 1e-9 D); returns
 * the chosen family: the least best residual, an earlier family (fewer incisions) kept unless
 * a later one is lower by more than KT_LP_TIE; -1 when none ran. */
int kt_lp_choose_best(int n, const int *ran, const int *nstep, const kt_astig pred[][KT_LP_MAXSTEP + 1], int *best);

/* One arc of the answer as the surgeon marks it. */
typedef struct kt_lp_arc {
    double centre, arc;         /* deg TABO [0, 360), deg */
    double from, to;            /* end points, deg [0, 360), in the order the surgeon marks them:
                                   clockwise seen from the front, from centre + arc/2 to
                                   centre - arc/2 */
    char from_clock[8], to_clock[8]; /* "h:mm" */
    double chord;               /* mm at the zone */
} kt_lp_arc;

/* The chosen answer's arcs (0 when no arc, 1 single, 2 a pair). */
int kt_lp_arcs(const kt_lp_answer *a, kt_lp_arc arcs[2]);
/* The chosen answer's predicted post-operative astigmatism, keratometric and total. */
void kt_lp_post(const kt_lp_answer *a, kt_astig *kerato, kt_astig *total);
/* The chosen family's arc, deg (0: no arc or none chosen). */
double kt_lp_chosen_arc(const kt_lp_answer *a);
/* The simulated keratometric SIA of arc step k of family i, D (double-angle difference from
 * arc step 0). */
double kt_lp_sia(const kt_lp_run *r, int k);
/* The clock hour of a meridian as the surgeon reads the eye (12 superior, 3 at the examiner's
 * right), "h:mm". */
void kt_lp_clock(double deg, char out[8]);
/* An axis (deg, [0, 180)) as printed with `decimals` places: one that would print as 180 is 0,
 * the same meridian. */
double kt_lp_axis_shown(double axis, int decimals);
/* The double-angle sum and difference of two astigmatisms. */
kt_astig kt_lp_astig_add(kt_astig a, kt_astig b);
kt_astig kt_lp_astig_sub(kt_astig a, kt_astig b);

#endif
