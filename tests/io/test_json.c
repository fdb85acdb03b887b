/* test_json.c: the JSON writer (lib/io/json.h): escaping ('"', '\', the control characters,
 * U+007F), valid UTF-8 passed through and invalid bytes replaced by U+FFFD, numbers finite or
 * null, nesting and pretty layout, and a misuse reported by kt_json_finish. The text is
 * compared with what RFC 8259 says it must be (tests/lriplan_json.sh parses a whole plan.json
 * with Python's json module). */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "json.h"
#include "kt_test.h"

/* What fn writes, as a string (caller frees). */
static char *capture(void (*fn)(kt_json *j), int pretty, int *rc)
{
    char *buf = NULL;
    size_t n = 0;
    FILE *f = open_memstream(&buf, &n);
    kt_json j;
    kt_err e = {0};
    kt_json_begin(&j, f, pretty);
    fn(&j);
    *rc = kt_json_finish(&j, "test", &e);
    fclose(f);
    return buf;
}

static void strings(kt_json *j)
{
    kt_json_obj(j, NULL);
    kt_json_str(j, "name", "O\"Brien \\ test\nline\ttab\x01\x7f");
    kt_json_str(j, "utf8", "Bj\xc3\xb6rk \xe2\x82\xac \xf0\x9f\x91\x81");
    kt_json_str(j, "latin1", "Bj\xf6rk \xc3");  /* not UTF-8: a Latin-1 byte, a cut sequence */
    kt_json_str(j, "surrogate", "\xed\xa0\x80"); /* an encoded surrogate is not UTF-8 */
    kt_json_end(j);
}

static void numbers(kt_json *j)
{
    kt_json_obj(j, NULL);
    kt_json_num(j, "a", 1.23456, 3);
    kt_json_num(j, "b", 2.5e-7, -4);
    kt_json_num(j, "nan", NAN, 3);
    kt_json_num(j, "inf", -INFINITY, -6);
    kt_json_int(j, "i", -42);
    kt_json_bool(j, "t", 1);
    kt_json_null(j, "z");
    kt_json_arr(j, "v");
    kt_json_num(j, NULL, 1, 0), kt_json_obj(j, NULL), kt_json_end(j), kt_json_arr(j, NULL), kt_json_end(j);
    kt_json_end(j);
    kt_json_end(j);
}

static void misuse_key(kt_json *j)
{
    kt_json_arr(j, NULL);
    kt_json_num(j, "key in an array", 1, 0);
    kt_json_end(j);
}

static void misuse_open(kt_json *j) { kt_json_obj(j, NULL); }

int main(void)
{
    int rc;
    char *s = capture(strings, 0, &rc);
    CHECK(rc == KT_OK, "strings written");
    const char *want = "{\"name\": \"O\\\"Brien \\\\ test\\nline\\ttab\\u0001\\u007f\", "
                       "\"utf8\": \"Bj\xc3\xb6rk \xe2\x82\xac \xf0\x9f\x91\x81\", \"latin1\": \"Bj\\ufffdrk \\ufffd\", "
                       "\"surrogate\": \"\\ufffd\\ufffd\\ufffd\"}\n";
    CHECK(strcmp(s, want) == 0, "escaped:\n%s\nwant\n%s", s, want);
    free(s);
    s = capture(numbers, 0, &rc);
    want = "{\"a\": 1.235, \"b\": 2.5e-07, \"nan\": null, \"inf\": null, \"i\": -42, \"t\": true, \"z\": null, "
           "\"v\": [1, {}, []]}\n";
    CHECK(rc == KT_OK && strcmp(s, want) == 0, "numbers:\n%s\nwant\n%s", s, want);
    free(s);
    s = capture(numbers, 1, &rc);
    CHECK(rc == KT_OK && strncmp(s, "{\n  \"a\": 1.235,\n  \"b\": 2.5e-07,", 30) == 0 && strstr(s, "\n  \"v\": [1, {}, []]\n}\n"),
          "pretty: the top object's members a line each:\n%s", s);
    free(s);
    s = capture(misuse_key, 0, &rc);
    CHECK(rc == KT_ERUN, "a key inside an array is a misuse");
    free(s);
    s = capture(misuse_open, 0, &rc);
    CHECK(rc == KT_ERUN, "an object left open is a misuse");
    free(s);
    return kt_test_done("test_json");
}
