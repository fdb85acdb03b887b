/* test_tsv.c: the tables' one reader (io/tsv.h): values written with %.17g read back exactly;
 * a non-number, an empty field, a missing column, a short row, a NUL byte, an empty file each
 * refused with "file:line:col: expected ..." at the right place; a 100 KiB line (longer than any
 * of the old fixed buffers), CRLF line ends, a last line without '\n', a byte-order mark and
 * empty lines read as they should. */
#define _POSIX_C_SOURCE 200809L
#include <float.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "kt_test.h"
#include "tsv.h"

static char dir[] = "/tmp/kt_tsv_XXXXXX";

/* Write n bytes of text to dir/name; its path. */
static const char *put(const char *name, const char *text, size_t n)
{
    static char path[256];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = fopen(path, "wb");
    if (!f || fwrite(text, 1, n, f) != n) {
        perror(path);
        exit(1);
    }
    fclose(f);
    return path;
}
#define PUT(name, lit) put(name, lit, sizeof lit - 1)

/* The error of reading column `col` of the first row as a number (flags), or "" when it
 * reads; *v the value. */
static const char *first_num(const char *path, const char *col, int flags, double *v)
{
    static kt_err e;
    e = (kt_err){0};
    kt_tsv t;
    if (kt_tsv_open(&t, path, &e)) return e.msg;
    int c = kt_tsv_need(&t, col, NULL);
    if (c >= 0 && kt_tsv_next(&t) > 0) kt_tsv_num(&t, c, flags, v);
    kt_tsv_close(&t);
    return e.code ? e.msg : "";
}

/* msg is "<dir>/name:tail". */
static int says(const char *msg, const char *name, const char *tail)
{
    char want[512];
    snprintf(want, sizeof want, "%s/%s:%s", dir, name, tail);
    return strcmp(msg, want) == 0;
}

static void test_exact(void)
{
    const double x[] = {0.1, -1.0 / 3, 3.141592653589793, 1e-300, DBL_MAX, DBL_MIN, 4.9406564584124654e-324,
                        -0.0, 123456789012345678.0, 2.5e-17};
    const int n = sizeof x / sizeof x[0];
    char text[4096];
    size_t len = (size_t)snprintf(text, sizeof text, "step\tvalue\tnote\n");
    for (int i = 0; i < n; i++) len += (size_t)snprintf(text + len, sizeof text - len, "%d\t%.17g\trow %d\n", i, x[i], i);
    kt_err e = {0};
    kt_tsv t;
    CHECK(kt_tsv_open(&t, put("exact.tsv", text, len), &e) == KT_OK, "%s", e.msg);
    if (e.code) return;
    CHECK(t.nhead == 3 && kt_tsv_find(&t, "note") == 2 && kt_tsv_find(&t, "nope") == -1, "header of %d", t.nhead);
    int cs = kt_tsv_need(&t, "step", NULL), cv = kt_tsv_need(&t, "value", NULL), rows = 0;
    while (kt_tsv_next(&t) > 0) {
        long long s = -1;
        double v = NAN;
        char note[32];
        snprintf(note, sizeof note, "row %d", rows);
        CHECK(kt_tsv_int(&t, cs, 0, 100, &s) == KT_OK && s == rows, "step %lld: %s", s, e.msg);
        CHECK(kt_tsv_num(&t, cv, 0, &v) == KT_OK && memcmp(&v, &x[rows], sizeof v) == 0, "row %d: %.17g, wrote %.17g",
              rows, v, x[rows]);
        CHECK(strcmp(kt_tsv_text(&t, 2), note) == 0, "row %d: text '%s'", rows, kt_tsv_text(&t, 2));
        CHECK(t.line == rows + 2, "row %d on line %d", rows, t.line);
        rows++;
    }
    CHECK(rows == n && e.code == 0, "%d rows of %d: %s", rows, n, e.msg);
    CHECK(kt_tsv_next(&t) == 0, "the end stays the end");
    kt_tsv_close(&t);
}

