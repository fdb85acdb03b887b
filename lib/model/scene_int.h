/* scene_int.h: what the scene reader's files share (private to lib/model/scene*.c). */
#ifndef KT_SCENE_INT_H
#define KT_SCENE_INT_H

#include "scene.h"
#include <stdio.h>

#include "yml.h"

extern const char *const kt_scene_eye_surfaces[];

/* s is one of the NULL-terminated list. */
int kt_scene_in_list(const char *const *list, const char *s);
/* A group name (letters, digits, '-', '_', '.') from node n into buf (KT_NAME_MAX). */
int kt_scene_name_field(kt_yml *y, const yaml_node_t *n, const char *what, char *buf, kt_err *e);
kt_yml_bounds kt_scene_range(double lo, double hi, int lo_open, int hi_open);

/* The eye block (scene_eye.c). */
void kt_scene_eye_defaults(kt_eye *eye);
int kt_scene_parse_eye(kt_yml *y, const yaml_node_t *n, kt_eye *eye, kt_err *e);

/* The white-to-white of `map` (an eye block or a patient's cornea; keratome-scene(5)): a length,
 * the horizontal diameter (the vertical one KT_EYE_WTW_DIFF less), or {horizontal, vertical},
 * a key left out taking its default (horizontal: *h unchanged; vertical: the horizontal less
 * KT_EYE_WTW_DIFF). Within bh and bv; the vertical at most the horizontal. Absent: *h and *v
 * unchanged. Bad input: KT_EINPUT at file:line:col. */
int kt_scene_parse_wtw(kt_yml *y, const yaml_node_t *map, const char *what, kt_yml_bounds bh, kt_yml_bounds bv,
                       double *h, double *v, kt_err *e);

/* The uncertainty section (scene_unc.c): defaults, then the entries of node n over them. */
void kt_scene_unc_defaults(kt_uncertainty *u);
int kt_scene_parse_uncertainty(kt_yml *y, const yaml_node_t *n, kt_uncertainty *u, kt_err *e);

/* The wound section (scene_wound.c): defaults, the entries of node n over them, and the
 * section as scene_write writes it (every field explicit). */
void kt_scene_wound_defaults(kt_wound_scene *w);
int kt_scene_parse_wound(kt_yml *y, const yaml_node_t *n, kt_wound_scene *w, kt_err *e);
void kt_scene_write_wound(FILE *f, const kt_wound_scene *w);

#endif
