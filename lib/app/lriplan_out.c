/* lriplan_out.c: lri-plan's answer: the predicted astigmatism per arc, the choice, plan.json
 * and the one-screen summary (lri-plan(1)). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "lriplan_int.h"

static kt_astig add(kt_astig a, kt_astig b)
{
    double x[2], y[2];
    kt_astig_xy(a, x);
    kt_astig_xy(b, y);
    return kt_astig_from_xy(x[0] + y[0], x[1] + y[1]);
}

/* A clock hour as the surgeon reads the eye (12 superior, 3 at the examiner's right), in
 * [1, 13): 12.5 is half past twelve. */
static double clock_hour(double deg)
{
    double h = fmod(3 - deg / 30 + 48, 12);
    return h < 1 ? h + 12 : h;
}

/* The clock position as "h:mm" (12:50 is just past twelve, towards one). */
void kt_lri_clock(double deg, char out[8])
{
    int m = (int)lround(clock_hour(deg) * 60) % 720;
    int h = m / 60 % 12;
    snprintf(out, 8, "%d:%02d", h == 0 ? 12 : h, m % 60);
}

static double wrap360(double d) { return fmod(fmod(d, 360) + 360, 360); }

void kt_lri_choose(kt_lri_answer *a)
{
    const kt_patient *p = &a->p;
    /* The posterior's toricity is in the mesh (keratome-patient(5)): the simulated total
     * corneal astigmatism (curvature's reading of both surfaces) carries it. */
    a->main_vec.mag = p->main_present && !p->main_simulate ? p->main_sia : 0;
    a->main_vec.axis = p->main_sia_axis;
    a->chosen = 0;
    double best = INFINITY;
    for (int i = 0; i < a->nfam; i++) {
        kt_lri_family *f = &a->fam[i];
        f->best = 0;
        for (int k = 0; k <= f->nstep; k++) {
            kt_astig sim = p->target_kind == KT_TARGET_TOTAL ? f->total[k] : f->kerato[k];
            f->pred[k] = add(sim, a->main_vec);
            if (f->pred[k].mag < f->pred[f->best].mag - 1e-9) f->best = k;
        }
        double r = f->pred[f->best].mag;
        /* Within 0.01 D, the fewer incisions (families run single first). */
        if (r < best - 0.01) best = r, a->chosen = i;
    }
    if (a->nfam) {
        const kt_lri_family *f0 = &a->fam[0];
        a->pre_kerato = add(f0->kerato_intact, a->main_vec);
        a->pre_total = add(f0->total_intact, a->main_vec);
    }
    kt_lri_main_sia(a);
}

int kt_lri_arcs(const kt_lri_answer *a, kt_lri_arc arcs[2])
{
    const kt_lri_family *f = &a->fam[a->chosen];
    if (a->nfam == 0 || f->arc[f->best] <= 0) return 0;
    int n = 1 + f->paired;
    for (int i = 0; i < n; i++) {
        kt_lri_arc *r = &arcs[i];
        r->centre = wrap360(f->meridian + 180 * i);
        r->arc = i ? f->arc_opp[f->best] : f->arc[f->best];
        r->from = wrap360(r->centre - r->arc / 2), r->to = wrap360(r->centre + r->arc / 2);
        kt_lri_clock(r->from, r->from_clock), kt_lri_clock(r->to, r->to_clock);
        r->chord = a->p.zone * sin(r->arc / 2 * KT_CURV_DEG);
    }
    return n;
}

void kt_lri_post(const kt_lri_answer *a, kt_astig *kerato, kt_astig *total)
{
    const kt_lri_family *f = &a->fam[a->chosen];
    *kerato = add(f->kerato[f->best], a->main_vec);
    *total = add(f->total[f->best], a->main_vec);
}

