/* yml.c: libyaml document loading and strict typed access with file:line:col errors. */
#include "yml.h"
#include "units.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

const kt_yml_bounds KT_YML_ANY = {-HUGE_VAL, HUGE_VAL, 0, 0};
const kt_yml_bounds KT_YML_POSITIVE = {0, HUGE_VAL, 1, 0};
const kt_yml_bounds KT_YML_NONNEG = {0, HUGE_VAL, 0, 0};

/* Units by dimension: name and factor to the internal unit. */
typedef struct unit {
    int dim;
    const char *name;
    double factor;
} unit;

static const unit UNITS[] = {
    {KT_UNIT_LENGTH, "mm", 1.0},
    {KT_UNIT_LENGTH, "um", 1e-3},
    {KT_UNIT_LENGTH, "\xc2\xb5m", 1e-3}, /* micro sign */
    {KT_UNIT_LENGTH, "cm", 10.0},
    {KT_UNIT_LENGTH, "m", 1e3},
    {KT_UNIT_PRESSURE, "MPa", 1.0},
    {KT_UNIT_PRESSURE, "kPa", 1e-3},
    {KT_UNIT_PRESSURE, "Pa", 1e-6},
    {KT_UNIT_PRESSURE, "GPa", 1e3},
    {KT_UNIT_PRESSURE, "N/mm2", 1.0},
    {KT_UNIT_PRESSURE, "N/mm^2", 1.0},
    /* 1 mmHg = 133.322387415 Pa (conventional millimetre of mercury). */
    {KT_UNIT_PRESSURE, "mmHg", KT_MMHG_MPA},
    {KT_UNIT_ANGLE, "deg", 1.0},
    {KT_UNIT_ANGLE, "rad", 57.295779513082320876798},
    {KT_UNIT_FORCE, "N", 1.0},
    {KT_UNIT_FORCE, "mN", 1e-3},
    {KT_UNIT_FORCE, "kN", 1e3},
    {KT_UNIT_POWER, "D", 1.0},
    {KT_UNIT_STIFFNESS, "MPa/mm", 1.0},
    {KT_UNIT_STIFFNESS, "N/mm3", 1.0},
    {KT_UNIT_STIFFNESS, "N/mm^3", 1.0},
    {KT_UNIT_STIFFNESS, "kPa/mm", 1e-3},
    {KT_UNIT_RATE, "/y", 1.0},
    {KT_UNIT_RATE, "1/y", 1.0},
    {KT_UNIT_RATE, "/year", 1.0},
    {KT_UNIT_RATE, "%/y", 0.01},
    /* a month is a twelfth of a Julian year (365.25 d) */
    {KT_UNIT_TIME, "months", 1.0},
    {KT_UNIT_TIME, "month", 1.0},
    {KT_UNIT_TIME, "d", 12 / 365.25},
    {KT_UNIT_TIME, "days", 12 / 365.25},
    {KT_UNIT_TIME, "wk", 12 * 7 / 365.25},
    {KT_UNIT_TIME, "weeks", 12 * 7 / 365.25},
    {KT_UNIT_TIME, "y", 12.0},
    {KT_UNIT_TIME, "years", 12.0},
};
#define NUNITS ((int)(sizeof UNITS / sizeof UNITS[0]))

/* The dimension with its article, for messages. */
static const char *A_DIM[] = {"a number", "a length", "a pressure", "an angle", "a force", "a power",
                              "a stiffness per area", "a rate per year", "a time"};
static const char *DIM_UNITS[] = {"", "mm, um, cm, m", "MPa, kPa, Pa, GPa, mmHg, N/mm2",
                                  "deg, rad", "N, mN, kN", "D", "MPa/mm, N/mm3, kPa/mm",
                                  "/y, 1/y, %/y", "months, d, wk, y"};

const char *kt_yml_unit_name(int dim)
{
    static const char *INTERNAL[] = {"", "mm", "MPa", "deg", "N", "D", "MPa/mm", "/y", "months"};
    return dim >= 0 && dim <= KT_UNIT_LAST ? INTERNAL[dim] : "";
}

