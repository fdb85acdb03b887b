/* lriplan_band.c: the first-order band on lri-plan's predicted residual and post-operative
 * astigmatism (issue 21; lri-plan(1), BAND).
 *
 * Every family's run is solved with augsolve --uncertainty; curvature writes its
 * derivatives.tsv: per step and quantity q, dR/dq of every reading, among them the keratometric
 * SIA's double-angle vector (sia_x_D, sia_y_D). The prediction is a double-angle sum
 *     v = pre-op (measured) + main incision (the surgeon's vector, or simulated in the run)
 *         + the arcs' simulated SIA,
 * so dv/dq = dSIA/dq of the run's step (from the run's intact step 0; a simulated main
 * incision's SIA is part of it, the measured pre-op and a surgeon's vector have no derivative).
 * The magnitude's derivative is the projection on v's direction,
 *     d|v|/dq = (v_x dSIA_x/dq + v_y dSIA_y/dq) / |v|,
 * and sd = sqrt(sum_q (d|v|/dq sd_q)^2), the quantities independent, as curvature's bands
 * (optics/curv_band.h); the 90% interval |v| +- 1.645 sd, its lower end clipped at 0. At a
 * vanishing |v| the direction is undefined: sd is then the rms of the two components' sd.
 * The total corneal prediction carries the keratometric SIA's derivatives: curvature bands the
 * anterior readings only, so the posterior's share of the SIA's spread is not in the band.
 * The quantities augsolve marks fd (the thickness and the incision's depth: they move the mesh
 * and the cut) have no derivative here and are named as left out. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "curv_band.h"
#include "lriplan_int.h"
#include "tsv.h"

/* The columns read from derivatives.tsv. */
enum { D_STEP, D_PARAM, D_METHOD, D_SD, D_USED, D_SX, D_SY, D_N };

static void add_left(kt_lri_bdata *b, const char *name)
{
    char have[300];
    snprintf(have, sizeof have, "%s,", b->left);
    for (char *t = strtok(have, " ,"); t; t = strtok(NULL, " ,"))
        if (strcmp(t, name) == 0) return;
    size_t n = strlen(b->left);
    snprintf(b->left + n, sizeof b->left - n, "%s%s", n ? ", " : "", name);
}

int kt_lri_band_read(const char *run, kt_lri_family *f, int skip, kt_err *e)
{
    static const char *const want[D_N] = {"step", "param", "method", "sd", "used", "sia_x_D", "sia_y_D"};
    kt_lri_bdata *b = &f->band;
    memset(b, 0, sizeof *b);
    char path[1300];
    if (snprintf(path, sizeof path, "%s/derivatives.tsv", run) >= (int)sizeof path)
        return kt_fail(e, KT_EINPUT, "%s/derivatives.tsv: path too long", run);
    if (access(path, F_OK) != 0)
        return kt_fail(e, KT_ERUN, "%s: cannot open (the run was solved with augsolve --uncertainty)", path);
    kt_tsv t;
    if (kt_tsv_open(&t, path, e)) return e->code;
    int col[D_N];
    for (int c = 0; c < D_N && !e->code; c++) col[c] = kt_tsv_need(&t, want[c], "a table of curvature(1)");
    while (!e->code && kt_tsv_next(&t) > 0) {
        const char *param = kt_tsv_text(&t, col[D_PARAM]), *method = kt_tsv_text(&t, col[D_METHOD]);
        long long step, used;
        double sd, sx, sy;
        if (!param || !method || kt_tsv_int(&t, col[D_STEP], 0, 1000000, &step) ||
            kt_tsv_int(&t, col[D_USED], 0, 1, &used) || kt_tsv_num(&t, col[D_SD], KT_TSV_NAN | KT_TSV_INF, &sd))
            break;
        int at = (int)step - skip;
        if (!used) { /* as curvature's "left out": an fd quantity with a spread and no --sens row */
            if (strcmp(method, "fd") == 0 && sd > 0) add_left(b, param);
            continue;
        }
        if (at < 0 || at > f->nstep) continue; /* step 0 before a simulated main incision's steps */
        if (kt_tsv_num(&t, col[D_SX], KT_TSV_NAN | KT_TSV_INF, &sx) ||
            kt_tsv_num(&t, col[D_SY], KT_TSV_NAN | KT_TSV_INF, &sy))
            break;
        int q = 0;
        while (q < b->nq && strcmp(b->q[q], param) != 0) q++;
        if (q == b->nq) {
            if (q == KT_LRIPLAN_MAXQ) {
                kt_tsv_fail(&t, col[D_PARAM], "expected at most %d quantities", KT_LRIPLAN_MAXQ);
                break;
            }
            snprintf(b->q[q], sizeof b->q[q], "%s", param);
            b->sd[q] = sd;
            b->nq++;
        }
        b->dsia[at][q][0] = sx;
        b->dsia[at][q][1] = sy;
        if (!isfinite(sx) || !isfinite(sy) || !(b->sd[q] >= 0))
            kt_fail(e, KT_ERUN, "%s:%d: the SIA's derivative along %s is not a number: numerical trouble in the "
                    "band", path, t.line, b->q[q]);
    }
    kt_tsv_close(&t);
    if (!e->code) b->on = 1;
    return e->code;
}

