/* aug_plan_factor.c: the augmented matrix of the final cut mesh in increment variables,
 * A = T^T K_final T (K_final from the fem layer's assembly), its free block ordered as
 * [a fill-reducing order of the intact block, then the increments in release order] and
 * factored once. */
#include "aug_plan.h"

#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "chol.h"
#include "wound.h"

void kt_plan_factor_free(kt_plan_factor *F)
{
    if (F->started) {
        cholmod_free_factor(&F->L, &F->c);
        cholmod_free_sparse(&F->A, &F->c);
        cholmod_finish(&F->c);
    }
    free(F->pos);
    free(F->nfree_at);
    free(F->fro_at);
    free(F->lrow);
    free(F->lcol);
    free(F->lval);
    memset(F, 0, sizeof *F);
}


/* Positions of the free variables, in variable order (intact DOFs first, then the increments
 * in release order), and how many are present after each step. */
static int positions(kt_plan_factor *F, const kt_edits_plan *p, kt_err *e)
{
    F->nvar = 3 * p->nn;
    F->pos = kt_calloc((size_t)F->nvar, sizeof(int), e);
    F->nfree_at = kt_calloc((size_t)p->nsteps + 1, sizeof(int), e);
    if (e->code) return e->code;
    int n = 0, k = 0;
    for (int v = 0; v < F->nvar; v++) {
        while (k <= p->nsteps && v == 3 * p->nn_at[k]) F->nfree_at[k++] = n;
        F->pos[v] = p->fixed[v] ? -1 : n++;
        if (v == 3 * p->nn0 - 1) F->nK = n;
    }
    while (k <= p->nsteps) F->nfree_at[k++] = n;
    F->nfree = n;
    return KT_OK;
}

/* Where the entries of A go: free-free into T (lower, in positions), the rest into the
 * lifting list in both orientations. fill = 0 only counts. */
typedef struct sink {
    kt_plan_factor *F;
    cholmod_triplet *T;
    size_t nt, nl;
    int fill;
} sink;

static void put(void *ctx, int v, int w, double x)
{
    sink *s = ctx;
    kt_plan_factor *F = s->F;
    int pv = F->pos[v], pw = F->pos[w];
    if (pv >= 0 && pw >= 0) {
        if (s->fill) {
            ((int *)s->T->i)[s->nt] = pv;
            ((int *)s->T->j)[s->nt] = pw;
            ((double *)s->T->x)[s->nt] = x;
        }
        s->nt++;
        return;
    }
    for (int o = 0; o < 1 + (v != w); o++) {
        if (s->fill) {
            F->lrow[s->nl] = o ? w : v;
            F->lcol[s->nl] = o ? v : w;
            F->lval[s->nl] = x;
        }
        s->nl++;
    }
}

int kt_plan_chain(const kt_edits_plan *p, int i, int *v)
{
    int n = 0, c = i % 3;
    for (int a = i / 3; a >= 0; a = p->parent[a]) {
        if (n == KT_PLAN_CHAIN_MAX) return -1;
        v[n++] = 3 * a + c;
    }
    return n;
}

/* K(i, j) of the full symmetric K into every pair of variables (v >= w) that sum i and j. */
static void scatter(void (*put)(void *, int, int, double), void *ctx, const int *ci, int ni,
                    const int *cj, int nj, double x)
{
    for (int a = 0; a < ni; a++)
        for (int b = 0; b < nj; b++)
            if (ci[a] >= cj[b]) put(ctx, ci[a], cj[b], x);
}

