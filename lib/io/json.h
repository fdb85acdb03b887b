/* json.h: the one JSON writer of the tools (plan.json, curvature --json, lri-nomogram --json):
 * RFC 8259 text, written as it goes onto a FILE (no tree in memory).
 *
 *     kt_json j;
 *     kt_json_begin(&j, f, 1);           (pretty: members of the top object a line each)
 *     kt_json_obj(&j, NULL);             (the top-level object)
 *     kt_json_str(&j, "name", name);
 *     kt_json_num(&j, "cyl_D", 1.234, 3);
 *     kt_json_arr(&j, "steps"); ... kt_json_end(&j);
 *     kt_json_end(&j);
 *     return kt_json_finish(&j, path, e);
 *
 * Keys and strings: '"' and '\' escaped, the control characters U+0000-U+001F and U+007F as
 * \b \f \n \r \t or \u00XX; valid UTF-8 is passed through as it is; a byte that is not part of
 * valid UTF-8 (a Latin-1 name, a cut sequence) becomes U+FFFD, so the output is always valid
 * UTF-8. Numbers: finite ones as "%.*f" (decimals >= 0) or "%.*g" (decimals < 0: -decimals
 * significant digits); NaN and the infinities have no JSON number: they are written as null (a
 * reader sees "no value"), never as a bare NaN. Members are written in the order given; a key is
 * the caller's (no check for duplicates). */
#ifndef KT_JSON_H
#define KT_JSON_H

#include <stdio.h>

#include "util.h"

#define KT_JSON_DEPTH 32

/* The writer's state. Owner: the caller (on its stack); nothing to free. */
typedef struct kt_json {
    FILE *f;
    int depth;                  /* open objects and arrays */
    int pretty;                 /* members at depth <= pretty on their own line, indented */
    unsigned char members[KT_JSON_DEPTH]; /* members written so far at each depth (0 or 1) */
    char close[KT_JSON_DEPTH];  /* '}' or ']' */
    int bad;                    /* a misuse (too deep, a key in an array, an end too many) */
} kt_json;

void kt_json_begin(kt_json *j, FILE *f, int pretty);
/* Open an object / an array as member `key` of the enclosing object (key NULL: an element of
 * the enclosing array, or the top-level value). */
void kt_json_obj(kt_json *j, const char *key);
void kt_json_arr(kt_json *j, const char *key);
/* Close the innermost object or array. */
void kt_json_end(kt_json *j);
void kt_json_str(kt_json *j, const char *key, const char *s);
void kt_json_num(kt_json *j, const char *key, double v, int decimals);
void kt_json_int(kt_json *j, const char *key, long long v);
void kt_json_bool(kt_json *j, const char *key, int v);
void kt_json_null(kt_json *j, const char *key);
/* Every value closed: the final newline; KT_ERUN naming `what` when the writer was misused or a
 * write failed (ferror). */
int kt_json_finish(kt_json *j, const char *what, kt_err *e);

/* s as a JSON string (with its quotes) on f, escaped as above. */
void kt_json_quote(FILE *f, const char *s);

#endif
