/* lriplan_out.c: lri-plan's plan.json (through the one JSON writer, lib/io/json.h) and its
 * one-screen summary (lri-plan(1), FILES). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "json.h"
#include "lp_family.h"
#include "lriplan_eye.h"
#include "lriplan_int.h"
#include "units.h"

static const char *eye_name(const kt_patient *p) { return p->eye == KT_EYE_OS ? "OS" : "OD"; }
static const char *target_name(const kt_patient *p)
{
    return p->target_kind == KT_TARGET_TOTAL ? "total corneal" : "keratometric";
}

/* An astigmatism as two members, key_D and key_axis_deg (the axis to 0.1 deg, adec decimals). */
static void jastig_to(kt_json *j, const char *key, kt_astig a, int dec, int adec)
{
    char k[96];
    snprintf(k, sizeof k, "%s_D", key), kt_json_num(j, k, a.mag, dec);
    snprintf(k, sizeof k, "%s_axis_deg", key), kt_json_num(j, k, kt_lp_axis_shown(a.axis, adec), adec);
}

static void jastig(kt_json *j, const char *key, kt_astig a, int dec) { jastig_to(j, key, a, dec, 1); }

static void json_patient(kt_json *j, const kt_lp_answer *a)
{
    const kt_patient *p = &a->eye.p;
    kt_json_obj(j, "patient");
    kt_json_str(j, "file", p->path), kt_json_str(j, "name", p->name), kt_json_str(j, "eye", eye_name(p));
    kt_json_str(j, "id", p->id), kt_json_str(j, "date_of_birth", p->dob), kt_json_str(j, "surgeon", p->surgeon);
    kt_json_num(j, "age", p->age, -6), kt_json_num(j, "iop_mmHg", p->iop / KT_MMHG_MPA, 2);
    kt_json_obj(j, "anterior");
    kt_json_str(j, "source", a->eye.fitted ? "pentacam" : "keratometry");
    kt_json_num(j, "k_steep_D", kt_patient_k(p->ant.r_steep), 3), kt_json_num(j, "k_flat_D", kt_patient_k(p->ant.r_flat), 3);
    kt_json_num(j, "steep_axis_deg", p->ant.axis, 2);
    kt_json_num(j, "r_steep_mm", p->ant.r_steep, 4), kt_json_num(j, "r_flat_mm", p->ant.r_flat, 4);
    kt_json_end(j);
    kt_json_obj(j, "posterior");
    kt_json_str(j, "source", p->post.source == KT_SOURCE_DEFAULT    ? "population default (Eom et al. 2015)"
                             : p->post.source == KT_SOURCE_PENTACAM ? "pentacam" : "keratometry");
    kt_json_num(j, "k_steep_D", kt_patient_post_k(p->post.r_steep), 3);
    kt_json_num(j, "k_flat_D", kt_patient_post_k(p->post.r_flat), 3);
    kt_json_num(j, "steep_axis_deg", p->post.axis, 2);
    kt_json_end(j);
    kt_json_num(j, "central_thickness_um", 1000 * p->t_central, 1);
    kt_json_num(j, "thickness_at_zone_um", 1000 * a->eye.t_zone, 1);
    kt_json_num(j, "white_to_white_mm", p->wtw, 2);
    kt_json_end(j);
}

/* A fitted surface; with mesh's departure (dep_order > 0), the surface the mesh carries
 * (kt_surffit_measured_eye: the base plus the map's Zernike departure) as mesh_surface. */
static void json_surffit(kt_json *j, const char *key, const kt_surffit *s, const kt_surffit *mesh)
{
    kt_json_obj(j, key);
    kt_json_num(j, "r_steep_mm", s->r_steep, 5), kt_json_num(j, "r_flat_mm", s->r_flat, 5);
    kt_json_num(j, "axis_deg", s->axis, 3), kt_json_num(j, "Q", s->conic, 4);
    kt_json_num(j, "rms_um", 1000 * s->rms, 3), kt_json_num(j, "max_um", 1000 * s->max_resid, 3);
    kt_json_int(j, "cells", s->npts);
    if (mesh->dep_order > 0) {
        kt_json_obj(j, "mesh_surface");
        kt_json_int(j, "zernike_order", mesh->dep_order), kt_json_num(j, "zone_mm", 2 * mesh->dep_radius, -6);
        kt_json_num(j, "rms_um", 1000 * mesh->dep_rms, 4), kt_json_num(j, "max_um", 1000 * mesh->dep_max, 4);
        kt_json_int(j, "cells", mesh->dep_npts);
        kt_json_end(j);
    }
    kt_json_end(j);
}

