/* aug_solve.c: Lset, J and H bookkeeping and the three solution steps of the augmented method,
 * with every R^-1 product a closure-restricted cholmod_solve2 on a sparse right-hand side. */
#include <klu.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "aug_impl.h"
#include "krylov.h"

static int base_fixed(const kt_aug *A, int i)
{
    return i < A->base->n0 && A->base->B[i];
}

/* R on the padding: the diagonal stiffness of the new DOF when it appeared (1 before that),
 * so the new columns of the Schur complement are as well scaled as the old ones. */
static double padv(const kt_aug *A, int j) { return A->pad[j] > 0 ? A->pad[j] : 1.0; }

/* ------------------------------------------------------------------ Lset, J */

static int lset_add(kt_aug *A, int dof, kt_err *e)
{
    if (A->Lpos[dof] >= 0) return KT_OK;
    if (A->m == A->mcap) {
        int cap = A->mcap ? 2 * A->mcap : 64;
        int *L = kt_realloc(A->Ldof, (size_t)cap, sizeof(int), e);
        if (!L) return e->code;
        A->Ldof = L;
        aug_col *J = kt_realloc(A->J, (size_t)cap, sizeof(aug_col), e);
        if (!J) return e->code;
        memset(J + A->mcap, 0, (size_t)(cap - A->mcap) * sizeof(aug_col));
        A->J = J;
        double *a2 = kt_realloc(A->a2, (size_t)cap, sizeof(double), e);
        if (!a2) return e->code;
        A->a2 = a2;
        double *rhs = kt_realloc(A->rhs, (size_t)cap, sizeof(double), e);
        if (!rhs) return e->code;
        A->rhs = rhs;
        A->mcap = cap;
    }
    A->Lpos[dof] = A->m;
    A->Ldof[A->m] = dof;
    A->J[A->m].n = 0;
    A->m++;
    return KT_OK;
}

/* J column of Lset entry k from the current K column of its DOF. */
static int set_jcol(kt_aug *A, int k, const aug_col *col, kt_err *e)
{
    int j = A->Ldof[k];
    aug_col *J = &A->J[k];
    double s = 1;
    for (int p = 0; p < col->n; p++)
        if (col->i[p] == j) s = col->x[p];
    if (j >= A->base->n0 && A->pad[j] == 0 && s > 0) A->pad[j] = s;
    if (A->cons[j]) { /* in D: s e_j, s = K(j,j) */
        if (aug_col_reserve(J, 1, e)) return e->code;
        J->i[0] = j;
        J->x[0] = s > 0 ? s : 1;
        J->n = 1;
        return KT_OK;
    }
    if (aug_col_reserve(J, col->n, e)) return e->code;
    J->n = 0;
    for (int p = 0; p < col->n; p++)
        if (!base_fixed(A, col->i[p]) && col->x[p] != 0) {
            J->i[J->n] = col->i[p];
            J->x[J->n++] = col->x[p];
        }
    return KT_OK;
}

/* Recompute the J columns of the Lset DOFs of the marked nodes. */
static int refresh_nodes(kt_aug *A, const int *nodes, int n, kt_err *e)
{
    aug_col col[3] = {{0}};
    for (int q = 0; q < n && !e->code; q++) {
        int a = nodes[q], any = 0;
        for (int c = 0; c < 3; c++) any |= A->Lpos[3 * a + c] >= 0;
        if (!any || aug_node_columns(A, a, col, e)) continue;
        for (int c = 0; c < 3 && !e->code; c++)
            if (A->Lpos[3 * a + c] >= 0) set_jcol(A, A->Lpos[3 * a + c], &col[c], e);
    }
    for (int c = 0; c < 3; c++) aug_col_free(&col[c]);
    return e->code;
}

/* Union of the J patterns (it contains Lset: every J column holds its own diagonal). */
static int jpattern(kt_aug *A, kt_err *e)
{
    A->dstamp++;
    A->njpat = 0;
    for (int k = 0; k < A->m; k++)
        for (int p = 0; p < A->J[k].n; p++) {
            int i = A->J[k].i[p];
            if (A->dmark[i] == A->dstamp) continue;
            A->dmark[i] = A->dstamp;
            if (A->njpat == A->jpcap) {
                int cap = A->jpcap ? 2 * A->jpcap : 256;
                int *pp = kt_realloc(A->Jpat, (size_t)cap, sizeof(int), e);
                if (!pp) return e->code;
                A->Jpat = pp;
                A->jpcap = cap;
            }
            A->Jpat[A->njpat++] = i;
        }
    return KT_OK;
}

