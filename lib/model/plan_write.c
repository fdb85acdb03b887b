/* plan_write.c: an eye plan as plan YAML (plan_write.h). */
#include "plan_write.h"
#include "yml.h"

#include <string.h>

static void tunnels(FILE *f, const kt_plan *p)
{
    if (p->ntunnel == 0) return;
    fputs("tunnels:\n", f);
    for (int i = 0; i < p->ntunnel; i++) {
        const kt_tunnel *t = &p->tunnel[i];
        fprintf(f, "  - meridian: %.17g deg\n    width: %.17g mm\n    length: %.17g mm\n    entry_diameter: %.17g mm\n"
                   "    steps: %d\n", t->meridian, t->width, t->length, t->entry_diameter, t->steps);
    }
}

static void incisions(FILE *f, const kt_plan *p)
{
    static const char *const DIR[] = {"cw", "ccw", "centre-out"};
    if (p->ninc == 0) return;
    fputs("incisions:\n", f);
    for (int i = 0; i < p->ninc; i++) {
        const kt_incision *in = &p->inc[i];
        fprintf(f, "  - meridian: %.17g deg\n    arc: %.17g deg\n", in->meridian, in->arc);
        if (in->arc_opposite > 0) fprintf(f, "    arc_opposite: %.17g deg\n", in->arc_opposite);
        if (in->depth_fraction > 0) fprintf(f, "    depth_fraction: %.17g\n", in->depth_fraction);
        else fprintf(f, "    depth: %.17g mm\n", in->depth);
        if (in->surface[0]) fputs("    position: {surface: ", f), kt_yml_put_quoted(f, in->surface), fputs("}\n", f);
        else fprintf(f, "    position: {diameter: %.17g mm}\n", in->diameter);
        fprintf(f, "    paired: %s\n    direction: %s\n", in->paired ? "true" : "false",
                DIR[in->direction >= 0 && in->direction <= 2 ? in->direction : 0]);
        if (in->prog.degrees_per_step > 0) fprintf(f, "    progression: {degrees_per_step: %.17g deg}\n", in->prog.degrees_per_step);
        else fprintf(f, "    progression: {nodes_per_step: %d}\n", in->prog.nodes_per_step);
    }
}

int kt_plan_write_eye(FILE *f, const kt_plan *p, const char *name, const char *scene, const char *header, kt_err *e)
{
    if (p->ndeform > 0 || p->planar.set)
        return kt_fail(e, KT_EINPUT, "%s: expected an eye plan of incisions and tunnels (deform and planar cuts are not written)",
                       p->path);
    if (header) kt_yml_put_comment(f, header);
    fputs("name: ", f), kt_yml_put_quoted(f, name), fputs("\nscene: ", f), kt_yml_put_quoted(f, scene), fputc('\n', f);
    if (p->prog.degrees_per_step > 0) fprintf(f, "progression: {degrees_per_step: %.17g deg}\n", p->prog.degrees_per_step);
    if (p->target.set) fprintf(f, "target: {magnitude: %.17g D, axis: %.17g deg}\n", p->target.magnitude, p->target.axis);
    fprintf(f, "snap: {fraction: %.17g, min_quality: %.17g}\n", p->snap.fraction, p->snap.min_quality);
    tunnels(f, p);
    incisions(f, p);
    if (ferror(f)) return kt_fail(e, KT_ERUN, "%s: write failed", p->path);
    return KT_OK;
}