void kt_lri_band_of(const kt_lri_family *f, int k, kt_astig v, kt_lri_band *out)
{
    const kt_lri_bdata *b = &f->band;
    out->sd = out->lo = out->hi = NAN;
    if (!b->on || k < 0 || k > f->nstep) return;
    double xy[2];
    kt_astig_xy(v, xy);
    double r = hypot(xy[0], xy[1]), var = 0;
    for (int q = 0; q < b->nq; q++) {
        const double *d = b->dsia[k][q];
        if (r > 1e-9) {
            double dm = (xy[0] * d[0] + xy[1] * d[1]) / r * b->sd[q];
            var += dm * dm;
        } else {
            var += 0.5 * (d[0] * d[0] + d[1] * d[1]) * b->sd[q] * b->sd[q];
        }
    }
    out->sd = sqrt(var);
    out->lo = fmax(0, v.mag - KT_BAND_Z90 * out->sd);
    out->hi = v.mag + KT_BAND_Z90 * out->sd;
}

/* The chosen answer's bands: the residual (the target's kind) and both post-operative ones. */
static int chosen_bands(const kt_lri_answer *a, kt_lri_band *res, kt_lri_band *kb, kt_lri_band *tb)
{
    if (a->nfam == 0) return 0;
    const kt_lri_family *f = &a->fam[a->chosen];
    kt_astig kpost, tpost;
    kt_lri_post(a, &kpost, &tpost);
    kt_lri_band_of(f, f->best, f->pred[f->best], res);
    kt_lri_band_of(f, f->best, kpost, kb);
    kt_lri_band_of(f, f->best, tpost, tb);
    return f->band.on;
}

static void json_band(FILE *j, const char *name, const kt_lri_band *b)
{
    if (isnan(b->sd)) fprintf(j, "\"%s\": null", name);
    else fprintf(j, "\"%s\": {\"sd_D\": %.4f, \"lo90_D\": %.4f, \"hi90_D\": %.4f}", name, b->sd, b->lo, b->hi);
}

void kt_lri_band_json(const kt_lri_answer *a, FILE *j)
{
    kt_lri_band res, kb, tb;
    if (!chosen_bands(a, &res, &kb, &tb)) {
        fprintf(j, "  \"band\": null,\n");
        return;
    }
    const kt_lri_family *f = &a->fam[a->chosen];
    fprintf(j, "  \"band\": {\"method\": \"first order: augsolve --uncertainty's derivatives of the keratometric "
               "SIA vector, projected on the prediction (lri-plan(1), BAND)\", \"quantities\": [");
    for (int q = 0; q < f->band.nq; q++)
        fprintf(j, "%s{\"name\": \"%s\", \"sd\": %.6g}", q ? ", " : "", f->band.q[q], f->band.sd[q]);
    fprintf(j, "], \"left_out\": \"%s\",\n    ", f->band.left);
    json_band(j, "predicted_residual", &res);
    fprintf(j, ",\n    ");
    json_band(j, "post_op_keratometric", &kb);
    fprintf(j, ",\n    ");
    json_band(j, "post_op_total", &tb);
    fprintf(j, ",\n    \"candidates\": [");
    for (int i = 0; i < a->nfam; i++) {
        const kt_lri_family *c = &a->fam[i];
        kt_lri_band cb;
        kt_lri_band_of(c, c->best, c->pred[c->best], &cb);
        fprintf(j, "%s{\"incisions\": \"%s\", ", i ? ", " : "", c->name);
        json_band(j, "best_residual", &cb);
        fputc('}', j);
    }
    fprintf(j, "]},\n");
}

void kt_lri_band_summary(const kt_lri_answer *a, FILE *s)
{
    kt_lri_band res, kb, tb;
    if (!chosen_bands(a, &res, &kb, &tb)) return;
    const kt_lri_family *f = &a->fam[a->chosen];
    fprintf(s, "  band (first order, tissue quantities): residual sd %.2f D, 90%% %.2f-%.2f D; post-op keratometric "
               "90%% %.2f-%.2f D, total corneal %.2f-%.2f D\n",
            res.sd, res.lo, res.hi, kb.lo, kb.hi, tb.lo, tb.hi);
    if (f->band.left[0]) fprintf(s, "    left out of the band (no derivative): %s\n", f->band.left);
}

void kt_lri_band_html(const kt_lri_answer *a, FILE *f)
{
    kt_lri_band res, kb, tb;
    if (!chosen_bands(a, &res, &kb, &tb)) return;
    const kt_lri_family *c = &a->fam[a->chosen];
    fprintf(f, "<p class=\"note band\">Band (first order, tissue quantities: ");
    for (int q = 0; q < c->band.nq; q++) fprintf(f, "%s%s", q ? ", " : "", c->band.q[q]);
    fprintf(f, "): predicted residual sd <b>%.2f D</b>, 90%% interval <b>%.2f&ndash;%.2f D</b>; post-operative "
               "keratometric %.2f&ndash;%.2f D, total corneal %.2f&ndash;%.2f D.",
            res.sd, res.lo, res.hi, kb.lo, kb.hi, tb.lo, tb.hi);
    if (c->band.left[0]) fprintf(f, " Left out (no derivative): %s.", c->band.left);
    fprintf(f, " The surgeon, the blade and healing are not in it.</p>\n");
}