static const char *file_name(const kt_yml *y) { return strcmp(y->path, "-") ? y->path : "<stdin>"; }

int kt_yml_line(const yaml_node_t *n) { return n ? (int)n->start_mark.line + 1 : 1; }
int kt_yml_col(const yaml_node_t *n) { return n ? (int)n->start_mark.column + 1 : 1; }

int kt_yml_fail(kt_yml *y, const yaml_node_t *n, kt_err *e, const char *fmt, ...)
{
    char msg[900];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    if (!n) return kt_fail(e, KT_EINPUT, "%s: %s", file_name(y), msg);
    return kt_fail(e, KT_EINPUT, "%s:%d:%d: %s", file_name(y), kt_yml_line(n), kt_yml_col(n), msg);
}

/* The parser's complaint as one line with the position it names. */
static int parse_error(kt_yml *y, const yaml_parser_t *p, kt_err *e)
{
    const char *problem = p->problem ? p->problem : "unknown error";
    if (p->error == YAML_READER_ERROR)
        return kt_fail(e, KT_EINPUT, "%s: byte %zu: expected UTF-8 YAML text: %s", file_name(y),
                       p->problem_offset, problem);
    if (p->error == YAML_MEMORY_ERROR) return kt_fail(e, KT_ERUN, "%s: out of memory", file_name(y));
    char ctx[256] = "";
    if (p->context)
        snprintf(ctx, sizeof ctx, " (%s at line %d)", p->context, (int)p->context_mark.line + 1);
    return kt_fail(e, KT_EINPUT, "%s:%d:%d: expected well-formed YAML: %s%s", file_name(y),
                   (int)p->problem_mark.line + 1, (int)p->problem_mark.column + 1, problem, ctx);
}

/* A scene or plan is one document: a second one is refused rather than ignored. */
static int single_document(kt_yml *y, yaml_parser_t *p, kt_err *e)
{
    yaml_document_t next;
    if (!yaml_parser_load(p, &next)) {
        parse_error(y, p, e);
        yaml_document_delete(&y->doc);
        return 0;
    }
    yaml_node_t *root = yaml_document_get_root_node(&next);
    if (root)
        kt_fail(e, KT_EINPUT, "%s:%d:%d: expected a single YAML document, found a second one",
                file_name(y), (int)next.start_mark.line + 1, (int)next.start_mark.column + 1);
    yaml_document_delete(&next);
    if (!root) return 1;
    yaml_document_delete(&y->doc);
    return 0;
}

/* The whole file into *text (at most KT_YML_MAX_BYTES; more is refused before parsing). */
static int read_text(kt_yml *y, const char *path, unsigned char **text, size_t *len, kt_err *e)
{
    FILE *f = strcmp(path, "-") ? fopen(path, "rb") : stdin;
    if (!f) return kt_fail(e, KT_EINPUT, "%s: cannot open: %s", path, strerror(errno));
    struct stat st;
    if (fstat(fileno(f), &st) == 0 && S_ISDIR(st.st_mode)) {
        if (f != stdin) fclose(f);
        return kt_fail(e, KT_EINPUT, "%s: cannot read: is a directory", file_name(y));
    }
    size_t cap = 4096, n = 0, got;
    unsigned char *b = kt_calloc(cap, 1, e);
    while (b && (got = fread(b + n, 1, cap - n, f)) > 0) {
        n += got;
        if (n > KT_YML_MAX_BYTES) {
            kt_fail(e, KT_EINPUT, "%s: expected a YAML file of at most %d bytes", file_name(y),
                    KT_YML_MAX_BYTES);
            break;
        }
        if (n == cap) {
            unsigned char *nb = kt_realloc(b, 2 * cap, 1, e);
            if (!nb) break;
            b = nb, cap *= 2;
        }
    }
    if (b && !e->code && ferror(f)) kt_fail(e, KT_EINPUT, "%s: read error: %s", path, strerror(errno));
    if (f != stdin) fclose(f);
    if (e->code) {
        free(b);
        return e->code;
    }
    *text = b;
    *len = n;
    return KT_OK;
}

