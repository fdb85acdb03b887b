/* curvature_band.c: curvature's first-order uncertainty bands (issue 21; curvature(1),
 * UNCERTAINTY): RUN/uncertainty.tsv and the dudp_<p> fields of the step VTKs (augsolve
 * --uncertainty), the --sens file's finite-difference rows, and the bands' outputs (the
 * columns of curvature.tsv, derivatives.tsv, the summary, the JSON). The arithmetic of a band
 * is optics/curv_band.h. */
#define _XOPEN_SOURCE 700
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "curvature_run.h"

#include "curv.h"
#include "curv_band.h"
#include "tsv.h"
#include "uqread.h"

#include "curvature_int.h"

static const char *method_name(int m)
{
    return m == KT_UQ_DERIVATIVE ? "derivative" : m == KT_UQ_FD ? "fd" : "none";
}

int kt_curvrun_band_setup(run_ctx *c, kt_err *e)
{
    const kt_curv_opts *o = c->o;
    char path[PATHMAX];
    int have = 0;
    if (o->run_dir && !o->no_bands) {
        if (kt_curvrun_join(path, o->run_dir, "uncertainty.tsv", e)) return e->code;
        have = access(path, F_OK) == 0;
    }
    if (!have) {
        if (o->sens)
            return kt_fail(e, KT_EINPUT, "--sens %s: expected a run folder with uncertainty.tsv (augsolve "
                           "--uncertainty)%s", o->sens, o->no_bands ? ", and no --no-uncertainty" : "");
        return KT_OK;
    }
    if (kt_uq_table_read(path, &c->uq, e)) return e->code;
    if (o->sens && kt_uq_sens_read(o->sens, &c->sens, e)) return e->code;
    int last = c->num[c->nstep - 1];
    for (int i = 0; i < c->sens.n; i++) {
        const kt_uq_sens_row *r = c->sens.r + i;
        int k = kt_uq_table_find(&c->uq, r->param);
        if (k < 0 || c->uq.p[k].method != KT_UQ_FD)
            return kt_fail(e, KT_EINPUT, "%s:%d:1: expected a quantity that %s marks fd, found %s (%s)", o->sens,
                           r->line, path, r->param, k < 0 ? "not listed there" : method_name(c->uq.p[k].method));
        if (kt_band_reading_find(r->reading) < 0)
            return kt_fail(e, KT_EINPUT, "%s:%d:%d: expected a reading with a band (k_steep_D, flattening_D, sia_D, "
                           "... see curvature(1)), found %s", o->sens, r->line, (int)strlen(r->param) + 2, r->reading);
        if (r->step > last)
            return kt_fail(e, KT_EINPUT, "%s:%d: expected a step of the run (0 to %d), found step %d", o->sens, r->line,
                           last, r->step);
    }
    int np = c->uq.n, nr = KT_RD_N;
    c->bands = 1;
    c->used = kt_calloc(np > 0 ? np : 1, sizeof(int), e);
    c->deriv = kt_calloc((size_t)c->nstep * (np > 0 ? np : 1) * nr, sizeof(double), e);
    c->eps = kt_calloc((size_t)c->nstep * (np > 0 ? np : 1), sizeof(double), e);
    c->sd = kt_calloc((size_t)c->nstep * nr, sizeof(double), e);
    c->val = kt_calloc((size_t)c->nstep * nr, sizeof(double), e);
    if (!c->used || !c->deriv || !c->eps || !c->sd || !c->val) return e->code;
    for (int k = 0; k < np; k++) {
        c->used[k] = c->uq.p[k].method == KT_UQ_DERIVATIVE;
        for (int i = 0; i < c->sens.n; i++)
            if (strcmp(c->sens.r[i].param, c->uq.p[k].name) == 0) c->used[k] = 1;
    }
    for (size_t i = 0; i < (size_t)c->nstep * (np > 0 ? np : 1); i++) c->eps[i] = NAN;
    return KT_OK;
}

void kt_curvrun_band_free(run_ctx *c)
{
    kt_uq_table_free(&c->uq);
    kt_uq_sens_free(&c->sens);
    free(c->used), free(c->deriv), free(c->eps), free(c->sd), free(c->val), free(c->b0_xyz), free(c->b0_dudp);
}

