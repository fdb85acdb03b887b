/* pentacam.c: read a Pentacam CSV map (layout in pentacam.h and keratome-patient(5)). */
#include "pentacam.h"

#include <ctype.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

#include "cursor.h"

#define MAXF (KT_PENTACAM_N + 3) /* fields read per line: label, 141 values, a trailing separator */

typedef struct reader {
    const char *path;
    const char *b;              /* the file, NUL-terminated */
    size_t n, line_at;          /* size, start of the current line */
    int line;                   /* 1-based number of the current line */
    char sep;
    kt_err *e;
    double lo, hi;              /* the values' range, in the file's units */
    const char *whose;          /* whose range it is ("" for the reader's own) */
} reader;

double kt_pentacam_coord(int i) { return -KT_PENTACAM_HALF + KT_PENTACAM_STEP * i; }

static int fail_at(reader *r, size_t at, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
static int fail_at(reader *r, size_t at, const char *fmt, ...)
{
    char msg[600];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    return kt_fail(r->e, KT_EINPUT, "%s:%d:%d: %s", r->path, r->line, (int)(at - r->line_at) + 1, msg);
}

/* The fields of the line at r->line_at: starts[k], lens[k]; *end the next line's start. */
static int split(reader *r, size_t *start, int *len, int max, size_t *end)
{
    size_t p = r->line_at, q = p;
    while (q < r->n && r->b[q] != '\n') q++;
    *end = q < r->n ? q + 1 : q;
    size_t stop = q > p && r->b[q - 1] == '\r' ? q - 1 : q;
    if (!r->sep) r->sep = memchr(r->b + p, ';', stop - p) ? ';' : ',';
    int k = 0;
    size_t f = p;
    for (size_t i = p; i <= stop; i++) {
        if (i < stop && r->b[i] != r->sep) continue;
        if (k < max) start[k] = f, len[k] = (int)(i - f);
        k++;
        f = i + 1;
    }
    return k;
}

/* Field text as a number; 1 when empty (no data), 0 parsed, -1 not a number. */
static int number(const reader *r, size_t s, int len, double *v)
{
    char buf[64];
    while (len > 0 && (r->b[s] == ' ' || r->b[s] == '\t')) s++, len--;
    while (len > 0 && (r->b[s + len - 1] == ' ' || r->b[s + len - 1] == '\t')) len--;
    if (len == 0) return 1;
    if (len >= (int)sizeof buf) return -1;
    memcpy(buf, r->b + s, len);
    buf[len] = '\0';
    if (r->sep == ';')
        for (char *c = buf; *c; c++)
            if (*c == ',') *c = '.';
    return kt_parse_double(buf, v) == 0 && isfinite(*v) ? 0 : -1;
}

/* Index of coordinate c on the lattice, or -1. */
static int lattice(double c)
{
    double i = (c + KT_PENTACAM_HALF) / KT_PENTACAM_STEP;
    long k = lround(i);
    return fabs(i - k) < 1e-4 && k >= 0 && k < KT_PENTACAM_N ? (int)k : -1;
}

/* 1 when the field's text contains word (ASCII, any case). */
static int has_word(const reader *r, size_t s, int len, const char *word)
{
    size_t w = strlen(word);
    for (int i = 0; i + (int)w <= len; i++) {
        size_t k = 0;
        while (k < w && tolower((unsigned char)r->b[s + i + k]) == word[k]) k++;
        if (k == w) return 1;
    }
    return 0;
}

/* 1 when the field, blanks and a final ':' aside, is exactly word (any case). */
static int is_word(const reader *r, size_t s, int len, const char *word)
{
    while (len > 0 && (r->b[s] == ' ' || r->b[s] == '\t')) s++, len--;
    while (len > 0 && (r->b[s + len - 1] == ' ' || r->b[s + len - 1] == '\t' || r->b[s + len - 1] == ':')) len--;
    return len == (int)strlen(word) && has_word(r, s, len, word);
}

/* What a header line says of the export: its eye, kind, surface and unit (pentacam.h). */
static void header_line(reader *r, kt_pentacam_map *m, const size_t *start, const int *len, int k)
{
    int col0 = (int)r->line_at;
    for (int i = 0; i < k && i < MAXF; i++) {
        size_t s = start[i];
        int col = (int)s - col0 + 1;
        if (i + 1 < k && i + 1 < MAXF && is_word(r, s, len[i], "eye")) {
            size_t v = start[i + 1];
            int vl = len[i + 1], eye = is_word(r, v, vl, "od") || is_word(r, v, vl, "right") ? KT_PENTACAM_OD
                                       : is_word(r, v, vl, "os") || is_word(r, v, vl, "left") ? KT_PENTACAM_OS : 0;
            if (eye && !m->eye) m->eye = eye, m->eye_line = r->line, m->eye_col = (int)v - col0 + 1;
        }
        int kind = has_word(r, s, len[i], "pachymetr") ? KT_PENTACAM_PACHYMETRY + 1
                   : has_word(r, s, len[i], "elevation") ? KT_PENTACAM_ELEVATION + 1 : 0;
        if (kind && !m->head_kind) {
            m->head_kind = kind, m->kind_line = r->line, m->kind_col = col;
            m->surface = has_word(r, s, len[i], "front") || has_word(r, s, len[i], "anterior") ? KT_PENTACAM_FRONT
                         : has_word(r, s, len[i], "back") || has_word(r, s, len[i], "posterior") ? KT_PENTACAM_BACK : 0;
        }
        const char *unit = has_word(r, s, len[i], "[mm]") ? "mm"
                           : has_word(r, s, len[i], "[um]") || has_word(r, s, len[i], "[\xc2\xb5m]") ? "um" : NULL;
        if (unit && !m->unit[0]) snprintf(m->unit, sizeof m->unit, "%s", unit), m->unit_line = r->line, m->unit_col = col;
    }
}

/* Find the x coordinate row: the first line whose fields after the first are all numbers and
 * at least 10 of them; it must be the lattice. The lines before it are the header. */
static int coord_row(reader *r, kt_pentacam_map *m, size_t *start, int *len, size_t *next)
{
    for (int h = 0; h <= KT_PENTACAM_HEADER_MAX && r->line_at < r->n; h++) {
        r->sep = 0;
        int k = split(r, start, len, MAXF, next), nums = 0, bad = 0;
        int kk = k > MAXF ? MAXF : k;
        for (int i = 1; i < kk; i++) {
            double v;
            int t = number(r, start[i], len[i], &v);
            if (t == 0) nums++;
            else if (t < 0 || i < kk - 1) bad = 1; /* an empty field only last */
        }
        if (!bad && nums >= 10) {
            if (nums != KT_PENTACAM_N)
                return fail_at(r, start[1], "expected the Pentacam grid's %d x coordinates (-7.0 to 7.0 mm, 0.1 mm "
                               "steps), found %d", KT_PENTACAM_N, nums);
            for (int i = 0; i < KT_PENTACAM_N; i++) {
                double v;
                number(r, start[i + 1], len[i + 1], &v);
                if (lattice(v) != i)
                    return fail_at(r, start[i + 1], "expected x coordinate %.1f mm (the Pentacam grid: -7.0 to 7.0 mm "
                                   "in 0.1 mm steps), found %g", kt_pentacam_coord(i), v);
            }
            return KT_OK;
        }
        header_line(r, m, start, len, k);
        r->line_at = *next, r->line++;
    }
    return kt_fail(r->e, KT_EINPUT, "%s: expected a Pentacam map export: no row of the grid's %d x coordinates "
                   "(-7.0 to 7.0 mm) within the first %d lines", r->path, KT_PENTACAM_N, KT_PENTACAM_HEADER_MAX + 1);
}

static int read_rows(reader *r, int kind, kt_pentacam_map *m, size_t *start, int *len, size_t next)
{
    unsigned char seen[KT_PENTACAM_N] = {0};
    int rows = 0;
    double lo = r->lo, hi = r->hi;
    const char *unit = kind == KT_PENTACAM_ELEVATION ? "mm" : "um";
    while (rows < KT_PENTACAM_N) {
        r->line_at = next, r->line++;
        if (r->line_at >= r->n)
            return kt_fail(r->e, KT_EINPUT, "%s:%d:1: expected %d rows of the grid, the file ends after %d", r->path,
                           r->line, KT_PENTACAM_N, rows);
        int k = split(r, start, len, MAXF, &next);
        if (k == 1 && len[0] == 0) continue; /* a blank line */
        double y;
        if (number(r, start[0], len[0], &y) != 0 || lattice(y) < 0)
            return fail_at(r, start[0], "expected the row's y coordinate on the Pentacam grid (-7.0 to 7.0 mm in 0.1 mm steps)");
        int j = lattice(y);
        if (seen[j]) return fail_at(r, start[0], "expected each y coordinate once, %.1f mm is repeated", y);
        seen[j] = 1;
        int trailing = k == KT_PENTACAM_N + 2 && len[KT_PENTACAM_N + 1] == 0;
        if (k != KT_PENTACAM_N + 1 && !trailing)
            return fail_at(r, start[k > MAXF ? MAXF - 1 : k - 1], "expected %d values after the y coordinate, found %d",
                           KT_PENTACAM_N, k - 1);
        for (int i = 0; i < KT_PENTACAM_N; i++) {
            double v;
            int t = number(r, start[i + 1], len[i + 1], &v);
            if (t < 0) return fail_at(r, start[i + 1], "expected a number or an empty cell (no data)");
            if (t == 1 || v == -1) {
                m->v[j * KT_PENTACAM_N + i] = NAN;
                continue;
            }
            if (!(v >= lo && v <= hi))
                return fail_at(r, start[i + 1], "expected %s in %s within [%g, %g]%s (or -1: no data), found %g",
                               kind == KT_PENTACAM_ELEVATION ? "an elevation" : "a pachymetry", unit, lo, hi, r->whose, v);
            m->v[j * KT_PENTACAM_N + i] = kind == KT_PENTACAM_ELEVATION ? v : v / 1000;
            m->nvalid++;
        }
        rows++;
    }
    return KT_OK;
}

int kt_pentacam_read(const char *path, int kind, kt_pentacam_map *m, kt_err *e)
{
    int elev = kind == KT_PENTACAM_ELEVATION;
    return kt_pentacam_read_range(path, kind, elev ? -0.5 : 100, elev ? 8 : 2000, "", m, e);
}

int kt_pentacam_read_range(const char *path, int kind, double lo, double hi, const char *whose, kt_pentacam_map *m,
                           kt_err *e)
{
    memset(m, 0, sizeof *m);
    kt_cursor c;
    if (kt_cursor_open(&c, path, "", KT_PENTACAM_MAX_BYTES, e)) return e->code; /* no magic */
    reader r = {c.path, (const char *)c.b, c.n, 0, 1, 0, e, lo, hi, whose ? whose : ""};
    size_t *start = kt_calloc(MAXF, sizeof(size_t), e), next = 0;
    int *len = kt_calloc(MAXF, sizeof(int), e);
    m->kind = kind;
    m->n = KT_PENTACAM_N;
    m->v = kt_calloc((size_t)KT_PENTACAM_N * KT_PENTACAM_N, sizeof(double), e);
    int rc = start && len && m->v ? KT_OK : e->code;
    if (rc == KT_OK && memchr(c.b, '\0', c.n)) rc = kt_fail(e, KT_EINPUT, "%s: expected a text file, found a NUL byte", c.path);
    if (rc == KT_OK) rc = coord_row(&r, m, start, len, &next);
    if (rc == KT_OK) rc = read_rows(&r, kind, m, start, len, next);
    if (rc == KT_OK && m->nvalid == 0) rc = kt_fail(e, KT_EINPUT, "%s: expected measured cells, every cell is empty", c.path);
    free(start), free(len);
    kt_cursor_close(&c);
    if (rc != KT_OK) kt_pentacam_free(m);
    return rc;
}

void kt_pentacam_free(kt_pentacam_map *m)
{
    free(m->v);
    m->v = NULL;
    m->nvalid = 0;
}