int aug_update_lset(kt_aug *A, const int *touched, int nt, const int *newc, int nc, kt_err *e)
{
    int *nodes = kt_calloc((size_t)(nt + nc + 1), sizeof(int), e);
    if (!nodes) return e->code;
    int nn = 0;
    A->nstamp++;
    for (int q = 0; q < nt; q++) {
        int a = touched[q];
        for (int c = 0; c < 3; c++)
            if (!base_fixed(A, 3 * a + c)) lset_add(A, 3 * a + c, e);
        A->nmark[a] = A->nstamp;
        nodes[nn++] = a;
    }
    for (int q = 0; q < nc; q++) {
        int j = newc[q];
        if (base_fixed(A, j)) continue;
        lset_add(A, j, e);
        if (A->nmark[j / 3] != A->nstamp) {
            A->nmark[j / 3] = A->nstamp;
            nodes[nn++] = j / 3;
        }
    }
    if (!e->code) refresh_nodes(A, nodes, nn, e);
    free(nodes);
    if (!e->code) jpattern(A, e);
    return e->code;
}

int aug_rebuild_lists(kt_aug *A, kt_err *e)
{
    const aug_base *b = A->base;
    for (int k = 0; k < A->m; k++) A->Lpos[A->Ldof[k]] = -1;
    A->m = 0;
    for (int k = 0; k < A->nd; k++) A->ind[A->dlist[k]] = 0;
    A->nd = 0;
    int n = 3 * A->mesh.nn, nn = 0;
    int *nodes = kt_calloc((size_t)A->mesh.nn + 1, sizeof(int), e);
    if (!nodes) return e->code;
    for (int j = 0; j < n && !e->code; j++) {
        int fresh = j >= b->n0;
        if (!base_fixed(A, j) && (fresh || A->touch_step[j / 3] > b->step ||
                                  (A->cons[j] && A->cons_step[j] > b->step))) {
            lset_add(A, j, e);
            if (nn == 0 || nodes[nn - 1] != j / 3) nodes[nn++] = j / 3;
        }
        if (fresh || A->rhs_step[j] > b->step) aug_dlist_add(A, j, e);
    }
    if (!e->code) refresh_nodes(A, nodes, nn, e);
    free(nodes);
    if (!e->code) jpattern(A, e);
    return e->code;
}

/* ----------------------------------------------------------- R^-1 products */

/* Load Bset with the unique DOFs < n0 of two lists; B gets v there (v is dense). */
static void fill_bset(kt_aug *A, const double *v, const int *p1, int n1, const int *p2, int n2,
                      const int *map)
{
    int n0 = A->base->n0, *Bi = A->Bset->i, cnt = 0;
    double *Bx = A->Bd->x;
    A->dstamp++;
    for (int s = 0; s < 2; s++) {
        const int *p = s ? p2 : p1;
        int n = s ? n2 : n1;
        for (int q = 0; q < n; q++) {
            int i = p[q];
            if (i >= n0 || A->dmark[i] == A->dstamp) continue;
            A->dmark[i] = A->dstamp;
            int r = map ? map[i] : i;
            Bi[cnt++] = r;
            Bx[r] = v[i];
        }
    }
    ((int *)A->Bset->p)[0] = 0;
    ((int *)A->Bset->p)[1] = cnt;
}

static int solve2(kt_aug *A, int sys, cholmod_dense *B, cholmod_sparse *Bset, kt_err *e)
{
    if (!cholmod_solve2(sys, A->base->L, B, Bset, &A->X, Bset ? &A->Xset : NULL, &A->Y, &A->E,
                        &A->c))
        return kt_fail(e, KT_ERUN, "CHOLMOD solve failed (status %d)", A->c.status);
    if (Bset) {
        int cl = ((int *)A->Xset->p)[1];
        if (cl > A->closure_max) A->closure_max = cl;
    }
    return KT_OK;
}

/* X = R^-1 v, exact on the closure of (pattern of v) u extra: X->x for DOFs < n0. */
static int rinv_sparse(kt_aug *A, const double *v, const int *pat, int np, const int *extra,
                       int ne, kt_err *e)
{
    fill_bset(A, v, pat, np, extra, ne, NULL);
    return solve2(A, CHOLMOD_A, A->Bd, A->Bset, e);
}

