/* plan_tunnel.h: the plan's `tunnels` block (private to plan.c and plan_tunnel.c). */
#ifndef KT_PLAN_TUNNEL_H
#define KT_PLAN_TUNNEL_H

#include "plan.h"
#include "yml.h"

/* Parse the `tunnels` sequence of an eye plan, check each tunnel against the scene's eye
 * (entry on the cornea or limbus, a length that reaches the posterior surface, a width that
 * fits) and derive its plane (kt_tunnel's derived fields). Bad input: KT_EINPUT at file:line:col. */
int kt_plan_parse_tunnels(kt_yml *y, const yaml_node_t *n, kt_plan *p, kt_err *e);

/* The plan steps of the tunnels (for the plan's step limit). */
int kt_plan_tunnel_steps(const kt_plan *p);

#endif
