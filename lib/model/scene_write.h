/* scene_write.h: write an eye scene as scene YAML (keratome-scene(5)) that kt_scene_load reads
 * back to the same values (lri-plan's PLAN_DIR/scene.yaml). */
#ifndef KT_SCENE_WRITE_H
#define KT_SCENE_WRITE_H

#include <stdio.h>

#include "scene.h"

/* Write s (model eye) to f with every field explicit, quantities in mm, um, MPa, deg and a
 * header comment naming how it was made (may be NULL). KT_ERUN when a write fails. */
int kt_scene_write_eye(FILE *f, const kt_scene *s, const char *header, kt_err *e);

#endif