static void json_fit(kt_json *j, const kt_lp_answer *a)
{
    const kt_lp_eye *y = &a->eye;
    if (!y->fitted) return;
    kt_json_obj(j, "fit");
    kt_json_num(j, "zone_mm", y->fit_ant.zone, -6);
    json_surffit(j, "anterior", &y->fit_ant, &a->scene.mesh_ant);
    if (y->fit_post_ok) json_surffit(j, "posterior", &y->fit_post, &a->scene.mesh_post);
    if (y->fit_pachy_ok) {
        const kt_pachyfit *q = &y->fit_pachy;
        kt_json_obj(j, "pachymetry");
        kt_json_num(j, "t0_um", 1000 * q->t0, 2), kt_json_num(j, "t2_um_per_mm2", 1000 * q->t2, 4);
        kt_json_num(j, "t4_um_per_mm4", 1000 * q->t4, 5), kt_json_num(j, "r_max_mm", q->r_max, -6);
        kt_json_num(j, "rms_um", 1000 * q->rms, 3), kt_json_num(j, "max_um", 1000 * q->max_resid, 3);
        kt_json_int(j, "cells", q->npts);
        kt_json_end(j);
    }
    kt_json_end(j);
}

static void json_main(kt_json *j, const kt_lp_answer *a)
{
    const kt_patient *p = &a->eye.p;
    int c = a->choice.chosen;
    kt_json_obj(j, "main_incision");
    kt_json_bool(j, "present", p->main_present);
    kt_json_num(j, "meridian_deg", p->main_meridian, 1), kt_json_num(j, "width_mm", p->main_width, 2);
    kt_json_str(j, "kind", p->main_kind == KT_MAIN_LIMBAL ? "limbal" : "clear_corneal");
    kt_json_str(j, "sia", !p->main_present ? "none" : p->main_simulate ? "simulated (a tunnel cut before the arcs)"
                                                                       : "surgeon's vector");
    kt_json_num(j, "sia_added_D", a->choice.main_vec.mag, 3), kt_json_num(j, "sia_axis_deg", kt_lp_axis_shown(a->choice.main_vec.axis, 1), 1);
    kt_json_int(j, "simulated_steps", c >= 0 ? a->run.r[c].skip : 0);
    jastig(j, "simulated_sia_keratometric", a->choice.main_sia_kerato, 4);
    jastig(j, "simulated_sia_total", a->choice.main_sia_total, 4);
    jastig(j, "sia_keratometric", a->choice.sia_kerato, 3); /* the SIA used, simulated or given */
    jastig(j, "sia_total", a->choice.sia_total, 3);
    kt_json_end(j);
}

static void json_arc(kt_json *j, const kt_lp_arc *q)
{
    kt_json_num(j, "centre_deg", q->centre, 2), kt_json_num(j, "arc_deg", q->arc, 1);
    kt_json_num(j, "from_deg", q->from, 1), kt_json_num(j, "to_deg", q->to, 1);
    kt_json_str(j, "from_clock", q->from_clock), kt_json_str(j, "to_clock", q->to_clock);
    kt_json_num(j, "chord_mm", q->chord, 2);
}