/* H R^-1 v: entry k from X (DOF < n0, R^-1 exact on the closure) or v itself (padding). */
static void gather_h(const kt_aug *A, const double *v, double *out)
{
    const double *X = A->X->x;
    for (int k = 0; k < A->m; k++) {
        int j = A->Ldof[k];
        out[k] = j < A->base->n0 ? X[j] : v[j] / padv(A, j);
    }
}

/* ------------------------------------------------------------- GMRES step */

static void scatter_j(kt_aug *A, const double *x, double *w, double sign)
{
    for (int k = 0; k < A->m; k++)
        for (int p = 0; p < A->J[k].n; p++) w[A->J[k].i[p]] += sign * A->J[k].x[p] * x[k];
}

/* y = H R^-1 J x */
static int schur_op(void *ctx, const double *x, double *y, kt_err *e)
{
    kt_aug *A = ctx;
    scatter_j(A, x, A->w2, 1.0);
    int rc = rinv_sparse(A, A->w2, A->Jpat, A->njpat, A->Ldof, A->m, e);
    if (!rc) gather_h(A, A->w2, y);
    for (int q = 0; q < A->njpat; q++) A->w2[A->Jpat[q]] = 0;
    return rc;
}

typedef struct klu_pre {
    klu_common kc;
    klu_symbolic *sym;
    klu_numeric *num;
    int m;
    int *Mp, *Mi;
    double *Mx;
} klu_pre;

static void klu_pre_free(klu_pre *P)
{
    if (P->num) klu_free_numeric(&P->num, &P->kc);
    if (P->sym) klu_free_symbolic(&P->sym, &P->kc);
    free(P->Mp);
    free(P->Mi);
    free(P->Mx);
}

/* S(r, l) of the approximate inverse (identity on the padding). */
static double s_entry(const kt_aug *A, int r, int l)
{
    const aug_base *b = A->base;
    if (r >= b->n0 || l >= b->n0) return r == l ? 1.0 / padv(A, l) : 0.0;
    if (A->o.precond == KT_AUG_PRECOND_DIAG) return r == l ? b->dinv[l] : 0.0;
    return b->spai[3 * (size_t)l + (r - l + 1)];
}

/* M = H S J as m x m CSC. */
static int build_m(kt_aug *A, klu_pre *P, kt_err *e)
{
    int m = A->m, band = A->o.precond == KT_AUG_PRECOND_SPAI ? 1 : 0;
    size_t cap = 0;
    for (int k = 0; k < m; k++) cap += (size_t)A->J[k].n * (2 * band + 1);
    P->Mp = kt_calloc((size_t)m + 1, sizeof(int), e);
    P->Mi = kt_calloc(cap ? cap : 1, sizeof(int), e);
    P->Mx = kt_calloc(cap ? cap : 1, sizeof(double), e);
    double *acc = kt_calloc((size_t)m, sizeof(double), e);
    int *mark = kt_calloc((size_t)m, sizeof(int), e);
    if (e->code) {
        free(acc);
        free(mark);
        return e->code;
    }
    int nz = 0;
    for (int k = 0; k < m; k++) {
        int start = nz;
        for (int p = 0; p < A->J[k].n; p++) {
            int l = A->J[k].i[p];
            for (int r = l - band; r <= l + band; r++) {
                if (r < 0 || r >= 3 * A->mesh.nn || A->Lpos[r] < 0) continue;
                double s = s_entry(A, r, l);
                if (s == 0) continue;
                int row = A->Lpos[r];
                if (mark[row] != k + 1) {
                    mark[row] = k + 1;
                    acc[row] = 0;
                    P->Mi[nz++] = row;
                }
                acc[row] += s * A->J[k].x[p];
            }
        }
        for (int q = start; q < nz; q++) P->Mx[q] = acc[P->Mi[q]];
        P->Mp[k + 1] = nz;
    }
    free(acc);
    free(mark);
    return KT_OK;
}

static int klu_setup(kt_aug *A, klu_pre *P, kt_err *e)
{
    memset(P, 0, sizeof *P);
    P->m = A->m;
    klu_defaults(&P->kc);
    if (build_m(A, P, e)) return e->code;
    P->sym = klu_analyze(P->m, P->Mp, P->Mi, &P->kc);
    if (P->sym) P->num = klu_factor(P->Mp, P->Mi, P->Mx, P->sym, &P->kc);
    if (!P->sym || !P->num) {
        kt_log(A->o.quiet, "augsolve: step %d: the %s preconditioner is singular (KLU status %d);"
               " GMRES runs without it\n", A->step,
               A->o.precond == KT_AUG_PRECOND_DIAG ? "diag" : "spai", P->kc.status);
        klu_pre_free(P);
        memset(P, 0, sizeof *P);
    }
    return KT_OK;
}

