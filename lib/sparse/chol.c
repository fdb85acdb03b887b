/* chol.c: CHOLMOD factorization with the bad pivot named by node and component. */
#include "chol.h"

#include <string.h>

static const char COMPONENT[3] = {'x', 'y', 'z'};

int kt_chol_factor(cholmod_sparse *A, cholmod_factor *L, cholmod_common *c, const char *what,
                   kt_err *e)
{
    cholmod_factorize(A, L, c);
    if (c->status != CHOLMOD_OK && c->status != CHOLMOD_NOT_POSDEF)
        return kt_fail(e, KT_ERUN, "%s: CHOLMOD factorization failed (status %d)", what, c->status);
    if (c->status == CHOLMOD_NOT_POSDEF || L->minor < L->n) {
        int dof = L->Perm ? ((const int *)L->Perm)[L->minor] : (int)L->minor;
        return kt_fail(e, KT_ERUN, "%s: stiffness matrix is not positive definite at node %d, DOF %c "
                       "(pivot %zu of %zu): is a body free to move rigidly, or a node in no element?",
                       what, dof / 3 + 1, COMPONENT[dof % 3], L->minor + 1, L->n);
    }
    return KT_OK;
}

cholmod_factor *kt_chol_analyze_factor(cholmod_sparse *A, cholmod_common *c, const char *what,
                                       kt_err *e)
{
    int saved = c->supernodal;
    c->supernodal = CHOLMOD_SUPERNODAL;
    cholmod_factor *L = cholmod_analyze(A, c);
    c->supernodal = saved;
    if (!L) {
        kt_fail(e, KT_ERUN, "%s: CHOLMOD analysis failed (status %d)", what, c->status);
        return NULL;
    }
    if (kt_chol_factor(A, L, c, what, e)) cholmod_free_factor(&L, c);
    return L;
}

cholmod_dense kt_chol_column(double *x, size_t n)
{
    cholmod_dense B;
    memset(&B, 0, sizeof B);
    B.nrow = B.nzmax = B.d = n;
    B.ncol = 1;
    B.x = x;
    B.xtype = CHOLMOD_REAL;
    B.dtype = CHOLMOD_DOUBLE;
    return B;
}
