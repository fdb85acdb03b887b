/* nomo_out.h: lri-nomogram's answer on standard output (lri-nomogram(1), OUTPUT): a few '#'
 * lines and a tab-separated table through the one TSV writer (lib/io/tsv.h), or (--json) one
 * JSON object through the one JSON writer (lib/io/json.h). */
#ifndef KT_NOMO_OUT_H
#define KT_NOMO_OUT_H

#include <stdio.h>

#include "nomo.h"

/* The answers ans[0] (one incision) and ans[1] (a pair; incisions 0: none in the table) of
 * query q, whose astigmatism to correct is pre D at pre_axis deg, on f. KT_ERUN when a write
 * fails. */
int kt_nomo_print(FILE *f, const kt_nomo_query *q, double pre, double pre_axis, const kt_nomo_answer ans[2], int json,
                  kt_err *e);

#endif