static int klu_apply(void *ctx, const double *x, double *y, kt_err *e)
{
    klu_pre *P = ctx;
    memcpy(y, x, sizeof(double) * P->m);
    if (!klu_solve(P->sym, P->num, P->m, 1, y, &P->kc))
        return kt_fail(e, KT_ERUN, "KLU solve failed (status %d)", P->kc.status);
    return KT_OK;
}

/* GMRES minimizes the Schur residual r_s weighted by W = R(Lset, Lset): the true residual of
 * the whole system is R(:,Lset) r_s (a force), so this puts the stopping test in force units. */
typedef struct weighted {
    kt_aug *A;
    int *Wp, *Wi;
    double *Wx, *tmp, *rhs;
} weighted;

static void weighted_free(weighted *W)
{
    free(W->Wp);
    free(W->Wi);
    free(W->Wx);
    free(W->tmp);
    free(W->rhs);
}

static int build_w(kt_aug *A, weighted *W, kt_err *e)
{
    const cholmod_sparse *R = A->base->R;
    const int *Rp = R->p, *Ri = R->i;
    const double *Rx = R->x;
    int m = A->m, n0 = A->base->n0;
    size_t cap = 0;
    for (int k = 0; k < m; k++)
        cap += A->Ldof[k] < n0 ? (size_t)(Rp[A->Ldof[k] + 1] - Rp[A->Ldof[k]]) : 1;
    W->A = A;
    W->Wp = kt_calloc((size_t)m + 1, sizeof(int), e);
    W->Wi = kt_calloc(cap ? cap : 1, sizeof(int), e);
    W->Wx = kt_calloc(cap ? cap : 1, sizeof(double), e);
    W->tmp = kt_calloc((size_t)m, sizeof(double), e);
    W->rhs = kt_calloc((size_t)m, sizeof(double), e);
    if (e->code) return e->code;
    int nz = 0;
    for (int k = 0; k < m; k++) {
        int j = A->Ldof[k];
        if (j >= n0) {
            W->Wi[nz] = k;
            W->Wx[nz++] = padv(A, j); /* R is diagonal on the padding */
        } else {
            for (int p = Rp[j]; p < Rp[j + 1]; p++)
                if (A->Lpos[Ri[p]] >= 0) {
                    W->Wi[nz] = A->Lpos[Ri[p]];
                    W->Wx[nz++] = Rx[p];
                }
        }
        W->Wp[k + 1] = nz;
    }
    return KT_OK;
}

static void w_apply(const weighted *W, const double *x, double *y)
{
    int m = W->A->m;
    memset(y, 0, sizeof(double) * m);
    for (int k = 0; k < m; k++)
        for (int p = W->Wp[k]; p < W->Wp[k + 1]; p++) y[W->Wi[p]] += W->Wx[p] * x[k];
}

static int weighted_op(void *ctx, const double *x, double *y, kt_err *e)
{
    weighted *W = ctx;
    if (schur_op(W->A, x, W->tmp, e)) return e->code;
    w_apply(W, W->tmp, y);
    return KT_OK;
}

/* ||fh|| over the free rows: the scale of the true residual. */
static double free_norm(const kt_aug *A)
{
    double s = 0;
    for (int i = 0; i < 3 * A->mesh.nn; i++)
        if (!A->cons[i]) s += A->fh[i] * A->fh[i];
    return sqrt(s);
}

static double vnorm(const double *x, int n)
{
    double s = 0;
    for (int i = 0; i < n; i++) s += x[i] * x[i];
    return sqrt(s);
}

