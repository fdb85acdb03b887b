/* yml.h: a libyaml document with strict, typed access for scene and plan files.
 *
 * Every error is KT_EINPUT with one line "file:line:col: what was expected" (1-based line and
 * column of the offending node). Quantities are strings with a unit ("7.8 mm", "540 um",
 * "15 mmHg", "0.3 MPa", "90 deg") converted to the internal units mm, MPa, deg, N, D. */
#ifndef KT_YML_H
#define KT_YML_H

#include <stdio.h>
#include <yaml.h>

#include "util.h"

/* Bounds on any scene or plan file (keratome-scene(5), LIMITS), checked before it is parsed:
 * its size, and how deep blocks (mappings, sequences) nest. Strings are bounded by the field
 * they fill (names KT_NAME_MAX, paths 1024 bytes). */
#define KT_YML_MAX_BYTES (1 << 20)
#define KT_YML_MAX_DEPTH 16

/* A loaded document; nodes returned by the getters live as long as it does. */
typedef struct kt_yml {
    yaml_document_t doc;
    char path[1024];            /* as given; "-" reads stdin and is named <stdin> */
    int loaded;
} kt_yml;

/* Dimensions of quantities, each with its internal unit. */
enum {
    KT_UNIT_NONE = 0,  /* a plain number, no unit allowed */
    KT_UNIT_LENGTH,    /* mm   (also um, cm, m) */
    KT_UNIT_PRESSURE,  /* MPa  (also Pa, kPa, GPa, mmHg, N/mm2) */
    KT_UNIT_ANGLE,     /* deg  (also rad) */
    KT_UNIT_FORCE,     /* N    (also mN, kN) */
    KT_UNIT_POWER,     /* D    (dioptres) */
    KT_UNIT_STIFFNESS, /* MPa/mm, a stiffness per area (also N/mm3, N/mm^3, kPa/mm) */
    KT_UNIT_RATE,      /* /y, a rate per year (also 1/y, /year, %/y) */
    KT_UNIT_TIME       /* months (also month, d, days, wk, weeks, y, years) */
};
#define KT_UNIT_LAST KT_UNIT_TIME

/* Closed or open bounds for range checks: lo <= v (lo < v if lo_open), likewise hi. */
typedef struct kt_yml_bounds {
    double lo, hi;
    int lo_open, hi_open;
} kt_yml_bounds;

extern const kt_yml_bounds KT_YML_ANY;      /* any finite value */
extern const kt_yml_bounds KT_YML_POSITIVE; /* (0, inf) */
extern const kt_yml_bounds KT_YML_NONNEG;   /* [0, inf) */

/* Load the first document of a file ("-" for stdin). A syntax error names file:line:col and
 * the parser's complaint; an empty file is an error. On failure y holds nothing to free. */
int kt_yml_load(kt_yml *y, const char *path, kt_err *e);
void kt_yml_free(kt_yml *y);

/* The root node, which must be a mapping (else KT_EINPUT). */
yaml_node_t *kt_yml_root(kt_yml *y, kt_err *e);

/* Record "file:line:col: <message>" for node n (n NULL: "file: <message>"). */
int kt_yml_fail(kt_yml *y, const yaml_node_t *n, kt_err *e, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));

/* 1-based line and column of a node. */
int kt_yml_line(const yaml_node_t *n);
int kt_yml_col(const yaml_node_t *n);

/* Check that n is a mapping whose keys are plain scalars, each at most once, each in the
 * NULL-terminated list allowed (NULL list: any key). 'what' names the block in messages. */
int kt_yml_check_map(kt_yml *y, const yaml_node_t *n, const char *what,
                     const char *const *allowed, kt_err *e);

/* The value of key in mapping map, or NULL when absent (map NULL: NULL). */
yaml_node_t *kt_yml_get(kt_yml *y, const yaml_node_t *map, const char *key);
/* Same, but absence is an error "expected key 'key' in <what>" at the map. */
yaml_node_t *kt_yml_require(kt_yml *y, const yaml_node_t *map, const char *key, const char *what,
                            kt_err *e);

