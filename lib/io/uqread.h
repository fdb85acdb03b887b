/* uqread.h: the two tables of parameter uncertainty that curvature reads (issue 21,
 * curvature(1) UNCERTAINTY):
 *   RUN/uncertainty.tsv  written by augsolve --uncertainty: one row per uncertain quantity,
 *                        header `param unit value sd method source` (tab-separated);
 *   the --sens file      finite-difference derivatives of readings for the `fd` quantities,
 *                        header `param reading dR_dp` and an optional `step` column (the step
 *                        the row is for; without it a row holds for every step after step 0).
 * Read by tsv.h. Bad input is KT_EINPUT "file:line:col: expected ..." (col: the field's first
 * byte in its line), nothing kept. */
#ifndef KT_UQREAD_H
#define KT_UQREAD_H

#include "util.h"

#define KT_UQ_NAME 64
#define KT_UQ_SOURCE 256

enum { KT_UQ_DERIVATIVE = 1, KT_UQ_FD, KT_UQ_NONE };

typedef struct kt_uq_param {
    char name[KT_UQ_NAME];     /* param: letters, digits and _ (dudp_<name> in the step VTKs) */
    char unit[KT_UQ_NAME];
    double value, sd;          /* sd >= 0, in unit */
    int method;                /* KT_UQ_* */
    char source[KT_UQ_SOURCE];
} kt_uq_param;

typedef struct kt_uq_table {
    int n;
    kt_uq_param *p;
} kt_uq_table;

/* Read uncertainty.tsv. Every param once; sd finite and >= 0; method derivative, fd or none. */
int kt_uq_table_read(const char *path, kt_uq_table *t, kt_err *e);
void kt_uq_table_free(kt_uq_table *t);
/* The index of param `name`, -1 when absent. */
int kt_uq_table_find(const kt_uq_table *t, const char *name);

/* One row of a --sens file: param, reading, step (-1: every step after step 0), dR/dp. */
typedef struct kt_uq_sens_row {
    char param[KT_UQ_NAME], reading[KT_UQ_NAME];
    int step;
    double dr_dp;
    int line;                  /* its line in the file, for messages */
} kt_uq_sens_row;

typedef struct kt_uq_sens {
    int n;
    kt_uq_sens_row *r;
} kt_uq_sens;

/* Read a --sens file: finite dR_dp, a step >= 0 when the column is there, no (param, reading,
 * step) twice. Which params and readings are allowed is the caller's check (kt_uq_sens_row.line
 * lets it name the line). */
int kt_uq_sens_read(const char *path, kt_uq_sens *s, kt_err *e);
void kt_uq_sens_free(kt_uq_sens *s);

#endif