static int gmres_step(kt_aug *A, kt_err *e)
{
    if (A->m == 0) return KT_OK;
    klu_pre P;
    weighted W;
    memset(&P, 0, sizeof P);
    memset(&W, 0, sizeof W);
    if (A->o.precond != KT_AUG_PRECOND_NONE && klu_setup(A, &P, e)) return e->code;
    if (build_w(A, &W, e)) {
        klu_pre_free(&P);
        weighted_free(&W);
        return e->code;
    }
    w_apply(&W, A->rhs, W.rhs);
    double fn = free_norm(A), wn = vnorm(W.rhs, A->m);
    /* stop when ||W r_s|| <= tol ||f^||, i.e. on the true relative residual */
    double tol = fn > 0 && wn > 0 ? A->o.tol * fn / wn : A->o.tol;
    kt_krylov_opts ko = {tol, A->o.restart, A->o.maxit > 0 ? A->o.maxit : 2000};
    kt_krylov_stats st;
    memset(A->a2, 0, sizeof(double) * A->m);
    kt_krylov_gmres(A->m, weighted_op, &W, P.num ? klu_apply : NULL, &P, W.rhs, A->a2, &ko, &st,
                    e);
    klu_pre_free(&P);
    weighted_free(&W);
    A->row.iters = st.iters;
    if (e->code) return e->code;
    if (!st.converged)
        return kt_fail(e, KT_ERUN, "step %d: GMRES did not reach the relative residual %.3g in %d "
                       "iterations (reached %.3g; m = %d): raise --maxit or --restart, use a "
                       "preconditioner, or loosen --tol", A->step, A->o.tol, st.iters,
                       st.relres * (fn > 0 && wn > 0 ? wn / fn : 1.0), A->m);
    return KT_OK;
}

/* ----------------------------------------------------------- steps 1 and 3 */

/* w = fh - fh0 on the DOFs where they differ (fh0 = 0 on the padding). */
static void load_d(kt_aug *A)
{
    const aug_base *b = A->base;
    for (int q = 0; q < A->nd; q++) {
        int i = A->dlist[q];
        A->w[i] = A->fh[i] - (i < b->n0 ? b->fh0[i] : 0.0);
    }
}

static int step1(kt_aug *A, kt_err *e)
{
    const aug_base *b = A->base;
    load_d(A);
    if (A->nd > 0 && rinv_sparse(A, A->w, A->dlist, A->nd, A->Ldof, A->m, e)) return e->code;
    const double *X = A->nd > 0 ? A->X->x : NULL;
    for (int k = 0; k < A->m; k++) {
        int j = A->Ldof[k];
        A->rhs[k] = j < b->n0 ? b->y0[j] + (X ? X[j] : 0.0) : A->w[j] / padv(A, j);
    }
    return KT_OK;
}

/* Full a1: sparse forward solve (L D) on the closure, then a dense back-substitution. */
static int back_full(kt_aug *A, const int *pat, int np, double *z, kt_err *e)
{
    const aug_base *b = A->base;
    int n0 = b->n0;
    fill_bset(A, A->w2, pat, np, NULL, 0, b->iperm);
    if (solve2(A, CHOLMOD_LD, A->Bd, A->Bset, e)) return e->code;
    cholmod_dense *Z = cholmod_zeros(n0, 1, CHOLMOD_REAL, &A->c);
    if (!Z) return kt_fail(e, KT_ERUN, "out of memory");
    const int *Xs = A->Xset->i;
    int nx = ((int *)A->Xset->p)[1];
    for (int q = 0; q < nx; q++) ((double *)Z->x)[Xs[q]] = ((double *)A->X->x)[Xs[q]];
    cholmod_dense *X2 = cholmod_solve(CHOLMOD_Lt, b->L, Z, &A->c);
    cholmod_free_dense(&Z, &A->c);
    if (!X2) return kt_fail(e, KT_ERUN, "CHOLMOD solve failed (status %d)", A->c.status);
    for (int k = 0; k < n0; k++) z[b->perm[k]] = ((double *)X2->x)[k];
    cholmod_free_dense(&X2, &A->c);
    return KT_OK;
}

static int step3(kt_aug *A, kt_err *e)
{
    const aug_base *b = A->base;
    int n = 3 * A->mesh.nn, n0 = b->n0;
    /* w2 = d - J a2 on dlist u Jpat */
    for (int q = 0; q < A->nd; q++) A->w2[A->dlist[q]] = A->w[A->dlist[q]];
    scatter_j(A, A->a2, A->w2, -1.0);
    int np = A->nd + A->njpat;
    int *pat = kt_calloc((size_t)np + 1, sizeof(int), e);
    if (!pat) return e->code;
    memcpy(pat, A->dlist, sizeof(int) * A->nd);
    memcpy(pat + A->nd, A->Jpat, sizeof(int) * A->njpat);
    if (A->outmask) {
        int *set = kt_calloc((size_t)n, sizeof(int), e), ns = 0;
        if (set) {
            for (int i = 0; i < n; i++)
                if (A->outmask[i]) set[ns++] = i;
            rinv_sparse(A, A->w2, pat, np, set, ns, e);
        }
        free(set);
        for (int i = 0; i < n && !e->code; i++)
            A->u[i] = !A->outmask[i] ? NAN : i < n0 ? b->y0[i] + ((double *)A->X->x)[i] : A->w2[i] / padv(A, i);
    } else if (back_full(A, pat, np, A->u, e) == KT_OK) {
        for (int i = 0; i < n0; i++) A->u[i] += b->y0[i];
        for (int i = n0; i < n; i++) A->u[i] = A->w2[i] / padv(A, i);
    }
    for (int q = 0; q < np; q++) A->w2[pat[q]] = 0;
    free(pat);
    return e->code;
}