/* The anterior nodes' dudp of every derivative quantity (np x 3 s->n; zero for the others). */
static int take_dudp(run_ctx *c, int step, const kt_vtk *v, const kt_surf *s, double *out, kt_err *e)
{
    for (int k = 0; k < c->uq.n; k++) {
        if (c->uq.p[k].method != KT_UQ_DERIVATIVE) continue;
        char name[KT_UQ_NAME + 8];
        snprintf(name, sizeof name, "dudp_%s", c->uq.p[k].name);
        const kt_vtk_field *f = kt_vtk_find(v, name, 0);
        if (!f || f->ncomp != 3)
            return kt_fail(e, KT_EINPUT, "%s: expected POINT_DATA field \"%s\" (3 components): the run's "
                           "uncertainty.tsv marks %s 'derivative' (augsolve --uncertainty writes it in every step)",
                           c->vtk[step], name, c->uq.p[k].name);
        double *d = out + (size_t)k * 3 * s->n;
        for (int i = 0; i < s->n; i++)
            for (int j = 0; j < 3; j++) {
                double x = f->v[3 * (size_t)s->node[i] + j];
                if (!isfinite(x))
                    return kt_fail(e, KT_EINPUT, "%s: %s is %g at point %d, an anterior node: expected a finite "
                                   "derivative there (is the cornea in augsolve's --output set?)", c->vtk[step], name,
                                   x, s->node[i]);
                d[3 * i + j] = x;
            }
    }
    return KT_OK;
}

int kt_curvrun_band_step(run_ctx *c, int step, const kt_vtk *v, const kt_surf *s, kt_err *e)
{
    if (!c->bands) return KT_OK;
    int np = c->uq.n, n = s->n, rc = KT_OK;
    double *dudp = kt_calloc((size_t)(np > 0 ? np : 1) * 3 * n, sizeof(double), e);
    if (!dudp) return e->code;
    if ((rc = take_dudp(c, step, v, s, dudp, e)) != KT_OK) {
        free(dudp);
        return rc;
    }
    if (step == 0) { /* kept: every later step's difference moves step 0 too */
        c->b0_n = n, c->b0_dudp = dudp;
        if (!(c->b0_xyz = kt_calloc((size_t)3 * n, sizeof(double), e))) return e->code;
        memcpy(c->b0_xyz, s->xyz, (size_t)3 * n * sizeof(double));
    }
    int n0 = c->b0_n;
    const kt_astig *tia = c->has_target ? &c->tia : NULL;
    double mer = isnan(c->meridian) ? (step > 0 ? c->res[0].k.axis_steep : 0) : c->meridian;
    for (int k = 0; rc == KT_OK && k < np; k++) {
        if (c->uq.p[k].method != KT_UQ_DERIVATIVE) continue;
        kt_band_pts p0 = {n0, c->b0_xyz, c->b0_dudp + (size_t)k * 3 * n0}, pk = {n, s->xyz, dudp + (size_t)k * 3 * n};
        double *d = c->deriv + ((size_t)step * np + k) * KT_RD_N;
        rc = kt_band_step_deriv(&p0, &pk, c->o->fit, c->o->order, c->o->zone, mer, tia, d, &c->eps[(size_t)step * np + k], e);
    }
    if (rc != KT_OK) {
        char msg[sizeof e->msg];
        snprintf(msg, sizeof msg, "%s", e->msg);
        e->code = 0;
        rc = kt_fail(e, rc, "%s: the uncertainty band's central difference: %s", c->vtk[step], msg);
    }
    if (step != 0) free(dudp);
    return rc;
}

/* A step's readings (unperturbed), the fd rows, the standard deviations. */
int kt_curvrun_band_finish(run_ctx *c, kt_err *e)
{
    if (!c->bands) return KT_OK;
    int np = c->uq.n;
    const kt_astig *tia = c->has_target ? &c->tia : NULL;
    double *contrib = kt_calloc((size_t)(np > 0 ? np : 1) * KT_RD_N, sizeof(double), e);
    if (!contrib) return e->code;
    for (int i = 0; i < c->nstep; i++) {
        double *val = c->val + (size_t)i * KT_RD_N;
        kt_band_readings(&c->res[0].fit, &c->res[i].fit, c->meridian, tia, val);
        for (int s = 0; s < c->sens.n; s++) {
            const kt_uq_sens_row *r = c->sens.r + s;
            if (r->step >= 0 ? r->step != c->num[i] : i == 0) continue;
            int k = kt_uq_table_find(&c->uq, r->param), q = kt_band_reading_find(r->reading);
            c->deriv[((size_t)i * np + k) * KT_RD_N + q] = r->dr_dp;
        }
        for (int k = 0; k < np; k++)
            for (int q = 0; q < KT_RD_N; q++) {
                double d = c->deriv[((size_t)i * np + k) * KT_RD_N + q];
                /* a reading that is NaN (coupling at step 0, no target) has a NaN band */
                if (isnan(val[q])) d = NAN;
                contrib[(size_t)k * KT_RD_N + q] = c->used[k] ? d * c->uq.p[k].sd : 0;
            }
        kt_band_sd(contrib, np, c->sd + (size_t)i * KT_RD_N);
    }
    free(contrib);
    return KT_OK;
}

