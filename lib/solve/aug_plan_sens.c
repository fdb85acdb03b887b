/* aug_plan_sens.c: the planned method's derivatives (aug_plan_sens.h). Every quantity is
 * carried at once: the matrix derivatives share one pattern (T^T K T's, over every variable)
 * and hold nd values per entry; a step's right-hand sides, products and substitutions run
 * over interleaved blocks (row i's nd values together), so the factor and the pattern are
 * read once per step for all quantities. */
#include "aug_plan_sens.h"
#include "chol.h"

#include "wound.h"

#include <stdlib.h>
#include <string.h>

void kt_plan_sens_free(kt_plan_sens *D)
{
    if (D->started) {
        cholmod_free_sparse(&D->P, &D->c);
        cholmod_finish(&D->c);
    }
    free(D->dAx);
    free(D->dfe);
    free(D->var);
    free(D->r);
    free(D->tf);
    free(D->y);
    free(D->z);
    free(D->p1);
    free(D->work);
    free(D->want);
    memset(D, 0, sizeof *D);
}

/* The variables' pattern as triplets (lower: v >= w); T NULL only counts. */
typedef struct tsink {
    cholmod_triplet *T;
    size_t nt;
} tsink;

static void tput(void *ctx, int v, int w, double x)
{
    (void)x;
    tsink *s = ctx;
    if (s->T) {
        ((int *)s->T->i)[s->nt] = v;
        ((int *)s->T->j)[s->nt] = w;
    }
    s->nt++;
}

/* D->P: the pattern of T^T K T on the final mesh (K's pattern through the chains; with a
 * healed wound K's pattern holds the cut face pairs' couplings, so the bridge's entries in the
 * variables, a subset of them through the chains, are in it). */
static int variable_pattern(kt_plan_sens *D, const kt_edits_plan *p, const kt_mesh *final,
                            const kt_materials *mats, kt_err *e)
{
    cholmod_sparse *K = kt_fem_pattern(final, kt_wound_on(mats) ? mats->wound : NULL, &D->c, e);
    if (!K) return e->code;
    tsink count = {NULL, 0};
    cholmod_triplet *T = NULL;
    if (kt_plan_transform(p, K, tput, &count, e) == KT_OK &&
        !(T = cholmod_allocate_triplet(D->nvar, D->nvar, count.nt ? count.nt : 1, -1,
                                       CHOLMOD_PATTERN, &D->c)))
        kt_fail(e, KT_ERUN, "out of memory for the derivatives' pattern");
    tsink fill = {T, 0};
    if (T && kt_plan_transform(p, K, tput, &fill, e) == KT_OK) {
        T->nnz = fill.nt;
        if (!(D->P = cholmod_triplet_to_sparse(T, fill.nt, &D->c)))
            kt_fail(e, KT_ERUN, "out of memory for the derivatives' pattern");
    }
    cholmod_free_triplet(&T, &D->c);
    cholmod_free_sparse(&K, &D->c);
    return e->code;
}

/* Position in D->P of the first row of node block n (rows 3n.. 3n+2, those >= w) in column w:
 * the pattern holds whole node blocks (K's, through same-component chains), so row v of the
 * block sits at the result + v - max(3n, w). -1: no such block. */
static int block_at(const cholmod_sparse *P, int n, int w)
{
    const int *Pp = P->p, *Pi = P->i;
    int lo = Pp[w], hi = Pp[w + 1], r0 = 3 * n > w ? 3 * n : w;
    while (lo < hi) {
        int mid = lo + (hi - lo) / 2;
        if (Pi[mid] < r0) lo = mid + 1;
        else hi = mid;
    }
    return lo < Pp[w + 1] && Pi[lo] == r0 ? lo : -1;
}

/* block_at(P, n, w) from q0 = block_at(P, n, 3m), m = w / 3: the three columns of node m hold
 * the same node blocks (whole 3 x 3 blocks below the diagonal one), so for n > m the block sits
 * c = w - 3m places further from the start of column w than of column 3m; for n == m it opens
 * column w. Checked against the pattern, else searched. */
static int block_in(const cholmod_sparse *P, int n, int w, int q0)
{
    const int *Pp = P->p, *Pi = P->i;
    int m = w / 3, q = -1;
    if (n == m) q = Pp[w];
    else if (n > m && q0 >= 0) q = Pp[w] + (q0 - Pp[3 * m]) - (w - 3 * m);
    if (q >= Pp[w] && q < Pp[w + 1] && Pi[q] == (n == m ? w : 3 * n)) return q;
    return block_at(P, n, w);
}

/* dAx(v, w) += x (nd values) for the rows v of node block nv >= w, column w: x + nd (v - v0);
 * q0: node nb's block in column 3 (w / 3) (block_in). */
