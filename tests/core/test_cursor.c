/* test_cursor.c: the byte cursor the file readers share: tokens, NUL bytes, positioned
 * messages ("file:line:col", "file: byte N", end of file), binary reads with byte swap, and
 * counts that the rest of the file cannot hold. */
#define _POSIX_C_SOURCE 200809L
#include <limits.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "cursor.h"
#include "kt_test.h"

static char dir[64];

static void write_bytes(const char *path, const void *b, size_t n)
{
    FILE *f = fopen(path, "wb");
    if (!f || fwrite(b, 1, n, f) != n) {
        perror(path);
        exit(1);
    }
    fclose(f);
}

static int open_text(kt_cursor *c, const char *name, const void *b, size_t n, char *path, kt_err *e)
{
    snprintf(path, 128, "%s/%s", dir, name);
    write_bytes(path, b, n);
    return kt_cursor_open(c, path, "", SIZE_MAX, e);
}

static int tok_is(kt_cursor *c, const char *want)
{
    const char *s;
    size_t len;
    if (kt_cursor_token(c, &s, &len, "a token")) return 0;
    return len == strlen(want) && memcmp(s, want, len) == 0;
}

static void test_missing(void)
{
    kt_cursor c;
    kt_err e = {0};
    char path[128];
    snprintf(path, sizeof path, "%s/no-such-file.msh", dir);
    CHECK(kt_cursor_open(&c, path, "", SIZE_MAX, &e) == KT_EINPUT, "rc %d", e.code);
    CHECK(strncmp(e.msg, path, strlen(path)) == 0 && strstr(e.msg, "cannot open"), "'%s'", e.msg);
    CHECK(c.b == NULL, "a failed open holds no buffer");
}

static void test_tokens_and_positions(void)
{
    const char text[] = "$Mesh  4.1\n\t  12  x\r\nlast";
    kt_cursor c;
    kt_err e = {0};
    char path[128], want[256];
    CHECK(open_text(&c, "tokens.txt", text, sizeof text - 1, path, &e) == KT_OK, "%s", e.msg);
    if (e.code) return;
    CHECK(c.n == sizeof text - 1 && c.b[c.n] == '\0', "size %zu, NUL-terminated", c.n);
    CHECK(tok_is(&c, "$Mesh") && tok_is(&c, "4.1") && tok_is(&c, "12"), "first three tokens");
    CHECK(tok_is(&c, "x"), "token after spaces");
    /* the item last read ("x") is at line 2, column 8 (the tab counts as one column) */
    CHECK(kt_cursor_fail(&c, "expected a number") == KT_EINPUT, "fail returns KT_EINPUT");
    snprintf(want, sizeof want, "%s:2:8: expected a number", path);
    CHECK(strcmp(e.msg, want) == 0, "'%s' vs '%s'", e.msg, want);
    kt_err e2 = {0};
    c.e = &e2;
    CHECK(tok_is(&c, "last"), "token after CR LF");
    CHECK(kt_cursor_fail(&c, "bad") && strstr(e2.msg, ":3:1: bad"), "'%s'", e2.msg);
    kt_err e3 = {0};
    c.e = &e3;
    const char *s;
    size_t len;
    CHECK(kt_cursor_token(&c, &s, &len, "the element count") == KT_EINPUT, "token past the end");
    snprintf(want, sizeof want, "%s: unexpected end of file: expected the element count", path);
    CHECK(strcmp(e3.msg, want) == 0, "'%s'", e3.msg);
    kt_cursor_close(&c);
    CHECK(c.b == NULL && c.n == 0, "closed");
}

static void test_nul_byte(void)
{
    const char text[] = "ab \0cd";
    kt_cursor c;
    kt_err e = {0};
    char path[128], want[256];
    CHECK(open_text(&c, "nul.txt", text, sizeof text - 1, path, &e) == KT_OK, "%s", e.msg);
    if (e.code) return;
    CHECK(c.n == 6, "the NUL byte is part of the file: %zu bytes", c.n);
    CHECK(tok_is(&c, "ab"), "token before the NUL");
    const char *s;
    size_t len;
    CHECK(kt_cursor_token(&c, &s, &len, "a node tag") == KT_EINPUT, "NUL accepted as a token");
    snprintf(want, sizeof want, "%s:1:4: expected a node tag, found a NUL byte", path);
    CHECK(strcmp(e.msg, want) == 0, "'%s'", e.msg);
    kt_cursor_close(&c);
    /* a NUL inside a token ends it */
    const char t2[] = "12\0 3";
    kt_err e2 = {0};
    CHECK(open_text(&c, "nul2.txt", t2, sizeof t2 - 1, path, &e2) == KT_OK, "%s", e2.msg);
    CHECK(kt_cursor_token(&c, &s, &len, "x") == KT_OK && len == 2, "token stops at the NUL: len %zu", len);
    kt_cursor_close(&c);
}

