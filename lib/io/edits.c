/* edits.c: reader and writer of the edits stream (man5 keratome-edits). */
#define _POSIX_C_SOURCE 200809L
#include "edits.h"

#include "mesh.h"

#include <errno.h>
#include <inttypes.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

/* A line being tokenized in place: tokens are split by blanks, columns are 1-based. */
typedef struct cursor {
    const char *line;
    char *p;
    int col;  /* column of the last token returned */
    int eol;  /* column just after the line's last character */
} cursor;

static cursor cursor_at(char *line)
{
    cursor c = {line, line, 1, (int)strlen(line) + 1};
    return c;
}

/* Record "name:line:col: msg" as bad input. */
static int bad(const kt_edits_reader *r, int col, kt_err *e, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));
static int bad(const kt_edits_reader *r, int col, kt_err *e, const char *fmt, ...)
{
    char msg[768];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    if (col > 0) return kt_fail(e, KT_EINPUT, "%s:%ld:%d: %s", r->name, r->line, col, msg);
    return kt_fail(e, KT_EINPUT, "%s:%ld: %s", r->name, r->line, msg);
}

static int is_blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; }

/* Cut a comment ('#' at the start or after a blank, outside a quoted string) and trailing
 * blanks; 1 if anything is left. */
static int strip(char *s)
{
    int quoted = 0;
    for (char *p = s; *p; p++) {
        if (quoted && *p == '\\' && p[1]) {
            p++;
            continue;
        }
        if (*p == '"') quoted = !quoted;
        if (!quoted && *p == '#' && (p == s || is_blank(p[-1]))) {
            *p = '\0';
            break;
        }
    }
    size_t n = strlen(s);
    while (n > 0 && is_blank(s[n - 1])) s[--n] = '\0';
    for (char *p = s; *p; p++)
        if (!is_blank(*p)) return 1;
    return 0;
}

/* The next content line into *buf; 1 read, 0 at end of stream, -1 error. A UTF-8 byte-order
 * mark at the start of the stream is skipped. */
static int read_line(kt_edits_reader *r, char **buf, size_t *cap, kt_err *e)
{
    for (;;) {
        errno = 0;
        long n = kt_line_read(r->f, buf, cap, KT_EDITS_MAX_LINE, e);
        if (n == -4) return -1;
        if (n == -1) {
            if (ferror(r->f)) return kt_fail(e, KT_ERUN, "%s: read error: %s", r->name,
                                             strerror(errno)), -1;
            return 0;
        }
        r->line++;
        if (n == -3)
            return bad(r, 0, e, "expected a line of at most %d bytes, found more", KT_EDITS_MAX_LINE), -1;
        if (n == -2)
            return bad(r, 0, e, "expected text, found a NUL byte"), -1;
        if (r->line == 1 && strncmp(*buf, "\xef\xbb\xbf", 3) == 0) memmove(*buf, *buf + 3, (size_t)n - 2);
        if (strip(*buf)) return 1;
    }
}

static char *next_tok(cursor *c)
{
    while (*c->p && is_blank(*c->p)) c->p++;
    if (!*c->p) return NULL;
    char *t = c->p;
    c->col = (int)(t - c->line) + 1;
    while (*c->p && !is_blank(*c->p)) c->p++;
    if (*c->p) *c->p++ = '\0';
    return t;
}

/* The rest of the line, trimmed of leading blanks (NULL if empty). */
static char *rest(cursor *c)
{
    while (*c->p && is_blank(*c->p)) c->p++;
    if (!*c->p) return NULL;
    c->col = (int)(c->p - c->line) + 1;
    return c->p;
}

/* A 1-based number in [1, max] converted to 0-based. */
static int get_index(kt_edits_reader *r, cursor *c, int max, const char *what, int *v, kt_err *e)
{
    char *t = next_tok(c);
    int col = t ? c->col : c->eol;
    int x;
    if (!t || kt_parse_int(t, &x) != 0)
        return bad(r, col, e, "expected %s (an integer)%s%s", what, t ? ", found " : "", t ? t : "");
    if (x < 1 || x > max)
        return bad(r, col, e, "expected %s in 1..%d, found %d", what, max, x);
    *v = x - 1;
    return KT_OK;
}

