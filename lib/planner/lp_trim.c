/* lp_trim.c: the candidates kept clear of the wounds (lp_trim.h). */
#include "lp_trim.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "eye.h"
#include "lp_family.h"
#include "lp_scene.h"

void kt_lp_trim_decide(const kt_lp_family *f, double step, const unsigned char *clash, const char *const *reason,
                       kt_lp_trim *t)
{
    memset(t, 0, sizeof *t);
    t->meridian = f->meridian;
    int k = 1;
    while (k <= f->nstep && !clash[k]) k++;
    t->nstep = k - 1;
    if (k > f->nstep) return;
    const char *why = reason && reason[k] && reason[k][0] ? reason[k] : "within the clearance of the main incision";
    if (t->nstep == 0) snprintf(t->why, sizeof t->why, "%s arcs left out: %s", f->name, why);
    else snprintf(t->why, sizeof t->why, "%s arcs at most %g deg: %s", f->name, t->nstep * step, why);
}

kt_lp_family kt_lp_family_cut(const kt_lp_answer *a, int i)
{
    kt_lp_family f = a->fam.f[i];
    f.meridian = a->trim.t[i].meridian;
    return f;
}

/* ---- the model's clearance ---- */

int kt_lp_wounds_of(const kt_lp_eye *eye, const kt_lp_scene *sc, kt_lp_wounds *w, kt_err *e)
{
    const kt_patient *p = &eye->p;
    memset(w, 0, sizeof *w);
    w->zone.rx = kt_eye_oval_radius(&sc->s.eye, p->zone, 0), w->zone.ry = kt_eye_oval_radius(&sc->s.eye, p->zone, 90);
    w->min = p->clearance;
    if (p->main_present) { /* simulated or not, its tunnel is where the surgeon cuts it */
        kt_tunnel t = sc->main;
        if (!sc->main_sim) {
            const char *field;
            char msg[400];
            memset(&t, 0, sizeof t);
            t.meridian = p->main_meridian, t.width = p->main_width, t.length = KT_TUNNEL_LENGTH;
            t.entry_diameter = kt_lp_main_entry(p, &sc->s), t.steps = KT_TUNNEL_STEPS;
            if (kt_tunnel_derive(&sc->s.eye, &t, &field, msg, sizeof msg))
                return kt_patient_fail(p, e, KT_PF_MAIN, -1, "its tunnel's %s: %s", field, msg);
        }
        kt_footprint_of_tunnel(&t, "the main incision", &w->w[w->nw++]);
    }
    if (p->side_present) { /* its footprint from the corneal edge in to the optical zone: the safe
                              side (it crosses every incision zone); not cut */
        kt_footprint *v = &w->w[w->nw++];
        v->meridian = p->side_meridian, v->width = p->side_width, v->name = "the side port";
        v->r_in = 0.5 * sc->s.eye.optical_zone, v->r_out = 0.5 * p->wtw;
    }
    return KT_OK;
}

/* 1 when the arc at `centre` of `arc` deg does not keep w's clearance from every wound (a NaN
 * clearance does not keep it); why names the first wound it comes near. */
static int arc_clash(const kt_lp_wounds *w, double centre, double arc, char *why, size_t n)
{
    for (int k = 0; k < w->nw; k++) {
        if (kt_clearance(&w->w[k], centre, arc, w->zone) >= w->min) continue;
        snprintf(why, n, "the arc at %.0f deg would come within %g deg of %s at %.0f deg (%.1f mm zone)",
                 kt_lp_deg_mark(centre), w->min, w->w[k].name ? w->w[k].name : "a wound", kt_lp_deg_mark(w->w[k].meridian),
                 2 * w->zone.rx);
        return 1;
    }
    return 0;
}

int kt_lp_clear_model(void *ctx, const kt_plan *p, char *why, size_t n)
{
    const kt_lp_wounds *w = ctx;
    for (int i = 0; i < p->ninc; i++) {
        const kt_incision *in = &p->inc[i];
        if (arc_clash(w, in->meridian, in->arc, why, n)) return 1;
        double opp = in->arc_opposite > 0 ? in->arc_opposite : in->arc;
        if (in->paired && arc_clash(w, fmod(in->meridian + 180, 360), opp, why, n)) return 1;
    }
    return 0;
}

/* ---- the decision for every family ---- */

typedef struct asker {
    const kt_lp_opts *o;
    const kt_lp_eye *eye;
    const kt_lp_scene *sc;
    kt_lp_clear clear;
    void *ctx;
} asker;

/* The decision for family f centred on `centre` (its arcs asked at each extent k = 1..nstep). */
static int ask(const asker *q, const kt_lp_family *f, double centre, kt_lp_trim *t, kt_err *e)
{
    unsigned char clash[KT_LP_MAXSTEP + 1] = {0};
    char why[KT_LP_MAXSTEP + 1][240];
    const char *reason[KT_LP_MAXSTEP + 1];
    for (int k = 0; k <= KT_LP_MAXSTEP; k++) why[k][0] = '\0', reason[k] = why[k];
    kt_lp_family g = *f;
    g.meridian = centre;
    kt_plan *p = kt_calloc(1, sizeof *p, e);
    if (!p) return e->code;
    for (int k = 1; k <= g.nstep && !e->code; k++)
        if (!kt_lp_family_plan(q->sc, q->eye, &g, q->o->step, k, p, e)) clash[k] = q->clear(q->ctx, p, why[k], sizeof why[k]) != 0;
    free(p);
    if (e->code) return e->code;
    kt_lp_trim_decide(&g, q->o->step, clash, reason, t);
    return KT_OK;
}

/* A single arc trimmed on the steeper half: on the other half when more of it clears there. */
static int other_half(const asker *q, const kt_lp_family *f, kt_lp_trim *t, kt_err *e)
{
    if (f->kind != KT_LP_SINGLE || t->nstep >= f->nstep) return KT_OK;
    kt_lp_trim u;
    if (ask(q, f, fmod(f->meridian + 180, 360), &u, e)) return e->code;
    if (u.nstep <= t->nstep) return KT_OK;
    char was[sizeof t->why];
    snprintf(was, sizeof was, "%s", t->why);
    *t = u, t->moved = 1;
    size_t n = strlen(t->why);
    snprintf(t->why + n, sizeof t->why - n, "%ssingle arc on the other half, at %.0f deg (on the steeper half, %s)",
             n ? "; " : "", t->meridian, was);
    return KT_OK;
}

int kt_lp_trims_make(const kt_lp_opts *o, const kt_lp_eye *eye, const kt_lp_scene *sc, const kt_lp_families *fam,
                     kt_lp_trims *trims, kt_err *e)
{
    memset(trims, 0, sizeof *trims);
    kt_lp_wounds w;
    asker q = {o, eye, sc, o->clear, o->clear_ctx};
    if (!q.clear) {
        if (kt_lp_wounds_of(eye, sc, &w, e)) return e->code;
        q.clear = kt_lp_clear_model, q.ctx = &w;
    }
    for (int i = 0; i < fam->n; i++) {
        kt_lp_trim *t = &trims->t[i];
        if (ask(&q, &fam->f[i], fam->f[i].meridian, t, e) || other_half(&q, &fam->f[i], t, e)) return e->code;
        if (t->why[0]) kt_log(o->quiet, "lri-plan: %s\n", t->why);
    }
    return KT_OK;
}
