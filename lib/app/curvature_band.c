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

static double max_abs(const double *d, int n3)
{
    double m = 0;
    for (int i = 0; i < n3; i++) m = fmax(m, fabs(d[i]));
    return m;
}

/* The zone fit of xyz + t dudp. */
static int fit_moved(run_ctx *c, const double *xyz, const double *dudp, int n, double t, double *buf, kt_fit *f,
                     kt_err *e)
{
    for (int i = 0; i < 3 * n; i++) buf[i] = xyz[i] + t * dudp[i];
    return kt_curv_fit(buf, n, c->o->fit, c->o->order, c->o->zone, 0, 0, f, NULL, 0, e);
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
    int n0 = c->b0_n, nb = n > n0 ? n : n0;
    double *buf = kt_calloc((size_t)3 * nb, sizeof(double), e);
    kt_fit *f = kt_calloc(4, sizeof(kt_fit), e); /* step 0 +, step 0 -, step +, step - */
    if (!buf || !f) rc = e->code;
    const kt_astig *tia = c->has_target ? &c->tia : NULL;
    double mer = isnan(c->meridian) ? (step > 0 ? c->res[0].k.axis_steep : 0) : c->meridian;
    for (int k = 0; rc == KT_OK && k < np; k++) {
        if (c->uq.p[k].method != KT_UQ_DERIVATIVE) continue;
        const double *d0 = c->b0_dudp + (size_t)k * 3 * n0, *di = dudp + (size_t)k * 3 * n;
        double m = fmax(max_abs(d0, 3 * n0), max_abs(di, 3 * n));
        double *d = c->deriv + ((size_t)step * np + k) * KT_RD_N;
        if (!(m > 0)) { /* this quantity does not move the cornea: no change */
            c->eps[(size_t)step * np + k] = 0;
            continue;
        }
        double eps = KT_BAND_DELTA_MM / m, plus[KT_RD_N], minus[KT_RD_N];
        c->eps[(size_t)step * np + k] = eps;
        rc = fit_moved(c, c->b0_xyz, d0, n0, eps, buf, f, e);
        if (rc == KT_OK) rc = fit_moved(c, c->b0_xyz, d0, n0, -eps, buf, f + 1, e);
        if (rc == KT_OK) rc = fit_moved(c, s->xyz, di, n, eps, buf, f + 2, e);
        if (rc == KT_OK) rc = fit_moved(c, s->xyz, di, n, -eps, buf, f + 3, e);
        if (rc != KT_OK) break;
        kt_band_readings(f, f + 2, mer, tia, plus);
        kt_band_readings(f + 1, f + 3, mer, tia, minus);
        kt_band_derivative(plus, minus, eps, d);
    }
    if (rc != KT_OK) {
        char msg[sizeof e->msg];
        snprintf(msg, sizeof msg, "%s", e->msg);
        e->code = 0;
        rc = kt_fail(e, rc, "%s: the uncertainty band's central difference: %s", c->vtk[step], msg);
    }
    free(buf), free(f);
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

static void put(FILE *f, double v, const char *fmt)
{
    if (isnan(v)) fputs("NaN", f);
    else fprintf(f, fmt, v);
}

void kt_curvrun_band_tsv_head(const run_ctx *c, FILE *f)
{
    if (!c->bands) return;
    fputs("\tsia_x_D\tsia_y_D", f);
    for (int q = 0; q < KT_RD_N; q++) {
        const char *n = kt_band_reading_name(q);
        fprintf(f, "\t%s_sd\t%s_lo90\t%s_hi90", n, n, n);
    }
}

void kt_curvrun_band_tsv_row(const run_ctx *c, int i, FILE *f)
{
    if (!c->bands) return;
    const double *val = c->val + (size_t)i * KT_RD_N, *sd = c->sd + (size_t)i * KT_RD_N;
    fputc('\t', f), put(f, val[KT_RD_SIA_X], "%.4f");
    fputc('\t', f), put(f, val[KT_RD_SIA_Y], "%.4f");
    for (int q = 0; q < KT_RD_N; q++) {
        double lo, hi;
        kt_band_interval(q, val[q], sd[q], &lo, &hi);
        fputc('\t', f), put(f, sd[q], "%.6f");
        fputc('\t', f), put(f, lo, "%.4f");
        fputc('\t', f), put(f, hi, "%.4f");
    }
}

/* derivatives.tsv: every step's dR/dp of every quantity (curvature(1), UNCERTAINTY). */
int kt_curvrun_band_write(run_ctx *c, kt_err *e)
{
    if (!c->bands) return KT_OK;
    char path[PATHMAX];
    kt_out out;
    if (kt_curvrun_tmp_path(c, path, "derivatives.tsv", e) || kt_curvrun_add_file(c, "derivatives.tsv", e) ||
        kt_out_open(&out, path, e))
        return e->code;
    FILE *f = out.f;
    fputs("step\tparam\tunit\tmethod\tsd\tused\teps", f);
    for (int q = 0; q < KT_RD_N; q++) fprintf(f, "\t%s", kt_band_reading_name(q));
    fputc('\n', f);
    int np = c->uq.n;
    for (int i = 0; i < c->nstep; i++)
        for (int k = 0; k < np; k++) {
            const kt_uq_param *p = c->uq.p + k;
            fprintf(f, "%d\t%s\t%s\t%s\t%.6g\t%d\t", c->num[i], p->name, p->unit, method_name(p->method), p->sd,
                    c->used[k]);
            put(f, c->eps[(size_t)i * np + k], "%.6g");
            for (int q = 0; q < KT_RD_N; q++) {
                fputc('\t', f);
                put(f, c->used[k] ? c->deriv[((size_t)i * np + k) * KT_RD_N + q] : NAN, "%.8g");
            }
            fputc('\n', f);
        }
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
    fputs(", sd ", f), put(f, c->sd[(size_t)i * KT_RD_N + KT_RD_SIA], "%.2f D");
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

static void jnum(FILE *f, const char *key, double v, int last)
{
    fprintf(f, "\"%s\": ", key);
    if (isfinite(v)) fprintf(f, "%.6g", v);
    else fputs("null", f);
    fputs(last ? "" : ", ", f);
}

static void jtext(FILE *f, const char *v)
{
    fputc('"', f);
    for (; *v; v++) {
        if (*v == '"' || *v == '\\') fprintf(f, "\\%c", *v);
        else if ((unsigned char)*v < 0x20) fprintf(f, "\\u%04x", *v);
        else fputc(*v, f);
    }
    fputc('"', f);
}

void kt_curvrun_band_json_top(const run_ctx *c, FILE *f)
{
    if (!c->bands) return;
    fputs("\"uncertainty\": {\"z90\": ", f);
    fprintf(f, "%.6g, \"delta_mm\": %.6g, \"params\": [", KT_BAND_Z90, KT_BAND_DELTA_MM);
    for (int k = 0; k < c->uq.n; k++) {
        const kt_uq_param *p = c->uq.p + k;
        fputs(k ? ", {\"param\": " : "{\"param\": ", f), jtext(f, p->name);
        fputs(", \"unit\": ", f), jtext(f, p->unit);
        fputs(", ", f), jnum(f, "value", p->value, 0), jnum(f, "sd", p->sd, 0);
        fputs("\"method\": ", f), jtext(f, method_name(p->method));
        fputs(", \"source\": ", f), jtext(f, p->source);
        fprintf(f, ", \"used\": %s, ", c->used[k] ? "true" : "false");
        jnum(f, "sia_sd_contrib_D", c->used[k] ? fabs(c->deriv[((size_t)(c->nstep - 1) * c->uq.n + k) * KT_RD_N + KT_RD_SIA] * p->sd) : NAN, 1);
        fputs("}", f);
    }
    fputs("]}, ", f);
}

void kt_curvrun_band_json_step(const run_ctx *c, int i, FILE *f)
{
    if (!c->bands) return;
    const double *val = c->val + (size_t)i * KT_RD_N, *sd = c->sd + (size_t)i * KT_RD_N;
    fputs(", ", f);
    jnum(f, "sia_x_D", val[KT_RD_SIA_X], 0);
    jnum(f, "sia_y_D", val[KT_RD_SIA_Y], 0);
    for (int q = 0; q < KT_RD_N; q++) {
        char k[96];
        double lo, hi;
        kt_band_interval(q, val[q], sd[q], &lo, &hi);
        snprintf(k, sizeof k, "%s_sd", kt_band_reading_name(q)), jnum(f, k, sd[q], 0);
        snprintf(k, sizeof k, "%s_lo90", kt_band_reading_name(q)), jnum(f, k, lo, 0);
        snprintf(k, sizeof k, "%s_hi90", kt_band_reading_name(q)), jnum(f, k, hi, q == KT_RD_N - 1);
    }
}