/* ---------------------------------------------------------------- outputs */

void kt_curvrun_band_tsv_head(const run_ctx *c, kt_tsvw *w)
{
    if (!c->bands) return;
    kt_tsvw_text(w, "sia_x_D"), kt_tsvw_text(w, "sia_y_D");
    char k[96];
    for (int q = 0; q < KT_RD_N; q++) {
        const char *n = kt_band_reading_name(q);
        snprintf(k, sizeof k, "%s_sd", n), kt_tsvw_text(w, k);
        snprintf(k, sizeof k, "%s_lo90", n), kt_tsvw_text(w, k);
        snprintf(k, sizeof k, "%s_hi90", n), kt_tsvw_text(w, k);
    }
}

void kt_curvrun_band_tsv_row(const run_ctx *c, int i, kt_tsvw *w)
{
    if (!c->bands) return;
    const double *val = c->val + (size_t)i * KT_RD_N, *sd = c->sd + (size_t)i * KT_RD_N;
    kt_tsvw_num(w, val[KT_RD_SIA_X], "%.4f"), kt_tsvw_num(w, val[KT_RD_SIA_Y], "%.4f");
    for (int q = 0; q < KT_RD_N; q++) {
        double lo, hi;
        kt_band_interval(q, val[q], sd[q], &lo, &hi);
        kt_tsvw_num(w, sd[q], "%.6f"), kt_tsvw_num(w, lo, "%.4f"), kt_tsvw_num(w, hi, "%.4f");
    }
}

/* derivatives.tsv: every step's dR/dp of every quantity (curvature(1), UNCERTAINTY). */
int kt_curvrun_band_write(run_ctx *c, kt_err *e)
{
    if (!c->bands) return KT_OK;
    static const char *const H[] = {"step", "param", "unit", "method", "sd", "used", "eps"};
    char path[PATHMAX];
    kt_out out;
    if (kt_curvrun_tmp_path(c, path, "derivatives.tsv", e) || kt_curvrun_add_file(c, "derivatives.tsv", e) ||
        kt_out_open(&out, path, e))
        return e->code;
    kt_tsvw w;
    kt_tsvw_begin(&w, out.f);
    for (int k = 0; k < 7; k++) kt_tsvw_text(&w, H[k]);
    for (int q = 0; q < KT_RD_N; q++) kt_tsvw_text(&w, kt_band_reading_name(q));
    kt_tsvw_end(&w);
    int np = c->uq.n;
    for (int i = 0; i < c->nstep; i++)
        for (int k = 0; k < np; k++) {
            const kt_uq_param *p = c->uq.p + k;
            kt_tsvw_int(&w, c->num[i]), kt_tsvw_text(&w, p->name), kt_tsvw_text(&w, p->unit);
            kt_tsvw_text(&w, method_name(p->method)), kt_tsvw_num(&w, p->sd, "%.6g"), kt_tsvw_int(&w, c->used[k]);
            kt_tsvw_num(&w, c->eps[(size_t)i * np + k], "%.6g");
            for (int q = 0; q < KT_RD_N; q++)
                kt_tsvw_num(&w, c->used[k] ? c->deriv[((size_t)i * np + k) * KT_RD_N + q] : NAN, "%.8g");
            kt_tsvw_end(&w);
        }
    if (kt_tsvw_finish(&w, path, e)) return kt_out_abort(&out), e->code;
    return kt_out_commit(&out, e);
}

int kt_curvrun_band_tornado(const run_ctx *c, const char **name, double *val)
{
    int np = c->uq.n, n = 0, i = c->nstep - 1;
    for (int k = 0; k < np; k++) {
        if (!c->used[k]) continue;
        double v = fabs(c->deriv[((size_t)i * np + k) * KT_RD_N + KT_RD_SIA] * c->uq.p[k].sd);
        int j = n++;
        while (j > 0 && !(val[j - 1] >= v)) name[j] = name[j - 1], val[j] = val[j - 1], j--;
        name[j] = c->uq.p[k].name, val[j] = v;
    }
    return n;
}

static void band_text(const run_ctx *c, int i, int q, const char *label, const char *unit, int dec, FILE *f)
{
    double v = c->val[(size_t)i * KT_RD_N + q], sd = c->sd[(size_t)i * KT_RD_N + q], lo, hi;
    kt_band_interval(q, v, sd, &lo, &hi);
    if (isnan(v)) return;
    /* "a-b" as the contract says; "a to b" when a minus sign would make that ambiguous */
    fprintf(f, "%s %.*f%s (90%%: %.*f%s%.*f)", label, dec, v, unit, dec, lo, lo < 0 || hi < 0 ? " to " : "-", dec, hi);
}

