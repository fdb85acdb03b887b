/* benchtab.c: step tables of benchmark runs -> the Markdown table of the planned method's
 * benchmark (conventions in benchtab.h). */
#include "benchtab.h"
#include "tsv.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void kt_bench_run_free(kt_bench_run *r)
{
    free(r->step);
    free(r->t);
    free(r->nnz_L);
    free(r->t_verify);
    free(r->ok);
    memset(r, 0, sizeof *r);
}

/* A TSV field as a number: "NaN" (or empty) is NaN; 0 on success. */
static int field_num(const char *s, double *v)
{
    if (!*s || strcmp(s, "NaN") == 0 || strcmp(s, "nan") == 0) {
        *v = NAN;
        return 0;
    }
    return kt_parse_double(s, v);
}

/* Split line (modified) at tabs into at most max fields; returns the count. */
static int split_tabs(char *line, char **f, int max)
{
    int n = 0;
    line[strcspn(line, "\r\n")] = 0;
    for (char *p = line; n < max;) {
        f[n++] = p;
        char *t = strchr(p, '\t');
        if (!t) break;
        *t = 0;
        p = t + 1;
    }
    return n;
}

enum { COL_STEP, COL_T, COL_NNZ, COL_VERIFY, COL_STATUS, NCOL };
static const char *const COL_NAME[NCOL] = {"step", "t_total_ms", "nnz_L", "t_verify_ms", "status"};

static int grow(kt_bench_run *r, int cap, kt_err *e)
{
    size_t c = (size_t)cap;
    int *step = kt_realloc(r->step, c, sizeof(int), e);
    if (step) r->step = step;
    double *t = kt_realloc(r->t, c, sizeof(double), e);
    if (t) r->t = t;
    double *z = kt_realloc(r->nnz_L, c, sizeof(double), e);
    if (z) r->nnz_L = z;
    double *v = kt_realloc(r->t_verify, c, sizeof(double), e);
    if (v) r->t_verify = v;
    unsigned char *ok = kt_realloc(r->ok, c, 1, e);
    if (ok) r->ok = ok;
    return e->code;
}

/* The current row of t into r->...[r->n]: a number, "NaN" or an empty field (NaN) in each
 * column of col, the step an integer. */
static int row(kt_bench_run *r, kt_tsv *t, const int *col, kt_err *e)
{
    double v[NCOL];
    long long step;
    if (kt_tsv_int(t, col[COL_STEP], 0, 1000000000, &step)) return e->code;
    for (int k = COL_T; k < COL_STATUS; k++) {
        const char *s = col[k] < 0 ? "" : kt_tsv_text(t, col[k]);
        v[k] = NAN;
        if (!s || (*s && kt_tsv_num(t, col[k], KT_TSV_NAN | KT_TSV_INF, &v[k]))) return e->code;
    }
    int i = r->n++;
    r->step[i] = (int)step;
    r->t[i] = v[COL_T];
    r->nnz_L[i] = v[COL_NNZ];
    r->t_verify[i] = v[COL_VERIFY];
    r->ok[i] = !(col[COL_STATUS] >= 0 && col[COL_STATUS] < t->nf && strcmp(t->f[col[COL_STATUS]], "ok"));
    if (isnan(r->t[i])) r->ok[i] = 0;
    return KT_OK;
}

int kt_bench_run_read(kt_bench_run *r, const char *label, const char *path, kt_err *e)
{
    memset(r, 0, sizeof *r);
    snprintf(r->label, sizeof r->label, "%s", label);
    r->peak_mb = NAN;
    kt_tsv t;
    if (kt_tsv_open(&t, path, e)) return e->code;
    int col[NCOL], cap = 0;
    for (int k = 0; k < NCOL && !e->code; k++)
        col[k] = k <= COL_T ? kt_tsv_need(&t, COL_NAME[k], "a step table") : kt_tsv_find(&t, COL_NAME[k]);
    while (!e->code && kt_tsv_next(&t) > 0) {
        if (r->n == cap && grow(r, cap = cap ? 2 * cap : 64, e)) break;
        row(r, &t, col, e);
    }
    kt_tsv_close(&t);
    return e->code;
}

