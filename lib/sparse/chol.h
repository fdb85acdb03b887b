/* chol.h: the one CHOLMOD helper keratome needs beyond CHOLMOD itself: a numeric factorization
 * that reports a non-positive pivot by the node and component it belongs to, and a dense
 * column view of a caller's array. DOF numbering: DOF 3*node + c, c = x, y, z. */
#ifndef KT_CHOL_H
#define KT_CHOL_H

#include <cholmod.h>

#include "util.h"

/* cholmod_start(c), then CHOLMOD kept off stdout: it prints nothing itself (c->print = 0) and
 * its errors and warnings go to stderr as one line "CHOLMOD error|warning: message (file:line)"
 * through c->error_handler, except the not-positive-definite warning, which every caller
 * reports in its own words (kt_chol_factor names the node). Every CHOLMOD workspace of keratome
 * starts here: a tool's stdout holds only its answer. */
void kt_chol_start(cholmod_common *c);

/* Factor A numerically into L (analysed before, with A's pattern; its memory checked first by
 * kt_chol_budget). KT_ERUN when CHOLMOD fails,
 * and when a pivot is not positive: then the message, prefixed by 'what' (e.g. "step 3"),
 * names the node (1-based) and component of the DOF, and the pivot's position. */
int kt_chol_factor(cholmod_sparse *A, cholmod_factor *L, cholmod_common *c, const char *what,
                   kt_err *e);

/* The memory a numeric factorization of the analysed L takes (the factor's values, sized
 * exactly by the symbolic analysis: L->xsize doubles supernodal, c->lnz simplicial, and the
 * largest update block), checked against what is left (kt_mem_budget) before any of it is
 * allocated: KT_ERUN "WHAT: out of memory: needs N MB, ..." when it cannot fit. KT_OK for an L
 * that holds values already (a refactorization reuses them). */
int kt_chol_budget(const cholmod_factor *L, const cholmod_common *c, const char *what, kt_err *e);

/* Records KT_ERUN "WHAT: CHOLMOD factorization failed (status N)", or "...: out of memory"
 * for CHOLMOD_OUT_OF_MEMORY, and returns it. */
int kt_chol_failed(int status, const char *what, kt_err *e);

/* cholmod_analyze(A, c), except that every METIS ordering is made here and its status checked.
 * CHOLMOD 3 ignores METIS_NodeND's return status; METIS 5.1 catches a SIGTERM that arrives
 * while it runs and returns early with no ordering, so inside cholmod_analyze a stopped
 * process would go on with CHOLMOD's fallback (AMD) or whatever the permutation's memory held:
 * another ordering, other last digits. Here METIS_NodeND is called on the same graph CHOLMOD
 * gives it (A + A' without the diagonal, default options) and its ordering handed to CHOLMOD
 * as given, so the factor is the one cholmod_analyze makes, and a METIS failure is an error.
 * Covers c->nmethods 1 with CHOLMOD_METIS and the default strategy (nmethods 0: AMD, then METIS
 * when AMD's fill is high, the smaller nnz(L) kept, AMD on a tie); other settings go to
 * cholmod_analyze as they are. A symmetric A (stype != 0). NULL on failure, with e set. */
cholmod_factor *kt_chol_analyze(cholmod_sparse *A, cholmod_common *c, kt_err *e);

/* Supernodal analysis (kt_chol_analyze) and factorization of A with c's orderings (CHOLMOD's
 * default unless set); NULL on failure (reported as kt_chol_factor does). */
cholmod_factor *kt_chol_analyze_factor(cholmod_sparse *A, cholmod_common *c, const char *what,
                                       kt_err *e);

/* An n x 1 dense matrix whose values are x (not copied, not to be freed by CHOLMOD). */
cholmod_dense kt_chol_column(double *x, size_t n);

#endif
