/* cursor.h: a byte cursor over a whole file in memory, shared by the file readers (MSH, VTK):
 * tokens, binary values, bounds checks against the rest of the file, and error messages that
 * name the position ("file:line:col" in text, "file: byte N" in a binary section). */
#ifndef KT_CURSOR_H
#define KT_CURSOR_H

#include <stddef.h>

#include "util.h"

typedef struct kt_cursor {
    const char *path;           /* for messages: the file, or "<stdin>" */
    const unsigned char *b;     /* the file's bytes, NUL-terminated (owned, see kt_cursor_open) */
    size_t n, p, at;            /* size, position, start of the item last read (for messages) */
    int bin, swap;              /* in a binary section; byte-swap binary values */
    kt_err *e;
} kt_cursor;

/* Read the whole file (path "-": stdin) into c->b, at most max bytes: a larger regular file is
 * refused before reading, a stream once it passes max. A file whose text does not begin with
 * magic (after a UTF-8 byte-order mark, which is skipped, and blanks) is read no further than
 * its first bytes, so /dev/zero or an endless pipe of anything else ends at once, the parser
 * then naming what it found at line 1; with magic "" (text of any kind), one with a NUL byte
 * among its first bytes. A regular file is read into a buffer of its size, a stream into one
 * that doubles. KT_EINPUT when it cannot be opened or read (a
 * directory), or is too large. */
int kt_cursor_open(kt_cursor *c, const char *path, const char *magic, size_t max, kt_err *e);
void kt_cursor_close(kt_cursor *c);

/* Record KT_EINPUT at c->at: "file:line:col: msg", "file: byte N: msg" in a binary section,
 * "file: unexpected end of file: msg" at the end. Returns KT_EINPUT. */
int kt_cursor_fail(kt_cursor *c, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

int kt_cursor_is_ws(unsigned char ch);

/* Next whitespace-delimited token (not empty, no NUL byte): *s points into the buffer. */
int kt_cursor_token(kt_cursor *c, const char **s, size_t *len, const char *what);

/* k raw bytes into dst, byte-swapped when c->swap. */
int kt_cursor_bytes(kt_cursor *c, void *dst, size_t k, const char *what);

/* A count of items each taking at least `each` bytes must fit in the rest of the file (and
 * in an int): a corrupt count is then an error instead of a huge allocation. */
int kt_cursor_fits(kt_cursor *c, size_t count, size_t each, const char *what);

/* The next token must be `word`. */
int kt_cursor_expect(kt_cursor *c, const char *word);

/* The next token as an integer within [lo, hi]. */
int kt_cursor_ll(kt_cursor *c, long long lo, long long hi, long long *v, const char *what);

/* The next value: a token in text; in a binary section (c->bin) raw bytes, byte-swapped when
 * c->swap: int as 4 bytes, size as 8 (at most SIZE_MAX / 2), double as 8. */
int kt_cursor_int(kt_cursor *c, int *v, const char *what);
int kt_cursor_size(kt_cursor *c, size_t *v, const char *what);
int kt_cursor_double(kt_cursor *c, double *v, const char *what);

#endif