int kt_bench_run_peak(kt_bench_run *r, const char *path, kt_err *e)
{
    FILE *in = fopen(path, "r");
    if (!in) return kt_fail(e, KT_EINPUT, "%s: cannot open the time record", path);
    char buf[1024], *f[4];
    double kb = NAN;
    while (fgets(buf, sizeof buf, in)) {
        const char *m = strstr(buf, "Maximum resident set size (kbytes):");
        if (m) {
            kb = strtod(m + strlen("Maximum resident set size (kbytes):"), NULL);
            break;
        }
        if (split_tabs(buf, f, 4) == 3 && !field_num(f[2], &kb)) break;
        kb = NAN;
    }
    fclose(in);
    if (!(kb > 0)) return kt_fail(e, KT_EINPUT, "%s: expected a peak resident set size", path);
    r->peak_mb = kb / 1024;
    return KT_OK;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

double kt_bench_median(double *x, int n)
{
    int m = 0;
    for (int i = 0; i < n; i++)
        if (!isnan(x[i])) x[m++] = x[i];
    if (!m) return NAN;
    qsort(x, (size_t)m, sizeof *x, cmp_double);
    return m % 2 ? x[m / 2] : 0.5 * (x[m / 2 - 1] + x[m / 2]);
}

static double min_of(const double *x, int n)
{
    double v = NAN;
    for (int i = 0; i < n; i++)
        if (!isnan(x[i]) && !(v <= x[i])) v = x[i];
    return v;
}

/* Row of base holding step k and completed, or -1. */
static int find_step(const kt_bench_run *base, int k)
{
    for (int i = 0; i < base->n; i++)
        if (base->step[i] == k) return base->ok[i] ? i : -1;
    return -1;
}

int kt_bench_summarize(const kt_bench_run *r, const kt_bench_run *base, double bw,
                       kt_bench_sum *s, kt_err *e)
{
    memset(s, 0, sizeof *s);
    int n = r->n ? r->n : 1, common = 0;
    double *t = kt_calloc((size_t)n, sizeof(double), e), *q = kt_calloc((size_t)n, sizeof(double), e);
    double *v = kt_calloc((size_t)n, sizeof(double), e), *w = kt_calloc((size_t)n, sizeof(double), e);
    if (!e->code) {
        for (int i = 0; i < r->n; i++) {
            s->whole += isnan(r->t[i]) ? 0 : r->t[i];
            t[i] = q[i] = v[i] = w[i] = NAN;
            if (r->step[i] < 1) continue;
            s->steps++;
            if (!r->ok[i]) {
                s->failed++;
                continue;
            }
            t[i] = r->t[i];
            int j = find_step(base, r->step[i]);
            if (j >= 0 && base->t[j] > 0) {
                q[i] = r->t[i] / base->t[j];
                common++;
            }
            if (r->t_verify[i] > 0 && r->t[i] > 0) v[i] = r->t_verify[i] / r->t[i];
            if (r->nnz_L[i] > 0 && bw > 0) w[i] = r->t[i] / (1e3 * 8 * r->nnz_L[i] / bw);
        }
        double worst = NAN;
        for (int i = 0; i < r->n; i++)
            if (!isnan(t[i]) && !(worst >= t[i])) worst = t[i];
        s->worst = worst;
        s->ratio_min = min_of(q, r->n);
        s->verify_min = min_of(v, r->n);
        s->med = kt_bench_median(t, r->n);
        s->ratio_med = kt_bench_median(q, r->n);
        s->verify_med = kt_bench_median(v, r->n);
        s->bw_med = kt_bench_median(w, r->n);
    }
    free(t);
    free(q);
    free(v);
    free(w);
    return e->code ? -1 : common;
}

/* A number with a unit, or "-" when NaN. */
static void cell(FILE *f, double x, const char *fmt)
{
    fputs(" | ", f);
    if (isnan(x)) fputc('-', f);
    else fprintf(f, fmt, x);
}

int kt_bench_table(FILE *f, const char *title, const kt_bench_run *runs, int n, double bw,
                   kt_err *e)
{
    if (n < 1) return kt_fail(e, KT_EINPUT, "benchmark table: expected at least one run");
    kt_bench_sum ref;
    if (kt_bench_summarize(&runs[n > 1], &runs[0], bw, &ref, e) < 0) return e->code;
    fprintf(f, "%s\n\n", title);
    fputs("| method | steps (failed) | step median ms | step worst ms | this / first, median "
          "(min) | whole plan ms | whole plan / one refactor | peak MB | peak / reference | "
          "step / (8 B nnz_L / bandwidth) |\n", f);
    fputs("|---|---|---|---|---|---|---|---|---|---|\n", f);
    for (int k = 0; k < n; k++) {
        kt_bench_sum s;
        if (kt_bench_summarize(&runs[k], &runs[0], bw, &s, e) < 0) return e->code;
        fprintf(f, "| %s | %d (%d)", runs[k].label, s.steps, s.failed);
        cell(f, s.med, "%.1f");
        cell(f, s.worst, "%.1f");
        fputs(" | ", f);
        if (isnan(s.ratio_med)) fputc('-', f);
        else fprintf(f, "%.3g (%.3g)", s.ratio_med, s.ratio_min);
        cell(f, s.whole, "%.0f");
        cell(f, s.whole / ref.med, "%.3g");
        cell(f, runs[k].peak_mb, "%.0f");
        cell(f, runs[k].peak_mb / runs[n > 1].peak_mb, "%.3g");
        cell(f, s.bw_med, "%.3g");
        fputs(" |\n", f);
    }
    for (int k = 0; k < n; k++) { /* same-process ratios from --verify */
        kt_bench_sum s;
        if (kt_bench_summarize(&runs[k], &runs[0], bw, &s, e) < 0) return e->code;
        if (!isnan(s.verify_med))
            fprintf(f, "\n%s: a fresh METIS factorization (--verify, same process) / its step: "
                    "median %.3g, min %.3g\n", runs[k].label, s.verify_med, s.verify_min);
    }
    return ferror(f) ? kt_fail(e, KT_ERUN, "benchmark table: write failed") : KT_OK;
}