int kt_plan_transform(const kt_edits_plan *p, const cholmod_sparse *K,
                      void (*put)(void *ctx, int v, int w, double x), void *ctx, kt_err *e)
{
    const int *Kp = K->p, *Ki = K->i, *Knz = K->nz;
    const double *Kx = K->xtype == CHOLMOD_PATTERN ? NULL : K->x;
    int ci[KT_PLAN_CHAIN_MAX], cj[KT_PLAN_CHAIN_MAX];
    for (int j = 0; j < (int)K->ncol; j++) {
        int nj = kt_plan_chain(p, j, cj);
        if (nj < 0) return kt_fail(e, KT_EINPUT, "node %d is split more than %d times", j / 3 + 1,
                                   KT_PLAN_CHAIN_MAX);
        int end = K->packed ? Kp[j + 1] : Kp[j] + Knz[j];
        for (int q = Kp[j]; q < end; q++) {
            int i = Ki[q];
            if (i < j) continue; /* lower triangle only */
            int ni = kt_plan_chain(p, i, ci);
            if (ni < 0) return kt_fail(e, KT_EINPUT, "a node is split more than %d times", KT_PLAN_CHAIN_MAX);
            double x = Kx ? Kx[q] : 0;
            scatter(put, ctx, ci, ni, cj, nj, x);
            if (i != j) scatter(put, ctx, cj, nj, ci, ni, x); /* the mirror entry K(j, i) */
        }
    }
    return KT_OK;
}

/* A = T^T K T + B: the elements' K through the chains, and a healed wound's bridge B directly
 * in the variables (wound.h: each jump is the difference of two chains without their common
 * part, increments only), so the intact block is exactly the intact stiffness and the bridge
 * lands on the increments' block alone (through T it would add and cancel on the intact DOFs,
 * up to rounding). Its leading block at step k is step k's own bridge (wound.h). */
static int plan_matrix(const kt_edits_plan *p, const cholmod_sparse *K, const kt_mesh *final,
                       const kt_materials *mats, sink *s, kt_err *e)
{
    if (kt_plan_transform(p, K, put, s, e)) return e->code;
    if (!kt_wound_on(mats)) return KT_OK;
    return kt_wound_assemble(mats->wound, final, p->parent, 1.0, put, s, e);
}

/* A_FF (lower, in free positions) and the lifting entries from the final mesh's stiffness. */
static int assemble(kt_plan_factor *F, const kt_edits_plan *p, const kt_mesh *final,
                    const kt_materials *mats, kt_err *e)
{
    double t0 = kt_now();
    kt_materials elem = *mats;
    elem.wound = NULL; /* the bridge goes in apart, in the variables (plan_matrix) */
    cholmod_sparse *K = kt_fem_assemble(final, &elem, NULL, &F->c, e);
    if (!K) return e->code;
    sink s = {F, NULL, 0, 0, 0};
    if (plan_matrix(p, K, final, mats, &s, e) == KT_OK) {
        s.T = cholmod_allocate_triplet(F->nfree, F->nfree, s.nt ? s.nt : 1, -1, CHOLMOD_REAL, &F->c);
        F->lrow = kt_calloc(s.nl ? s.nl : 1, sizeof(int), e);
        F->lcol = kt_calloc(s.nl ? s.nl : 1, sizeof(int), e);
        F->lval = kt_calloc(s.nl ? s.nl : 1, sizeof(double), e);
        if (!s.T && !e->code) kt_fail(e, KT_ERUN, "out of memory for the augmented matrix");
    }
    if (!e->code) {
        F->nlift = (int)s.nl;
        s.nt = s.nl = 0;
        s.fill = 1;
        plan_matrix(p, K, final, mats, &s, e);
        s.T->nnz = s.nt;
    }
    cholmod_free_sparse(&K, &F->c);
    if (!e->code && !(F->A = cholmod_triplet_to_sparse(s.T, s.nt, &F->c)))
        kt_fail(e, KT_ERUN, "CHOLMOD triplet conversion failed (status %d)", F->c.status);
    cholmod_free_triplet(&s.T, &F->c);
    F->t_assemble = kt_now() - t0;
    return e->code;
}

/* ||A_k||_F for every step: each stored entry (i, j), i >= j, belongs to the leading blocks
 * from the step that releases position i on; twice for off-diagonal entries. */