/* A first pass over the parser's events: collections nest at most KT_YML_MAX_DEPTH deep. A
 * syntax error is left to the loading pass, which reports it. */
static int check_depth(kt_yml *y, const unsigned char *text, size_t len, kt_err *e)
{
    yaml_parser_t p;
    if (!yaml_parser_initialize(&p))
        return kt_fail(e, KT_ERUN, "%s: cannot initialize the YAML parser", file_name(y));
    yaml_parser_set_input_string(&p, text, len);
    int depth = 0, done = 0;
    while (!done && !e->code) {
        yaml_event_t ev;
        if (!yaml_parser_parse(&p, &ev)) break;
        if (ev.type == YAML_SEQUENCE_START_EVENT || ev.type == YAML_MAPPING_START_EVENT) {
            if (++depth > KT_YML_MAX_DEPTH)
                kt_fail(e, KT_EINPUT, "%s:%d:%d: expected blocks nested at most %d deep",
                        file_name(y), (int)ev.start_mark.line + 1, (int)ev.start_mark.column + 1,
                        KT_YML_MAX_DEPTH);
        } else if (ev.type == YAML_SEQUENCE_END_EVENT || ev.type == YAML_MAPPING_END_EVENT) {
            depth--;
        }
        done = ev.type == YAML_STREAM_END_EVENT;
        yaml_event_delete(&ev);
    }
    yaml_parser_delete(&p);
    return e->code;
}

int kt_yml_load(kt_yml *y, const char *path, kt_err *e)
{
    memset(y, 0, sizeof *y);
    if (strlen(path) >= sizeof y->path)
        return kt_fail(e, KT_EINPUT, "%.200s...: path too long", path);
    strcpy(y->path, path);
    unsigned char *text = NULL;
    size_t len = 0;
    if (read_text(y, path, &text, &len, e)) return e->code;
    if (check_depth(y, text, len, e)) {
        free(text);
        return e->code;
    }
    yaml_parser_t p;
    if (!yaml_parser_initialize(&p)) {
        free(text);
        return kt_fail(e, KT_ERUN, "%s: cannot initialize the YAML parser", path);
    }
    yaml_parser_set_input_string(&p, text, len);
    int ok = yaml_parser_load(&p, &y->doc);
    if (!ok) parse_error(y, &p, e);
    if (ok && yaml_document_get_root_node(&y->doc)) ok = single_document(y, &p, e);
    yaml_parser_delete(&p);
    free(text);
    if (!ok) return e->code;
    y->loaded = 1;
    if (!yaml_document_get_root_node(&y->doc)) {
        kt_yml_free(y);
        return kt_fail(e, KT_EINPUT, "%s:1:1: expected a YAML mapping, found an empty document", path);
    }
    return KT_OK;
}

void kt_yml_free(kt_yml *y)
{
    if (y->loaded) yaml_document_delete(&y->doc);
    y->loaded = 0;
}

static const char *type_name(const yaml_node_t *n)
{
    if (!n) return "nothing";
    if (n->type == YAML_MAPPING_NODE) return "a mapping";
    if (n->type == YAML_SEQUENCE_NODE) return "a sequence";
    return "a scalar";
}

yaml_node_t *kt_yml_root(kt_yml *y, kt_err *e)
{
    yaml_node_t *r = y->loaded ? yaml_document_get_root_node(&y->doc) : NULL;
    if (!r || r->type != YAML_MAPPING_NODE) {
        kt_yml_fail(y, r, e, "expected a mapping of keys at the top level, found %s", type_name(r));
        return NULL;
    }
    return r;
}

/* The text of a scalar node, or NULL if n is not a scalar. */
static const char *scalar(const yaml_node_t *n)
{
    return n && n->type == YAML_SCALAR_NODE ? (const char *)n->data.scalar.value : NULL;
}