static int get_double(kt_edits_reader *r, cursor *c, const char *what, double *v, kt_err *e)
{
    char *t = next_tok(c);
    int col = t ? c->col : c->eol;
    if (!t || kt_parse_number(t, v) != 0)
        return bad(r, col, e, "expected %s (a finite number)%s%s", what, t ? ", found " : "",
                   t ? t : "");
    return KT_OK;
}

static int expect_end_of_line(kt_edits_reader *r, cursor *c, kt_err *e)
{
    char *t = next_tok(c);
    if (t) return bad(r, c->col, e, "expected end of line, found '%s'", t);
    return KT_OK;
}

static int hex_digit(char ch)
{
    return ch >= '0' && ch <= '9' ? ch - '0' : ch >= 'a' && ch <= 'f' ? ch - 'a' + 10
         : ch >= 'A' && ch <= 'F' ? ch - 'A' + 10 : -1;
}

/* A double-quoted string at c->p (the writers' form of paths and labels, keratome-edits(5)):
 * its unescaped text into dst (size bytes); c->p moves past the closing quote. */
static int get_quoted(kt_edits_reader *r, cursor *c, char *dst, size_t size, const char *what,
                      kt_err *e)
{
    int col0 = (int)(c->p - c->line) + 1;
    size_t n = 0;
    char *p = c->p + 1;
    for (;; p++) {
        int col = (int)(p - c->line) + 1;
        char ch = *p;
        if (ch == '\0') return bad(r, col0, e, "expected %s closed by '\"'", what);
        if (ch == '"') break;
        if (ch == '\\') {
            char x = *++p;
            int h1, h2;
            if (x == '\\' || x == '"') ch = x;
            else if (x == 'n') ch = '\n';
            else if (x == 't') ch = '\t';
            else if (x == 'r') ch = '\r';
            else if (x == 'x' && (h1 = hex_digit(p[1])) >= 0 && (h2 = hex_digit(p[2])) >= 0 &&
                     (h1 || h2)) {
                ch = (char)(16 * h1 + h2);
                p += 2;
            } else
                return bad(r, col, e, "expected an escape \\\\, \\\", \\n, \\t, \\r or \\xHH "
                           "(not 00) in %s", what);
        }
        if (n + 1 >= size) return bad(r, col0, e, "expected %s under %zu bytes", what, size);
        dst[n++] = ch;
    }
    dst[n] = '\0';
    if (n == 0) return bad(r, col0, e, "expected %s, found \"\"", what);
    c->p = p + 1;
    if (*c->p && !is_blank(*c->p))
        return bad(r, (int)(c->p - c->line) + 1, e, "expected a blank after the closing '\"'");
    return KT_OK;
}

/* A path after its keyword: a quoted string (what cutplan writes), or else the rest of the
 * line, at most 1023 bytes. */
static int get_path(kt_edits_reader *r, cursor *c, const char *key, char *dst, kt_err *e)
{
    if (dst[0]) return bad(r, 1, e, "expected one '%s' header line, found a second", key);
    char *t = rest(c);
    if (!t) return bad(r, c->eol, e, "expected a file name after '%s'", key);
    if (*t == '"') {
        if (get_quoted(r, c, dst, 1024, "a file name", e)) return e->code;
        return expect_end_of_line(r, c, e);
    }
    if (strlen(t) >= 1024) return bad(r, c->col, e, "expected a file name under 1024 bytes");
    strcpy(dst, t);
    return KT_OK;
}

