/* tsv.h: the tab-separated tables the tools write and read back (the reader, and below it the
 * writer) (curvature.tsv, steps.tsv,
 * derivatives.tsv, uncertainty.tsv, the --sens file, the benchmarks' step tables): a header line
 * naming the columns, then a row a line, fields split at tabs. The whole file is read (at most
 * KT_TSV_MAX_BYTES), so a line of any length is read whole; a line ending "\r\n" reads as one
 * ending "\n", a last line without '\n' is read, empty lines are skipped, a UTF-8 byte-order
 * mark before the header is skipped. Bad input is KT_EINPUT with one line naming the place,
 * "file:line:col: expected ..." (col: the 1-based byte of the field in its line).
 *
 *     kt_tsv t;
 *     if (kt_tsv_open(&t, path, e)) return e->code;
 *     int c = kt_tsv_need(&t, "cyl_D", NULL);
 *     double v;
 *     while (c >= 0 && kt_tsv_next(&t) > 0 && kt_tsv_num(&t, c, 0, &v) == KT_OK) ...;
 *     kt_tsv_close(&t);
 *     return e->code;
 */
#ifndef KT_TSV_H
#define KT_TSV_H

#include <stdio.h>

#include "cursor.h"

/* The largest table read, bytes: a bound on memory (about twice this) for an endless stream,
 * which is refused once past it. The tools' tables are kilobytes (curvature.tsv: about 600
 * bytes a step; derivatives.tsv: about 150 bytes a step and quantity); a larger one is refused
 * loudly, never cut. */
#define KT_TSV_MAX_BYTES ((size_t)16 << 20)

/* What kt_tsv_num takes besides a finite number: "nan" (any case, as strtod), "inf". */
enum { KT_TSV_NAN = 1, KT_TSV_INF = 2 };

/* One table being read. Owner: kt_tsv_open / kt_tsv_close. */
typedef struct kt_tsv {
    kt_cursor c;          /* the file's bytes, split in place (tabs and line ends made NULs) */
    int nhead, nf;        /* columns of the header; fields of the current row */
    char **head, **f;     /* their texts, into c.b */
    int line;             /* the current row's line (1: the header) */
    const char *bol;      /* the start of the current row's line (columns in messages) */
    int fcap;
} kt_tsv;

/* Read the file (path "-": stdin) and its header line. KT_OK, or KT_EINPUT: "file: cannot
 * open: why", "file:1:1: expected a header line, found an empty file", a NUL byte, too large. */
int kt_tsv_open(kt_tsv *t, const char *path, kt_err *e);
void kt_tsv_close(kt_tsv *t);

/* The index of the header's column `name`, -1 when absent. */
int kt_tsv_find(const kt_tsv *t, const char *name);
/* The same, when absent or given twice -1 and KT_EINPUT "file:1:1: expected a column NAME
 * (what)" (what may be NULL) / "file:1:C: column NAME given twice". */
int kt_tsv_need(kt_tsv *t, const char *name, const char *what);

/* The next row: 1, 0 at the end of the file, -1 on a NUL byte (KT_EINPUT). */
int kt_tsv_next(kt_tsv *t);

/* The current row's field of column col (an index of the header): its text, or NULL and
 * KT_EINPUT "file:L:C: expected a field in column NAME, found the end of the line". */
const char *kt_tsv_text(kt_tsv *t, int col);
/* The field as a number (strtod: the whole field, no blank before it, not out of range), finite
 * unless flags (KT_TSV_*) take more. KT_OK, or KT_EINPUT "file:L:C: expected a number in column
 * NAME, found 'x'"; *v unchanged then. */
int kt_tsv_num(kt_tsv *t, int col, int flags, double *v);
/* The field as a decimal integer in [lo, hi]; KT_OK or KT_EINPUT "file:L:C: expected an integer
 * from lo to hi in column NAME, found 'x'". */
int kt_tsv_int(kt_tsv *t, int col, long long lo, long long hi, long long *v);

/* A caller's own error at the current row's field col (-1: the line's start): KT_EINPUT
 * "file:L:C: msg". Returns KT_EINPUT. */
int kt_tsv_fail(kt_tsv *t, int col, const char *fmt, ...) __attribute__((format(printf, 3, 4)));

/* ---- the writer: the one writer of those tables ----
 *
 *     kt_tsvw w;
 *     kt_tsvw_begin(&w, f);
 *     kt_tsvw_text(&w, "step"), kt_tsvw_text(&w, "cyl_D"), kt_tsvw_end(&w);      (the header)
 *     kt_tsvw_int(&w, 3), kt_tsvw_num(&w, cyl, "%.4f"), kt_tsvw_end(&w);         (a row)
 *     return kt_tsvw_finish(&w, path, e);
 *
 * A number is written with the caller's printf format; a NaN as "NaN" and the infinities as
 * "inf" and "-inf", what kt_tsv_num reads back with KT_TSV_NAN | KT_TSV_INF. A text field with
 * a tab or a line end would split the table: it is a misuse. Every row has the header's count
 * of fields (the first line ended is the header). A misuse is KT_ERUN at kt_tsvw_finish, so is
 * a failed write. */
typedef struct kt_tsvw {
    FILE *f;
    int ncol;             /* the header's fields (-1 until it is ended) */
    int col;              /* fields of the line being written */
    int bad;              /* a misuse: what */
    char why[96];
} kt_tsvw;

void kt_tsvw_begin(kt_tsvw *w, FILE *f);
void kt_tsvw_text(kt_tsvw *w, const char *s);
void kt_tsvw_num(kt_tsvw *w, double v, const char *fmt);
void kt_tsvw_int(kt_tsvw *w, long long v);
/* End the line (the header, or a row). */
void kt_tsvw_end(kt_tsvw *w);
int kt_tsvw_finish(kt_tsvw *w, const char *what, kt_err *e);

#endif