static int frobenius(kt_plan_factor *F, int nsteps, kt_err *e)
{
    if (!(F->fro_at = kt_calloc((size_t)nsteps + 1, sizeof(double), e))) return e->code;
    const int *Ap = F->A->p, *Ai = F->A->i;
    const double *Ax = F->A->x;
    int k = 0;
    for (int j = 0; j < F->nfree; j++)
        for (int q = Ap[j]; q < Ap[j + 1]; q++) {
            int i = Ai[q];
            while (k > 0 && F->nfree_at[k - 1] > i) k--;
            while (F->nfree_at[k] <= i) k++;
            F->fro_at[k] += (i == j ? 1 : 2) * Ax[q] * Ax[q];
        }
    for (k = 1; k <= nsteps; k++) F->fro_at[k] += F->fro_at[k - 1];
    for (k = 0; k <= nsteps; k++) F->fro_at[k] = sqrt(F->fro_at[k]);
    return KT_OK;
}

/* The leading nK x nK block of A (the intact stiffness on its free DOFs). */
static cholmod_sparse *intact_block(kt_plan_factor *F)
{
    const int *Ap = F->A->p, *Ai = F->A->i;
    size_t nz = 0;
    for (int j = 0; j < F->nK; j++)
        for (int q = Ap[j]; q < Ap[j + 1]; q++) nz += Ai[q] < F->nK;
    cholmod_sparse *B = cholmod_allocate_sparse(F->nK, F->nK, nz, 1, 1, -1, CHOLMOD_PATTERN, &F->c);
    if (!B) return NULL;
    int *Bp = B->p, *Bi = B->i, n = 0;
    for (int j = 0; j < F->nK; j++) {
        Bp[j] = n;
        for (int q = Ap[j]; q < Ap[j + 1]; q++)
            if (Ai[q] < F->nK) Bi[n++] = Ai[q];
    }
    Bp[F->nK] = n;
    return B;
}

/* The free intact DOFs in the order of perm0 (3 nn0 DOFs; the constrained ones dropped) into
 * P[0..nK); -1 when perm0 is not a permutation of them. */
static int restrict_order(const kt_plan_factor *F, const int *perm0, int nn0, int *P)
{
    int n = 0, nvar = 3 * nn0;
    for (int k = 0; k < nvar; k++) {
        int v = perm0[k];
        if (v < 0 || v >= nvar) return -1;
        if (F->pos[v] < 0) continue;
        if (n == F->nK) return -1;
        P[n++] = F->pos[v];
    }
    return n == F->nK ? 0 : -1;
}

/* P: the intact block's fill-reducing order (postordered on its tree), then the increments.
 * With perm0 (ordering METIS) the order is perm0's, analysed without a METIS run. */
static int *order(kt_plan_factor *F, int ordering, const int *perm0, int nn0, kt_err *e)
{
    int *P = kt_calloc((size_t)F->nfree ? (size_t)F->nfree : 1, sizeof(int), e);
    if (!P) return NULL;
    for (int q = 0; q < F->nfree; q++) P[q] = q;
    if (ordering == KT_AUG_ORDER_NATURAL || F->nK == 0) return P;
    cholmod_sparse *B = intact_block(F);
    F->c.nmethods = 1;
    F->c.method[0].ordering = ordering == KT_AUG_ORDER_AMD ? CHOLMOD_AMD : CHOLMOD_METIS;
    F->c.postorder = 1;
    F->c.supernodal = CHOLMOD_SIMPLICIAL;
    kt_err ae = {0};
    cholmod_factor *Lb = NULL;
    if (B && perm0 && ordering == KT_AUG_ORDER_METIS && restrict_order(F, perm0, nn0, P) == 0) {
        F->c.method[0].ordering = CHOLMOD_GIVEN;
        if (!(Lb = cholmod_analyze_p(B, P, NULL, 0, &F->c)))
            kt_fail(&ae, KT_ERUN, "CHOLMOD analysis failed (status %d)", F->c.status);
        F->reused_order = 1;
    } else if (B) {
        Lb = kt_chol_analyze(B, &F->c, &ae);
    }
    F->lnz_ref = F->c.lnz;
    F->fl_ref = F->c.fl;
    if (Lb) memcpy(P, Lb->Perm, sizeof(int) * (size_t)F->nK);
    else if (!B) kt_fail(e, KT_ERUN, "CHOLMOD could not form the intact block (status %d)", F->c.status);
    else kt_fail(e, ae.code, "the intact block: %s", ae.msg);
    cholmod_free_factor(&Lb, &F->c);
    cholmod_free_sparse(&B, &F->c);
    if (e->code) {
        free(P);
        return NULL;
    }
    return P;
}