static int add_block(kt_plan_sens *D, int nb, int w, int r0, int r1, const double *x, int q0,
                     kt_err *e)
{
    int q = block_in(D->P, nb, w, q0), v0 = 3 * nb > w ? 3 * nb : w, nd = D->nd;
    const int *Pi = D->P->i;
    for (int r = r0; r < r1; r++) {
        int v = 3 * nb + r;
        if (v < w) continue;
        int at = q + v - v0;
        if (q < 0 || Pi[at] != v)
            return kt_fail(e, KT_ERUN, "derivative entry (%d, %d) outside the plan's pattern", v, w);
        double *d = D->dAx + (size_t)nd * at;
        for (int k = 0; k < nd; k++) d[k] += x[(r - r0) * nd + k];
    }
    return KT_OK;
}

/* One element's nd matrices (Ke + k ld^2, ld = 3 nv) into dAx as kt_plan_transform takes the
 * assembled K: every lower entry K(I, J) of tet t's nodes, and its mirror, through the
 * chains; ch[a] holds 3x node a's chain (nch[a] nodes). */
static int scatter(kt_plan_sens *D, const int *t, int nv, const int (*ch)[KT_PLAN_CHAIN_MAX],
                   const int *nch, const double *Ke, int *q0, kt_err *e)
{
    int ld = 3 * nv, nd = D->nd;
    double x[3 * KT_FEM_MULTI_MAX], xm[3 * KT_FEM_MULTI_MAX];
    for (int b = 0; b < nv; b++)
        for (int a = 0; a < nv; a++) {
            if (t[a] < t[b]) continue;
            int same = t[a] == t[b], nab = nch[a] * nch[b];
            /* the node pairs' blocks in their first columns, searched once for the 3 columns */
            for (int al = 0; al < nch[a]; al++)
                for (int be = 0; be < nch[b]; be++) {
                    int na = ch[a][al] / 3, nb = ch[b][be] / 3;
                    q0[al * nch[b] + be] = block_at(D->P, na, 3 * nb);
                    q0[nab + al * nch[b] + be] = block_at(D->P, nb, 3 * na);
                }
            for (int c = 0; c < 3; c++) {
                /* column c of the node pair: rows r (K(3t[a]+r, 3t[b]+c)), and the mirror
                 * K(3t[b]+c, 3t[a]+r) as column r's row c (off the diagonal entry) */
                int r0 = same ? c : 0;
                for (int r = r0; r < 3; r++)
                    for (int k = 0; k < nd; k++)
                        x[(r - r0) * nd + k] = Ke[(size_t)k * ld * ld + (3 * a + r) * ld + 3 * b + c];
                for (int al = 0; al < nch[a]; al++)
                    for (int be = 0; be < nch[b]; be++) {
                        int na = ch[a][al] / 3, nb = ch[b][be] / 3, ab = al * nch[b] + be;
                        if (add_block(D, na, 3 * nb + c, r0, 3, x, q0[ab], e)) return e->code;
                        for (int r = r0; r < 3; r++) { /* the mirror: (3nb + c, 3na + r) */
                            if (same && r == c) continue;
                            for (int k = 0; k < nd; k++) xm[k] = x[(r - r0) * nd + k];
                            if (add_block(D, nb, 3 * na + r, c, c + 1, xm, q0[nab + ab], e))
                                return e->code;
                        }
                    }
            }
        }
    return KT_OK;
}

/* Every dA/dq into D->dAx and the release forces into D->dfe: one pass over the final mesh's
 * tets (a tet's data and forces do not change with the cut). */
