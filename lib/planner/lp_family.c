/* lp_family.c: the candidate families and their plans in memory (lp_family.h). */
#include "lp_family.h"

#include <math.h>
#include <string.h>

int kt_lp_families_make(const kt_lp_opts *o, const kt_lp_eye *eye, kt_lp_families *fam, kt_err *e)
{
    static const char *const NAMES[KT_LP_NFAM] = {"single", "paired", "unequal"};
    const kt_patient *p = &eye->p;
    int allow[KT_LP_NFAM] = {p->arcs != KT_ARCS_PAIRED, p->arcs != KT_ARCS_SINGLE,
                             p->arcs != KT_ARCS_SINGLE && eye->ratio < KT_LP_SYMMETRIC};
    int nstep = (int)floor(p->max_arc / o->step + 1e-9);
    memset(fam, 0, sizeof *fam);
    if (nstep > KT_LP_MAXSTEP)
        return kt_fail(e, KT_EINPUT, "--step %g: expected at most %d steps to max_arc", o->step, KT_LP_MAXSTEP);
    for (int k = 0; k < KT_LP_NFAM; k++) {
        if (!allow[k]) continue;
        kt_lp_family *f = &fam->f[fam->n++];
        f->kind = k;
        f->paired = k > 0, f->unequal = k == KT_LP_UNEQUAL;
        snprintf(f->name, sizeof f->name, "%s", NAMES[k]);
        f->meridian = k == KT_LP_PAIRED ? p->ant.axis : eye->steep_half;
        f->ratio = k == KT_LP_UNEQUAL ? eye->ratio : 1;
        f->nstep = nstep;
    }
    return KT_OK;
}

/* The main incision's tunnel (lp_scene.c derived it on the same eye). */
static int add_main(const kt_lp_scene *sc, kt_plan *p, kt_err *e)
{
    if (!sc->main_sim) return KT_OK;
    kt_tunnel t;
    memset(&t, 0, sizeof t);
    t.meridian = sc->main.meridian, t.width = sc->main.width, t.length = sc->main.length;
    t.entry_diameter = sc->main.entry_diameter, t.steps = sc->main.steps;
    return kt_plan_add_tunnel(p, &t, e);
}

int kt_lp_family_plan(const kt_lp_scene *sc, const kt_lp_eye *eye, const kt_lp_family *f, double step, int nstep,
                      kt_plan *p, kt_err *e)
{
    const kt_patient *pt = &eye->p;
    char name[64];
    snprintf(name, sizeof name, "lri-%s", f->name);
    kt_plan_init(p, &sc->s, name);
    p->prog.degrees_per_step = step;
    kt_incision in;
    memset(&in, 0, sizeof in);
    in.meridian = f->meridian, in.arc = nstep * step;
    if (f->unequal) in.arc_opposite = f->ratio * nstep * step;
    if (pt->depth_fraction > 0) in.depth_fraction = pt->depth_fraction;
    else in.depth = pt->depth;
    snprintf(in.surface, sizeof in.surface, "%s", sc->s.eye.ring[0].name);
    in.paired = f->paired, in.direction = KT_BLADE_CENTRE_OUT, in.prog = p->prog;
    if (add_main(sc, p, e)) return e->code;
    return kt_plan_add_incision(p, &in, e);
}