/* "mesh "FILE" NN NE" (quoted, as cutplan writes it), then expected end of line. */
static int parse_mesh_quoted(kt_edits_reader *r, cursor *c, kt_err *e)
{
    if (get_quoted(r, c, r->h.mesh, sizeof r->h.mesh, "a file name", e)) return e->code;
    char *t = next_tok(c);
    if (!t || kt_parse_int(t, &r->h.nn) != 0 || r->h.nn < 1 || r->h.nn > KT_MESH_MAX_NODES)
        return bad(r, t ? c->col : c->eol, e, "expected the mesh node count (an integer in 1..%d)%s%s",
                   KT_MESH_MAX_NODES, t ? ", found " : "", t ? t : "");
    t = next_tok(c);
    if (!t || kt_parse_int(t, &r->h.ne) != 0 || r->h.ne < 1 || r->h.ne > KT_MESH_MAX_TETS)
        return bad(r, t ? c->col : c->eol, e, "expected the mesh tet count (an integer in 1..%d)%s%s",
                   KT_MESH_MAX_TETS, t ? ", found " : "", t ? t : "");
    return expect_end_of_line(r, c, e);
}

/* "mesh FILE NN NE": the file name quoted, or bare (it may then hold blanks: the counts are
 * the last two tokens). */
static int parse_mesh_line(kt_edits_reader *r, cursor *c, kt_err *e)
{
    char *t = rest(c);
    if (t && *t == '"') return parse_mesh_quoted(r, c, e);
    int col0 = t ? c->col : c->eol;
    char *sp2 = t ? strrchr(t, ' ') : NULL;
    char *tab2 = t ? strrchr(t, '\t') : NULL;
    if (tab2 > sp2) sp2 = tab2;
    if (!t || !sp2) return bad(r, col0, e, "expected 'mesh FILE NODES TETS'");
    char *ne_s = sp2 + 1;
    int ne_col = (int)(ne_s - c->line) + 1;
    while (sp2 > t && is_blank(sp2[-1])) sp2--;
    *sp2 = '\0';
    char *sp1 = strrchr(t, ' '), *tab1 = strrchr(t, '\t');
    if (tab1 > sp1) sp1 = tab1;
    if (!sp1) return bad(r, col0, e, "expected 'mesh FILE NODES TETS'");
    char *nn_s = sp1 + 1;
    int nn_col = (int)(nn_s - c->line) + 1;
    while (sp1 > t && is_blank(sp1[-1])) sp1--;
    *sp1 = '\0';
    if (kt_parse_int(nn_s, &r->h.nn) != 0 || r->h.nn < 1 || r->h.nn > KT_MESH_MAX_NODES)
        return bad(r, nn_col, e, "expected the mesh node count (an integer in 1..%d), found '%s'",
                   KT_MESH_MAX_NODES, nn_s);
    if (kt_parse_int(ne_s, &r->h.ne) != 0 || r->h.ne < 1 || r->h.ne > KT_MESH_MAX_TETS)
        return bad(r, ne_col, e, "expected the mesh tet count (an integer in 1..%d), found '%s'",
                   KT_MESH_MAX_TETS, ne_s);
    if (strlen(t) >= sizeof r->h.mesh) return bad(r, col0, e, "expected a file name under 1024 bytes");
    strcpy(r->h.mesh, t);
    return KT_OK;
}

/* "hash HEX": the mesh's content hash, exactly 16 hex digits. */
static int parse_hash(kt_edits_reader *r, cursor *c, kt_err *e)
{
    if (r->h.has_hash) return bad(r, 1, e, "expected one 'hash' header line, found a second");
    char *t = next_tok(c);
    int col = t ? c->col : c->eol;
    uint64_t v = 0;
    size_t n = t ? strlen(t) : 0;
    for (size_t i = 0; i < n && n == 16; i++) {
        char ch = t[i];
        int d = ch >= '0' && ch <= '9' ? ch - '0' : ch >= 'a' && ch <= 'f' ? ch - 'a' + 10 : -1;
        if (d < 0) n = 0;
        v = v << 4 | (uint64_t)(d < 0 ? 0 : d);
    }
    if (n != 16)
        return bad(r, col, e, "expected the mesh hash as 16 lower-case hex digits%s%s",
                   t ? ", found " : "", t ? t : "");
    r->h.hash = v;
    r->h.has_hash = 1;
    return expect_end_of_line(r, c, e);
}

