/* uqread.c: uncertainty.tsv and the --sens file (uqread.h). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tsv.h"
#include "uqread.h"

static int ident(const char *s)
{
    if (!*s || strlen(s) >= KT_UQ_NAME) return 0;
    for (; *s; s++)
        if (!((*s >= 'a' && *s <= 'z') || (*s >= 'A' && *s <= 'Z') || (*s >= '0' && *s <= '9') || *s == '_')) return 0;
    return 1;
}

/* Read the rows of path, calling row() for each after the header; cols names the header's
 * columns (the first nreq required, in this order at its start, then optional ones: col[k] their
 * index, -1 when absent). Every row has as many fields as the header. */
typedef int (*row_fn)(void *ctx, kt_tsv *t, const int *col, kt_err *e);

static int read_table(const char *path, const char *const *cols, int nreq, int nopt, int *col, row_fn row, void *ctx,
                      kt_err *e)
{
    kt_tsv t;
    if (kt_tsv_open(&t, path, e)) return e->code;
    for (int k = 0; k < nreq + nopt && !e->code; k++)
        if ((col[k] = kt_tsv_find(&t, cols[k])) >= 0) col[k] = kt_tsv_need(&t, cols[k], NULL); /* not twice */
    for (int k = 0; k < nreq && !e->code; k++)
        if (col[k] != k) {
            char want[256] = "";
            for (int j = 0; j < nreq; j++) strcat(strcat(want, j ? "\\t" : ""), cols[j]);
            kt_fail(e, KT_EINPUT, "%s:1:1: expected the header %s%s", t.c.path, want, nopt ? " (and optional columns)" : "");
        }
    while (!e->code && kt_tsv_next(&t) > 0) {
        if (t.nf != t.nhead)
            kt_tsv_fail(&t, t.nf < t.nhead ? t.nf : t.nhead, "expected %d tab-separated fields as the header, found %d",
                        t.nhead, t.nf);
        else row(ctx, &t, col, e);
    }
    kt_tsv_close(&t);
    return e->code;
}

/* ---------------------------------------------------------------- uncertainty.tsv */

static int table_row(void *ctx, kt_tsv *in, const int *col, kt_err *e)
{
    (void)col;
    kt_uq_table *t = ctx;
    char **f = in->f;
    if (!ident(f[0]))
        return kt_tsv_fail(in, 0, "expected a param name of letters, digits and _ (at most %d), found '%s'",
                           KT_UQ_NAME - 1, f[0]);
    if (kt_uq_table_find(t, f[0]) >= 0) return kt_tsv_fail(in, 0, "param %s given twice", f[0]);
    if (strlen(f[1]) >= KT_UQ_NAME) return kt_tsv_fail(in, 1, "expected a unit (at most %d characters)", KT_UQ_NAME - 1);
    kt_uq_param p;
    memset(&p, 0, sizeof p);
    strcpy(p.name, f[0]);
    strcpy(p.unit, f[1]);
    if (kt_parse_double(f[2], &p.value) || !isfinite(p.value))
        return kt_tsv_fail(in, 2, "expected the value as a finite number, found '%s'", f[2]);
    if (kt_parse_double(f[3], &p.sd) || !isfinite(p.sd) || p.sd < 0)
        return kt_tsv_fail(in, 3, "expected the sd as a finite number >= 0, found '%s'", f[3]);
    if (strcmp(f[4], "derivative") == 0) p.method = KT_UQ_DERIVATIVE;
    else if (strcmp(f[4], "fd") == 0) p.method = KT_UQ_FD;
    else if (strcmp(f[4], "none") == 0) p.method = KT_UQ_NONE;
    else return kt_tsv_fail(in, 4, "expected the method derivative, fd or none, found '%s'", f[4]);
    snprintf(p.source, sizeof p.source, "%s", f[5]);
    kt_uq_param *q = kt_realloc(t->p, (size_t)t->n + 1, sizeof *q, e);
    if (!q) return e->code;
    t->p = q;
    t->p[t->n++] = p;
    return KT_OK;
}

int kt_uq_table_read(const char *path, kt_uq_table *t, kt_err *e)
{
    static const char *const cols[] = {"param", "unit", "value", "sd", "method", "source"};
    int col[6];
    memset(t, 0, sizeof *t);
    int rc = read_table(path, cols, 6, 0, col, table_row, t, e);
    if (rc != KT_OK) kt_uq_table_free(t);
    return rc;
}

void kt_uq_table_free(kt_uq_table *t)
{
    free(t->p);
    memset(t, 0, sizeof *t);
}

int kt_uq_table_find(const kt_uq_table *t, const char *name)
{
    for (int i = 0; i < t->n; i++)
        if (strcmp(t->p[i].name, name) == 0) return i;
    return -1;
}

/* ---------------------------------------------------------------- --sens */

static int sens_row(void *ctx, kt_tsv *in, const int *col, kt_err *e)
{
    kt_uq_sens *s = ctx;
    kt_uq_sens_row r;
    char **f = in->f;
    memset(&r, 0, sizeof r);
    r.line = in->line;
    if (!ident(f[0])) return kt_tsv_fail(in, 0, "expected a param name of letters, digits and _, found '%s'", f[0]);
    if (!ident(f[1])) return kt_tsv_fail(in, 1, "expected a reading (a curvature.tsv column), found '%s'", f[1]);
    strcpy(r.param, f[0]);
    strcpy(r.reading, f[1]);
    if (kt_parse_double(f[2], &r.dr_dp) || !isfinite(r.dr_dp))
        return kt_tsv_fail(in, 2, "expected dR_dp as a finite number, found '%s'", f[2]);
    r.step = -1;
    if (col[3] >= 0 && (kt_parse_int(f[col[3]], &r.step) || r.step < 0))
        return kt_tsv_fail(in, col[3], "expected a step number >= 0, found '%s'", f[col[3]]);
    for (int i = 0; i < s->n; i++)
        if (strcmp(s->r[i].param, r.param) == 0 && strcmp(s->r[i].reading, r.reading) == 0 && s->r[i].step == r.step)
            return kt_tsv_fail(in, 0, "%s / %s%s given twice (first on line %d)", r.param, r.reading,
                               r.step >= 0 ? " at this step" : "", s->r[i].line);
    kt_uq_sens_row *q = kt_realloc(s->r, (size_t)s->n + 1, sizeof *q, e);
    if (!q) return e->code;
    s->r = q;
    s->r[s->n++] = r;
    return KT_OK;
}

int kt_uq_sens_read(const char *path, kt_uq_sens *s, kt_err *e)
{
    static const char *const cols[] = {"param", "reading", "dR_dp", "step"};
    int col[4];
    memset(s, 0, sizeof *s);
    int rc = read_table(path, cols, 3, 1, col, sens_row, s, e);
    if (rc != KT_OK) kt_uq_sens_free(s);
    return rc;
}

void kt_uq_sens_free(kt_uq_sens *s)
{
    free(s->r);
    memset(s, 0, sizeof *s);
}
