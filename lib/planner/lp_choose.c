/* lp_choose.c: the predictions, the choice and its read-out (lp_choose.h). */
#include "lp_choose.h"

#include <math.h>
#include <string.h>

kt_astig kt_lp_astig_add(kt_astig a, kt_astig b)
{
    double x[2], y[2];
    kt_astig_xy(a, x);
    kt_astig_xy(b, y);
    return kt_astig_from_xy(x[0] + y[0], x[1] + y[1]);
}

kt_astig kt_lp_astig_sub(kt_astig a, kt_astig b)
{
    double x[2], y[2];
    kt_astig_xy(a, x);
    kt_astig_xy(b, y);
    return kt_astig_from_xy(x[0] - y[0], x[1] - y[1]);
}

int kt_lp_choose_best(int n, const int *ran, const int *nstep, const kt_astig pred[][KT_LP_MAXSTEP + 1], int *best)
{
    int chosen = -1;
    double low = INFINITY;
    for (int i = 0; i < n; i++) {
        best[i] = 0;
        if (!ran[i]) continue;
        for (int k = 0; k <= nstep[i]; k++) { /* a NaN prediction is never the best */
            double m = pred[i][k].mag, mb = pred[i][best[i]].mag;
            if (isfinite(m) && (!isfinite(mb) || m < mb - 1e-9)) best[i] = k;
        }
        double r = pred[i][best[i]].mag;
        if (!isfinite(r)) continue; /* no finite prediction: the family does not compete */
        if (chosen < 0 || r < low - KT_LP_TIE) low = r, chosen = i; /* within the tie: the fewer incisions */
    }
    return chosen;
}

void kt_lp_choose(const kt_lp_eye *eye, const kt_lp_families *fam, const kt_lp_runs *runs, kt_lp_choice *c)
{
    const kt_patient *p = &eye->p;
    memset(c, 0, sizeof *c);
    /* The posterior's toricity is in the mesh (keratome-patient(5)): the simulated total
     * corneal astigmatism carries it. A simulated main incision is in the runs already. */
    c->main_vec.mag = p->main_present && !p->main_simulate ? p->main_sia : 0;
    c->main_vec.axis = p->main_sia_axis;
    int ran[KT_LP_NFAM] = {0}, nstep[KT_LP_NFAM] = {0}, first = -1;
    for (int i = 0; i < fam->n; i++) {
        const kt_lp_run *r = &runs->r[i];
        ran[i] = r->ran, nstep[i] = r->nstep;
        if (r->ran && first < 0) first = i;
        for (int k = 0; r->ran && k <= r->nstep; k++)
            c->pred[i][k] = kt_lp_astig_add(p->target_kind == KT_TARGET_TOTAL ? r->total[k] : r->kerato[k], c->main_vec);
    }
    c->chosen = kt_lp_choose_best(fam->n, ran, nstep, (const kt_astig(*)[KT_LP_MAXSTEP + 1])c->pred, c->best);
    if (first < 0) return;
    const kt_lp_run *r0 = &runs->r[first];
    c->pre_kerato = kt_lp_astig_add(r0->kerato_intact, c->main_vec);
    c->pre_total = kt_lp_astig_add(r0->total_intact, c->main_vec);
    if (r0->skip > 0) {
        c->main_sia_kerato = kt_lp_astig_sub(r0->kerato[0], r0->kerato_intact);
        c->main_sia_total = kt_lp_astig_sub(r0->total[0], r0->total_intact);
    }
    c->bare_kerato = r0->kerato_intact, c->bare_total = r0->total_intact;
    c->with_kerato = r0->skip > 0 ? r0->kerato[0] : c->pre_kerato;
    c->with_total = r0->skip > 0 ? r0->total[0] : c->pre_total;
    c->sia_kerato = kt_lp_astig_sub(c->with_kerato, c->bare_kerato);
    c->sia_total = kt_lp_astig_sub(c->with_total, c->bare_total);
}

/* A clock hour as the surgeon reads the eye (12 superior, 3 at the examiner's right), in
 * [1, 13): 12.5 is half past twelve. */
static double clock_hour(double deg)
{
    double h = fmod(3 - deg / 30 + 48, 12);
    return h < 1 ? h + 12 : h;
}

void kt_lp_clock(double deg, char out[8])
{
    int m = (int)lround(clock_hour(deg) * 60) % 720;
    int h = m / 60 % 12;
    snprintf(out, 8, "%d:%02d", h == 0 ? 12 : h, m % 60);
}

double kt_lp_axis_shown(double axis, int decimals)
{
    return axis >= 180 - 0.5 * pow(10, -decimals) ? 0 : axis;
}

static double wrap360(double d) { return fmod(fmod(d, 360) + 360, 360); }

double kt_lp_chosen_arc(const kt_lp_answer *a)
{
    int i = a->choice.chosen;
    return i < 0 ? 0 : a->run.r[i].arc[a->choice.best[i]];
}

int kt_lp_arcs(const kt_lp_answer *a, kt_lp_arc arcs[2])
{
    int c = a->choice.chosen;
    if (c < 0 || !(kt_lp_chosen_arc(a) > 0)) return 0;
    const kt_lp_family *f = &a->fam.f[c];
    const kt_lp_run *r = &a->run.r[c];
    int n = 1 + f->paired, k = a->choice.best[c];
    for (int i = 0; i < n; i++) {
        kt_lp_arc *q = &arcs[i];
        q->centre = wrap360(a->trim.t[c].meridian + 180 * i); /* the trim's: a single arc may be moved */
        q->arc = i ? r->arc_opp[k] : r->arc[k];
        /* clockwise as seen from the front (the surgeon's order, whichever side they sit): from the
         * counter-clockwise end to the clockwise one, TABO angles decreasing */
        q->from = wrap360(q->centre + q->arc / 2), q->to = wrap360(q->centre - q->arc / 2);
        kt_lp_clock(q->from, q->from_clock), kt_lp_clock(q->to, q->to_clock);
        q->chord = kt_patient_zone_chord(&a->eye.p, q->centre, q->arc); /* on the oval zone */
    }
    return n;
}

void kt_lp_post(const kt_lp_answer *a, kt_astig *kerato, kt_astig *total)
{
    int c = a->choice.chosen;
    kerato->mag = kerato->axis = total->mag = total->axis = 0;
    if (c < 0) return;
    const kt_lp_run *r = &a->run.r[c];
    int k = a->choice.best[c];
    *kerato = kt_lp_astig_add(r->kerato[k], a->choice.main_vec);
    *total = kt_lp_astig_add(r->total[k], a->choice.main_vec);
}

double kt_lp_sia(const kt_lp_run *r, int k)
{
    return kt_lp_astig_sub(r->kerato[k], r->kerato[0]).mag;
}