static int parse_version(kt_edits_reader *r, char *line, kt_err *e)
{
    cursor c = cursor_at(line);
    char *t = next_tok(&c);
    if (!t || strcmp(t, "keratome-edits") != 0)
        return bad(r, c.col, e, "expected 'keratome-edits 1' (the format's first line)");
    t = next_tok(&c);
    if (!t || strcmp(t, "1") != 0)
        return bad(r, t ? c.col : c.eol, e, "expected format version 1%s%s",
                   t ? ", found " : "", t ? t : "");
    return expect_end_of_line(r, &c, e);
}

int kt_edits_open(kt_edits_reader *r, FILE *f, const char *name, kt_err *e)
{
    memset(r, 0, sizeof *r);
    r->f = f;
    r->name = name;
    struct stat st;
    if (fstat(fileno(f), &st) == 0 && S_ISDIR(st.st_mode))
        return kt_fail(e, KT_EINPUT, "%s: cannot read: is a directory", name);
    char *buf = NULL;
    size_t cap = 0;
    int rc = read_line(r, &buf, &cap, e);
    if (rc == 0) bad(r, 0, e, "expected 'keratome-edits 1', found an empty stream");
    if (rc > 0) parse_version(r, buf, e);
    while (e->code == KT_OK) {
        rc = read_line(r, &buf, &cap, e);
        if (rc < 0) break;
        if (rc == 0) {
            bad(r, 0, e, "expected a 'mesh FILE NODES TETS' header line before the end");
            break;
        }
        cursor c = cursor_at(buf);
        char *key = next_tok(&c);
        if (strcmp(key, "scene") == 0) {
            get_path(r, &c, "scene", r->h.scene, e);
        } else if (strcmp(key, "plan") == 0) {
            get_path(r, &c, "plan", r->h.plan, e);
        } else if (strcmp(key, "hash") == 0) {
            parse_hash(r, &c, e);
        } else if (strcmp(key, "mesh") == 0) {
            if (parse_mesh_line(r, &c, e) == KT_OK) break;
        } else {
            bad(r, c.col, e, "expected a header line 'scene', 'plan', 'hash' or 'mesh', found '%s'", key);
        }
    }
    free(buf);
    r->nn_cur = r->h.nn;
    return e->code;
}

/* Make room for one more edit in s. */
static kt_edit *grow(kt_step *s, kt_err *e)
{
    if (s->n == s->cap) {
        int cap = s->cap ? 2 * s->cap : 16;
        kt_edit *ed = kt_realloc(s->edit, (size_t)cap, sizeof *ed, e);
        if (!ed) return NULL;
        s->edit = ed;
        s->cap = cap;
    }
    kt_edit *ed = &s->edit[s->n];
    memset(ed, 0, sizeof *ed);
    return ed;
}

static int parse_dup(kt_edits_reader *r, cursor *c, kt_step *s, kt_err *e)
{
    kt_edit ed = {0};
    ed.kind = KT_EDIT_DUP;
    ed.line = r->line;
    if (get_index(r, c, r->nn_cur, "a node number", &ed.node, e)) return e->code;
    if (get_index(r, c, INT_MAX, "the new node's number", &ed.new_node, e)) return e->code;
    if (ed.new_node != r->nn_cur)
        return bad(r, c->col, e, "expected new node number %d (the next free one), found %d",
                   r->nn_cur + 1, ed.new_node + 1);
    if (r->nn_cur >= KT_MESH_MAX_NODES)
        return bad(r, c->col, e, "expected at most %d nodes, duplicated ones included",
                   KT_MESH_MAX_NODES);
    int most = r->h.ne < KT_EDITS_MAX_DUP_TETS ? r->h.ne : KT_EDITS_MAX_DUP_TETS;
    if (get_index(r, c, most, "the count of moved tets", &ed.nel, e)) return e->code;
    ed.nel++;
    kt_edit *slot = grow(s, e);
    if (!slot) return e->code;
    ed.el = kt_calloc((size_t)ed.nel, sizeof(int), e);
    if (!ed.el) return e->code;
    for (int i = 0; i < ed.nel; i++) {
        if (get_index(r, c, r->h.ne, "a tet number", &ed.el[i], e)) break;
        if (i == 0) ed.col = c->col;
        for (int j = 0; j < i; j++)
            if (ed.el[j] == ed.el[i]) {
                bad(r, c->col, e, "expected distinct tets, found %d twice", ed.el[i] + 1);
                break;
            }
        if (e->code) break;
    }
    if (e->code == KT_OK) expect_end_of_line(r, c, e);
    if (e->code) {
        free(ed.el);
        return e->code;
    }
    *slot = ed;
    s->n++;
    r->nn_cur++;
    return KT_OK;
}

