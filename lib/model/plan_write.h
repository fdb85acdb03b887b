/* plan_write.h: write an eye plan as plan YAML (keratome-plan(5)) that kt_plan_load reads back
 * to the same values: a plan made in memory (lri-plan's chosen plan, PLAN_DIR/run/plan.yaml),
 * so the tools (cutplan, curvature) can read what was planned. */
#ifndef KT_PLAN_WRITE_H
#define KT_PLAN_WRITE_H

#include <stdio.h>

#include "plan.h"

/* Write p's tunnels, incisions (each with its ring by surface name, or its diameter, and its
 * depth as a fraction or a length), progression and target to f, with name, scene (the path
 * the file names, relative to the file's folder) and a header comment (may be NULL). Deform
 * and planar cuts are not written (KT_EINPUT: a plan that has them is not an eye plan made in
 * memory); KT_ERUN when a write fails. Numbers in %.17g: they read back exactly. */
int kt_plan_write_eye(FILE *f, const kt_plan *p, const char *name, const char *scene, const char *header, kt_err *e);

#endif