/* The analysis's prediction against the intact block's METIS analysis: refuse when the factor
 * would hold more than max_ratio times its nonzeros (memory: the factor is most of a run's
 * peak), or take longer than a fresh factorization at every step would: more flops than
 * KT_PLAN_FLOP_SPEEDUP x (nsteps + 1) times the intact block's (aug_plan.h: the plan would then
 * cost more time than refactoring). */
static void size_check(kt_plan_factor *F, double max_ratio, int nsteps)
{
    F->lnz_plan = F->c.lnz;
    F->fl_plan = F->c.fl;
    if (!(max_ratio > 0) || !(F->lnz_ref > 0) || !(F->fl_ref > 0)) return;
    double rl = F->lnz_plan / F->lnz_ref, rf = F->fl_plan / F->fl_ref;
    double rf_max = KT_PLAN_FLOP_SPEEDUP * (nsteps + 1);
    if (rl <= max_ratio && rf <= rf_max) return;
    F->refused = 1;
    snprintf(F->why, sizeof F->why, "its factor would hold %.3g nonzeros and take %.3g flops: "
             "%.3gx and %.3gx those of METIS on the intact block (%.3g, %.3g), beyond "
             "--plan-max-ratio %g or the time of %d fresh factorizations (%gx their flops)",
             F->lnz_plan, F->fl_plan, rl, rf, F->lnz_ref, F->fl_ref, max_ratio, nsteps + 1, rf_max);
}

/* F->fl_* and F->x_*: the planned factor's flops and values by part (aug_plan.h). */
static void breakdown(kt_plan_factor *F)
{
    const cholmod_factor *L = F->L;
    if (!L->is_super) return;
    const int *S = L->super, *pi = L->pi, *Ls = L->s;
    int ns = (int)L->nsuper;
    F->nsuper = ns;
    F->root_cols = ns ? S[ns] - S[ns - 1] : 0;
    for (int s = 0; s < ns; s++) {
        int k1 = S[s], nscol = S[s + 1] - k1, nsrow = pi[s + 1] - pi[s], rm = 0;
        for (int q = pi[s]; q < pi[s + 1]; q++) rm += Ls[q] >= F->nK;
        for (int j = 0; j < nscol; j++) {
            double c = nsrow - j, cm = rm; /* increment rows lie below every intact column */
            if (k1 + j >= F->nK) {
                F->fl_S += c * c;
                F->x_S += nsrow;
            } else {
                double ci = c - cm;
                F->fl_K += ci * ci;
                F->fl_W += c * c - ci * ci;
                F->x_K += nsrow - rm;
                F->x_W += rm;
            }
        }
    }
}

/* The increments' block in panels (aug_plan.h). CHOLMOD's analysis makes the dense trailing block (the
 * increments, with the intact separator columns whose rows hold all of them) one supernode, a
 * full square of which only the lower triangle is used, and sizes its update workspace by the
 * largest contribution to it (maxcsize: an intact supernode's increment rows, squared). Split
 * every supernode holding an increment column into panels of KT_PLAN_PANEL columns, each keeping
 * the rows of the supernode from its first column on (a suffix of the supernode's sorted row
 * list: a panel is a supernode of its own, the next panel its parent): the block is then stored
 * lower, in panels, wasting at most half a panel's square per panel, and the largest update is
 * a panel's width by the rows below. The columns, their rows and the numbers are unchanged (the
 * same factorization: the panels are a finer supernodal partition of the same L). */
