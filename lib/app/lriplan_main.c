/* lriplan_main.c: the patient's main cataract incision simulated (keratome-patient(5), THE MAIN
 * INCISION): a tunnel of keratome-plan(5) cut as the first steps of every family's run, so its
 * effect and its interaction with the arcs come from the same model. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lriplan_int.h"
#include "plan.h"

#define MAIN_STEPS KT_TUNNEL_STEPS

/* The external entry: the corneal edge (white-to-white) for a clear-corneal incision, the
 * middle of the limbal band for a limbal one. */
static double entry_diameter(const kt_patient *p, const kt_scene *s)
{
    return p->wtw + (p->main_kind == KT_MAIN_LIMBAL ? s->eye.limbus_width : 0);
}

int kt_lri_main_check(const kt_patient *p, kt_scene *s, kt_err *e)
{
    if (!kt_lri_main_steps(p)) return KT_OK;
    kt_tunnel t = {0};
    t.meridian = p->main_meridian, t.width = p->main_width, t.length = KT_TUNNEL_LENGTH;
    t.entry_diameter = entry_diameter(p, s), t.steps = MAIN_STEPS;
    const char *field;
    char msg[400];
    if (kt_tunnel_derive(&s->eye, &t, &field, msg, sizeof msg))
        return kt_patient_fail(p, e, KT_PF_MAIN, -1, "its tunnel's %s: %s", field, msg);
    /* The mesh follows the main incision's site: the cylinder around the tunnel's rectangle
     * (seen from the front) meshed at the incision's size (eye.mesh_size.site). */
    double re = hypot(t.entry[0], t.entry[1]), ri = hypot(t.exit[0], t.exit[1]);
    s->eye.site_meridian = p->main_meridian;
    s->eye.site_distance = 0.5 * (re + ri);
    s->eye.site_radius = hypot(0.5 * (re - ri), 0.5 * p->main_width);
    return KT_OK;
}

int kt_lri_wounds(const kt_patient *p, const kt_scene *s, kt_wound w[2], int *nw, kt_err *e)
{
    *nw = 0;
    if (p->main_present) {
        kt_tunnel t = {0};
        t.meridian = p->main_meridian, t.width = p->main_width, t.length = KT_TUNNEL_LENGTH;
        t.entry_diameter = entry_diameter(p, s), t.steps = MAIN_STEPS;
        const char *field;
        char msg[400];
        if (kt_tunnel_derive(&s->eye, &t, &field, msg, sizeof msg))
            return kt_fail(e, KT_EINPUT, "%s: main_incision: its tunnel's %s: %s", p->path, field, msg);
        kt_wound_of_tunnel(&t, "the main incision", &w[(*nw)++]);
    }
    if (p->side_present) { /* its footprint from the corneal edge in to the optical zone: the
                              safe side (it crosses every incision zone); not cut */
        kt_wound *v = &w[(*nw)++];
        v->meridian = p->side_meridian, v->width = p->side_width, v->name = "the side port";
        v->r_in = 0.5 * s->eye.optical_zone, v->r_out = 0.5 * p->wtw;
    }
    return KT_OK;
}

int kt_lri_main_steps(const kt_patient *p) { return p->main_present && p->main_simulate ? MAIN_STEPS : 0; }

int kt_lri_main_plan(FILE *f, const kt_patient *p, const kt_scene *s)
{
    if (!kt_lri_main_steps(p)) return 0;
    double entry = entry_diameter(p, s); /* the tunnel's length: the plan's default */
    fprintf(f, "# the main incision: a %s tunnel, %.17g mm wide, its entry on the %.17g mm circle\n",
            p->main_kind == KT_MAIN_LIMBAL ? "limbal" : "clear-corneal", p->main_width, entry);
    fprintf(f, "tunnels:\n  - meridian: %.17g deg\n    width: %.17g mm\n    entry_diameter: %.17g mm\n    steps: %d\n",
            p->main_meridian, p->main_width, entry, MAIN_STEPS);
    return ferror(f) ? -1 : 0;
}

static kt_astig diff(kt_astig a, kt_astig b)
{
    double x[2], y[2];
    kt_astig_xy(a, x);
    kt_astig_xy(b, y);
    return kt_astig_from_xy(x[0] - y[0], x[1] - y[1]);
}

void kt_lri_main_sia(kt_lri_answer *a)
{
    a->main_sia_kerato.mag = a->main_sia_total.mag = 0;
    a->main_sia_kerato.axis = a->main_sia_total.axis = 0;
    if (!a->main_steps || a->nfam < 1) return;
    const kt_lri_family *f = &a->fam[0];
    a->main_sia_kerato = diff(f->kerato[0], f->kerato_intact);
    a->main_sia_total = diff(f->total[0], f->total_intact);
}

int kt_lri_main_count(const char *edits, int *n, kt_err *e)
{
    *n = 0;
    FILE *in = fopen(edits, "r");
    if (!in) return kt_fail(e, KT_ERUN, "%s: cannot open", edits);
    char *line = NULL;
    size_t cap = 0;
    long got;
    int last = 0, ln = 0; /* the tunnel's steps come first; they end at the first other step */
    while ((got = kt_line_read(in, &line, &cap, (size_t)1 << 20, e)) >= 0) {
        ln++;
        if (strncmp(line, "step ", 5) != 0) continue;
        if (!strstr(line, "(tunnel ")) break;
        last = atoi(line + 5);
    }
    free(line);
    fclose(in);
    if (got < -1) /* a line cut short would be misread: refused */
        return got == -4 ? e->code : kt_fail(e, KT_EINPUT, "%s:%d:1: expected a line of text, found %s", edits, ln + 1,
                                              got == -2 ? "a NUL byte" : "a line longer than 1 MiB");
    *n = last;
    return KT_OK;
}
