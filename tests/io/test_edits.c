/* test_edits.c: the edits stream round-trips through writer and reader; bad streams are
 * rejected with file:line:col and KT_EINPUT. */
#define _POSIX_C_SOURCE 200809L
#include <stdlib.h>
#include <string.h>

#include "edits.h"
#include "kt_test.h"

/* Parse a whole stream from a string; returns the number of steps, or -1 with e set. */
static int parse_all(const char *text, kt_err *e, kt_edits_reader *r, kt_step *last)
{
    FILE *f = fmemopen((void *)text, strlen(text), "r");
    if (!f) return -1;
    int steps = -1;
    if (kt_edits_open(r, f, "t.edits", e) == KT_OK) {
        steps = 0;
        int rc;
        while ((rc = kt_edits_next(r, last, e)) == 1) steps++;
        if (rc < 0) steps = -1;
    }
    fclose(f);
    return steps;
}

static void expect_error(const char *text, const char *where, const char *what)
{
    kt_err e = {0};
    kt_edits_reader r;
    kt_step s = {0};
    int n = parse_all(text, &e, &r, &s);
    CHECK(n == -1 && e.code == KT_EINPUT, "expected bad input for %s (got %d, code %d)", where,
          n, e.code);
    CHECK(strncmp(e.msg, where, strlen(where)) == 0, "message '%s' should start with '%s'", e.msg,
          where);
    CHECK(strstr(e.msg, what) != NULL, "message '%s' should mention '%s'", e.msg, what);
    kt_step_free(&s);
}

static void test_roundtrip(void)
{
    kt_err e = {0};
    char *buf = NULL;
    size_t len = 0;
    FILE *f = open_memstream(&buf, &len);
    kt_edits_header h = {0};
    strcpy(h.scene, "/abs/scene dir/eye #2.yaml");           /* " #" is no comment */
    strcpy(h.plan, "/abs/\"plan\" \\ 'x'\t.yaml\n");       /* quotes, backslash, tab, newline */
    strcpy(h.mesh, "/abs/my mesh.msh 1 2");                  /* looks like counts */
    h.nn = 10;
    h.ne = 7;
    CHECK(kt_edits_write_header(f, &h, &e) == KT_OK, "%s", e.msg);
    kt_step s = {0};
    s.index = 1;
    strcpy(s.label, "arc 0-5 deg (a #1\nb)");
    int el[3] = {0, 6, 3};
    kt_edit d = {.kind = KT_EDIT_DUP, .node = 4, .new_node = 10, .nel = 3, .el = el};
    kt_edit fx = {.kind = KT_EDIT_FIX, .node = 10, .mask = 5, .v = {0.1, 0, -1.0 / 3}};
    kt_edit fo = {.kind = KT_EDIT_FORCE, .node = 2, .v = {1e-3, -2.5, 0}};
    CHECK(kt_step_add(&s, &d, &e) == KT_OK && kt_step_add(&s, &fx, &e) == KT_OK &&
              kt_step_add(&s, &fo, &e) == KT_OK, "%s", e.msg);
    CHECK(kt_edits_write_step(f, &s, &e) == KT_OK, "%s", e.msg);
    kt_step_clear(&s);
    s.index = 2;
    kt_edit d2 = {.kind = KT_EDIT_DUP, .node = 10, .new_node = 11, .nel = 1, .el = el + 1};
    CHECK(kt_step_add(&s, &d2, &e) == KT_OK, "%s", e.msg);
    CHECK(kt_edits_write_step(f, &s, &e) == KT_OK, "%s", e.msg);
    CHECK(kt_edits_write_done(f, 2, &e) == KT_OK, "%s", e.msg);
    kt_step_free(&s);
    fclose(f);

    kt_edits_reader r;
    FILE *g = fmemopen(buf, len, "r");
    CHECK(kt_edits_open(&r, g, "mem", &e) == KT_OK, "%s", e.msg);
    CHECK(strcmp(r.h.scene, h.scene) == 0 && strcmp(r.h.plan, h.plan) == 0 &&
              strcmp(r.h.mesh, h.mesh) == 0 && r.h.nn == 10 && r.h.ne == 7,
          "header '%s' '%s' '%s' %d %d", r.h.scene, r.h.plan, r.h.mesh, r.h.nn, r.h.ne);
    kt_step t = {0};
    CHECK(kt_edits_next(&r, &t, &e) == 1, "%s", e.msg);
    CHECK(t.index == 1 && strcmp(t.label, "arc 0-5 deg (a #1\nb)") == 0 && t.n == 3, "step 1 %d '%s' %d",
          t.index, t.label, t.n);
    if (t.n == 3) {
        CHECK(t.edit[0].kind == KT_EDIT_DUP && t.edit[0].node == 4 && t.edit[0].new_node == 10 &&
                  t.edit[0].nel == 3 && t.edit[0].el[0] == 0 && t.edit[0].el[1] == 6 &&
                  t.edit[0].el[2] == 3, "dup read back");
        CHECK(t.edit[1].kind == KT_EDIT_FIX && t.edit[1].node == 10 && t.edit[1].mask == 5 &&
                  t.edit[1].v[0] == 0.1 && t.edit[1].v[2] == -1.0 / 3, "fix read back exactly");
        CHECK(t.edit[2].kind == KT_EDIT_FORCE && t.edit[2].node == 2 && t.edit[2].v[0] == 1e-3 &&
                  t.edit[2].v[1] == -2.5 && t.edit[2].v[2] == 0, "force read back exactly");
    }
    CHECK(kt_edits_next(&r, &t, &e) == 1 && t.index == 2 && t.n == 1 && t.edit[0].new_node == 11,
          "step 2: %s", e.msg);
    CHECK(kt_edits_next(&r, &t, &e) == 0 && r.done, "end of stream: %s", e.msg);
    CHECK(kt_edits_next(&r, &t, &e) == 0, "after the end: %s", e.msg);
    kt_step_free(&t);
    fclose(g);
    free(buf);
}