static int parse_fix(kt_edits_reader *r, cursor *c, kt_step *s, kt_err *e)
{
    kt_edit ed = {0};
    ed.kind = KT_EDIT_FIX;
    ed.line = r->line;
    if (get_index(r, c, r->nn_cur, "a node number", &ed.node, e)) return e->code;
    char *t = next_tok(c);
    int col = t ? c->col : c->eol;
    if (!t) return bad(r, col, e, "expected components (a subset of 'xyz')");
    for (const char *p = t; *p; p++) {
        unsigned bit = *p == 'x' ? 1u : *p == 'y' ? 2u : *p == 'z' ? 4u : 0u;
        if (!bit || (ed.mask & bit))
            return bad(r, col, e, "expected components as distinct letters of 'xyz', found '%s'", t);
        ed.mask |= bit;
    }
    for (int k = 0; k < 3; k++)
        if (ed.mask & (1u << k))
            if (get_double(r, c, "a displacement in mm", &ed.v[k], e)) return e->code;
    if (expect_end_of_line(r, c, e)) return e->code;
    return kt_step_add(s, &ed, e);
}

static int parse_force(kt_edits_reader *r, cursor *c, kt_step *s, kt_err *e)
{
    kt_edit ed = {0};
    ed.kind = KT_EDIT_FORCE;
    ed.line = r->line;
    if (get_index(r, c, r->nn_cur, "a node number", &ed.node, e)) return e->code;
    for (int k = 0; k < 3; k++)
        if (get_double(r, c, "a force component in N", &ed.v[k], e)) return e->code;
    if (expect_end_of_line(r, c, e)) return e->code;
    return kt_step_add(s, &ed, e);
}

/* "step N [label]": N must follow the previous step. */
static int parse_step_line(kt_edits_reader *r, char *line, kt_step *s, kt_err *e)
{
    cursor c = cursor_at(line);
    char *key = next_tok(&c);
    if (strcmp(key, "step") != 0)
        return bad(r, c.col, e, "expected 'step %d' or 'done %d', found '%s'", r->last_step + 1,
                   r->last_step, key);
    int idx;
    char *t = next_tok(&c);
    if (r->last_step >= KT_EDITS_MAX_STEPS)
        return bad(r, c.col, e, "expected at most %d steps", KT_EDITS_MAX_STEPS);
    if (!t || kt_parse_int(t, &idx) != 0 || idx != r->last_step + 1)
        return bad(r, t ? c.col : c.eol, e, "expected step number %d%s%s",
                   r->last_step + 1, t ? ", found " : "", t ? t : "");
    s->index = idx;
    char *label = rest(&c);
    if (label && *label == '"') {
        if (get_quoted(r, &c, s->label, sizeof s->label, "a label", e)) return e->code;
        return expect_end_of_line(r, &c, e);
    }
    if (label) snprintf(s->label, sizeof s->label, "%s", label);
    return KT_OK;
}

/* "done N", the stream's last record: N, the number of steps, must be the steps read. */
static int parse_done(kt_edits_reader *r, cursor *c, kt_err *e)
{
    char *t = next_tok(c);
    int n;
    if (!t || kt_parse_int(t, &n) != 0 || n != r->last_step)
        return bad(r, t ? c->col : c->eol, e, "expected 'done %d' (the number of steps read)%s%s",
                   r->last_step, t ? ", found done " : "", t ? t : "");
    if (n < 1) return bad(r, 1, e, "expected at least one step before 'done'");
    return expect_end_of_line(r, c, e);
}