static void test_binary(void)
{
    unsigned char b[] = {'h', 'd', '\n', 0x01, 0x02, 0x03, 0x04, 0x11, 0x22, 0x33, 0x44, 0x55, 0x66, 0x77, 0x88, 0xAB};
    kt_cursor c;
    kt_err e = {0};
    char path[128], want[256];
    CHECK(open_text(&c, "bin.dat", b, sizeof b, path, &e) == KT_OK, "%s", e.msg);
    if (e.code) return;
    CHECK(tok_is(&c, "hd"), "text header");
    c.p++; /* the newline after the header */
    c.bin = 1;
    uint32_t u = 0, us = 0;
    CHECK(kt_cursor_bytes(&c, &u, 4, "an int") == KT_OK, "%s", e.msg);
    uint32_t host;
    memcpy(&host, b + 3, 4);
    CHECK(u == host && c.p == 7, "plain read: %08x vs %08x", u, host);
    c.p = 3;
    c.swap = 1;
    CHECK(kt_cursor_bytes(&c, &us, 4, "an int") == KT_OK, "%s", e.msg);
    unsigned char *ub = (unsigned char *)&us;
    CHECK(ub[0] == 0x04 && ub[1] == 0x03 && ub[2] == 0x02 && ub[3] == 0x01, "swapped: %02x %02x %02x %02x", ub[0],
          ub[1], ub[2], ub[3]);
    /* an 8-byte double swapped twice is the original */
    double d = 0, d2;
    c.swap = 0;
    CHECK(kt_cursor_bytes(&c, &d, 8, "a double") == KT_OK, "%s", e.msg);
    c.p -= 8;
    c.swap = 1;
    CHECK(kt_cursor_bytes(&c, &d2, 8, "a double") == KT_OK, "%s", e.msg);
    unsigned char *p1 = (unsigned char *)&d, *p2 = (unsigned char *)&d2;
    int mirrored = 1;
    for (int i = 0; i < 8; i++) mirrored &= p1[i] == p2[7 - i];
    CHECK(mirrored && p1[0] == 0x11 && c.p == 15, "8-byte swap");
    /* an error at a binary position names the byte */
    CHECK(kt_cursor_fail(&c, "expected a positive tag") == KT_EINPUT, "fail");
    snprintf(want, sizeof want, "%s: byte 7: expected a positive tag", path);
    CHECK(strcmp(e.msg, want) == 0, "'%s'", e.msg);
    /* 4 bytes with 1 left: end of file, nothing consumed */
    kt_err e2 = {0};
    c.e = &e2;
    CHECK(kt_cursor_bytes(&c, &u, 4, "a node count") == KT_EINPUT && c.p == 15, "short read at %zu", c.p);
    snprintf(want, sizeof want, "%s: unexpected end of file: expected a node count (4 binary bytes)", path);
    CHECK(strcmp(e2.msg, want) == 0, "'%s'", e2.msg);
    unsigned char last = 0;
    CHECK(kt_cursor_bytes(&c, &last, 1, "a byte") == KT_OK && last == 0xAB && c.p == 16, "the last byte");
    CHECK(kt_cursor_bytes(&c, &last, 1, "a byte") == KT_EINPUT, "a read past the end");
    kt_cursor_close(&c);
}