int kt_yml_map_len(const yaml_node_t *n)
{
    if (!n || n->type != YAML_MAPPING_NODE) return 0;
    return (int)(n->data.mapping.pairs.top - n->data.mapping.pairs.start);
}

const char *kt_yml_map_key(kt_yml *y, const yaml_node_t *n, int i, yaml_node_t **key_node,
                           yaml_node_t **value)
{
    if (i < 0 || i >= kt_yml_map_len(n)) return NULL;
    yaml_node_pair_t *pair = n->data.mapping.pairs.start + i;
    yaml_node_t *k = yaml_document_get_node(&y->doc, pair->key);
    if (key_node) *key_node = k;
    if (value) *value = yaml_document_get_node(&y->doc, pair->value);
    return scalar(k);
}

/* "a, b, c" from a NULL-terminated list, truncated to fit. */
static void join(const char *const *list, char *buf, size_t size)
{
    buf[0] = 0;
    for (int i = 0; list && list[i]; i++) {
        size_t len = strlen(buf);
        snprintf(buf + len, size - len, "%s%s", i ? ", " : "", list[i]);
    }
}

int kt_yml_check_map(kt_yml *y, const yaml_node_t *n, const char *what,
                     const char *const *allowed, kt_err *e)
{
    if (!n || n->type != YAML_MAPPING_NODE)
        return kt_yml_fail(y, n, e, "%s: expected a mapping of keys, found %s", what, type_name(n));
    int len = kt_yml_map_len(n);
    for (int i = 0; i < len; i++) {
        yaml_node_t *kn;
        const char *key = kt_yml_map_key(y, n, i, &kn, NULL);
        if (!key) return kt_yml_fail(y, kn, e, "%s: expected a plain key, found %s", what, type_name(kn));
        for (int j = 0; j < i; j++) {
            yaml_node_t *prev;
            const char *pk = kt_yml_map_key(y, n, j, &prev, NULL);
            if (pk && strcmp(pk, key) == 0)
                return kt_yml_fail(y, kn, e, "%s: duplicate key '%s' (first given at line %d)", what,
                                   key, kt_yml_line(prev));
        }
        if (!allowed) continue;
        int known = 0;
        for (int j = 0; allowed[j] && !known; j++) known = strcmp(allowed[j], key) == 0;
        if (!known) {
            char list[600];
            join(allowed, list, sizeof list);
            return kt_yml_fail(y, kn, e, "%s: unknown key '%s', expected one of: %s", what, key, list);
        }
    }
    return KT_OK;
}

yaml_node_t *kt_yml_get(kt_yml *y, const yaml_node_t *map, const char *key)
{
    int len = kt_yml_map_len(map);
    for (int i = 0; i < len; i++) {
        yaml_node_t *v;
        const char *k = kt_yml_map_key(y, map, i, NULL, &v);
        if (k && strcmp(k, key) == 0) return v;
    }
    return NULL;
}

yaml_node_t *kt_yml_require(kt_yml *y, const yaml_node_t *map, const char *key, const char *what,
                            kt_err *e)
{
    yaml_node_t *v = kt_yml_get(y, map, key);
    if (!v) kt_yml_fail(y, map, e, "%s: expected key '%s'", what, key);
    return v;
}

int kt_yml_seq_len(const yaml_node_t *n)
{
    if (!n || n->type != YAML_SEQUENCE_NODE) return 0;
    return (int)(n->data.sequence.items.top - n->data.sequence.items.start);
}

yaml_node_t *kt_yml_seq_item(kt_yml *y, const yaml_node_t *n, int i)
{
    if (i < 0 || i >= kt_yml_seq_len(n)) return NULL;
    return yaml_document_get_node(&y->doc, n->data.sequence.items.start[i]);
}