static void test_comments_and_blanks(void)
{
    const char *text = "# made by hand\n\nkeratome-edits 1   # version\nmesh m.msh 5 2\n"
                       "step 1\n  force 5 0 0 1 # pull\n\nend\nstep 2 two words\nend\ndone 2 # all\n\n";
    kt_err e = {0};
    kt_edits_reader r;
    kt_step s = {0};
    CHECK(parse_all(text, &e, &r, &s) == 2, "%s", e.msg);
    CHECK(r.h.scene[0] == '\0' && strcmp(r.h.mesh, "m.msh") == 0, "optional scene");
    FILE *f = fmemopen((void *)text, strlen(text), "r");
    CHECK(kt_edits_open(&r, f, "t", &e) == KT_OK && kt_edits_next(&r, &s, &e) == 1 &&
              s.n == 1 && s.edit[0].v[2] == 1 && kt_edits_next(&r, &s, &e) == 1,
          "%s", e.msg);
    CHECK(strcmp(s.label, "two words") == 0 && s.n == 0, "label '%s'", s.label);
    fclose(f);
    kt_step_free(&s);
}

/* The mesh hash line: written when set, read back exactly; absent in older headers. */
static void test_hash(void)
{
    kt_err e = {0};
    char *buf = NULL;
    size_t len = 0;
    FILE *f = open_memstream(&buf, &len);
    kt_edits_header h = {0};
    strcpy(h.mesh, "m.msh");
    h.nn = 5;
    h.ne = 2;
    h.has_hash = 1;
    h.hash = 0xf00dcafe0123abcdull;
    CHECK(kt_edits_write_header(f, &h, &e) == KT_OK, "%s", e.msg);
    fclose(f);
    CHECK(strstr(buf, "\nhash f00dcafe0123abcd\nmesh \"m.msh\" 5 2\n") != NULL, "header text: %s", buf);
    kt_edits_reader r;
    FILE *g = fmemopen(buf, len, "r");
    CHECK(kt_edits_open(&r, g, "t", &e) == KT_OK && r.h.has_hash && r.h.hash == h.hash,
          "hash read back: %s", e.msg);
    fclose(g);
    free(buf);
    const char *old = "keratome-edits 1\nmesh m.msh 5 2\n";
    g = fmemopen((void *)old, strlen(old), "r");
    CHECK(kt_edits_open(&r, g, "t", &e) == KT_OK && !r.h.has_hash,
          "a header without hash is read: %s", e.msg);
    fclose(g);
}