static void json_plan(kt_json *j, const kt_lp_answer *a)
{
    const kt_patient *p = &a->eye.p;
    int c = a->choice.chosen, k = a->choice.best[c];
    const kt_lp_run *r = &a->run.r[c];
    kt_lp_arc arcs[2], none;
    int narc = kt_lp_arcs(a, arcs);
    memset(&none, 0, sizeof none);
    none.centre = none.from = none.to = a->trim.t[c].meridian;
    kt_json_obj(j, "plan");
    kt_json_str(j, "incisions", a->fam.f[c].name);
    json_arc(j, narc ? &arcs[0] : &none);
    kt_json_num(j, "arc_opposite_deg", r->arc_opp[k], 1);
    kt_json_num(j, "zone_mm", p->zone, 2), kt_json_num(j, "blade_um", 1000 * a->eye.blade, 0);
    kt_json_arr(j, "arcs");
    for (int i = 0; i < narc; i++) kt_json_obj(j, NULL), json_arc(j, &arcs[i]), kt_json_end(j);
    kt_json_end(j);
    jastig(j, "predicted_residual", a->choice.pred[c][k], 3);
    kt_json_bool(j, "reached", a->choice.pred[c][k].mag <= p->target_residual);
    kt_astig kp, tp;
    kt_lp_post(a, &kp, &tp);
    jastig(j, "post_op_keratometric", kp, 3);
    jastig(j, "post_op_total", tp, 3);
    kt_json_int(j, "run_step", k + r->skip);
    kt_json_end(j);
}

static void json_band1(kt_json *j, const char *key, const kt_lp_band *b)
{
    kt_json_obj(j, key);
    kt_json_num(j, "mean_D", b->mag, 4), kt_json_num(j, "sd_D", b->sd, 4);
    kt_json_num(j, "lo90_D", b->lo, 4), kt_json_num(j, "hi90_D", b->hi, 4);
    kt_json_arr(j, "vector_D"), kt_json_num(j, NULL, b->mean[0], 5), kt_json_num(j, NULL, b->mean[1], 5), kt_json_end(j);
    kt_json_arr(j, "cov_D2");
    kt_json_num(j, NULL, b->cov.xx, -6), kt_json_num(j, NULL, b->cov.xy, -6), kt_json_num(j, NULL, b->cov.yy, -6);
    kt_json_end(j);
    kt_json_end(j);
}

static void json_band(kt_json *j, const kt_lp_answer *a, const kt_lriplan_opts *o)
{
    const kt_lp_bands *b = &a->band;
    if (!b->on) {
        kt_json_null(j, "band");
        return;
    }
    kt_json_obj(j, "band");
    kt_json_str(j, "method", "the prediction's double-angle vector as a 2-D normal distribution (mean: the prediction; "
                             "covariance: the SIA's derivatives along the tissue quantities, the extra term and the "
                             "non-tissue term (nontissue_cv |SIA|)^2 along the SIA); the "
                             "magnitude's 5% and 95% quantiles (lri-plan(1), BAND)");
    kt_json_arr(j, "quantities");
    for (int q = 0; q < a->run.nq; q++) {
        kt_json_obj(j, NULL);
        kt_json_str(j, "name", kt_uq_name(a->run.q[q])), kt_json_num(j, "sd", a->run.sd[q], -6);
        kt_json_end(j);
    }
    kt_json_end(j);
    kt_json_str(j, "left_out", a->run.left);
    kt_json_arr(j, "extra_cov_D2");
    kt_json_num(j, NULL, o->band_extra.xx, -6), kt_json_num(j, NULL, o->band_extra.xy, -6);
    kt_json_num(j, NULL, o->band_extra.yy, -6);
    kt_json_end(j);
    kt_json_num(j, "sia_sd_D", b->sia_sd, 4), kt_json_num(j, "sia_sd_tissue_D", b->sia_sd_tissue, 4);
    kt_json_num(j, "nontissue_cv", a->scene.s.unc.nontissue_cv, -6);
    json_band1(j, "predicted_residual", &b->residual);
    json_band1(j, "post_op_keratometric", &b->post_kerato);
    json_band1(j, "post_op_total", &b->post_total);
    kt_json_arr(j, "candidates");
    for (int i = 0; i < a->fam.n; i++) {
        if (!a->run.r[i].ran) continue;
        kt_json_obj(j, NULL);
        kt_json_str(j, "incisions", a->fam.f[i].name);
        json_band1(j, "best_residual", &b->best[i]);
        kt_json_end(j);
    }
    kt_json_end(j);
    kt_json_end(j);
}