int kt_yml_check_seq(kt_yml *y, const yaml_node_t *n, const char *what, int min_len,
                     int max_len, kt_err *e)
{
    if (!n || n->type != YAML_SEQUENCE_NODE)
        return kt_yml_fail(y, n, e, "%s: expected a sequence, found %s", what, type_name(n));
    int len = kt_yml_seq_len(n);
    if (len < min_len || len > max_len) {
        if (min_len == max_len)
            return kt_yml_fail(y, n, e, "%s: expected %d items, found %d", what, min_len, len);
        return kt_yml_fail(y, n, e, "%s: expected %d to %d items, found %d", what, min_len, max_len, len);
    }
    return KT_OK;
}

/* The scalar text of n, or an error "expected <kind>". */
static const char *need_scalar(kt_yml *y, const yaml_node_t *n, const char *what, const char *kind,
                               kt_err *e)
{
    const char *s = scalar(n);
    if (!s) {
        kt_yml_fail(y, n, e, "%s: expected %s, found %s", what, kind, type_name(n));
        return NULL;
    }
    if (strlen(s) != n->data.scalar.length) {
        kt_yml_fail(y, n, e, "%s: expected %s, found a string with a NUL byte", what, kind);
        return NULL;
    }
    return s;
}

static int in_bounds(double v, kt_yml_bounds b)
{
    if (b.lo_open ? !(v > b.lo) : !(v >= b.lo)) return 0;
    if (b.hi_open ? !(v < b.hi) : !(v <= b.hi)) return 0;
    return 1;
}

/* " > 0 mm", " in [0, 1)", or "" for no bounds. */
static void bounds_text(kt_yml_bounds b, const char *u, char *buf, size_t size)
{
    const char *sp = *u ? " " : "";
    int has_lo = isfinite(b.lo), has_hi = isfinite(b.hi);
    if (has_lo && has_hi)
        snprintf(buf, size, " in %c%g, %g%c%s%s", b.lo_open ? '(' : '[', b.lo, b.hi,
                 b.hi_open ? ')' : ']', sp, u);
    else if (has_lo)
        snprintf(buf, size, " %s %g%s%s", b.lo_open ? ">" : ">=", b.lo, sp, u);
    else if (has_hi)
        snprintf(buf, size, " %s %g%s%s", b.hi_open ? "<" : "<=", b.hi, sp, u);
    else
        buf[0] = 0;
}

/* strtod over the whole leading number; *end after it. 0 on success. */
static int lead_number(const char *s, double *v, const char **end)
{
    while (*s == ' ' || *s == '\t') s++;
    if (!*s) return -1;
    char *p;
    errno = 0;
    double x = strtod(s, &p);
    if (p == s || errno == ERANGE || !isfinite(x)) return -1;
    *v = x;
    *end = p;
    return 0;
}

int kt_yml_parse_quantity(const char *text, int dim, double *v)
{
    double x;
    const char *p;
    if (lead_number(text, &x, &p)) return -1;
    while (*p == ' ' || *p == '\t') p++;
    if (dim == KT_UNIT_NONE) {
        if (*p) return -1;
        *v = x;
        return 0;
    }
    size_t len = strlen(p);
    while (len && (p[len - 1] == ' ' || p[len - 1] == '\t')) len--;
    for (int i = 0; i < NUNITS; i++)
        if (UNITS[i].dim == dim && strlen(UNITS[i].name) == len && strncmp(UNITS[i].name, p, len) == 0) {
            *v = x * UNITS[i].factor;
            return 0;
        }
    return -1;
}