static void test_fits(void)
{
    unsigned char b[100];
    memset(b, ' ', sizeof b);
    kt_cursor c;
    kt_err e = {0};
    char path[128];
    CHECK(open_text(&c, "fits.dat", b, sizeof b, path, &e) == KT_OK, "%s", e.msg);
    if (e.code) return;
    c.p = 20; /* 80 bytes left */
    CHECK(kt_cursor_fits(&c, 10, 8, "nodes") == KT_OK, "10 x 8 in 80 bytes");
    CHECK(kt_cursor_fits(&c, 0, 8, "nodes") == KT_OK, "no items");
    CHECK(e.code == 0, "%s", e.msg);
    CHECK(kt_cursor_fits(&c, 11, 8, "nodes") == KT_EINPUT, "11 x 8 in 80 bytes accepted");
    CHECK(strstr(e.msg, "nodes 11 is more than the rest of the file can hold") != NULL, "'%s'", e.msg);
    kt_err e2 = {0};
    c.e = &e2;
    /* a count whose product with the size overflows size_t is still refused */
    CHECK(kt_cursor_fits(&c, SIZE_MAX / 2 + 1, 4, "elements") == KT_EINPUT, "overflowing count accepted");
    kt_err e3 = {0};
    c.e = &e3;
    CHECK(kt_cursor_fits(&c, (size_t)INT_MAX + 1, 0, "tags") == KT_EINPUT, "a count beyond INT_MAX accepted");
    kt_cursor_close(&c);
}

/* Bounded while reading (issue 26): a file not starting with the magic is read no further than
 * its first bytes; a larger file than the limit is refused; a directory says so; a UTF-8
 * byte-order mark is skipped. */
static void test_bounds(void)
{
    kt_cursor c;
    char path[128];
    kt_err e = {0};
    CHECK(kt_cursor_open(&c, "/dev/zero", "$MeshFormat", (size_t)1 << 32, &e) == KT_OK, "%s", e.msg);
    CHECK(c.n > 0 && c.n <= (1 << 17), "/dev/zero: %zu bytes read", c.n);
    kt_cursor_close(&c);

    static char big[200000];
    for (size_t i = 0; i < sizeof big; i += 2) big[i] = 'y', big[i + 1] = '\n';
    snprintf(path, sizeof path, "%s/yes.msh", dir);
    write_bytes(path, big, sizeof big);
    CHECK(kt_cursor_open(&c, path, "$MeshFormat", (size_t)1 << 32, &e) == KT_OK, "%s", e.msg);
    CHECK(c.n < sizeof big, "a wrong start: %zu of %zu bytes read", c.n, sizeof big);
    kt_cursor_close(&c);
    /* a regular file is read whole into a buffer of its size (fstat), bytes as written */
    CHECK(kt_cursor_open(&c, path, "", (size_t)1 << 32, &e) == KT_OK, "%s", e.msg);
    CHECK(c.n == sizeof big && c.b[c.n] == '\0' && memcmp(c.b, big, sizeof big) == 0, "whole file: %zu of %zu bytes",
          c.n, sizeof big);
    kt_cursor_close(&c);
    /* without a magic, text of any kind: /dev/zero's NUL bytes end the read at once */
    CHECK(kt_cursor_open(&c, "/dev/zero", "", (size_t)1 << 32, &e) == KT_OK, "%s", e.msg);
    CHECK(c.n > 0 && c.n <= (1 << 17), "/dev/zero without a magic: %zu bytes read", c.n);
    kt_cursor_close(&c);
    kt_err e2 = {0};
    CHECK(kt_cursor_open(&c, path, "", 1000, &e2) == KT_EINPUT && strstr(e2.msg, "at most 1000 bytes"),
          "'%s'", e2.msg);
    kt_err e3 = {0};
    CHECK(kt_cursor_open(&c, dir, "", 1000, &e3) == KT_EINPUT && strstr(e3.msg, "is a directory"),
          "'%s'", e3.msg);
    kt_err e4 = {0};
    const char bom[] = "\xef\xbb\xbf  $MeshFormat 4.1";
    CHECK(open_text(&c, "bom.msh", bom, sizeof bom - 1, path, &e4) == KT_OK, "%s", e4.msg);
    CHECK(tok_is(&c, "$MeshFormat"), "the byte-order mark is skipped");
    kt_cursor_close(&c);
}

int main(void)
{
    snprintf(dir, sizeof dir, "/tmp/kt-cursor-XXXXXX");
    if (!mkdtemp(dir)) {
        perror("mkdtemp");
        return 1;
    }
    test_missing();
    test_tokens_and_positions();
    test_nul_byte();
    test_binary();
    test_fits();
    test_bounds();
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    if (system(cmd) != 0) fprintf(stderr, "could not remove %s\n", dir);
    return kt_test_done("test_cursor");
}