static void json_halves(kt_json *j, const kt_lp_eye *y)
{
    if (!y->halves_ok) return;
    kt_json_obj(j, "halves");
    kt_json_num(j, "k_at_axis_D", y->halves.k_a, 3), kt_json_num(j, "k_opposite_D", y->halves.k_b, 3);
    kt_json_num(j, "k_flat_D", y->halves.k_flat, 3), kt_json_num(j, "astig_at_axis_D", y->half_a, 3);
    kt_json_num(j, "astig_opposite_D", y->half_b, 3), kt_json_num(j, "steeper_half_deg", y->steep_half, 1);
    kt_json_num(j, "ratio", y->ratio, 4), kt_json_int(j, "cells", y->halves.npts);
    kt_json_end(j);
}

/* dsia: {quantity: [d SIA_x, d SIA_y]} per unit of each band quantity, the SIA from the intact
 * eye as a double-angle vector (|SIA| cos 2a, |SIA| sin 2a). */
static void json_dsia(kt_json *j, const kt_lp_answer *a, const double (*d)[2])
{
    kt_json_obj(j, "dsia");
    for (int q = 0; q < a->run.nq; q++) {
        kt_json_arr(j, kt_uq_name(a->run.q[q]));
        kt_json_num(j, NULL, d[q][0], 6), kt_json_num(j, NULL, d[q][1], 6);
        kt_json_end(j);
    }
    kt_json_end(j);
}

/* One candidate family: its best, its trimming, its solver, its curve. */
static void json_candidate(kt_json *j, const kt_lp_answer *a, int i)
{
    const kt_lp_family *f = &a->fam.f[i];
    const kt_lp_run *r = &a->run.r[i];
    int b = a->choice.best[i];
    kt_json_obj(j, NULL);
    kt_json_str(j, "incisions", f->name), kt_json_num(j, "meridian_deg", a->trim.t[i].meridian, 2);
    kt_json_num(j, "ratio", f->ratio, 4);
    kt_json_bool(j, "run", r->ran), kt_json_bool(j, "moved", a->trim.t[i].moved);
    kt_json_str(j, "trimmed", a->trim.t[i].why);
    kt_json_num(j, "max_arc_deg", r->ran ? r->arc[r->nstep] : 0, 1);
    kt_json_str(j, "method", r->ran ? kt_aug_method_name(r->method) : "");
    if (r->fallback[0]) kt_json_str(j, "fallback", r->fallback);
    else kt_json_null(j, "fallback");
    kt_json_num(j, "best_arc_deg", r->arc[b], 1), kt_json_num(j, "best_arc_opposite_deg", r->arc_opp[b], 1);
    jastig(j, "best_residual", a->choice.pred[i][b], 3);
    kt_json_arr(j, "curve");
    for (int k = 0; r->ran && k <= r->nstep; k++) {
        kt_json_obj(j, NULL);
        kt_json_num(j, "arc_deg", r->arc[k], 1), kt_json_num(j, "arc_opposite_deg", r->arc_opp[k], 2);
        jastig(j, "residual", a->choice.pred[i][k], 4);
        jastig_to(j, "keratometric", r->kerato[k], 4, 3);
        jastig_to(j, "total", r->total[k], 4, 3);
        kt_json_num(j, "sia_D", kt_lp_sia(r, k), 4);
        jastig_to(j, "sia_intact", kt_lp_astig_sub(r->kerato[k], r->kerato_intact), 5, 3);
        json_dsia(j, a, r->dsia[k]);
        kt_json_end(j);
    }
    kt_json_end(j);
    kt_json_end(j);
}

