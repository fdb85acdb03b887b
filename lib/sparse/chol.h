/* chol.h: the one CHOLMOD helper keratome needs beyond CHOLMOD itself: a numeric factorization
 * that reports a non-positive pivot by the node and component it belongs to, and a dense
 * column view of a caller's array. DOF numbering: DOF 3*node + c, c = x, y, z. */
#ifndef KT_CHOL_H
#define KT_CHOL_H

#include <cholmod.h>

#include "util.h"

/* Factor A numerically into L (analysed before, with A's pattern). KT_ERUN when CHOLMOD fails,
 * and when a pivot is not positive: then the message, prefixed by 'what' (e.g. "step 3"),
 * names the node (1-based) and component of the DOF, and the pivot's position. */
int kt_chol_factor(cholmod_sparse *A, cholmod_factor *L, cholmod_common *c, const char *what,
                   kt_err *e);

/* Supernodal analysis and factorization of A with CHOLMOD's default ordering; NULL on failure
 * (reported as kt_chol_factor does). */
cholmod_factor *kt_chol_analyze_factor(cholmod_sparse *A, cholmod_common *c, const char *what,
                                       kt_err *e);

/* An n x 1 dense matrix whose values are x (not copied, not to be freed by CHOLMOD). */
cholmod_dense kt_chol_column(double *x, size_t n);

#endif