/* Explain why text is not a quantity of dimension dim. */
static int quantity_error(kt_yml *y, const yaml_node_t *n, const char *what, int dim,
                          const char *text, kt_err *e)
{
    double x;
    const char *p;
    if (lead_number(text, &x, &p))
        return kt_yml_fail(y, n, e, "%s: expected %s with a unit (%s), got '%s'", what,
                           A_DIM[dim], DIM_UNITS[dim], text);
    while (*p == ' ' || *p == '\t') p++;
    if (!*p)
        return kt_yml_fail(y, n, e, "%s: expected %s with a unit (%s), got '%s' without a unit",
                           what, A_DIM[dim], DIM_UNITS[dim], text);
    for (int i = 0; i < NUNITS; i++)
        if (strcmp(UNITS[i].name, p) == 0)
            return kt_yml_fail(y, n, e, "%s: expected %s (%s), got %s in '%s'", what,
                               A_DIM[dim], DIM_UNITS[dim], A_DIM[UNITS[i].dim], text);
    return kt_yml_fail(y, n, e, "%s: expected %s unit (%s), got unknown unit '%s'", what,
                       A_DIM[dim], DIM_UNITS[dim], p);
}

int kt_yml_quantity(kt_yml *y, const yaml_node_t *n, const char *what, int dim, kt_yml_bounds b,
                    double *v, kt_err *e)
{
    if (dim < 0 || dim > KT_UNIT_LAST) return kt_fail(e, KT_ERUN, "%s: bad unit dimension %d", what, dim);
    const char *s = need_scalar(y, n, what, dim ? "a quantity with a unit" : "a number", e);
    if (!s) return e->code;
    double x;
    if (dim == KT_UNIT_NONE) {
        if (kt_yml_parse_quantity(s, dim, &x))
            return kt_yml_fail(y, n, e, "%s: expected a number, got '%s'", what, s);
    } else if (kt_yml_parse_quantity(s, dim, &x)) {
        return quantity_error(y, n, what, dim, s, e);
    }
    if (!in_bounds(x, b)) {
        char range[160];
        bounds_text(b, kt_yml_unit_name(dim), range, sizeof range);
        return kt_yml_fail(y, n, e, "%s: expected %s%s, got '%s'", what, A_DIM[dim], range, s);
    }
    *v = x;
    return KT_OK;
}

int kt_yml_number(kt_yml *y, const yaml_node_t *n, const char *what, kt_yml_bounds b,
                  double *v, kt_err *e)
{
    return kt_yml_quantity(y, n, what, KT_UNIT_NONE, b, v, e);
}

int kt_yml_int(kt_yml *y, const yaml_node_t *n, const char *what, int lo, int hi, int *v,
               kt_err *e)
{
    const char *s = need_scalar(y, n, what, "an integer", e);
    if (!s) return e->code;
    char *p;
    errno = 0;
    long x = strtol(s, &p, 10);
    while (*p == ' ') p++;
    if (p == s || *p || errno == ERANGE || x < INT_MIN || x > INT_MAX)
        return kt_yml_fail(y, n, e, "%s: expected an integer, got '%s'", what, s);
    if (x < lo || x > hi)
        return kt_yml_fail(y, n, e, "%s: expected an integer in [%d, %d], got '%s'", what, lo, hi, s);
    *v = (int)x;
    return KT_OK;
}

int kt_yml_bool(kt_yml *y, const yaml_node_t *n, const char *what, int *v, kt_err *e)
{
    const char *s = need_scalar(y, n, what, "true or false", e);
    if (!s) return e->code;
    if (!strcmp(s, "true") || !strcmp(s, "True") || !strcmp(s, "TRUE")) *v = 1;
    else if (!strcmp(s, "false") || !strcmp(s, "False") || !strcmp(s, "FALSE")) *v = 0;
    else return kt_yml_fail(y, n, e, "%s: expected true or false, got '%s'", what, s);
    return KT_OK;
}

int kt_yml_string(kt_yml *y, const yaml_node_t *n, const char *what, char *buf, size_t size,
                  kt_err *e)
{
    const char *s = need_scalar(y, n, what, "a string", e);
    if (!s) return e->code;
    if (!*s) return kt_yml_fail(y, n, e, "%s: expected a non-empty string", what);
    if (strlen(s) >= size)
        return kt_yml_fail(y, n, e, "%s: expected a string of at most %zu characters", what, size - 1);
    strcpy(buf, s);
    return KT_OK;
}