static void json_provenance(kt_json *j, const kt_lp_answer *a, const kt_lriplan_opts *o, const kt_lri_files *fl)
{
    char hash[32];
    snprintf(hash, sizeof hash, "%016llx", (unsigned long long)a->mesh.hash);
    kt_json_obj(j, "provenance");
    kt_json_str(j, "scene", "scene.yaml"), kt_json_str(j, "mesh", "eye.msh"), kt_json_str(j, "mesh_hash", hash);
    kt_json_int(j, "mesh_nodes", a->mesh.m.nn), kt_json_bool(j, "fast", o->fast), kt_json_num(j, "step_deg", o->step, -6);
    kt_json_num(j, "mesh_seconds", a->mesh.seconds, 1), kt_json_num(j, "solve_seconds", a->run.solve_seconds, 1);
    kt_json_int(j, "jobs", a->run.jobs);
    kt_json_obj(j, "cpu_seconds");
    kt_json_num(j, "mesh", a->mesh.cpu, 1), kt_json_num(j, "physics", a->run.cpu_physics, 1);
    double cut = 0, solve = 0, read = 0, out = 0;
    for (int i = 0; i < a->fam.n; i++)
        cut += a->run.r[i].cpu_cut, solve += a->run.r[i].cpu_solve, read += a->run.r[i].cpu_read, out += a->run.r[i].cpu_sink;
    kt_json_num(j, "cut", cut, 1), kt_json_num(j, "solve", solve, 1), kt_json_num(j, "read", read, 1);
    kt_json_num(j, "step_files", out, 1);
    kt_json_end(j);
    kt_json_str(j, "date", fl->date), kt_json_str(j, "view", kt_lri_view_name(o->view));
    kt_json_str(j, "plan_html", "plan.html");
    kt_json_str(j, "run", fl->run ? fl->run : ""), kt_json_str(j, "report", fl->report ? fl->report : "");
    kt_json_end(j);
}

int kt_lri_write_json(const kt_lp_answer *a, const kt_lriplan_opts *o, const kt_lri_files *fl, const char *path, kt_err *e)
{
    const kt_patient *p = &a->eye.p;
    kt_out out;
    if (kt_out_open(&out, path, e)) return e->code;
    kt_json j;
    kt_json_begin(&j, out.f, 1);
    kt_json_obj(&j, NULL);
    kt_json_str(&j, "tool", "lri-plan"), kt_json_str(&j, "version", KT_VERSION);
    json_patient(&j, a);
    json_fit(&j, a);
    json_main(&j, a);
    kt_json_obj(&j, "target");
    kt_json_str(&j, "astigmatism", p->target_kind == KT_TARGET_TOTAL ? "total_corneal" : "keratometric");
    kt_json_num(&j, "residual_D", p->target_residual, 2);
    kt_json_end(&j);
    kt_json_obj(&j, "pre_op");
    jastig(&j, "keratometric", a->choice.pre_kerato, 3), jastig(&j, "total", a->choice.pre_total, 3);
    kt_json_obj(&j, "without_main_incision");
    jastig(&j, "keratometric", a->choice.bare_kerato, 3), jastig(&j, "total", a->choice.bare_total, 3);
    kt_json_end(&j);
    kt_json_obj(&j, "with_main_incision");
    jastig(&j, "keratometric", a->choice.with_kerato, 3), jastig(&j, "total", a->choice.with_total, 3);
    kt_json_end(&j);
    kt_json_end(&j);
    json_plan(&j, a);
    json_band(&j, a, o);
    json_halves(&j, &a->eye);
    kt_json_arr(&j, "fallback");
    for (int i = 0; i < a->fam.n; i++)
        if (a->run.r[i].fallback[0]) kt_json_str(&j, NULL, a->run.r[i].fallback);
    kt_json_end(&j);
    kt_json_arr(&j, "candidates");
    for (int i = 0; i < a->fam.n; i++) json_candidate(&j, a, i);
    kt_json_end(&j);
    json_provenance(&j, a, o, fl);
    kt_json_end(&j);
    if (kt_json_finish(&j, path, e)) return kt_out_abort(&out), e->code;
    return kt_out_commit(&out, e);
}

/* ---------------------------------------------------------------- the summary */

#define AX0(a) kt_lp_axis_shown((a), 0) /* an axis as "%.0f" prints it */

