/* cursor.c: a byte cursor over a file in memory, with positioned error messages. */
#include "cursor.h"

#include <errno.h>
#include <limits.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

/* 1 when the text at b (n bytes) cannot begin with magic: after a UTF-8 byte-order mark and
 * blanks, its first bytes differ (0 while too few bytes were read to tell). Without a magic
 * (""), a text of any kind: a NUL byte among the first n is wrong. */
static int wrong_start(const unsigned char *b, size_t n, const char *magic, int at_end)
{
    size_t i = n >= 3 && memcmp(b, "\xef\xbb\xbf", 3) == 0 ? 3 : 0, k = strlen(magic);
    if (k == 0 && memchr(b, '\0', n)) return 1;
    while (i < n && kt_cursor_is_ws(b[i])) i++;
    if (i == n) return at_end;
    size_t m = n - i < k ? n - i : k;
    if (memcmp(b + i, magic, m) != 0) return 1;
    return at_end && m < k;
}

/* b reallocated to nc bytes (*cap := nc); NULL, b freed, when memory runs out. */
static unsigned char *grow(unsigned char *b, size_t *cap, size_t nc, kt_err *e)
{
    unsigned char *nb = kt_realloc(b, nc, 1, e);
    if (!nb) free(b);
    else *cap = nc;
    return nb;
}

int kt_cursor_open(kt_cursor *c, const char *path, const char *magic, size_t max, kt_err *e)
{
    memset(c, 0, sizeof *c);
    c->e = e;
    c->path = strcmp(path, "-") == 0 ? "<stdin>" : path;
    FILE *f = strcmp(path, "-") == 0 ? stdin : fopen(path, "rb");
    if (!f) return kt_fail(e, KT_EINPUT, "%s: cannot open: %s", c->path, strerror(errno));
    struct stat st;
    int rc = KT_OK, have = fstat(fileno(f), &st) == 0;
    if (have && S_ISDIR(st.st_mode))
        rc = kt_fail(e, KT_EINPUT, "%s: cannot read: is a directory", c->path);
    else if (have && S_ISREG(st.st_mode) && (unsigned long long)st.st_size > max)
        rc = kt_fail(e, KT_EINPUT, "%s: expected a file of at most %zu bytes, found %lld", c->path,
                     max, (long long)st.st_size);
    /* A regular file's buffer is sized from its size once its start is checked (+2: its NUL and
     * one byte more, so that the read meets the end without growing it); a stream's, or a file
     * that grows while read, by doubling. */
    size_t whole = have && S_ISREG(st.st_mode) && !rc ? (size_t)st.st_size + 2 : 0;
    size_t cap = whole && whole < (1 << 16) ? whole : 1 << 16, n = 0;
    unsigned char *b = rc ? NULL : kt_calloc(cap, 1, e);
    int checked = 0;
    while (b) {
        if (n + 1 >= cap && !(b = grow(b, &cap, cap * 2, e))) break;
        size_t got = fread(b + n, 1, cap - 1 - n, f);
        n += got;
        if (!checked && (n >= 64 || got == 0)) {
            checked = 1; /* wrong from the start: the parser's error names it, read no more */
            if (wrong_start(b, n, magic, got == 0)) break;
            if (whole > cap && !(b = grow(b, &cap, whole, e))) break; /* right: the whole file */
        }
        if (got == 0) break;
        if (n > max) {
            rc = kt_fail(e, KT_EINPUT, "%s: expected a file of at most %zu bytes, found more",
                         c->path, max);
            break;
        }
    }
    int err = b && ferror(f) ? errno : 0;
    if (f != stdin) fclose(f);
    if (!b) return e->code;
    if (rc || err) {
        free(b);
        return rc ? rc : kt_fail(e, KT_EINPUT, "%s: read error: %s", c->path, strerror(err));
    }
    b[n] = '\0';
    c->b = b;
    c->n = n;
    if (n >= 3 && memcmp(b, "\xef\xbb\xbf", 3) == 0) c->p = 3; /* a UTF-8 byte-order mark */
    return KT_OK;
}

void kt_cursor_close(kt_cursor *c)
{
    free((void *)c->b);
    c->b = NULL;
    c->n = c->p = c->at = 0;
}

int kt_cursor_fail(kt_cursor *c, const char *fmt, ...)
{
    char msg[768];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    if (c->at >= c->n) return kt_fail(c->e, KT_EINPUT, "%s: unexpected end of file: %s", c->path, msg);
    if (c->bin) return kt_fail(c->e, KT_EINPUT, "%s: byte %zu: %s", c->path, c->at, msg);
    size_t line = 1, col = 1;
    for (size_t i = 0; i < c->at; i++) {
        if (c->b[i] == '\n') line++, col = 1;
        else col++;
    }
    return kt_fail(c->e, KT_EINPUT, "%s:%zu:%zu: %s", c->path, line, col, msg);
}

