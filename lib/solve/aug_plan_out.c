/* aug_plan_out.c: restricted output for the planned method: the supernodes of L that the back
 * substitution needs for the DOFs of an output node set (their ancestors in the supernodal
 * elimination tree); kt_plan_back (aug_plan_subst.c) then substitutes on them only. */
#include "aug_plan.h"

#include <stdlib.h>
#include <string.h>

/* The supernode holding each column, and each supernode's parent (-1: a root). */
static int super_tree(const cholmod_factor *L, int *col_super, int *parent)
{
    const int *S = L->super, *pi = L->pi, *Ls = L->s;
    int ns = (int)L->nsuper;
    for (int s = 0; s < ns; s++)
        for (int j = S[s]; j < S[s + 1]; j++) col_super[j] = s;
    for (int s = 0; s < ns; s++) {
        int nscol = S[s + 1] - S[s], nsrow = pi[s + 1] - pi[s];
        parent[s] = nsrow > nscol ? col_super[Ls[pi[s] + nscol]] : -1;
    }
    return ns;
}

int kt_plan_state_restrict(kt_plan_state *st, const kt_edits_plan *p, const kt_plan_factor *F,
                           const unsigned char *nodes, kt_err *e)
{
    free(st->want);
    st->want = NULL;
    st->want_cols = 0;
    const cholmod_factor *L = F->L;
    if (!L->is_super || !nodes) return KT_OK;
    int n = F->nfree, ns = (int)L->nsuper;
    int *col_super = kt_calloc((size_t)n ? (size_t)n : 1, sizeof(int), e);
    int *parent = kt_calloc((size_t)ns ? (size_t)ns : 1, sizeof(int), e);
    int *ipos = kt_calloc((size_t)n ? (size_t)n : 1, sizeof(int), e);
    unsigned char *need = kt_calloc((size_t)p->nn, 1, e);
    unsigned char *want = st->want = kt_calloc((size_t)ns ? (size_t)ns : 1, 1, e);
    if (!e->code) {
        super_tree(L, col_super, parent);
        const int *Perm = L->Perm;
        for (int q = 0; q < n; q++) ipos[Perm[q]] = q;
        for (int a = 0; a < p->nn; a++) /* an output node needs its ancestors' variables */
            if (nodes[a])
                for (int b = a; b >= 0 && !need[b]; b = p->parent[b]) need[b] = 1;
        for (int v = 0; v < F->nvar; v++) {
            if (!need[v / 3] || F->pos[v] < 0) continue;
            for (int s = col_super[ipos[F->pos[v]]]; s >= 0 && !want[s]; s = parent[s])
                want[s] = 1;
        }
        const int *S = L->super;
        for (int s = 0; s < ns; s++)
            if (want[s]) st->want_cols += S[s + 1] - S[s];
    }
    free(col_super);
    free(parent);
    free(ipos);
    free(need);
    return e->code;
}