int kt_plan_split_panels(cholmod_factor *L, int nK, int width, cholmod_common *c, kt_err *e)
{
    if (!L->is_super || width <= 0) return KT_OK;
    const int *S = L->super, *pi = L->pi, *Ls = L->s;
    int ns = (int)L->nsuper, ns2 = 0;
    size_t ssize = 0, xsize = 0;
    for (int s = 0; s < ns; s++) {
        int k1 = S[s], nscol = S[s + 1] - k1, nsrow = pi[s + 1] - pi[s];
        int w = S[s + 1] > nK ? width : nscol;
        for (int a = 0; a < nscol; a += w) {
            int b = a + w < nscol ? a + w : nscol;
            ns2++;
            ssize += (size_t)(nsrow - a);
            xsize += (size_t)(b - a) * (size_t)(nsrow - a);
        }
    }
    if (ns2 == ns) return KT_OK;
    if (xsize > (size_t)INT_MAX)
        return kt_fail(e, KT_ERUN, "the planned factor's values (%zu) overflow CHOLMOD's int "
                       "indices", xsize);
    int *S2 = cholmod_malloc((size_t)ns2 + 1, sizeof(int), c);
    int *pi2 = cholmod_malloc((size_t)ns2 + 1, sizeof(int), c);
    int *px2 = cholmod_malloc((size_t)ns2 + 1, sizeof(int), c);
    int *Ls2 = cholmod_malloc(ssize, sizeof(int), c);
    int *piece = cholmod_malloc((size_t)L->n + 1, sizeof(int), c); /* column -> panel */
    if (!S2 || !pi2 || !px2 || !Ls2 || !piece) {
        cholmod_free((size_t)ns2 + 1, sizeof(int), S2, c);
        cholmod_free((size_t)ns2 + 1, sizeof(int), pi2, c);
        cholmod_free((size_t)ns2 + 1, sizeof(int), px2, c);
        cholmod_free(ssize, sizeof(int), Ls2, c);
        cholmod_free((size_t)L->n + 1, sizeof(int), piece, c);
        return kt_fail(e, KT_ERUN, "out of memory splitting the planned factor into panels");
    }
    int t = 0, ps = 0, px = 0;
    for (int s = 0; s < ns; s++) {
        int k1 = S[s], nscol = S[s + 1] - k1, nsrow = pi[s + 1] - pi[s];
        int w = S[s + 1] > nK ? width : nscol;
        for (int a = 0; a < nscol; a += w, t++) {
            int b = a + w < nscol ? a + w : nscol;
            S2[t] = k1 + a;
            pi2[t] = ps;
            px2[t] = px;
            for (int q = pi[s] + a; q < pi[s + 1]; q++) Ls2[ps++] = Ls[q];
            px += (b - a) * (nsrow - a);
            for (int j = k1 + a; j < k1 + b; j++) piece[j] = t;
        }
    }
    S2[ns2] = (int)L->n;
    pi2[ns2] = ps;
    px2[ns2] = px;
    /* CHOLMOD's workspace sizes for the new partition: the largest update (rows of a supernode
     * in an ancestor's columns times its rows from there on) and the largest row count below a
     * supernode's own columns (the solves' E). */
    size_t maxcsize = 1, maxesize = 1;
    for (int d = 0; d < ns2; d++) {
        int p = pi2[d] + S2[d + 1] - S2[d], pend = pi2[d + 1];
        if ((size_t)(pend - p) > maxesize) maxesize = (size_t)(pend - p);
        while (p < pend) {
            int a = piece[Ls2[p]], q = p;
            while (q < pend && piece[Ls2[q]] == a) q++;
            size_t cs = (size_t)(q - p) * (size_t)(pend - p);
            if (cs > maxcsize) maxcsize = cs;
            p = q;
        }
    }
    cholmod_free((size_t)L->n + 1, sizeof(int), piece, c);
    cholmod_free(L->nsuper + 1, sizeof(int), L->super, c);
    cholmod_free(L->nsuper + 1, sizeof(int), L->pi, c);
    cholmod_free(L->nsuper + 1, sizeof(int), L->px, c);
    cholmod_free(L->ssize, sizeof(int), L->s, c);
    L->super = S2;
    L->pi = pi2;
    L->px = px2;
    L->s = Ls2;
    L->nsuper = (size_t)ns2;
    L->ssize = ssize;
    L->xsize = xsize;
    L->maxcsize = maxcsize;
    L->maxesize = maxesize;
    return KT_OK;
}

