/* scene_wound.c: the scene's `wound:` section (keratome-scene(5), WOUND): the wound's state
 * (immediate or healed) and the healed scar's bridge stiffness, its age rule and time course,
 * with the provisional defaults of scene.h (docs/physics.md, "Healing"). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "scene_int.h"

void kt_scene_wound_defaults(kt_wound_scene *w)
{
    memset(w, 0, sizeof *w);
    w->state = KT_WOUND_IMMEDIATE;
    w->bridge_stiffness = KT_WOUND_K_DEFAULT;
    w->age_rate = KT_WOUND_AGE_RATE_DEFAULT;
    w->age = NAN;
    w->months = NAN;
    w->heal_time = KT_WOUND_HEAL_TIME_DEFAULT;
}

double kt_scene_wound_age(const kt_scene *s)
{
    if (isfinite(s->wound.age)) return s->wound.age;
    if (isfinite(s->unc.age)) return s->unc.age;
    return KT_WOUND_AGE_PIVOT;
}

double kt_scene_wound_k(const kt_scene *s)
{
    return s->wound.state == KT_WOUND_HEALED ? kt_scene_wound_k_healed(s) : 0;
}

double kt_scene_wound_k_healed(const kt_scene *s)
{
    const kt_wound_scene *w = &s->wound;
    double k = w->bridge_stiffness * exp(-w->age_rate * (kt_scene_wound_age(s) - KT_WOUND_AGE_PIVOT));
    if (isfinite(w->months)) k *= -expm1(-w->months / w->heal_time);
    return k;
}

static const char *const WOUND_KEYS[] = {"state", "bridge_stiffness", "age_rate", "age", "months",
                                         "heal_time", NULL};
static const char *const STATES[] = {"immediate", "healed", NULL};

/* Ranges: k up to 1e6 MPa/mm (the uncut eye's limit is reached long before: docs/physics.md);
 * age_rate within +-0.2 /y (exp(+-0.2 x 70 y) spans 1e-6..1e6); ages 0-130 y; months 0 to 50
 * years; heal_time above 0, up to 50 years. */
int kt_scene_parse_wound(kt_yml *y, const yaml_node_t *n, kt_wound_scene *w, kt_err *e)
{
    const char *what = "wound";
    if (kt_yml_check_map(y, n, what, WOUND_KEYS, e)) return e->code;
    if (kt_yml_key_choice(y, n, what, "state", STATES, &w->state, e) ||
        kt_yml_key_quantity(y, n, what, "bridge_stiffness", KT_UNIT_STIFFNESS, kt_scene_range(0, 1e6, 0, 0),
                            &w->bridge_stiffness, e) ||
        kt_yml_key_quantity(y, n, what, "age_rate", KT_UNIT_RATE, kt_scene_range(-0.2, 0.2, 0, 0), &w->age_rate, e) ||
        kt_yml_key_number(y, n, what, "age", kt_scene_range(0, 130, 0, 0), &w->age, e) ||
        kt_yml_key_quantity(y, n, what, "months", KT_UNIT_TIME, kt_scene_range(0, 600, 0, 0), &w->months, e) ||
        kt_yml_key_quantity(y, n, what, "heal_time", KT_UNIT_TIME, kt_scene_range(0, 600, 1, 0),
                            &w->heal_time, e))
        return e->code;
    return KT_OK;
}

void kt_scene_write_wound(FILE *f, const kt_wound_scene *w)
{
    fprintf(f, "wound:\n  state: %s\n  bridge_stiffness: %.17g MPa/mm\n  age_rate: %.17g /y\n",
            STATES[w->state], w->bridge_stiffness, w->age_rate);
    if (isfinite(w->age)) fprintf(f, "  age: %.17g\n", w->age);
    if (isfinite(w->months)) fprintf(f, "  months: %.17g months\n", w->months);
    fprintf(f, "  heal_time: %.17g months\n", w->heal_time);
}