/* Sequences: check the type and length range; item i (0-based). */
int kt_yml_check_seq(kt_yml *y, const yaml_node_t *n, const char *what, int min_len,
                     int max_len, kt_err *e);
int kt_yml_seq_len(const yaml_node_t *n);
yaml_node_t *kt_yml_seq_item(kt_yml *y, const yaml_node_t *n, int i);

/* The key string of pair i of a mapping (for walking maps with free keys, e.g. materials). */
int kt_yml_map_len(const yaml_node_t *n);
const char *kt_yml_map_key(kt_yml *y, const yaml_node_t *n, int i, yaml_node_t **key_node,
                           yaml_node_t **value);

/* Typed getters on a node; 'what' names the field in messages ("eye.central_thickness"). */
int kt_yml_number(kt_yml *y, const yaml_node_t *n, const char *what, kt_yml_bounds b,
                  double *v, kt_err *e);
int kt_yml_int(kt_yml *y, const yaml_node_t *n, const char *what, int lo, int hi, int *v,
               kt_err *e);
int kt_yml_bool(kt_yml *y, const yaml_node_t *n, const char *what, int *v, kt_err *e);
/* A scalar string that fits in size bytes (including the terminating 0), non-empty. */
int kt_yml_string(kt_yml *y, const yaml_node_t *n, const char *what, char *buf, size_t size,
                  kt_err *e);
/* One of the NULL-terminated choices; *idx is its index. */
int kt_yml_choice(kt_yml *y, const yaml_node_t *n, const char *what, const char *const *choices,
                  int *idx, kt_err *e);
/* A quantity "<number> <unit>" of dimension dim, converted to internal units and checked
 * against b (in internal units). dim KT_UNIT_NONE is a plain number. */
int kt_yml_quantity(kt_yml *y, const yaml_node_t *n, const char *what, int dim, kt_yml_bounds b,
                    double *v, kt_err *e);

/* Optional keys: absent leaves *v unchanged and returns KT_OK; present is parsed as above.
 * 'what' is the block name; messages say "<what>.<key>". */
int kt_yml_key_number(kt_yml *y, const yaml_node_t *map, const char *what, const char *key,
                      kt_yml_bounds b, double *v, kt_err *e);
int kt_yml_key_int(kt_yml *y, const yaml_node_t *map, const char *what, const char *key, int lo,
                   int hi, int *v, kt_err *e);
int kt_yml_key_bool(kt_yml *y, const yaml_node_t *map, const char *what, const char *key, int *v,
                    kt_err *e);
int kt_yml_key_string(kt_yml *y, const yaml_node_t *map, const char *what, const char *key,
                      char *buf, size_t size, kt_err *e);
int kt_yml_key_choice(kt_yml *y, const yaml_node_t *map, const char *what, const char *key,
                      const char *const *choices, int *idx, kt_err *e);
int kt_yml_key_quantity(kt_yml *y, const yaml_node_t *map, const char *what, const char *key,
                        int dim, kt_yml_bounds b, double *v, kt_err *e);

/* Parse "<number> <unit>" text outside a document (e.g. command-line options); 0 on success. */
int kt_yml_parse_quantity(const char *text, int dim, double *v);

/* The internal unit's name for a dimension ("mm", "MPa", ...; "" for KT_UNIT_NONE). */
const char *kt_yml_unit_name(int dim);

/* Writing YAML (scene_write, plan_write, run.yaml): s as a double-quoted scalar ('"' and '\'
 * escaped, a line end as \n, a tab as \t, other control bytes as \xNN: paths may hold ':' '#'
 * or a line end, which a plain scalar cannot); s as a comment, every line of it behind "# "
 * (other control characters as spaces), so no text ends the comment early. */
void kt_yml_put_quoted(FILE *f, const char *s);
void kt_yml_put_comment(FILE *f, const char *s);

#endif