int kt_lri_write_json(const kt_lri_answer *a, const kt_lriplan_opts *o, const char *report, const char *path, kt_err *e)
{
    const kt_patient *p = &a->p;
    const kt_lri_family *f = &a->fam[a->chosen];
    double arc = f->arc[f->best];
    kt_out out;
    if (kt_out_open(&out, path, e)) return e->code;
    FILE *j = out.f;
    fprintf(j, "{\n  \"tool\": \"lri-plan\", \"version\": \"%s\",\n", KT_VERSION);
    fprintf(j, "  \"patient\": {\"file\": \"%s\", \"name\": \"%s\", \"eye\": \"%s\", \"age\": %g, \"iop_mmHg\": %.2f,\n",
            p->path, p->name, p->eye == KT_EYE_OS ? "OS" : "OD", p->age, p->iop / 133.322387415e-6);
    fprintf(j, "    \"anterior\": {\"source\": \"%s\", \"k_steep_D\": %.3f, \"k_flat_D\": %.3f, \"steep_axis_deg\": %.2f, "
               "\"r_steep_mm\": %.4f, \"r_flat_mm\": %.4f},\n",
            a->fitted ? "pentacam" : "keratometry", kt_patient_k(p->ant.r_steep), kt_patient_k(p->ant.r_flat), p->ant.axis,
            p->ant.r_steep, p->ant.r_flat);
    fprintf(j, "    \"posterior\": {\"source\": \"%s\", \"k_steep_D\": %.3f, \"k_flat_D\": %.3f, \"steep_axis_deg\": %.2f},\n",
            p->post.source == KT_SOURCE_DEFAULT ? "population default (Koch et al. 2012)"
            : p->post.source == KT_SOURCE_PENTACAM ? "pentacam" : "keratometry",
            kt_patient_post_k(p->post.r_steep), kt_patient_post_k(p->post.r_flat), p->post.axis);
    fprintf(j, "    \"central_thickness_um\": %.1f, \"thickness_at_zone_um\": %.1f, \"white_to_white_mm\": %.2f},\n",
            1000 * p->t_central, 1000 * a->t_zone, p->wtw);
    if (a->fitted) {
        fprintf(j, "  \"fit\": {\"zone_mm\": %g, \"anterior\": {\"r_steep_mm\": %.5f, \"r_flat_mm\": %.5f, \"axis_deg\": %.3f, "
                   "\"Q\": %.4f, \"rms_um\": %.3f, \"max_um\": %.3f, \"cells\": %d}",
                a->fit_ant.zone, a->fit_ant.r_steep, a->fit_ant.r_flat, a->fit_ant.axis, a->fit_ant.conic, 1000 * a->fit_ant.rms,
                1000 * a->fit_ant.max_resid, a->fit_ant.npts);
        if (a->fit_post_ok)
            fprintf(j, ",\n    \"posterior\": {\"r_steep_mm\": %.5f, \"r_flat_mm\": %.5f, \"axis_deg\": %.3f, \"Q\": %.4f, "
                       "\"rms_um\": %.3f, \"max_um\": %.3f, \"cells\": %d}",
                    a->fit_post.r_steep, a->fit_post.r_flat, a->fit_post.axis, a->fit_post.conic, 1000 * a->fit_post.rms,
                    1000 * a->fit_post.max_resid, a->fit_post.npts);
        if (a->fit_pachy_ok)
            fprintf(j, ",\n    \"pachymetry\": {\"t0_um\": %.2f, \"t2_um_per_mm2\": %.4f, \"t4_um_per_mm4\": %.5f, \"r_max_mm\": %g, "
                       "\"rms_um\": %.3f, \"max_um\": %.3f, \"cells\": %d}",
                    1000 * a->fit_pachy.t0, 1000 * a->fit_pachy.t2, 1000 * a->fit_pachy.t4, a->fit_pachy.r_max,
                    1000 * a->fit_pachy.rms, 1000 * a->fit_pachy.max_resid, a->fit_pachy.npts);
        fprintf(j, "},\n");
    }
    fprintf(j, "  \"main_incision\": {\"present\": %s, \"meridian_deg\": %.1f, \"width_mm\": %.2f, \"kind\": \"%s\", "
               "\"sia\": \"%s\", \"sia_added_D\": %.3f, \"sia_axis_deg\": %.1f, \"simulated_steps\": %d, "
               "\"simulated_sia_keratometric_D\": %.4f, \"simulated_sia_keratometric_axis_deg\": %.1f, "
               "\"simulated_sia_total_D\": %.4f, \"simulated_sia_total_axis_deg\": %.1f},\n",
            p->main_present ? "true" : "false", p->main_meridian, p->main_width,
            p->main_kind == KT_MAIN_LIMBAL ? "limbal" : "clear_corneal",
            !p->main_present ? "none" : p->main_simulate ? "simulated (a tunnel cut before the arcs)" : "surgeon's vector",
            a->main_vec.mag, a->main_vec.axis, a->main_steps, a->main_sia_kerato.mag, a->main_sia_kerato.axis,
            a->main_sia_total.mag, a->main_sia_total.axis);
    fprintf(j, "  \"target\": {\"astigmatism\": \"%s\", \"residual_D\": %.2f},\n",
            p->target_kind == KT_TARGET_TOTAL ? "total_corneal" : "keratometric", p->target_residual);
    fprintf(j, "  \"pre_op\": {\"keratometric_D\": %.3f, \"keratometric_axis_deg\": %.1f, \"total_D\": %.3f, \"total_axis_deg\": %.1f},\n",
            a->pre_kerato.mag, a->pre_kerato.axis, a->pre_total.mag, a->pre_total.axis);
    kt_lri_arc arcs[2];
    int narc = kt_lri_arcs(a, arcs);
    kt_astig kpost, tpost;
    kt_lri_post(a, &kpost, &tpost);
    fprintf(j, "  \"plan\": {\"incisions\": \"%s\", \"arc_deg\": %.1f, \"arc_opposite_deg\": %.1f, \"centre_deg\": %.2f, "
               "\"from_deg\": %.1f, \"to_deg\": %.1f, \"from_clock\": \"%s\", \"to_clock\": \"%s\", \"chord_mm\": %.2f, "
               "\"zone_mm\": %.2f, \"blade_um\": %.0f,\n",
            f->name, arc, f->arc_opp[f->best], narc ? arcs[0].centre : f->meridian, narc ? arcs[0].from : f->meridian,
            narc ? arcs[0].to : f->meridian, narc ? arcs[0].from_clock : "", narc ? arcs[0].to_clock : "",
            narc ? arcs[0].chord : 0.0, p->zone, 1000 * a->blade);
    fprintf(j, "    \"arcs\": [");
    for (int i = 0; i < narc; i++)
        fprintf(j, "%s{\"centre_deg\": %.2f, \"arc_deg\": %.1f, \"from_deg\": %.1f, \"to_deg\": %.1f, \"from_clock\": \"%s\", "
                   "\"to_clock\": \"%s\", \"chord_mm\": %.2f}",
                i ? ", " : "", arcs[i].centre, arcs[i].arc, arcs[i].from, arcs[i].to, arcs[i].from_clock, arcs[i].to_clock,
                arcs[i].chord);
    fprintf(j, "],\n");
    fprintf(j, "    \"predicted_residual_D\": %.3f, \"predicted_residual_axis_deg\": %.1f, \"reached\": %s,\n", f->pred[f->best].mag,
            f->pred[f->best].axis, f->pred[f->best].mag <= p->target_residual ? "true" : "false");
    fprintf(j, "    \"post_op_keratometric_D\": %.3f, \"post_op_keratometric_axis_deg\": %.1f, \"post_op_total_D\": %.3f, "
               "\"post_op_total_axis_deg\": %.1f},\n",
            kpost.mag, kpost.axis, tpost.mag, tpost.axis);
    kt_lri_band_json(a, j);
    if (a->halves_ok)
        fprintf(j, "  \"halves\": {\"k_at_axis_D\": %.3f, \"k_opposite_D\": %.3f, \"k_flat_D\": %.3f, \"astig_at_axis_D\": %.3f, "
                   "\"astig_opposite_D\": %.3f, \"steeper_half_deg\": %.1f, \"ratio\": %.4f, \"cells\": %d},\n",
                a->halves.k_a, a->halves.k_b, a->halves.k_flat, a->half_a, a->half_b, a->steep_half, a->ratio,
                a->halves.npts);
    fprintf(j, "  \"candidates\": [");
    for (int i = 0; i < a->nfam; i++) {
        const kt_lri_family *c = &a->fam[i];
        fprintf(j, "%s\n    {\"incisions\": \"%s\", \"meridian_deg\": %.2f, \"ratio\": %.4f, \"best_arc_deg\": %.1f, "
                   "\"best_arc_opposite_deg\": %.1f, \"best_residual_D\": %.3f, \"best_residual_axis_deg\": %.1f, \"curve\": [",
                i ? "," : "", c->name, c->meridian, c->ratio, c->arc[c->best], c->arc_opp[c->best], c->pred[c->best].mag,
                c->pred[c->best].axis);
        for (int k = 0; k <= c->nstep; k++)
            fprintf(j, "%s{\"arc_deg\": %.1f, \"arc_opposite_deg\": %.2f, \"residual_D\": %.4f, \"residual_axis_deg\": %.1f, \"keratometric_D\": %.4f, "
                       "\"total_D\": %.4f, \"sia_D\": %.4f}",
                    k ? ", " : "", c->arc[k], c->arc_opp[k], c->pred[k].mag, c->pred[k].axis, c->kerato[k].mag, c->total[k].mag,
                    kt_lri_sia(c, k));
        fprintf(j, "]}");
    }
    fprintf(j, "\n  ],\n  \"provenance\": {\"scene\": \"scene.yaml\", \"mesh\": \"eye.msh\", \"mesh_hash\": \"%016llx\", "
               "\"mesh_nodes\": %d, \"fast\": %s, \"step_deg\": %g, \"mesh_seconds\": %.1f, \"solve_seconds\": %.1f, "
               "\"plan_html\": \"plan.html\", \"report\": \"%s\"}\n}\n",
            (unsigned long long)a->mesh_hash, a->nodes, o->fast ? "true" : "false", o->step, a->mesh_seconds,
            a->solve_seconds, report ? report : "");
    if (ferror(j)) {
        kt_out_abort(&out);
        return kt_fail(e, KT_ERUN, "%s: write failed", path);
    }
    return kt_out_commit(&out, e);
}

