/* aug_intact.c: the factor of the intact stiffness on its free DOFs, made once per stream
 * (supernodal L L^T in the run's ordering; natural keeps mesh-prep's order, which puts the
 * surfaces to be cut last, at the top of the elimination tree), with full substitutions and
 * the forward substitution restricted to the supernodes a sparse column reaches. */
#include <stdlib.h>
#include <string.h>

#include <cblas.h>

#include "aug_impl.h"

void kt_aug_intact_free(aug_intact *F, cholmod_common *c)
{
    cholmod_free_sparse(&F->K, c);
    cholmod_free_factor(&F->L, c);
    cholmod_free_dense(&F->w[0], c);
    cholmod_free_dense(&F->w[1], c);
    cholmod_free_dense(&F->Y, c);
    cholmod_free_dense(&F->E, c);
    free(F->pos);
    free(F->iperm);
    free(F->sparent);
    free(F->col_super);
    memset(F, 0, sizeof *F);
}

/* The free block of the intact K (lower, stype -1) in free positions. */
static cholmod_sparse *free_block(aug_intact *F, const aug_stream *s, cholmod_common *c,
                                  kt_err *e)
{
    cholmod_sparse *K = kt_fem_assemble(&s->mesh, &s->mats, NULL, c, e);
    if (!K) return NULL;
    const int *Kp = K->p, *Ki = K->i, *Knz = K->nz;
    const double *Kx = K->x;
    size_t nz = 0;
    for (int j = 0; j < (int)K->ncol; j++) {
        if (F->pos[j] < 0) continue;
        int end = K->packed ? Kp[j + 1] : Kp[j] + Knz[j];
        for (int q = Kp[j]; q < end; q++) nz += Ki[q] >= j && F->pos[Ki[q]] >= 0;
    }
    cholmod_sparse *B = cholmod_allocate_sparse(F->nK, F->nK, nz, 0, 1, -1, CHOLMOD_REAL, c);
    if (!B) {
        cholmod_free_sparse(&K, c);
        kt_fail(e, KT_ERUN, "out of memory for the intact stiffness");
        return NULL;
    }
    int *Bp = B->p, *Bi = B->i, n = 0;
    double *Bx = B->x;
    for (int j = 0; j < (int)K->ncol; j++) {
        if (F->pos[j] < 0) continue;
        Bp[F->pos[j]] = n;
        int end = K->packed ? Kp[j + 1] : Kp[j] + Knz[j];
        for (int q = Kp[j]; q < end; q++)
            if (Ki[q] >= j && F->pos[Ki[q]] >= 0) {
                Bi[n] = F->pos[Ki[q]];
                Bx[n++] = Kx[q];
            }
    }
    Bp[F->nK] = n;
    cholmod_free_sparse(&K, c);
    return B;
}

/* Supernode of each column and parent of each supernode. */
static int tree(aug_intact *F, kt_err *e)
{
    const cholmod_factor *L = F->L;
    const int *S = L->super, *pi = L->pi, *Ls = L->s;
    F->nsuper = (int)L->nsuper;
    F->sparent = kt_calloc((size_t)F->nsuper + 1, sizeof(int), e);
    F->col_super = kt_calloc((size_t)F->nK + 1, sizeof(int), e);
    F->iperm = kt_calloc((size_t)F->nK + 1, sizeof(int), e);
    if (e->code) return e->code;
    for (int s = 0; s < F->nsuper; s++)
        for (int k = S[s]; k < S[s + 1]; k++) F->col_super[k] = s;
    for (int s = 0; s < F->nsuper; s++) {
        int ncol = S[s + 1] - S[s], nrow = pi[s + 1] - pi[s];
        F->sparent[s] = nrow > ncol ? F->col_super[Ls[pi[s] + ncol]] : -1;
        if (nrow > F->maxrow) F->maxrow = nrow;
    }
    const int *P = L->Perm;
    for (int k = 0; k < F->nK; k++) F->iperm[P[k]] = k;
    return KT_OK;
}