int kt_cursor_is_ws(unsigned char ch) { return ch == ' ' || ch == '\t' || ch == '\r' || ch == '\n'; }

int kt_cursor_token(kt_cursor *c, const char **s, size_t *len, const char *what)
{
    while (c->p < c->n && kt_cursor_is_ws(c->b[c->p])) c->p++;
    c->at = c->p;
    if (c->p >= c->n) return kt_cursor_fail(c, "expected %s", what);
    size_t q = c->p;
    while (q < c->n && !kt_cursor_is_ws(c->b[q]) && c->b[q] != '\0') q++;
    if (q == c->p) return kt_cursor_fail(c, "expected %s, found a NUL byte", what);
    *s = (const char *)c->b + c->p;
    *len = q - c->p;
    c->p = q;
    return KT_OK;
}

int kt_cursor_bytes(kt_cursor *c, void *dst, size_t k, const char *what)
{
    c->at = c->p;
    if (c->n - c->p < k) {
        c->at = c->n;
        return kt_cursor_fail(c, "expected %s (%zu binary bytes)", what, k);
    }
    unsigned char *d = dst;
    if (c->swap)
        for (size_t i = 0; i < k; i++) d[i] = c->b[c->p + k - 1 - i];
    else
        memcpy(d, c->b + c->p, k);
    c->p += k;
    return KT_OK;
}

int kt_cursor_fits(kt_cursor *c, size_t count, size_t each, const char *what)
{
    if (count > INT_MAX || (count && (c->n - c->p) / count < each))
        return kt_cursor_fail(c, "%s %zu is more than the rest of the file can hold", what, count);
    return KT_OK;
}

int kt_cursor_expect(kt_cursor *r, const char *word)
{
    const char *s;
    size_t len;
    if (kt_cursor_token(r, &s, &len, word)) return r->e->code;
    if (len != strlen(word) || memcmp(s, word, len) != 0)
        return kt_cursor_fail(r, "expected %s, found '%.*s'", word, (int)(len > 40 ? 40 : len), s);
    return KT_OK;
}

/* The next token, NUL-terminated in buf (size bytes); a longer one is an error naming `kind`. */
static int token_text(kt_cursor *r, char *buf, size_t size, const char *what, const char *kind)
{
    const char *s;
    size_t len;
    if (kt_cursor_token(r, &s, &len, what)) return r->e->code;
    if (len >= size) return kt_cursor_fail(r, "expected %s (%s), found '%.20s...'", what, kind, s);
    memcpy(buf, s, len);
    buf[len] = '\0';
    return KT_OK;
}

/* Parse a token as an integer within [lo, hi]. */
int kt_cursor_ll(kt_cursor *r, long long lo, long long hi, long long *v, const char *what)
{
    char buf[32];
    if (token_text(r, buf, sizeof buf, what, "an integer")) return r->e->code;
    size_t len = strlen(buf);
    char *end;
    errno = 0;
    long long x = strtoll(buf, &end, 10);
    if (end != buf + len || errno == ERANGE)
        return kt_cursor_fail(r, "expected %s (an integer), found '%s'", what, buf);
    if (x < lo || x > hi) return kt_cursor_fail(r, "%s %s out of range [%lld, %lld]", what, buf, lo, hi);
    *v = x;
    return KT_OK;
}

int kt_cursor_int(kt_cursor *r, int *v, const char *what)
{
    if (r->bin) {
        int32_t x = 0;
        if (kt_cursor_bytes(r, &x, 4, what)) return r->e->code;
        *v = x;
        return KT_OK;
    }
    long long x = 0;
    if (kt_cursor_ll(r, INT_MIN, INT_MAX, &x, what)) return r->e->code;
    *v = (int)x;
    return KT_OK;
}

int kt_cursor_size(kt_cursor *r, size_t *v, const char *what)
{
    if (r->bin) {
        uint64_t x = 0;
        if (kt_cursor_bytes(r, &x, 8, what)) return r->e->code;
        if (x > SIZE_MAX / 2) return kt_cursor_fail(r, "%s %llu out of range", what, (unsigned long long)x);
        *v = (size_t)x;
        return KT_OK;
    }
    long long x = 0;
    if (kt_cursor_ll(r, 0, LLONG_MAX, &x, what)) return r->e->code;
    *v = (size_t)x;
    return KT_OK;
}

int kt_cursor_double(kt_cursor *r, double *v, const char *what)
{
    if (r->bin) return kt_cursor_bytes(r, v, 8, what);
    char buf[64];
    if (token_text(r, buf, sizeof buf, what, "a number")) return r->e->code;
    char *end;
    *v = strtod(buf, &end);
    if (*end) return kt_cursor_fail(r, "expected %s (a number), found '%s'", what, buf);
    return KT_OK;
}