/* u on Lset from a2; u = g on every constrained DOF; reactions in D from a2. */
static void finish_u(kt_aug *A)
{
    int n = 3 * A->mesh.nn;
    for (int k = 0; k < A->m; k++) {
        int j = A->Ldof[k];
        if (A->outmask && !A->outmask[j]) continue;
        if (!A->cons[j]) A->u[j] = A->a2[k];
    }
    for (int i = 0; i < n; i++)
        if (A->cons[i] && (!A->outmask || A->outmask[i])) A->u[i] = A->g[i];
    for (int q = 0; q < A->nd; q++) A->w[A->dlist[q]] = 0;
}

int aug_solve_augmented(kt_aug *A, kt_err *e)
{
    A->closure_max = 0;
    double t0 = kt_now();
    if (step1(A, e)) return e->code;
    double t1 = kt_now();
    if (gmres_step(A, e)) return e->code;
    double t2 = kt_now();
    if (step3(A, e)) return e->code;
    finish_u(A);
    double t3 = kt_now();
    A->row.t_step1 = aug_ms(t1 - t0);
    A->row.t_step2 = aug_ms(t2 - t1);
    A->row.t_step3 = aug_ms(t3 - t2);
    A->row.closure_max = A->closure_max;
    A->react_valid = 0;
    return KT_OK;
}

/* Reaction -s a2 at the D DOFs (the rest is computed on demand from element columns). */
void aug_react_from_a2(kt_aug *A)
{
    for (int k = 0; k < A->m; k++) {
        int j = A->Ldof[k];
        if (A->cons[j]) A->react[j] = -A->J[k].x[0] * A->a2[k];
    }
}

/* ||(T a' - fh)_free|| / ||fh_free|| with T = R with the Lset columns replaced by J. */
double aug_residual(kt_aug *A, kt_err *e)
{
    const aug_base *b = A->base;
    int n = 3 * A->mesh.nn, n0 = b->n0;
    if (A->outmask) return NAN;
    cholmod_dense *V = cholmod_zeros(n0, 1, CHOLMOD_REAL, &A->c);
    cholmod_dense *Rv = cholmod_zeros(n0, 1, CHOLMOD_REAL, &A->c);
    double *r = kt_calloc((size_t)n, sizeof(double), e);
    double res = NAN;
    if (V && Rv && r) {
        double *v = V->x;
        memcpy(v, A->u, sizeof(double) * n0);
        for (int k = 0; k < A->m; k++)
            if (A->Ldof[k] < n0) v[A->Ldof[k]] = 0;
        double one[2] = {1, 0}, zero[2] = {0, 0};
        cholmod_sdmult(b->R, 0, one, zero, V, Rv, &A->c);
        memcpy(r, Rv->x, sizeof(double) * n0);
        scatter_j(A, A->a2, r, 1.0);
        double num = 0, den = 0;
        for (int i = 0; i < n; i++) {
            if (A->cons[i]) continue;
            double d = r[i] - A->fh[i];
            num += d * d;
            den += A->fh[i] * A->fh[i];
        }
        res = den > 0 ? sqrt(num / den) : sqrt(num);
    } else if (!e->code) {
        kt_fail(e, KT_ERUN, "out of memory");
    }
    cholmod_free_dense(&V, &A->c);
    cholmod_free_dense(&Rv, &A->c);
    free(r);
    return res;
}

void aug_solve_free(kt_aug *A)
{
    for (int k = 0; k < A->mcap; k++) aug_col_free(&A->J[k]);
    free(A->J);
    free(A->Ldof);
    free(A->a2);
    free(A->rhs);
    free(A->Jpat);
    free(A->dlist);
    cholmod_free_dense(&A->Bd, &A->c);
    cholmod_free_dense(&A->X, &A->c);
    cholmod_free_dense(&A->Y, &A->c);
    cholmod_free_dense(&A->E, &A->c);
    cholmod_free_sparse(&A->Bset, &A->c);
    cholmod_free_sparse(&A->Xset, &A->c);
}
