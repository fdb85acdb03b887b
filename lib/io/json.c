/* json.c: the JSON writer (json.h). */
#include "json.h"

#include <math.h>
#include <string.h>

void kt_json_begin(kt_json *j, FILE *f, int pretty)
{
    memset(j, 0, sizeof *j);
    j->f = f;
    j->pretty = pretty;
}

/* The length of the valid UTF-8 sequence at s (1-4), 0 when the bytes there are not one. */
static int utf8_len(const unsigned char *s)
{
    unsigned c = s[0];
    if (c < 0x80) return 1;
    int n = c >= 0xC2 && c <= 0xDF ? 2 : c >= 0xE0 && c <= 0xEF ? 3 : c >= 0xF0 && c <= 0xF4 ? 4 : 0;
    if (!n) return 0;
    for (int k = 1; k < n; k++)
        if ((s[k] & 0xC0) != 0x80) return 0;
    if (c == 0xE0 && s[1] < 0xA0) return 0;   /* overlong */
    if (c == 0xED && s[1] > 0x9F) return 0;   /* a surrogate */
    if (c == 0xF0 && s[1] < 0x90) return 0;   /* overlong */
    if (c == 0xF4 && s[1] > 0x8F) return 0;   /* beyond U+10FFFF */
    return n;
}

void kt_json_quote(FILE *f, const char *str)
{
    const unsigned char *s = (const unsigned char *)(str ? str : "");
    fputc('"', f);
    while (*s) {
        unsigned c = *s;
        int n = utf8_len(s);
        if (c == '"' || c == '\\') fprintf(f, "\\%c", c);
        else if (c == '\n') fputs("\\n", f);
        else if (c == '\t') fputs("\\t", f);
        else if (c == '\r') fputs("\\r", f);
        else if (c == '\b') fputs("\\b", f);
        else if (c == '\f') fputs("\\f", f);
        else if (c < 0x20 || c == 0x7f) fprintf(f, "\\u%04x", c);
        else if (n == 0) fputs("\\ufffd", f); /* not UTF-8: the replacement character */
        else fwrite(s, 1, (size_t)n, f);
        s += n ? n : 1;
    }
    fputc('"', f);
}

/* The separator, the line break and indent, and the key of the next member. */
static void member(kt_json *j, const char *key)
{
    if (j->depth > 0) {
        int d = j->depth - 1;
        int in_obj = j->close[d] == '}';
        if ((in_obj && !key) || (!in_obj && key)) j->bad = 1;
        if (j->members[d]) fputc(',', j->f);
        if (j->depth <= j->pretty) fprintf(j->f, "\n%*s", 2 * j->depth, "");
        else if (j->members[d]) fputc(' ', j->f);
        j->members[d] = 1;
    } else if (key) {
        j->bad = 1;
    }
    if (key && j->depth > 0 && j->close[j->depth - 1] == '}') {
        kt_json_quote(j->f, key);
        fputs(": ", j->f);
    }
}

static void open_(kt_json *j, const char *key, char open, char close)
{
    member(j, key);
    fputc(open, j->f);
    if (j->depth == KT_JSON_DEPTH) {
        j->bad = 1;
        return;
    }
    j->close[j->depth] = close;
    j->members[j->depth] = 0;
    j->depth++;
}

void kt_json_obj(kt_json *j, const char *key) { open_(j, key, '{', '}'); }
void kt_json_arr(kt_json *j, const char *key) { open_(j, key, '[', ']'); }

void kt_json_end(kt_json *j)
{
    if (j->depth == 0) {
        j->bad = 1;
        return;
    }
    j->depth--;
    if (j->members[j->depth] && j->depth < j->pretty) fprintf(j->f, "\n%*s", 2 * j->depth, "");
    fputc(j->close[j->depth], j->f);
}

void kt_json_str(kt_json *j, const char *key, const char *s)
{
    member(j, key);
    kt_json_quote(j->f, s);
}

void kt_json_num(kt_json *j, const char *key, double v, int decimals)
{
    member(j, key);
    if (!isfinite(v)) fputs("null", j->f);
    else if (decimals >= 0) fprintf(j->f, "%.*f", decimals, v);
    else fprintf(j->f, "%.*g", -decimals, v);
}

void kt_json_int(kt_json *j, const char *key, long long v)
{
    member(j, key);
    fprintf(j->f, "%lld", v);
}

void kt_json_bool(kt_json *j, const char *key, int v)
{
    member(j, key);
    fputs(v ? "true" : "false", j->f);
}

void kt_json_null(kt_json *j, const char *key)
{
    member(j, key);
    fputs("null", j->f);
}

int kt_json_finish(kt_json *j, const char *what, kt_err *e)
{
    if (j->bad || j->depth != 0) return kt_fail(e, KT_ERUN, "%s: the JSON writer was misused (an unclosed or misplaced value)", what);
    fputc('\n', j->f);
    if (ferror(j->f)) return kt_fail(e, KT_ERUN, "%s: write failed", what);
    return KT_OK;
}
