/* tsv.c: tab-separated tables with a header, read whole and split in place (tsv.h). */
#include "tsv.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

/* The next non-empty line from c.p: its fields into *fv (grown, *cap entries), *nf of them; the
 * line's start in *bol, its number counted in t->line. 1, 0 at the end, -1 on a NUL byte. */
static int split_line(kt_tsv *t, char ***fv, int *cap, int *nf, const char **bol)
{
    kt_cursor *c = &t->c;
    char *b = (char *)c->b; /* owned by the cursor, and by this reader alone */
    for (;;) {
        if (c->p >= c->n) return 0;
        char *s = b + c->p, *nl = memchr(s, '\n', c->n - c->p);
        size_t len = nl ? (size_t)(nl - s) : c->n - c->p;
        t->line++;
        c->p += len + (nl != NULL);
        const char *nul = memchr(s, '\0', len);
        if (nul) {
            kt_fail(c->e, KT_EINPUT, "%s:%d:%d: expected a line of text, found a NUL byte", c->path, t->line,
                    (int)(nul - s) + 1);
            return -1;
        }
        if (len > 0 && s[len - 1] == '\r') len--;
        s[len] = '\0';
        if (len == 0) continue; /* an empty line */
        *bol = s;
        int n = 0;
        for (char *p = s;; p++) {
            if (n == *cap) {
                int nc = *cap ? 2 * *cap : 32;
                char **g = kt_realloc(*fv, (size_t)nc, sizeof(char *), c->e);
                if (!g) return -1;
                *fv = g, *cap = nc;
            }
            (*fv)[n++] = p;
            p = strchr(p, '\t');
            if (!p) break;
            *p = '\0';
        }
        *nf = n;
        return 1;
    }
}

int kt_tsv_open(kt_tsv *t, const char *path, kt_err *e)
{
    memset(t, 0, sizeof *t);
    if (kt_cursor_open(&t->c, path, "", KT_TSV_MAX_BYTES, e)) return e->code;
    int hcap = 0, r = split_line(t, &t->head, &hcap, &t->nhead, &t->bol);
    if (r == 0) {
        t->line = 1;
        kt_fail(e, KT_EINPUT, "%s:1:1: expected a header line, found an empty file", t->c.path);
    }
    if (r <= 0) {
        kt_tsv_close(t);
        return e->code;
    }
    return KT_OK;
}

void kt_tsv_close(kt_tsv *t)
{
    kt_cursor_close(&t->c);
    free(t->head);
    free(t->f);
    t->head = t->f = NULL;
    t->nhead = t->nf = t->fcap = 0;
}

int kt_tsv_find(const kt_tsv *t, const char *name)
{
    for (int i = 0; i < t->nhead; i++)
        if (strcmp(t->head[i], name) == 0) return i;
    return -1;
}

int kt_tsv_need(kt_tsv *t, const char *name, const char *what)
{
    int k = kt_tsv_find(t, name);
    if (k < 0) {
        kt_fail(t->c.e, KT_EINPUT, "%s:1:1: expected a column %s%s%s%s", t->c.path, name, what ? " (" : "",
                what ? what : "", what ? ")" : "");
        return -1;
    }
    for (int i = k + 1; i < t->nhead; i++)
        if (strcmp(t->head[i], name) == 0) {
            kt_fail(t->c.e, KT_EINPUT, "%s:1:%d: column %s given twice", t->c.path,
                    (int)(t->head[i] - t->head[0]) + 1, name);
            return -1;
        }
    return k;
}

int kt_tsv_next(kt_tsv *t)
{
    t->nf = 0;
    return split_line(t, &t->f, &t->fcap, &t->nf, &t->bol);
}

int kt_tsv_fail(kt_tsv *t, int col, const char *fmt, ...)
{
    char msg[768];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    size_t at = 0; /* the field's start; past the line's end for a field it lacks */
    if (col >= 0 && col < t->nf) at = (size_t)(t->f[col] - t->bol);
    else if (col >= 0 && t->nf > 0) at = (size_t)(t->f[t->nf - 1] - t->bol) + strlen(t->f[t->nf - 1]);
    return kt_fail(t->c.e, KT_EINPUT, "%s:%d:%zu: %s", t->c.path, t->line, at + 1, msg);
}