static int element_pass(kt_plan_sens *D, const kt_edits_plan *p, const kt_mesh *final,
                        const kt_materials *mats, kt_err *e)
{
    const kt_fem_sens *S = D->S;
    int nd = D->nd, nv = kt_tet_nv(final->order), ld = 3 * nv, sig = 0, nch[10];
    const kt_fem_tetdata *td[KT_FEM_MULTI_MAX];
    for (int k = 0; k < nd; k++) {
        td[k] = &S->d[k].td;
        sig |= td[k]->sig != NULL;
    }
    size_t nnz = ((const int *)D->P->p)[D->P->ncol];
    if (!(D->dAx = kt_calloc(nnz * nd, sizeof(double), e))) return e->code;
    if (sig && !(D->dfe = kt_calloc((size_t)final->ne * ld * nd, sizeof(double), e)))
        return e->code;
    double *Ke = kt_calloc((size_t)ld * ld * nd, sizeof(double), e), fe[30 * KT_FEM_MULTI_MAX];
    int(*ch)[KT_PLAN_CHAIN_MAX] = kt_calloc(10, sizeof *ch, e);
    int *q0 = kt_calloc(2 * (size_t)KT_PLAN_CHAIN_MAX * KT_PLAN_CHAIN_MAX, sizeof(int), e);
    for (int el = 0; el < final->ne && !e->code; el++) {
        const int *t = final->tet + (size_t)el * nv;
        for (int a = 0; a < nv && !e->code; a++)
            if ((nch[a] = kt_plan_chain(p, 3 * t[a], ch[a])) < 0)
                kt_fail(e, KT_EINPUT, "node %d is split more than %d times", t[a] + 1,
                        KT_PLAN_CHAIN_MAX);
        if (e->code || kt_fem_element_multi(final, mats, td, nd, el, Ke, sig ? fe : NULL, e) ||
            scatter(D, t, nv, (const int(*)[KT_PLAN_CHAIN_MAX])ch, nch, Ke, q0, e))
            break;
        for (int r = 0; sig && r < ld; r++)
            for (int k = 0; k < nd; k++) D->dfe[((size_t)el * ld + r) * nd + k] = fe[k * ld + r];
    }
    free(Ke);
    free(ch);
    free(q0);
    return e->code;
}

/* dA/dheal = the bridge B in the variables (wound.h), into dAx's slot k of every entry. */
typedef struct heal_sink {
    kt_plan_sens *D;
    int k;
    kt_err *e;
} heal_sink;

static void heal_put(void *ctx, int v, int w, double x)
{
    heal_sink *h = ctx;
    if (h->e->code) return;
    kt_plan_sens *D = h->D;
    int q = block_at(D->P, v / 3, w), v0 = 3 * (v / 3) > w ? 3 * (v / 3) : w, at = q + v - v0;
    if (q < 0 || ((const int *)D->P->i)[at] != v) {
        kt_fail(h->e, KT_ERUN, "bridge entry (%d, %d) outside the plan's pattern", v, w);
        return;
    }
    D->dAx[(size_t)D->nd * at + h->k] += x;
}

static int heal_pass(kt_plan_sens *D, const kt_edits_plan *p, const kt_mesh *final,
                     const kt_materials *mats, kt_err *e)
{
    for (int k = 0; k < D->nd && !e->code; k++) {
        if (D->S->d[k].dwound == 0 || !kt_wound_on(mats)) continue;
        heal_sink h = {D, k, e};
        if (kt_wound_assemble(mats->wound, final, p->parent, D->S->d[k].dwound, heal_put, &h, e))
            break;
    }
    return e->code;
}

int kt_plan_sens_matrices(kt_plan_sens *D, const kt_fem_sens *S, const kt_edits_plan *p,
                          const kt_mesh *final, const kt_materials *mats, kt_err *e)
{
    double t0 = kt_now();
    memset(D, 0, sizeof *D);
    D->S = S;
    D->nd = S->nd;
    D->nvar = 3 * p->nn;
    kt_chol_start(&D->c);
    D->started = 1;
    if (D->nd > KT_FEM_MULTI_MAX)
        return kt_fail(e, KT_ERUN, "%d derivative quantities (at most %d)", D->nd,
                       KT_FEM_MULTI_MAX);
    if (D->nd && (variable_pattern(D, p, final, mats, e) || element_pass(D, p, final, mats, e) ||
                  heal_pass(D, p, final, mats, e)))
        return e->code;
    D->t_setup = kt_now() - t0;
    return KT_OK;
}

int kt_plan_sens_bind(kt_plan_sens *D, const kt_plan_factor *F, kt_err *e)
{
    size_t n = (size_t)D->nvar, nd = (size_t)(D->nd ? D->nd : 1), nf = (size_t)F->nfree + 1;
    D->var = kt_calloc(nf, sizeof(int), e);
    D->r = kt_calloc(n * nd, sizeof(double), e);
    D->tf = kt_calloc(n * nd, sizeof(double), e);
    D->y = kt_calloc(n * nd, sizeof(double), e);
    D->z = kt_calloc(nf * nd, sizeof(double), e);
    D->p1 = kt_calloc(n, sizeof(double), e);
    D->work = kt_calloc((size_t)F->maxrow * nd, sizeof(double), e);
    if (e->code) return e->code;
    for (int v = 0; v < D->nvar; v++)
        if (F->pos[v] >= 0) D->var[F->pos[v]] = v;
    return KT_OK;
}

/* D->tf (n x nd) := T^T df/dq on the cut mesh: pressures (the step's pressure view), the
 * release of dsig0/dq, summed through the chains. */