/* Bounds (keratome-edits(5), LIMITS) refuse before anything is allocated for them. */
static void test_limits(void)
{
    char buf[512];
    expect_error("keratome-edits 1\nmesh m.msh 100000001 2\n", "t.edits:2:12:", "1..100000000");
    expect_error("keratome-edits 1\nmesh m.msh 5 2000000000\n", "t.edits:2:14:", "1..100000000");
    snprintf(buf, sizeof buf, "keratome-edits 1\nmesh m.msh 5 99999999\nstep 1\ndup 1 6 99999999 1\nend\n");
    expect_error(buf, "t.edits:4:9:", "count of moved tets in 1..10000");
    expect_error("keratome-edits 1\nhash 12\nmesh m.msh 5 2\n", "t.edits:2:6:", "16 lower-case hex");
    expect_error("keratome-edits 1\nhash 0123456789abcdeg\nmesh m.msh 5 2\n", "t.edits:2:6:", "hex");
    expect_error("keratome-edits 1\nhash 0123456789abcdef\nhash 0123456789abcdef\nmesh m.msh 5 2\n",
                 "t.edits:3:1:", "second");
}

/* The stream's end (issue 26, item 1): a stream without its 'done N' record, or whose count
 * is not the steps read, is cut short; so is a header alone. */
static void test_end(void)
{
    const char *H = "keratome-edits 1\nmesh m.msh 5 2\n";
    char buf[512];
    expect_error(H, "t.edits:2:", "expected 'step 1', found the end of the stream (a header alone");
    snprintf(buf, sizeof buf, "%sstep 1\nforce 1 0 0 1\nend\nstep 2\nend\n", H);
    expect_error(buf, "t.edits:7:", "expected 'step 3' or 'done 2'");
    snprintf(buf, sizeof buf, "%sstep 1\nend\ndone 3\n", H);
    expect_error(buf, "t.edits:5:6:", "expected 'done 1'");
    snprintf(buf, sizeof buf, "%sdone 0\n", H);
    expect_error(buf, "t.edits:3:1:", "at least one step");
    snprintf(buf, sizeof buf, "%sstep 1\nend\ndone 1 x\n", H);
    expect_error(buf, "t.edits:5:8:", "end of line");
    snprintf(buf, sizeof buf, "%sstep 1\nend\ndone 1\nstep 2\nend\n", H);
    expect_error(buf, "t.edits:6:1:", "end of the stream after 'done 1'");
    snprintf(buf, sizeof buf, "%sstep 1\nend\ndone\n", H);
    expect_error(buf, "t.edits:5:5:", "expected 'done 1'");
    kt_err e = {0};
    kt_edits_reader r;
    kt_step s = {0};
    snprintf(buf, sizeof buf, "%sstep 1\nend\n  done 1   # the end\n# more\n\n", H);
    CHECK(parse_all(buf, &e, &r, &s) == 1, "done with a comment: %s", e.msg);
    kt_step_free(&s);
}

/* Quoted paths and labels (item 4): escapes, and what the reader refuses. */
static void test_quoted(void)
{
    kt_err e = {0};
    kt_edits_reader r;
    kt_step s = {0};
    const char *t = "keratome-edits 1\nscene \"/a b/eye #2.yaml\"  # c\nplan \"p\\x41\\\\\\\"q\\n\"\n"
                    "mesh \"m #1.msh\" 5 2\nstep 1 \"x # y\"\nend\ndone 1\n";
    CHECK(parse_all(t, &e, &r, &s) == 1, "quoted: %s", e.msg);
    CHECK(strcmp(r.h.scene, "/a b/eye #2.yaml") == 0 && strcmp(r.h.plan, "pA\\\"q\n") == 0 &&
              strcmp(r.h.mesh, "m #1.msh") == 0 && r.h.nn == 5 && r.h.ne == 2,
          "quoted: '%s' '%s' '%s' %d %d", r.h.scene, r.h.plan, r.h.mesh, r.h.nn, r.h.ne);
    FILE *f = fmemopen((void *)t, strlen(t), "r");
    CHECK(kt_edits_open(&r, f, "t", &e) == KT_OK && kt_edits_next(&r, &s, &e) == 1 &&
              strcmp(s.label, "x # y") == 0, "quoted label '%s': %s", s.label, e.msg);
    fclose(f);
    kt_step_free(&s);
    expect_error("keratome-edits 1\nscene \"abc\n", "t.edits:2:7:", "closed by '\"'");
    expect_error("keratome-edits 1\nscene \"a\\qb\"\n", "t.edits:2:9:", "escape");
    expect_error("keratome-edits 1\nscene \"a\\x00\"\n", "t.edits:2:9:", "escape");
    expect_error("keratome-edits 1\nscene \"a\"b\n", "t.edits:2:10:", "blank after");
    expect_error("keratome-edits 1\nscene \"a\" b\n", "t.edits:2:11:", "end of line");
    expect_error("keratome-edits 1\nscene \"\"\n", "t.edits:2:7:", "found \"\"");
    expect_error("keratome-edits 1\nmesh \"m\" 5\n", "t.edits:2:11:", "tet count");
}