int kt_aug_intact_build(aug_intact *F, const aug_stream *s, int ordering, cholmod_common *c,
                     kt_err *e)
{
    memset(F, 0, sizeof *F);
    double t0 = kt_now();
    int n0 = 3 * s->nn0;
    F->pos = kt_calloc((size_t)n0, sizeof(int), e);
    if (!F->pos) return e->code;
    for (int j = 0; j < n0; j++) F->pos[j] = s->fixed0[j] ? -1 : F->nK++;
    if (F->nK == 0) return kt_fail(e, KT_EINPUT, "every DOF of the intact scene is fixed");
    if (!(F->K = free_block(F, s, c, e))) return e->code;
    if (kt_aug_analyze(F->K, ordering, KT_AUG_FACTOR_SUPERNODAL, c, &F->L, e) ||
        kt_chol_factor(F->K, F->L, c, "the intact stiffness", e))
        return e->code;
    if (!F->L->is_super)
        return kt_fail(e, KT_ERUN, "CHOLMOD returned a simplicial factor of the intact stiffness");
    F->nnzL = c->lnz;
    F->t_factor = kt_now() - t0;
    return tree(F, e);
}

static int solve_sys(aug_intact *F, int sys, cholmod_dense *in, cholmod_dense **out,
                     cholmod_common *c, kt_err *e)
{
    if (!cholmod_solve2(sys, F->L, in, NULL, out, NULL, &F->Y, &F->E, c))
        return kt_fail(e, KT_ERUN, "CHOLMOD solve failed (status %d)", c->status);
    return KT_OK;
}

/* Two solves in a row on nK values: in -> out. */
static int two(aug_intact *F, int s1, int s2, const double *in, double *out, cholmod_common *c,
               kt_err *e)
{
    cholmod_dense B = kt_chol_column((double *)in, (size_t)F->nK);
    if (solve_sys(F, s1, &B, &F->w[0], c, e) || solve_sys(F, s2, F->w[0], &F->w[1], c, e))
        return e->code;
    memcpy(out, F->w[1]->x, (size_t)F->nK * sizeof(double));
    return KT_OK;
}

int kt_aug_intact_forward(aug_intact *F, const double *b, double *y, cholmod_common *c, kt_err *e)
{
    return two(F, CHOLMOD_P, CHOLMOD_L, b, y, c, e);
}

int kt_aug_intact_back(aug_intact *F, const double *y, double *x, cholmod_common *c, kt_err *e)
{
    return two(F, CHOLMOD_Lt, CHOLMOD_Pt, y, x, c, e);
}

static int cmp_int(const void *a, const void *b)
{
    int x = *(const int *)a, y = *(const int *)b;
    return (x > y) - (x < y);
}

int kt_aug_intact_closure(const aug_intact *F, const int *rows, int n, int *sup, int *mark,
                          int stamp)
{
    int ns = 0;
    for (int q = 0; q < n; q++)
        for (int s = F->col_super[rows[q]]; s >= 0 && mark[s] != stamp; s = F->sparent[s]) {
            mark[s] = stamp;
            sup[ns++] = s;
        }
    qsort(sup, (size_t)ns, sizeof(int), cmp_int);
    return ns;
}

void kt_aug_intact_forward_on(const aug_intact *F, const int *sup, int ns, double *x, double *tmp)
{
    const cholmod_factor *L = F->L;
    const int *S = L->super, *pi = L->pi, *px = L->px, *Ls = L->s;
    const double *Lx = L->x;
    for (int q = 0; q < ns; q++) {
        int s = sup[q], k1 = S[s], ncol = S[s + 1] - k1, nrow = pi[s + 1] - pi[s];
        const double *Xs = Lx + px[s];
        cblas_dtrsv(CblasColMajor, CblasLower, CblasNoTrans, CblasNonUnit, ncol, Xs, nrow,
                    x + k1, 1);
        int nb = nrow - ncol;
        if (nb == 0) continue;
        cblas_dgemv(CblasColMajor, CblasNoTrans, nb, ncol, 1.0, Xs + ncol, nrow, x + k1, 1, 0.0,
                    tmp, 1);
        const int *rows = Ls + pi[s] + ncol;
        for (int i = 0; i < nb; i++) x[rows[i]] -= tmp[i];
    }
}