static int loads(kt_plan_sens *D, kt_plan_state *s, const kt_edits_plan *p, kt_err *e)
{
    const kt_fem_sens *S = D->S;
    const kt_mesh *m = &s->mesh;
    int nd = D->nd, n = 3 * m->nn, nv = kt_tet_nv(m->order), ld = 3 * nv;
    memset(D->r, 0, (size_t)n * nd * sizeof(double));
    for (int k = 0; k < nd; k++) {
        const kt_fem_dparam *d = &S->d[k];
        int any = 0;
        memset(D->p1, 0, (size_t)n * sizeof(double));
        for (int i = 0; i < S->npress; i++)
            if (d->dpress[i] != 0) {
                any = 1;
                if (kt_fem_pressure(&s->pview, S->ptag[i], d->dpress[i], D->p1, e)) return e->code;
            }
        for (int x = 0; any && x < n; x++) D->r[(size_t)x * nd + k] += D->p1[x];
    }
    for (int el = 0; D->dfe && el < m->ne; el++) {
        const int *t = m->tet + (size_t)el * nv;
        const double *fe = D->dfe + (size_t)el * ld * nd;
        for (int a = 0; a < nv; a++)
            for (int c = 0; c < 3; c++) {
                double *r = D->r + (3 * (size_t)t[a] + c) * nd;
                const double *f = fe + (size_t)(3 * a + c) * nd;
                for (int k = 0; k < nd; k++) r[k] += f[k];
            }
    }
    memset(D->tf, 0, (size_t)n * nd * sizeof(double));
    for (int i = 0; i < n; i++)
        for (int a = i / 3; a >= 0; a = p->parent[a]) {
            double *t = D->tf + (3 * (size_t)a + i % 3) * nd;
            const double *r = D->r + (size_t)i * nd;
            for (int k = 0; k < nd; k++) t[k] += r[k];
        }
    return KT_OK;
}

/* D->y (n x nd) := (dA/dq) v for every quantity, on the variables present (< n). */
static void product(kt_plan_sens *D, int n, const double *v)
{
    const int *Pp = D->P->p, *Pi = D->P->i;
    int nd = D->nd;
    double *y = D->y;
    memset(y, 0, (size_t)n * nd * sizeof(double));
    for (int j = 0; j < n; j++)
        for (int q = Pp[j]; q < Pp[j + 1]; q++) {
            int i = Pi[q];
            if (i >= n) break; /* row indices sorted */
            const double *x = D->dAx + (size_t)nd * q;
            double *yi = y + (size_t)i * nd, *yj = y + (size_t)j * nd;
            for (int k = 0; k < nd; k++) yi[k] += x[k] * v[j];
            if (i != j)
                for (int k = 0; k < nd; k++) yj[k] += x[k] * v[i];
        }
}

int kt_plan_sens_solve(kt_plan_sens *D, kt_plan_state *s, const kt_edits_plan *p,
                       const kt_plan_factor *F, double *du, kt_err *e)
{
    double t0 = kt_now();
    int nd = D->nd, nn = s->mesh.nn, n = 3 * nn, N = F->nfree_at[s->step];
    if (nd == 0) return KT_OK;
    const int *Perm = F->L->Perm;
    if (loads(D, s, p, e)) return e->code;
    product(D, n, s->v);
    /* T^T df/dq - (dA/dq)_k v on the free variables, into L's numbering */
    memset(D->z, 0, (size_t)F->nfree * nd * sizeof(double));
    for (int q = 0; q < N; q++) {
        size_t v = (size_t)D->var[Perm[q]] * nd;
        for (int k = 0; k < nd; k++) D->z[(size_t)q * nd + k] = D->tf[v + k] - D->y[v + k];
    }
    kt_plan_forward_multi(F, D->work, 0, N, nd, N, D->z); /* rows >= N: not read, zeroed */
    memset(D->z + (size_t)N * nd, 0, (size_t)(F->nfree - N) * nd * sizeof(double));
    kt_plan_back_multi(F, D->want, D->work, N, nd, D->z);
    /* dv (constrained variables: their values do not depend on q), du = T dv */
    double *dv = D->y;
    memset(dv, 0, (size_t)n * nd * sizeof(double));
    for (int q = 0; q < F->nfree; q++) {
        int v = D->var[Perm[q]];
        if (v < n) memcpy(dv + (size_t)v * nd, D->z + (size_t)q * nd, nd * sizeof(double));
    }
    for (int k = 0; k < nd; k++) {
        double *o = du + (size_t)k * n;
        for (int a = 0; a < nn; a++)
            for (int c = 0; c < 3; c++)
                o[3 * a + c] = dv[(3 * (size_t)a + c) * nd + k] +
                               (p->parent[a] >= 0 ? o[3 * p->parent[a] + c] : 0);
    }
    D->t_steps += kt_now() - t0;
    return KT_OK;
}