int main(void)
{
    test_end();
    test_quoted();
    test_roundtrip();
    test_hash();
    test_limits();
    test_comments_and_blanks();
    const char *H = "keratome-edits 1\nmesh m.msh 5 2\n";
    char buf[512];
    expect_error("", "t.edits:0:", "empty stream");
    expect_error("keratome-edits 2\n", "t.edits:1:16:", "version 1");
    expect_error("keratome-edits 1\nscene a\n", "t.edits:2:", "'mesh");
    expect_error("keratome-edits 1\nmesh m.msh 5 2\nstep 1\nend\nfoo\n", "t.edits:5:1:", "'done 1'");
    expect_error("keratome-edits 1\nmesh m.msh five 2\n", "t.edits:2:12:", "node count");
    expect_error("keratome-edits 1\nfoo\n", "t.edits:2:1:", "header line");
    snprintf(buf, sizeof buf, "%sstep 2\nend\n", H);
    expect_error(buf, "t.edits:3:6:", "step number 1");
    snprintf(buf, sizeof buf, "%sstep 1\ndup 1 6 1 2\n", H);
    expect_error(buf, "t.edits:4:", "'end' of step 1");
    snprintf(buf, sizeof buf, "%sstep 1\ndup 9 6 1 2\nend\n", H);
    expect_error(buf, "t.edits:4:5:", "node number in 1..5");
    snprintf(buf, sizeof buf, "%sstep 1\ndup 1 7 1 2\nend\n", H);
    expect_error(buf, "t.edits:4:7:", "new node number 6");
    snprintf(buf, sizeof buf, "%sstep 1\ndup 1 6 2 2 3\nend\n", H);
    expect_error(buf, "t.edits:4:13:", "tet number in 1..2");
    snprintf(buf, sizeof buf, "%sstep 1\ndup 1 6 2 2 2\nend\n", H);
    expect_error(buf, "t.edits:4:13:", "distinct");
    snprintf(buf, sizeof buf, "%sstep 1\ndup 1 6 1 2 1\nend\n", H);
    expect_error(buf, "t.edits:4:13:", "end of line");
    snprintf(buf, sizeof buf, "%sstep 1\ndup 1 6 1 2\nforce 6 0 0 1\nend\nstep 2\nforce 7 1 1 1\nend\n", H);
    expect_error(buf, "t.edits:8:7:", "node number in 1..6");
    snprintf(buf, sizeof buf, "%sstep 1\nfix 1 xw 0 0\nend\n", H);
    expect_error(buf, "t.edits:4:7:", "'xyz'");
    snprintf(buf, sizeof buf, "%sstep 1\nfix 1 xx 0 0\nend\n", H);
    expect_error(buf, "t.edits:4:7:", "distinct");
    snprintf(buf, sizeof buf, "%sstep 1\nfix 1 xz 0\nend\n", H);
    expect_error(buf, "t.edits:4:11:", "displacement");
    snprintf(buf, sizeof buf, "%sstep 1\nforce 1 0 nan 0\nend\n", H);
    expect_error(buf, "t.edits:4:11:", "finite");
    snprintf(buf, sizeof buf, "%sstep 1\nmove 1\nend\n", H);
    expect_error(buf, "t.edits:4:1:", "'dup'");
    return kt_test_done("test_edits");
}