static void summary_cornea(const kt_lp_answer *a, FILE *s)
{
    const kt_patient *p = &a->eye.p;
    const kt_lp_eye *y = &a->eye;
    fprintf(s, "  cornea (%s): K %.2f / %.2f D @ %.0f deg; posterior %.2f / %.2f D @ %.0f deg (%s)\n",
            y->fitted ? "Pentacam fit" : "keratometry", kt_patient_k(p->ant.r_steep), kt_patient_k(p->ant.r_flat), p->ant.axis,
            kt_patient_post_k(p->post.r_steep), kt_patient_post_k(p->post.r_flat), p->post.axis,
            p->post.source == KT_SOURCE_DEFAULT ? "population default, Eom et al. 2015" : "measured");
    if (y->fitted)
        fprintf(s, "  fit over %g mm: anterior Q %.3f, residual rms %.2f um (max %.2f um, %d cells)%s\n", y->fit_ant.zone,
                y->fit_ant.conic, 1000 * y->fit_ant.rms, 1000 * y->fit_ant.max_resid, y->fit_ant.npts,
                y->fit_post_ok ? "" : "; no posterior map");
    if (y->fitted && y->fit_post_ok)
        fprintf(s, "               posterior Q %.3f, residual rms %.2f um (max %.2f um, %d cells)\n", y->fit_post.conic,
                1000 * y->fit_post.rms, 1000 * y->fit_post.max_resid, y->fit_post.npts);
    if (y->fitted && y->fit_pachy_ok)
        fprintf(s, "               pachymetry %.0f um central, residual rms %.2f um (max %.2f um)\n", 1000 * y->fit_pachy.t0,
                1000 * y->fit_pachy.rms, 1000 * y->fit_pachy.max_resid);
    const kt_surffit *ma = &a->scene.mesh_ant, *mp = &a->scene.mesh_post;
    if (a->scene.measured && ma->dep_order > 0) {
        fprintf(s, "  mesh: the measured surfaces (Zernike order %d): anterior over %.1f mm, residual rms %.3f um (max %.3f um)",
                ma->dep_order, 2 * ma->dep_radius, 1000 * ma->dep_rms, 1000 * ma->dep_max);
        if (mp->dep_order > 0)
            fprintf(s, "; posterior over %.1f mm, %.3f um (max %.3f um)", 2 * mp->dep_radius, 1000 * mp->dep_rms,
                    1000 * mp->dep_max);
        fputc('\n', s);
    }
    fprintf(s, "  pre-op astigmatism%s: keratometric %.2f D @ %.0f, total corneal %.2f D @ %.0f\n",
            a->choice.main_vec.mag > 0 ? " (with the main incision's SIA)" : "", a->choice.pre_kerato.mag,
            AX0(a->choice.pre_kerato.axis), a->choice.pre_total.mag, AX0(a->choice.pre_total.axis));
    if (p->main_present)
        fprintf(s, "  main incision: %g mm %s at %.0f deg: %s\n", p->main_width,
                p->main_kind == KT_MAIN_LIMBAL ? "limbal" : "clear corneal", p->main_meridian,
                p->main_simulate ? "simulated, cut before the arcs" : "surgeon's SIA added");
    if (a->scene.main_sim)
        fprintf(s, "  main incision's simulated SIA: keratometric %.2f D @ %.0f, total corneal %.2f D @ %.0f\n",
                a->choice.main_sia_kerato.mag, AX0(a->choice.main_sia_kerato.axis), a->choice.main_sia_total.mag,
                AX0(a->choice.main_sia_total.axis));
    if (y->halves_ok)
        fprintf(s, "  half-meridians: %.2f D @ %.0f and %.2f D @ %.0f over K flat %.2f D: %s\n", y->half_a, p->ant.axis,
                y->half_b, fmod(p->ant.axis + 180, 360), y->halves.k_flat,
                y->ratio < KT_LP_SYMMETRIC ? "asymmetric, unequal pairs tried" : "symmetric");
}

