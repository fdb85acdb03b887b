/* cgalin.c: counts in the CGAL mesher's input headers checked against the file's size. */
#include "cgalin.h"

#include <ctype.h>
#include <errno.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>

/* The next token of an OFF header (comments from '#' to the end of a line skipped) into tok
 * (size bytes); 0 at the end of the text. */
static int off_token(FILE *f, char *tok, size_t size)
{
    int ch;
    size_t n = 0;
    for (;;) {
        ch = getc(f);
        if (ch == '#')
            while ((ch = getc(f)) != EOF && ch != '\n') {}
        if (ch == EOF) return 0;
        if (!isspace(ch)) break;
    }
    while (ch != EOF && !isspace(ch) && ch != '#') {
        if (n + 1 < size) tok[n++] = (char)ch;
        ch = getc(f);
    }
    if (ch == '#') ungetc(ch, f);
    tok[n] = '\0';
    return 1;
}

static int to_count(const char *s, long long *v)
{
    char *end;
    errno = 0;
    *v = strtoll(s, &end, 10);
    return end != s && *end == '\0' && errno == 0 && *v >= 0;
}

/* A count at the start of s (digits up to a blank or the line's end). */
static int to_count_prefix(const char *s, long long *v)
{
    char *end;
    errno = 0;
    *v = strtoll(s, &end, 10);
    return end != s && (*end == '\n' || *end == ' ' || *end == '\0') && errno == 0 && *v >= 0;
}

/* An OFF header: [ST][C][N][4][n]OFF [BINARY] [dim] NV NF NE. */
static int check_off(FILE *f, const char *path, long long size, kt_err *e)
{
    char tok[64];
    long long c[3];
    int binary = 0, ndim = 0, k = 0;
    if (!off_token(f, tok, sizeof tok)) return kt_fail(e, KT_EINPUT, "%s: expected an OFF header", path);
    size_t len = strlen(tok);
    if (len >= 3 && strcmp(tok + len - 3, "OFF") == 0) {
        ndim = len >= 4 && tok[len - 4] == 'n';
        long pos = ftell(f);
        if (off_token(f, tok, sizeof tok) && strcmp(tok, "BINARY") == 0) binary = 1;
        else if (fseek(f, pos, SEEK_SET) != 0) return kt_fail(e, KT_EINPUT, "%s: cannot seek", path);
        if (binary) {
            int ch;
            while ((ch = getc(f)) != EOF && ch != '\n') {}
            for (k = 0; k < 3 + ndim; k++) {
                unsigned char b[4];
                if (fread(b, 1, 4, f) != 4) return kt_fail(e, KT_EINPUT, "%s: expected the OFF counts", path);
                c[k < ndim ? 0 : k - ndim] = (long long)((uint32_t)b[0] << 24 | (uint32_t)b[1] << 16 |
                                                         (uint32_t)b[2] << 8 | b[3]);
            }
        }
        if (!binary && !off_token(f, tok, sizeof tok)) return kt_fail(e, KT_EINPUT, "%s: expected the OFF counts", path);
    }
    if (!binary) {
        if (ndim && !off_token(f, tok, sizeof tok)) return kt_fail(e, KT_EINPUT, "%s: expected the OFF counts", path);
        for (k = 0; k < 3; k++) {
            if (k > 0 && !off_token(f, tok, sizeof tok)) break;
            if (!to_count(tok, &c[k]))
                return kt_fail(e, KT_EINPUT, "%s: expected the OFF counts (vertices faces edges), found '%s'", path, tok);
        }
        if (k < 2) return kt_fail(e, KT_EINPUT, "%s: expected the OFF counts", path);
    }
    long long vb = binary ? 12 : 6, fb = binary ? 16 : 2;
    if (c[0] > INT32_MAX || c[1] > INT32_MAX || c[0] * vb + c[1] * fb > size)
        return kt_fail(e, KT_EINPUT, "%s: expected counts the file can hold: %lld vertices and "
                       "%lld faces need at least %lld bytes, the file has %lld", path, c[0], c[1],
                       c[0] > INT32_MAX || c[1] > INT32_MAX ? -1 : c[0] * vb + c[1] * fb, size);
    return KT_OK;
}

/* A plain INR header ("#INRIMAGE-4#{" ... "##}", 256 bytes): its voxels fit the file. */
static int check_inr(FILE *f, const char *path, long long size, kt_err *e)
{
    char h[257] = "";
    size_t n = fread(h, 1, 256, f);
    h[n] = '\0';
    if (strncmp(h, "#INRIMAGE-4#{", 13) != 0) return KT_OK; /* CGAL says what it is not */
    long long d[4] = {1, 1, 1, 1}, bits = 8;
    static const char *key[4] = {"XDIM=", "YDIM=", "ZDIM=", "VDIM="};
    for (int i = 0; i < 4; i++) {
        const char *p = strstr(h, key[i]);
        if (p && (!to_count_prefix(p + 5, &d[i]) || d[i] > INT32_MAX))
            return kt_fail(e, KT_EINPUT, "%s: expected %s with a count", path, key[i]);
    }
    const char *p = strstr(h, "PIXSIZE=");
    if (p && (!to_count_prefix(p + 8, &bits) || bits < 1 || bits > 64))
        return kt_fail(e, KT_EINPUT, "%s: expected PIXSIZE= with 1-64 bits", path);
    long double need = (long double)d[0] * d[1] * d[2] * d[3] * (long double)bits / 8 + 256;
    if (need > (long double)size)
        return kt_fail(e, KT_EINPUT, "%s: expected an image the file can hold: %lldx%lldx%lld "
                       "voxels need %.0Lf bytes, the file has %lld", path, d[0], d[1], d[2], need, size);
    return KT_OK;
}

static int ends_with(const char *s, const char *suffix)
{
    size_t a = strlen(s), b = strlen(suffix);
    return a >= b && strcasecmp(s + a - b, suffix) == 0;
}

int kt_cgalin_check(const char *path, kt_err *e)
{
    struct stat st;
    if (stat(path, &st) != 0) return kt_fail(e, KT_EINPUT, "%s: cannot open: %s", path, strerror(errno));
    if (!S_ISREG(st.st_mode))
        return kt_fail(e, KT_EINPUT, "%s: expected a regular file, found %s", path,
                       S_ISDIR(st.st_mode) ? "a directory" : "a device, FIFO or socket");
    long long size = (long long)st.st_size;
    if (size > KT_CGALIN_MAX_BYTES)
        return kt_fail(e, KT_EINPUT, "%s: expected a file of at most %lld bytes, found %lld", path,
                       KT_CGALIN_MAX_BYTES, size);
    int off = ends_with(path, ".off"), inr = ends_with(path, ".inr");
    if (!off && !inr) return KT_OK;
    FILE *f = fopen(path, "rb");
    if (!f) return kt_fail(e, KT_EINPUT, "%s: cannot open: %s", path, strerror(errno));
    int rc = off ? check_off(f, path, size, e) : check_inr(f, path, size, e);
    fclose(f);
    return rc;
}