int kt_yml_choice(kt_yml *y, const yaml_node_t *n, const char *what, const char *const *choices,
                  int *idx, kt_err *e)
{
    char list[600];
    join(choices, list, sizeof list);
    const char *s = scalar(n);
    if (!s) return kt_yml_fail(y, n, e, "%s: expected one of: %s, found %s", what, list, type_name(n));
    for (int i = 0; choices[i]; i++)
        if (strcmp(choices[i], s) == 0) {
            *idx = i;
            return KT_OK;
        }
    return kt_yml_fail(y, n, e, "%s: expected one of: %s, got '%s'", what, list, s);
}

/* "<what>.<key>" for messages. */
static const char *field(char *buf, size_t size, const char *what, const char *key)
{
    if (what && *what) snprintf(buf, size, "%s.%s", what, key);
    else snprintf(buf, size, "%s", key);
    return buf;
}

int kt_yml_key_number(kt_yml *y, const yaml_node_t *map, const char *what, const char *key,
                      kt_yml_bounds b, double *v, kt_err *e)
{
    yaml_node_t *n = kt_yml_get(y, map, key);
    char f[256];
    return n ? kt_yml_number(y, n, field(f, sizeof f, what, key), b, v, e) : KT_OK;
}

int kt_yml_key_int(kt_yml *y, const yaml_node_t *map, const char *what, const char *key, int lo,
                   int hi, int *v, kt_err *e)
{
    yaml_node_t *n = kt_yml_get(y, map, key);
    char f[256];
    return n ? kt_yml_int(y, n, field(f, sizeof f, what, key), lo, hi, v, e) : KT_OK;
}

int kt_yml_key_bool(kt_yml *y, const yaml_node_t *map, const char *what, const char *key, int *v,
                    kt_err *e)
{
    yaml_node_t *n = kt_yml_get(y, map, key);
    char f[256];
    return n ? kt_yml_bool(y, n, field(f, sizeof f, what, key), v, e) : KT_OK;
}

int kt_yml_key_string(kt_yml *y, const yaml_node_t *map, const char *what, const char *key,
                      char *buf, size_t size, kt_err *e)
{
    yaml_node_t *n = kt_yml_get(y, map, key);
    char f[256];
    return n ? kt_yml_string(y, n, field(f, sizeof f, what, key), buf, size, e) : KT_OK;
}

int kt_yml_key_choice(kt_yml *y, const yaml_node_t *map, const char *what, const char *key,
                      const char *const *choices, int *idx, kt_err *e)
{
    yaml_node_t *n = kt_yml_get(y, map, key);
    char f[256];
    return n ? kt_yml_choice(y, n, field(f, sizeof f, what, key), choices, idx, e) : KT_OK;
}

int kt_yml_key_quantity(kt_yml *y, const yaml_node_t *map, const char *what, const char *key,
                        int dim, kt_yml_bounds b, double *v, kt_err *e)
{
    yaml_node_t *n = kt_yml_get(y, map, key);
    char f[256];
    return n ? kt_yml_quantity(y, n, field(f, sizeof f, what, key), dim, b, v, e) : KT_OK;
}

void kt_yml_put_quoted(FILE *f, const char *v)
{
    fputc('"', f);
    for (const unsigned char *p = (const unsigned char *)v; *p; p++) {
        if (*p == '"' || *p == '\\') fprintf(f, "\\%c", *p);
        else if (*p == '\n') fputs("\\n", f);
        else if (*p == '\t') fputs("\\t", f);
        else if (*p < 0x20 || *p == 0x7f) fprintf(f, "\\x%02x", *p);
        else fputc(*p, f);
    }
    fputc('"', f);
}

void kt_yml_put_comment(FILE *f, const char *s)
{
    fputs("# ", f);
    for (; *s; s++) {
        if (*s == '\n') fputs("\n# ", f);
        else fputc((unsigned char)*s < 0x20 || *s == 0x7f ? ' ' : *s, f);
    }
    fputc('\n', f);
}
