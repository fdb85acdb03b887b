/* uqread.c: uncertainty.tsv and the --sens file (uqread.h). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "uqread.h"

#define MAXF 16
#define LINE_MAX_BYTES 8192

/* Split a line (its '\n' and a '\r' before it dropped) at tabs: at most MAXF fields. */
static int split(char *s, char **f)
{
    size_t len = strlen(s);
    while (len > 0 && (s[len - 1] == '\n' || s[len - 1] == '\r')) s[--len] = '\0';
    int n = 0;
    for (char *p = s;; p++) {
        if (n == MAXF) return MAXF + 1;
        f[n++] = p;
        p = strchr(p, '\t');
        if (!p) break;
        *p = '\0';
    }
    return n;
}

static int ident(const char *s)
{
    if (!*s || strlen(s) >= KT_UQ_NAME) return 0;
    for (; *s; s++)
        if (!((*s >= 'a' && *s <= 'z') || (*s >= 'A' && *s <= 'Z') || (*s >= '0' && *s <= '9') || *s == '_')) return 0;
    return 1;
}

/* Read the lines of path, calling row() for each after the header; cols names the header's
 * columns (the first ncol required in order, then optional ones). */
typedef int (*row_fn)(void *ctx, const char *path, int line, char **f, int nf, const int *col, kt_err *e);

static int read_table(const char *path, const char *const *cols, int nreq, int nopt, int *col, row_fn row, void *ctx,
                      kt_err *e)
{
    FILE *fp = fopen(path, "r");
    if (!fp) return kt_fail(e, KT_EINPUT, "%s: cannot open", path);
    char *buf = NULL, *f[MAXF + 1];
    size_t cap = 0;
    int line = 0, rc = KT_OK, nhead = 0, rows = 0;
    for (;;) {
        long got = kt_line_read(fp, &buf, &cap, LINE_MAX_BYTES, e);
        if (got == -1) break;
        line++;
        if (got == -4) { rc = e->code; break; }
        if (got < 0) {
            rc = kt_fail(e, KT_EINPUT, "%s:%d: expected a text line (%s)", path, line,
                         got == -2 ? "found a NUL byte" : "line too long");
            break;
        }
        int nf = split(buf, f);
        if (nf > MAXF) {
            rc = kt_fail(e, KT_EINPUT, "%s:%d: expected at most %d tab-separated fields", path, line, MAXF);
            break;
        }
        if (line == 1) {
            nhead = nf;
            for (int k = 0; k < nreq + nopt; k++) col[k] = -1;
            for (int i = 0; i < nf; i++)
                for (int k = 0; k < nreq + nopt; k++)
                    if (strcmp(f[i], cols[k]) == 0) {
                        if (col[k] >= 0) {
                            rc = kt_fail(e, KT_EINPUT, "%s:1: column '%s' given twice", path, cols[k]);
                            goto out;
                        }
                        col[k] = i;
                    }
            for (int k = 0; k < nreq; k++)
                if (col[k] != k) {
                    char want[256] = "";
                    for (int j = 0; j < nreq; j++) strcat(strcat(want, j ? "\\t" : ""), cols[j]);
                    rc = kt_fail(e, KT_EINPUT, "%s:1: expected the header %s%s", path, want,
                                 nopt ? " (and optional columns)" : "");
                    goto out;
                }
            continue;
        }
        if (nf == 1 && f[0][0] == '\0') continue; /* an empty line */
        if (nf != nhead) {
            rc = kt_fail(e, KT_EINPUT, "%s:%d: expected %d tab-separated fields as the header, found %d", path, line,
                         nhead, nf);
            break;
        }
        if ((rc = row(ctx, path, line, f, nf, col, e)) != KT_OK) break;
        rows++;
    }
    if (rc == KT_OK && line == 0) rc = kt_fail(e, KT_EINPUT, "%s:1: expected a header line, found an empty file", path);
out:
    if (rc == KT_OK && ferror(fp)) rc = kt_fail(e, KT_EINPUT, "%s: read error", path);
    free(buf);
    fclose(fp);
    (void)rows;
    return rc;
}

/* ---------------------------------------------------------------- uncertainty.tsv */

static int table_row(void *ctx, const char *path, int line, char **f, int nf, const int *col, kt_err *e)
{
    (void)nf, (void)col;
    kt_uq_table *t = ctx;
    if (!ident(f[0]))
        return kt_fail(e, KT_EINPUT, "%s:%d:1: expected a param name of letters, digits and _ (at most %d), found '%s'",
                       path, line, KT_UQ_NAME - 1, f[0]);
    if (kt_uq_table_find(t, f[0]) >= 0) return kt_fail(e, KT_EINPUT, "%s:%d:1: param %s given twice", path, line, f[0]);
    if (strlen(f[1]) >= KT_UQ_NAME) return kt_fail(e, KT_EINPUT, "%s:%d:2: expected a unit (at most %d characters)", path, line, KT_UQ_NAME - 1);
    kt_uq_param p;
    memset(&p, 0, sizeof p);
    strcpy(p.name, f[0]);
    strcpy(p.unit, f[1]);
    if (kt_parse_double(f[2], &p.value) || !isfinite(p.value))
        return kt_fail(e, KT_EINPUT, "%s:%d:3: expected the value as a finite number, found '%s'", path, line, f[2]);
    if (kt_parse_double(f[3], &p.sd) || !isfinite(p.sd) || p.sd < 0)
        return kt_fail(e, KT_EINPUT, "%s:%d:4: expected the sd as a finite number >= 0, found '%s'", path, line, f[3]);
    if (strcmp(f[4], "derivative") == 0) p.method = KT_UQ_DERIVATIVE;
    else if (strcmp(f[4], "fd") == 0) p.method = KT_UQ_FD;
    else if (strcmp(f[4], "none") == 0) p.method = KT_UQ_NONE;
    else return kt_fail(e, KT_EINPUT, "%s:%d:5: expected the method derivative, fd or none, found '%s'", path, line, f[4]);
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

static int sens_row(void *ctx, const char *path, int line, char **f, int nf, const int *col, kt_err *e)
{
    (void)nf;
    kt_uq_sens *s = ctx;
    kt_uq_sens_row r;
    memset(&r, 0, sizeof r);
    r.line = line;
    if (!ident(f[0]))
        return kt_fail(e, KT_EINPUT, "%s:%d:1: expected a param name of letters, digits and _, found '%s'", path, line, f[0]);
    if (!ident(f[1]))
        return kt_fail(e, KT_EINPUT, "%s:%d:2: expected a reading (a curvature.tsv column), found '%s'", path, line, f[1]);
    strcpy(r.param, f[0]);
    strcpy(r.reading, f[1]);
    if (kt_parse_double(f[2], &r.dr_dp) || !isfinite(r.dr_dp))
        return kt_fail(e, KT_EINPUT, "%s:%d:3: expected dR_dp as a finite number, found '%s'", path, line, f[2]);
    r.step = -1;
    if (col[3] >= 0 && (kt_parse_int(f[col[3]], &r.step) || r.step < 0))
        return kt_fail(e, KT_EINPUT, "%s:%d:%d: expected a step number >= 0, found '%s'", path, line, col[3] + 1,
                       f[col[3]]);
    for (int i = 0; i < s->n; i++)
        if (strcmp(s->r[i].param, r.param) == 0 && strcmp(s->r[i].reading, r.reading) == 0 && s->r[i].step == r.step)
            return kt_fail(e, KT_EINPUT, "%s:%d:1: %s / %s%s given twice (first on line %d)", path, line, r.param,
                           r.reading, r.step >= 0 ? " at this step" : "", s->r[i].line);
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