static void test_refused(void)
{
    /* a table (one file each), the column read as a number with flags, the message expected
     * after "<file>:" ("" : it reads) */
    static const struct {
        const char *text, *col;
        int flags;
        const char *want;
    } bad[] = {
        {"x\ty\n1\tabc\n", "y", 0, "2:3: expected a number in column y, found 'abc'"},
        {"x\ty\n1\t2.5x\n", "y", 0, "2:3: expected a number in column y, found '2.5x'"},
        {"x\ty\n\t2\n", "x", 0, "2:1: expected a number in column x, found an empty field"},
        {"x\ty\n1\t 2\n", "y", 0, "2:3: expected a number in column y, found ' 2'"},
        {"x\ty\n1\t2\n", "z", 0, "1:1: expected a column z"},
        {"x\ty\tx\n1\t2\t3\n", "x", 0, "1:5: column x given twice"},
        {"x\ty\tz\n10\t20\n", "z", 0, "2:6: expected a field in column z, found the end of the line"},
        {"x\ty\n1\tnan\n", "y", 0, "2:3: expected a number in column y, found 'nan'"},
        {"x\ty\n1\t-inf\n", "y", KT_TSV_NAN, "2:3: expected a number in column y, found '-inf'"},
        {"x\ty\n1\t1e999\n", "y", KT_TSV_INF, "2:3: expected a number in column y, found '1e999'"},
        {"", "y", 0, "1:1: expected a header line, found an empty file"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        char name[32];
        double v = 7;
        snprintf(name, sizeof name, "bad-%zu.tsv", i);
        const char *m = first_num(put(name, bad[i].text, strlen(bad[i].text)), bad[i].col, bad[i].flags, &v);
        CHECK(says(m, name, bad[i].want) && v == 7, "%s: %s", name, m);
    }
    double v = 7;
    const char *m = first_num(PUT("nan.tsv", "x\ty\n1\tNaN\n"), "y", KT_TSV_NAN, &v);
    CHECK(*m == 0 && isnan(v), "NaN allowed: %s", m);
    m = first_num(PUT("inf.tsv", "x\ty\n1\t-inf\n"), "y", KT_TSV_INF, &v);
    CHECK(*m == 0 && isinf(v) && v < 0, "inf allowed: %s", m);
    m = first_num(put("nul.tsv", "x\ty\n1\t2\0003\n", 10), "y", 0, &v);
    CHECK(says(m, "nul.tsv", "2:4: expected a line of text, found a NUL byte"), "%s", m);

    /* integers, and a caller's own message at a field */
    kt_err e = {0};
    kt_tsv t;
    long long s = 0;
    CHECK(kt_tsv_open(&t, PUT("int.tsv", "step\tk\n3.0\t-4\n"), &e) == KT_OK, "%s", e.msg);
    CHECK(kt_tsv_next(&t) == 1 && kt_tsv_int(&t, 1, -10, 10, &s) == KT_OK && s == -4, "-4: %s", e.msg);
    CHECK(kt_tsv_int(&t, 0, 0, 10, &s) == KT_EINPUT &&
              says(e.msg, "int.tsv", "2:1: expected an integer from 0 to 10 in column step, found '3.0'"), "%s", e.msg);
    e = (kt_err){0};
    CHECK(kt_tsv_fail(&t, 1, "step %d is odd", 3) == KT_EINPUT && says(e.msg, "int.tsv", "2:5: step 3 is odd"), "%s",
          e.msg);
    kt_tsv_close(&t);
}

static void test_layout(void)
{
    double v = 0;
    const char *m;
    /* a 100 KiB first field: read whole, the column of what follows counted past it */
    size_t big = 100 * 1024, len;
    char *text = malloc(big + 64);
    len = (size_t)sprintf(text, "name\ty\n");
    memset(text + len, 'a', big);
    len += big;
    len += (size_t)sprintf(text + len, "\t0.125\n");
    m = first_num(put("long.tsv", text, len), "y", 0, &v);
    CHECK(*m == 0 && v == 0.125, "a 100 KiB line: %s, %g", m, v);
    len -= 6;
    len += (size_t)sprintf(text + len, "q\n");
    m = first_num(put("long2.tsv", text, len), "y", 0, &v);
    char tail[128];
    snprintf(tail, sizeof tail, "2:%zu: expected a number in column y, found 'q'", big + 2);
    CHECK(says(m, "long2.tsv", tail), "%s", m);
    free(text);

    m = first_num(PUT("crlf.tsv", "x\ty\r\n1\t-2.75\r\n"), "y", 0, &v);
    CHECK(*m == 0 && v == -2.75, "CRLF: %s, %g", m, v);
    m = first_num(PUT("crlf2.tsv", "x\ty\r\n1\tz\r\n"), "y", 0, &v);
    CHECK(says(m, "crlf2.tsv", "2:3: expected a number in column y, found 'z'"), "CRLF, no CR in the field: %s", m);
    m = first_num(PUT("noeol.tsv", "x\ty\n1\t6.5"), "y", 0, &v);
    CHECK(*m == 0 && v == 6.5, "no newline at the end: %s, %g", m, v);
    m = first_num(PUT("bom.tsv", "\xef\xbb\xbfx\ty\n1\t8\n"), "x", 0, &v);
    CHECK(*m == 0 && v == 1, "byte-order mark: %s, %g", m, v);

    kt_err e = {0};
    kt_tsv t;
    CHECK(kt_tsv_open(&t, PUT("gaps.tsv", "\n\nx\n\n5\n\r\n6\n"), &e) == KT_OK, "%s", e.msg);
    int n = 0, lines[2] = {0, 0};
    while (kt_tsv_next(&t) > 0 && n < 2) lines[n++] = t.line;
    CHECK(n == 2 && lines[0] == 5 && lines[1] == 7 && e.code == 0, "rows on lines %d, %d (%d rows)", lines[0], lines[1], n);
    kt_tsv_close(&t);
    e = (kt_err){0};
    CHECK(kt_tsv_open(&t, PUT("only-blank.tsv", "\n\r\n"), &e) == KT_EINPUT && strstr(e.msg, "found an empty file"),
          "%s", e.msg);
    e = (kt_err){0};
    char path[300];
    snprintf(path, sizeof path, "%s/none.tsv", dir);
    CHECK(kt_tsv_open(&t, path, &e) == KT_EINPUT && says(e.msg, "none.tsv", " cannot open: No such file or directory"),
          "%s", e.msg);
}

int main(void)
{
    if (!mkdtemp(dir)) return 1;
    test_exact();
    test_refused();
    test_layout();
    char cmd[300];
    snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
    if (system(cmd)) fprintf(stderr, "could not remove %s\n", dir);
    return kt_test_done("test_tsv");
}