static int factorize(kt_plan_factor *F, const int *P, int factor, int panel, double max_ratio,
                     int nsteps, kt_err *e)
{
    F->c.nmethods = 1;
    F->c.method[0].ordering = CHOLMOD_GIVEN;
    F->c.postorder = 0; /* keep the increments last, in release order */
    F->c.supernodal = factor == KT_AUG_FACTOR_SIMPLICIAL ? CHOLMOD_SIMPLICIAL : CHOLMOD_SUPERNODAL;
    F->c.final_ll = 0;
    F->L = cholmod_analyze_p(F->A, (int *)P, NULL, 0, &F->c);
    if (!F->L) return kt_fail(e, KT_ERUN, "CHOLMOD analysis failed (status %d)", F->c.status);
    const int *LP = F->L->Perm;
    for (int q = 0; q < F->nfree; q++)
        if (LP[q] != P[q])
            return kt_fail(e, KT_ERUN, "CHOLMOD did not keep the given order at %d", q);
    size_check(F, max_ratio, nsteps);
    if (!F->refused && kt_plan_split_panels(F->L, F->nK, panel, &F->c, e)) return e->code;
    breakdown(F);
    if (F->refused) return KT_OK;
    if (kt_chol_budget(F->L, &F->c, "the planned augmented matrix", e)) return e->code;
    cholmod_factorize(F->A, F->L, &F->c);
    if (F->c.status == CHOLMOD_NOT_POSDEF || F->L->minor < F->L->n)
        return kt_fail(e, KT_ERUN, "the planned augmented matrix is not positive definite at "
                       "free variable %d (pivot %zu of %zu): is a body free to move rigidly?",
                       LP[F->L->minor], F->L->minor + 1, F->L->n);
    if (F->c.status != CHOLMOD_OK)
        return kt_chol_failed(F->c.status, "the planned augmented matrix", e);
    F->nnzL = F->c.lnz;
    return KT_OK;
}

int kt_plan_factor_build(kt_plan_factor *F, const kt_edits_plan *p, const kt_mesh *final,
                         const kt_materials *mats, int ordering, int factor, int panel,
                         double max_ratio, kt_err *e)
{
    return kt_plan_factor_build_with(F, p, final, mats, ordering, NULL, factor, panel, max_ratio, e);
}

int kt_plan_factor_build_with(kt_plan_factor *F, const kt_edits_plan *p, const kt_mesh *final,
                              const kt_materials *mats, int ordering, const int *perm0,
                              int factor, int panel, double max_ratio, kt_err *e)
{
    memset(F, 0, sizeof *F);
    kt_chol_start(&F->c);
    F->started = 1;
    if (positions(F, p, e) || assemble(F, p, final, mats, e) || frobenius(F, p->nsteps, e))
        return e->code;
    double t0 = kt_now();
    int *P = order(F, ordering, perm0, p->nn0, e);
    if (!P) return e->code;
    double t1 = kt_now();
    if (factorize(F, P, factor, panel, max_ratio, p->nsteps, e) == KT_OK && !F->refused)
        kt_plan_subst_init(F);
    free(P);
    F->t_order = t1 - t0;
    F->t_factor = kt_now() - t1;
    return e->code;
}