static const char *col_name(const kt_tsv *t, int col)
{
    return col >= 0 && col < t->nhead ? t->head[col] : "?";
}

const char *kt_tsv_text(kt_tsv *t, int col)
{
    if (col >= 0 && col < t->nf) return t->f[col];
    kt_tsv_fail(t, col, "expected a field in column %s, found the end of the line", col_name(t, col));
    return NULL;
}

/* "found 'x'" of a field, at most 40 bytes of it. */
static int found_fail(kt_tsv *t, int col, const char *what, const char *s)
{
    size_t len = strlen(s);
    if (!len) return kt_tsv_fail(t, col, "expected %s in column %s, found an empty field", what, col_name(t, col));
    return kt_tsv_fail(t, col, "expected %s in column %s, found '%.*s%s'", what, col_name(t, col),
                       (int)(len > 40 ? 40 : len), s, len > 40 ? "..." : "");
}

int kt_tsv_num(kt_tsv *t, int col, int flags, double *v)
{
    const char *s = kt_tsv_text(t, col);
    if (!s) return KT_EINPUT;
    char *end;
    errno = 0;
    double x = strtod(s, &end);
    /* out of range: an overflow (an underflow is the nearest subnormal, as written) */
    int ok = *s && *s != ' ' && *s != '\t' && *s != '\v' && *s != '\f' && *end == '\0' &&
             !(errno == ERANGE && isinf(x));
    if (ok && isnan(x)) ok = flags & KT_TSV_NAN;
    if (ok && isinf(x)) ok = flags & KT_TSV_INF;
    if (!ok) return found_fail(t, col, "a number", s);
    *v = x;
    return KT_OK;
}

int kt_tsv_int(kt_tsv *t, int col, long long lo, long long hi, long long *v)
{
    const char *s = kt_tsv_text(t, col);
    if (!s) return KT_EINPUT;
    char *end;
    errno = 0;
    long long x = strtoll(s, &end, 10);
    if (!((*s >= '0' && *s <= '9') || *s == '-' || *s == '+') || *end || errno == ERANGE || x < lo || x > hi) {
        char what[80];
        snprintf(what, sizeof what, "an integer from %lld to %lld", lo, hi);
        return found_fail(t, col, what, s);
    }
    *v = x;
    return KT_OK;
}

/* ---------------------------------------------------------------- the writer */

void kt_tsvw_begin(kt_tsvw *w, FILE *f)
{
    memset(w, 0, sizeof *w);
    w->f = f;
    w->ncol = -1;
}

static void sep(kt_tsvw *w)
{
    if (w->col++ > 0) fputc('\t', w->f);
}

static void misuse(kt_tsvw *w, const char *why)
{
    if (!w->bad) snprintf(w->why, sizeof w->why, "%s", why);
    w->bad = 1;
}

void kt_tsvw_text(kt_tsvw *w, const char *s)
{
    sep(w);
    if (strpbrk(s, "\t\n\r")) misuse(w, "a field with a tab or a line end");
    fputs(s, w->f);
}

void kt_tsvw_num(kt_tsvw *w, double v, const char *fmt)
{
    sep(w);
    if (isnan(v)) fputs("NaN", w->f);
    else if (isinf(v)) fputs(v > 0 ? "inf" : "-inf", w->f);
    else fprintf(w->f, fmt, v);
}

void kt_tsvw_int(kt_tsvw *w, long long v)
{
    sep(w);
    fprintf(w->f, "%lld", v);
}

void kt_tsvw_end(kt_tsvw *w)
{
    fputc('\n', w->f);
    if (w->ncol < 0) w->ncol = w->col;
    else if (w->col != w->ncol) misuse(w, "a row without the header's count of fields");
    w->col = 0;
}

int kt_tsvw_finish(kt_tsvw *w, const char *what, kt_err *e)
{
    if (w->col != 0) misuse(w, "a line not ended");
    if (w->bad) return kt_fail(e, KT_ERUN, "%s: the table writer was misused: %s", what, w->why);
    if (ferror(w->f)) return kt_fail(e, KT_ERUN, "%s: write failed", what);
    return KT_OK;
}