static int parse_edit_line(kt_edits_reader *r, char *line, kt_step *s, int *done, kt_err *e)
{
    cursor c = cursor_at(line);
    char *key = next_tok(&c);
    long most = 4L * r->nn_cur + 1024; /* edits in one step: bounded by the mesh (man5) */
    if (s->n >= most && strcmp(key, "end") != 0)
        return bad(r, c.col, e, "expected at most %ld edits in step %d (4 per node and 1024)",
                   most, s->index);
    if (strcmp(key, "dup") == 0) return parse_dup(r, &c, s, e);
    if (strcmp(key, "fix") == 0) return parse_fix(r, &c, s, e);
    if (strcmp(key, "force") == 0) return parse_force(r, &c, s, e);
    if (strcmp(key, "end") == 0) {
        *done = 1;
        return expect_end_of_line(r, &c, e);
    }
    return bad(r, c.col, e, "expected 'dup', 'fix', 'force' or 'end', found '%s'", key);
}

/* After "done": only blanks and comments may follow. */
static int after_done(kt_edits_reader *r, char **buf, size_t *cap, kt_err *e)
{
    int rc = read_line(r, buf, cap, e);
    if (rc > 0) {
        cursor c = cursor_at(*buf);
        char *t = next_tok(&c);
        return bad(r, c.col, e, "expected the end of the stream after 'done %d', found '%s'",
                   r->last_step, t);
    }
    return rc < 0 ? e->code : KT_OK;
}

int kt_edits_next(kt_edits_reader *r, kt_step *s, kt_err *e)
{
    kt_step_clear(s);
    if (r->done) return 0;
    char *buf = NULL;
    size_t cap = 0;
    int rc = read_line(r, &buf, &cap, e);
    if (rc == 0 && r->last_step == 0)
        bad(r, 0, e, "expected 'step 1', found the end of the stream (a header alone, cut short: "
            "the writer stopped or the pipe broke)");
    else if (rc == 0)
        bad(r, 0, e, "expected 'step %d' or 'done %d', found the end of the stream (cut short: "
            "the writer stopped or the pipe broke)", r->last_step + 1, r->last_step);
    if (rc <= 0) {
        free(buf);
        return -1;
    }
    const char *k = buf;
    while (is_blank(*k)) k++;
    if (strncmp(k, "done", 4) == 0 && (k[4] == '\0' || is_blank(k[4]))) {
        cursor c0 = cursor_at(buf);
        next_tok(&c0);
        if (parse_done(r, &c0, e) == KT_OK) after_done(r, &buf, &cap, e);
        free(buf);
        if (e->code) return -1;
        r->done = 1;
        return 0;
    }
    int done = 0;
    if (parse_step_line(r, buf, s, e) == KT_OK) {
        while (!done) {
            rc = read_line(r, &buf, &cap, e);
            if (rc < 0) break;
            if (rc == 0) {
                bad(r, 0, e, "expected 'end' of step %d, found the end of the stream", s->index);
                break;
            }
            if (parse_edit_line(r, buf, s, &done, e)) break;
        }
    }
    free(buf);
    if (e->code) return -1;
    r->last_step = s->index;
    return 1;
}

void kt_step_clear(kt_step *s)
{
    for (int i = 0; i < s->n; i++) free(s->edit[i].el);
    s->n = 0;
    s->index = 0;
    s->label[0] = '\0';
}

void kt_step_free(kt_step *s)
{
    kt_step_clear(s);
    free(s->edit);
    memset(s, 0, sizeof *s);
}

int kt_step_add(kt_step *s, const kt_edit *ed, kt_err *e)
{
    int *el = NULL;
    if (ed->kind == KT_EDIT_DUP) {
        el = kt_calloc(ed->nel > 0 ? (size_t)ed->nel : 1, sizeof(int), e);
        if (!el) return e->code;
        if (ed->nel > 0) memcpy(el, ed->el, (size_t)ed->nel * sizeof(int));
    }
    kt_edit *slot = grow(s, e);
    if (!slot) {
        free(el);
        return e->code;
    }
    *slot = *ed;
    slot->el = el;
    s->n++;
    return KT_OK;
}