void kt_curvrun_band_summary(const run_ctx *c, FILE *f)
{
    if (!c->bands) return;
    int i = c->nstep - 1, np = c->uq.n, nused = 0;
    for (int k = 0; k < np; k++) nused += c->used[k];
    fprintf(f, "uncertainty, step %d (first order, %d independent quantit%s, 90%% = +-1.645 sd): ", c->num[i], nused,
            nused == 1 ? "y" : "ies");
    band_text(c, i, KT_RD_SIA, "SIA", " D", 2, f);
    double sia_sd = c->sd[(size_t)i * KT_RD_N + KT_RD_SIA];
    if (isnan(sia_sd)) fputs(", sd NaN", f);
    else fprintf(f, ", sd %.2f D", sia_sd);
    fputs("; ", f), band_text(c, i, KT_RD_FLAT, "flattening", " D", 2, f);
    fputs("; ", f), band_text(c, i, KT_RD_STEEP, "steepening", " D", 2, f);
    if (!isnan(c->val[(size_t)i * KT_RD_N + KT_RD_COUPLING])) fputs("; ", f), band_text(c, i, KT_RD_COUPLING, "coupling", "", 2, f);
    fputs("; ", f), band_text(c, i, KT_RD_K_STEEP, "K steep", " D", 2, f);
    fputs("; ", f), band_text(c, i, KT_RD_K_FLAT, "K flat", " D", 2, f);
    if (c->has_target) fputs("; ", f), band_text(c, i, KT_RD_DV, "residual (difference vector)", " D", 2, f);
    fputc('\n', f);
    const char *name[256];
    double val[256];
    int n = np <= 256 ? kt_curvrun_band_tornado(c, name, val) : 0;
    if (n > 0) {
        fputs("SIA sd by quantity:", f);
        for (int k = 0; k < n; k++) fprintf(f, "%s %s %.3f D", k ? "," : "", name[k], val[k]);
        fputc('\n', f);
    }
    int left = 0;
    for (int k = 0; k < np; k++)
        if (!c->used[k] && c->uq.p[k].method == KT_UQ_FD && c->uq.p[k].sd > 0) {
            fprintf(f, "%s%s", left++ ? ", " : "left out (method fd, no --sens rows): ", c->uq.p[k].name);
        }
    if (left) fputc('\n', f);
}

void kt_curvrun_band_json_top(const run_ctx *c, kt_json *j)
{
    if (!c->bands) return;
    kt_json_obj(j, "uncertainty");
    kt_json_num(j, "z90", KT_BAND_Z90, -6), kt_json_num(j, "delta_mm", KT_BAND_DELTA_MM, -6);
    kt_json_arr(j, "params");
    for (int k = 0; k < c->uq.n; k++) {
        const kt_uq_param *p = c->uq.p + k;
        kt_json_obj(j, NULL);
        kt_json_str(j, "param", p->name), kt_json_str(j, "unit", p->unit);
        kt_json_num(j, "value", p->value, -6), kt_json_num(j, "sd", p->sd, -6);
        kt_json_str(j, "method", method_name(p->method)), kt_json_str(j, "source", p->source);
        kt_json_bool(j, "used", c->used[k]);
        kt_json_num(j, "sia_sd_contrib_D",
                    c->used[k] ? fabs(c->deriv[((size_t)(c->nstep - 1) * c->uq.n + k) * KT_RD_N + KT_RD_SIA] * p->sd) : NAN, -6);
        kt_json_end(j);
    }
    kt_json_end(j);
    kt_json_end(j);
}

void kt_curvrun_band_json_step(const run_ctx *c, int i, kt_json *j)
{
    if (!c->bands) return;
    const double *val = c->val + (size_t)i * KT_RD_N, *sd = c->sd + (size_t)i * KT_RD_N;
    kt_json_num(j, "sia_x_D", val[KT_RD_SIA_X], -6);
    kt_json_num(j, "sia_y_D", val[KT_RD_SIA_Y], -6);
    for (int q = 0; q < KT_RD_N; q++) {
        char k[96];
        double lo, hi;
        kt_band_interval(q, val[q], sd[q], &lo, &hi);
        snprintf(k, sizeof k, "%s_sd", kt_band_reading_name(q)), kt_json_num(j, k, sd[q], -6);
        snprintf(k, sizeof k, "%s_lo90", kt_band_reading_name(q)), kt_json_num(j, k, lo, -6);
        snprintf(k, sizeof k, "%s_hi90", kt_band_reading_name(q)), kt_json_num(j, k, hi, -6);
    }
}