static void summary_candidates(const kt_lp_answer *a, FILE *s)
{
    fprintf(s, "  candidates (best of each, residual %s):\n", target_name(&a->eye.p));
    for (int i = 0; i < a->fam.n; i++) {
        const kt_lp_family *f = &a->fam.f[i];
        const kt_lp_run *r = &a->run.r[i];
        if (!r->ran) continue;
        int b = a->choice.best[i];
        char arcs[48];
        if (f->unequal) snprintf(arcs, sizeof arcs, "%.0f + %.1f deg", r->arc[b], r->arc_opp[b]);
        else snprintf(arcs, sizeof arcs, "%s%.0f deg", f->paired ? "2 x " : "", r->arc[b]);
        fprintf(s, "    %-7s at %3.0f deg: %-16s residual %.2f D @ %3.0f%s\n", f->name, a->trim.t[i].meridian, arcs,
                a->choice.pred[i][b].mag, AX0(a->choice.pred[i][b].axis), i == a->choice.chosen ? "  <- chosen" : "");
        if (r->fallback[0]) fprintf(s, "      the planned method fell back (%s)\n", r->fallback);
    }
    for (int i = 0; i < a->fam.n; i++) /* the clearance's trimming (lri-plan(1), CLEARANCE) */
        if (a->trim.t[i].why[0]) fprintf(s, "    (%s)\n", a->trim.t[i].why);
}

static void summary_band(const kt_lp_answer *a, FILE *s)
{
    const kt_lp_bands *b = &a->band;
    if (!b->on) return;
    fprintf(s, "  band (2-D; tissue quantities, non-tissue cv %.2f): residual 90%% %.2f-%.2f D (SIA sd %.2f D); "
               "post-op keratometric 90%% %.2f-%.2f D, total corneal %.2f-%.2f D\n",
            a->scene.s.unc.nontissue_cv, b->residual.lo, b->residual.hi, b->sia_sd, b->post_kerato.lo,
            b->post_kerato.hi, b->post_total.lo, b->post_total.hi);
    if (a->run.left[0]) fprintf(s, "    left out of the band (no derivative): %s\n", a->run.left);
}

void kt_lri_summary(const kt_lp_answer *a, const kt_lriplan_opts *o, const kt_lri_files *fl, FILE *s)
{
    const kt_patient *p = &a->eye.p;
    int c = a->choice.chosen, k = a->choice.best[c];
    fprintf(s, "lri-plan: %s, %s, %g y\n", p->name, p->eye == KT_EYE_OS ? "OS (left)" : "OD (right)", p->age);
    summary_cornea(a, s);
    summary_candidates(a, s);
    kt_lp_arc arcs[2];
    int narc = kt_lp_arcs(a, arcs);
    if (narc == 0) fprintf(s, "  answer: no arc (none lowers the %s residual)\n", target_name(p));
    else fprintf(s, "  answer: %s at the %.1f mm zone, blade %.0f um deep:\n", a->fam.f[c].name, p->zone, 1000 * a->eye.blade);
    for (int i = 0; i < narc; i++)
        fprintf(s, "    arc %d: %.0f deg centred on %.0f, from %.0f to %.0f deg clockwise (%s to %s o'clock), chord %.2f mm\n", i + 1,
                arcs[i].arc, kt_lp_deg_mark(arcs[i].centre), kt_lp_deg_mark(arcs[i].from), kt_lp_deg_mark(arcs[i].to),
                arcs[i].from_clock, arcs[i].to_clock, arcs[i].chord);
    kt_astig kp, tp;
    kt_lp_post(a, &kp, &tp);
    fprintf(s, "  post-op: keratometric %.2f D @ %.0f, total corneal %.2f D @ %.0f\n", kp.mag, AX0(kp.axis), tp.mag, AX0(tp.axis));
    const kt_astig *r = &a->choice.pred[c][k];
    int dg = kt_lp_res_digits(r->mag, p->target_residual);
    fprintf(s, "  predicted %s residual %.*f D @ %.0f: %s the %.*f D target\n", target_name(p), dg, r->mag, AX0(r->axis),
            r->mag <= p->target_residual ? "reaches" : "does NOT reach", dg, p->target_residual);
    summary_band(a, s);
    fprintf(s, "  written: %s/plan.html, plan.json%s%s, scene.yaml, eye.msh (mesh %.0f s, solves %.0f s%s)\n", o->outdir,
            fl->report ? ", " : "", fl->report ? fl->report : "", a->mesh.seconds, a->run.solve_seconds,
            o->fast ? ", --fast" : "");
}