static int check_written(FILE *f, kt_err *e)
{
    if (fflush(f) != 0 || ferror(f)) return kt_fail(e, KT_ERUN, "write failed: %s",
                                                    kt_io_cause(errno));
    return KT_OK;
}

/* s double-quoted: '\\' and '"' escaped, control bytes as \n \t \r or \xHH, so '#', blanks,
 * quotes and newlines in a path survive the reader (keratome-edits(5)). */
static void put_quoted(FILE *f, const char *s)
{
    fputc('"', f);
    for (const unsigned char *p = (const unsigned char *)s; *p; p++) {
        if (*p == '\\' || *p == '"') fprintf(f, "\\%c", *p);
        else if (*p == '\n') fputs("\\n", f);
        else if (*p == '\t') fputs("\\t", f);
        else if (*p == '\r') fputs("\\r", f);
        else if (*p < 0x20 || *p == 0x7f) fprintf(f, "\\x%02x", *p);
        else fputc(*p, f);
    }
    fputc('"', f);
}

static void put_path_line(FILE *f, const char *key, const char *path)
{
    fprintf(f, "%s ", key);
    put_quoted(f, path);
    fputc('\n', f);
}

int kt_edits_write_header(FILE *f, const kt_edits_header *h, kt_err *e)
{
    fprintf(f, "keratome-edits 1\n");
    if (h->scene[0]) put_path_line(f, "scene", h->scene);
    if (h->plan[0]) put_path_line(f, "plan", h->plan);
    if (h->has_hash) fprintf(f, "hash %016" PRIx64 "\n", h->hash);
    fputs("mesh ", f);
    put_quoted(f, h->mesh[0] ? h->mesh : "-");
    fprintf(f, " %d %d\n", h->nn, h->ne);
    return check_written(f, e);
}

int kt_edits_write_done(FILE *f, int nsteps, kt_err *e)
{
    if (nsteps < 1) return kt_fail(e, KT_ERUN, "edits: a stream needs at least one step");
    fprintf(f, "done %d\n", nsteps);
    return check_written(f, e);
}

int kt_edits_write_step(FILE *f, const kt_step *s, kt_err *e)
{
    fprintf(f, "step %d", s->index);
    if (s->label[0]) {
        fputc(' ', f);
        put_quoted(f, s->label);
    }
    fputc('\n', f);
    static const char comp[3] = {'x', 'y', 'z'};
    for (int i = 0; i < s->n; i++) {
        const kt_edit *ed = &s->edit[i];
        if ((ed->kind == KT_EDIT_DUP && ed->nel < 1) || (ed->kind == KT_EDIT_FIX && !(ed->mask & 7u)))
            return kt_fail(e, KT_ERUN, "edits: step %d: edit %d moves no tet or fixes no component",
                           s->index, i + 1);
        if (ed->kind == KT_EDIT_DUP) {
            fprintf(f, "dup %d %d %d", ed->node + 1, ed->new_node + 1, ed->nel);
            for (int j = 0; j < ed->nel; j++) fprintf(f, " %d", ed->el[j] + 1);
            fputc('\n', f);
        } else if (ed->kind == KT_EDIT_FIX) {
            fprintf(f, "fix %d ", ed->node + 1);
            for (int k = 0; k < 3; k++)
                if (ed->mask & (1u << k)) fputc(comp[k], f);
            for (int k = 0; k < 3; k++)
                if (ed->mask & (1u << k)) fprintf(f, " %.17g", ed->v[k]);
            fputc('\n', f);
        } else if (ed->kind == KT_EDIT_FORCE) {
            fprintf(f, "force %d %.17g %.17g %.17g\n", ed->node + 1, ed->v[0], ed->v[1], ed->v[2]);
        } else {
            return kt_fail(e, KT_ERUN, "edits: unknown edit kind %d", ed->kind);
        }
    }
    fprintf(f, "end\n");
    return check_written(f, e);
}