void kt_lri_summary(const kt_lri_answer *a, const kt_lriplan_opts *o, FILE *s)
{
    const kt_patient *p = &a->p;
    const kt_lri_family *f = &a->fam[a->chosen];
    fprintf(s, "lri-plan: %s, %s, %g y\n", p->name, p->eye == KT_EYE_OS ? "OS (left)" : "OD (right)", p->age);
    fprintf(s, "  cornea (%s): K %.2f / %.2f D @ %.0f deg; posterior %.2f / %.2f D @ %.0f deg (%s)\n",
            a->fitted ? "Pentacam fit" : "keratometry", kt_patient_k(p->ant.r_steep), kt_patient_k(p->ant.r_flat), p->ant.axis,
            kt_patient_post_k(p->post.r_steep), kt_patient_post_k(p->post.r_flat), p->post.axis,
            p->post.source == KT_SOURCE_DEFAULT ? "population default" : "measured");
    if (a->fitted)
        fprintf(s, "  fit over %g mm: anterior Q %.3f, residual rms %.2f um (max %.2f um, %d cells)%s\n", a->fit_ant.zone,
                a->fit_ant.conic, 1000 * a->fit_ant.rms, 1000 * a->fit_ant.max_resid, a->fit_ant.npts,
                a->fit_post_ok ? "" : "; no posterior map");
    if (a->fitted && a->fit_post_ok)
        fprintf(s, "               posterior Q %.3f, residual rms %.2f um (max %.2f um, %d cells)\n", a->fit_post.conic,
                1000 * a->fit_post.rms, 1000 * a->fit_post.max_resid, a->fit_post.npts);
    if (a->fitted && a->fit_pachy_ok)
        fprintf(s, "               pachymetry %.0f um central, residual rms %.2f um (max %.2f um)\n", 1000 * a->fit_pachy.t0,
                1000 * a->fit_pachy.rms, 1000 * a->fit_pachy.max_resid);
    fprintf(s, "  pre-op astigmatism%s: keratometric %.2f D @ %.0f, total corneal %.2f D @ %.0f\n",
            a->main_vec.mag > 0 ? " (with the main incision's SIA)" : "", a->pre_kerato.mag, a->pre_kerato.axis,
            a->pre_total.mag, a->pre_total.axis);
    if (p->main_present)
        fprintf(s, "  main incision: %g mm %s at %.0f deg: %s\n", p->main_width,
                p->main_kind == KT_MAIN_LIMBAL ? "limbal" : "clear corneal", p->main_meridian,
                p->main_simulate ? "simulated, cut before the arcs" : "surgeon's SIA added");
    if (a->main_steps)
        fprintf(s, "  main incision's simulated SIA: keratometric %.2f D @ %.0f, total corneal %.2f D @ %.0f\n",
                a->main_sia_kerato.mag, a->main_sia_kerato.axis, a->main_sia_total.mag, a->main_sia_total.axis);
    if (a->halves_ok)
        fprintf(s, "  half-meridians: %.2f D @ %.0f and %.2f D @ %.0f over K flat %.2f D: %s\n", a->half_a, p->ant.axis,
                a->half_b, fmod(p->ant.axis + 180, 360), a->halves.k_flat,
                a->ratio < KT_LRIPLAN_SYMMETRIC ? "asymmetric, unequal pairs tried" : "symmetric");
    fprintf(s, "  candidates (best of each, residual %s):\n", p->target_kind == KT_TARGET_TOTAL ? "total corneal" : "keratometric");
    for (int i = 0; i < a->nfam; i++) {
        const kt_lri_family *c = &a->fam[i];
        char arcs[48];
        if (c->unequal) snprintf(arcs, sizeof arcs, "%.0f + %.1f deg", c->arc[c->best], c->arc_opp[c->best]);
        else snprintf(arcs, sizeof arcs, "%s%.0f deg", c->paired ? "2 x " : "", c->arc[c->best]);
        fprintf(s, "    %-7s at %3.0f deg: %-16s residual %.2f D @ %3.0f%s\n", c->name, c->meridian, arcs, c->pred[c->best].mag,
                c->pred[c->best].axis, i == a->chosen ? "  <- chosen" : "");
    }
    for (int k = 0; k < 3; k++)
        if (a->clear_note[k][0]) fprintf(s, "    (%s)\n", a->clear_note[k]);
    kt_lri_arc arcs[2];
    int narc = kt_lri_arcs(a, arcs);
    if (narc == 0) {
        fprintf(s, "  answer: no arc (none lowers the %s residual)\n",
                p->target_kind == KT_TARGET_TOTAL ? "total corneal" : "keratometric");
    } else {
        fprintf(s, "  answer: %s at the %.1f mm zone, blade %.0f um deep:\n", f->name, p->zone, 1000 * a->blade);
        for (int i = 0; i < narc; i++)
            fprintf(s, "    arc %d: %.0f deg centred on %.0f, from %.0f to %.0f deg (%s to %s o'clock), chord %.2f mm\n", i + 1,
                    arcs[i].arc, arcs[i].centre, arcs[i].from, arcs[i].to, arcs[i].from_clock, arcs[i].to_clock, arcs[i].chord);
    }
    kt_astig kpost, tpost;
    kt_lri_post(a, &kpost, &tpost);
    fprintf(s, "  post-op: keratometric %.2f D @ %.0f, total corneal %.2f D @ %.0f\n", kpost.mag, kpost.axis, tpost.mag,
            tpost.axis);
    fprintf(s, "  predicted %s residual %.2f D @ %.0f: %s the %.2f D target\n",
            p->target_kind == KT_TARGET_TOTAL ? "total corneal" : "keratometric", f->pred[f->best].mag, f->pred[f->best].axis,
            f->pred[f->best].mag <= p->target_residual ? "reaches" : "does NOT reach", p->target_residual);
    kt_lri_band_summary(a, s);
    fprintf(s, "  written: %s/plan.html, plan.json, report/report.html, scene.yaml, eye.msh, run-*/ (mesh %.0f s, solves %.0f s%s)\n", o->outdir,
            a->mesh_seconds, a->solve_seconds, o->fast ? ", --fast" : "");
}
