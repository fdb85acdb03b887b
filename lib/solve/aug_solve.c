/* aug_solve.c: one step of the augmented method, top to bottom: loads on the cut mesh (fem
 * layer) -> right-hand side in the variables -> substitutions with the intact factor and the
 * dense Schur factor -> backward error (one step of iterative refinement above --tol) ->
 * displacement u = T v.
 *
 * The bordered system [K C; C^T D] [x_K; d] = [b_K; b_R] is solved as
 *   y = L^-1 P b_K,  d = S^-1 (b_R - W^T y),  x_K = P^T L^-T (y - W d). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "aug_impl.h"

void kt_aug_rhs_free(aug_rhs *r)
{
    free(r->u0);
    free(r->z);
    free(r->b);
    free(r->x);
    free(r->r);
    free(r->dx);
    free(r->y);
    memset(r, 0, sizeof *r);
}

static int rhs_size(aug_rhs *r, int nK, int m, int n, kt_err *e)
{
    kt_aug_rhs_free(r);
    r->nK = nK, r->m = m, r->n = n;
    size_t nv = (size_t)nK + m;
    r->u0 = kt_calloc((size_t)n, sizeof(double), e);
    r->z = kt_calloc((size_t)n, sizeof(double), e);
    r->b = kt_calloc(nv, sizeof(double), e);
    r->x = kt_calloc(nv, sizeof(double), e);
    r->r = kt_calloc(nv, sizeof(double), e);
    r->dx = kt_calloc(nv, sizeof(double), e);
    r->y = kt_calloc((size_t)nK, sizeof(double), e);
    return e->code;
}

/* The variable at the root of DOF i's chain (an intact DOF). */
static int root(const aug_stream *s, int i)
{
    int a = i / 3;
    while (s->parent[a] >= 0) a = s->parent[a];
    return 3 * a + i % 3;
}

/* z = f - K u0, u0 the displacement the intact scene's constraints give every DOF (their
 * values carried by the increments' chains); element by element where u0 is not zero. */
static int lifted_loads(const aug_stream *s, aug_rhs *r, kt_err *e)
{
    const kt_mesh *m = &s->mesh;
    int nv = kt_tet_nv(m->order), nd = 3 * nv, any = 0;
    for (int i = 0; i < r->n; i++) {
        int v = root(s, i);
        r->u0[i] = s->fixed0[v] ? s->g[v] : 0.0;
        any |= r->u0[i] != 0;
        r->z[i] = s->f[i];
    }
    if (!any) return KT_OK;
    double Ke[900], ue[30];
    for (int t = 0; t < m->ne; t++) {
        const int *tn = m->tet + (size_t)t * nv;
        int nz = 0;
        for (int l = 0; l < nv; l++)
            for (int c = 0; c < 3; c++) nz |= (ue[3 * l + c] = r->u0[3 * tn[l] + c]) != 0;
        if (!nz) continue;
        if (kt_fem_element(m, &s->mats, t, Ke, e)) return e->code;
        for (int p = 0; p < nd; p++) {
            double acc = 0;
            for (int q = 0; q < nd; q++) acc += Ke[(size_t)p * nd + q] * ue[q];
            r->z[3 * tn[p / 3] + p % 3] -= acc;
        }
    }
    return KT_OK;
}

/* b = T^T z on the free variables; the multipliers' rows s (g - u0). */
static void assemble_rhs(const aug_stream *s, const aug_intact *F, const aug_border *B, aug_rhs *r)
{
    double *bR = r->b + r->nK;
    for (int i = 0; i < r->n; i++) {
        int c = i % 3;
        for (int a = i / 3; a >= 0; a = s->parent[a]) {
            int v = 3 * a + c;
            if (a < s->nn0) {
                if (F->pos[v] >= 0) r->b[F->pos[v]] += r->z[i];
            } else {
                bR[B->apos[v]] += r->z[i];
            }
        }
    }
    for (int q = 0; q < B->m; q++)
        if (B->var[q].kind == AUG_MULTIPLIER) {
            int j = B->var[q].dof;
            bR[q] = B->var[q].scale * (s->g[j] - r->u0[j]);
        }
}

/* x = A^-1 b by the bordered factor. */
static int substitute(kt_aug *A, const double *b, double *x, kt_err *e)
{
    aug_intact *F = &A->F;
    int nK = F->nK;
    double *y = A->r.y, *d = x + nK;
    if (kt_aug_intact_forward(F, b, y, &A->c, e)) return e->code;
    memcpy(d, b + nK, (size_t)A->B.m * sizeof(double));
    kt_aug_border_wt(&A->B, F, y, d);
    kt_aug_border_solve(&A->B, d);
    kt_aug_border_w(&A->B, F, d, y);
    return kt_aug_intact_back(F, y, x, &A->c, e);
}

/* r = b - A x; returns ||r|| / ||b|| and sets *backward = ||r|| / (|| |A||x| || + ||b||). */
static double residual(const kt_aug *A, const double *b, const double *x, double *r, double *ax,
                       double *backward)
{
    const cholmod_sparse *K = A->F.K;
    const int *Kp = K->p, *Ki = K->i;
    const double *Kx = K->x;
    int nK = A->F.nK, m = A->B.m;
    size_t nv = (size_t)nK + m;
    memcpy(r, b, nv * sizeof(double));
    memset(ax, 0, nv * sizeof(double));
    for (int j = 0; j < nK; j++)
        for (int q = Kp[j]; q < Kp[j + 1]; q++) {
            int i = Ki[q];
            r[i] -= Kx[q] * x[j];
            ax[i] += fabs(Kx[q] * x[j]);
            if (i != j) {
                r[j] -= Kx[q] * x[i];
                ax[j] += fabs(Kx[q] * x[i]);
            }
        }
    for (int q = 0; q < m; q++) {
        const aug_col *C = &A->B.var[q].C, *D = &A->B.var[q].D;
        int Q = nK + q;
        for (int p = 0; p < C->n; p++) {
            int i = C->i[p];
            r[i] -= C->x[p] * x[Q];
            ax[i] += fabs(C->x[p] * x[Q]);
            r[Q] -= C->x[p] * x[i];
            ax[Q] += fabs(C->x[p] * x[i]);
        }
        for (int p = 0; p < D->n; p++) {
            int R = nK + D->i[p];
            r[R] -= D->x[p] * x[Q];
            ax[R] += fabs(D->x[p] * x[Q]);
            if (R != Q) {
                r[Q] -= D->x[p] * x[R];
                ax[Q] += fabs(D->x[p] * x[R]);
            }
        }
    }
    double rr = 0, bb = 0, aa = 0;
    for (size_t i = 0; i < nv; i++) {
        rr += r[i] * r[i];
        bb += b[i] * b[i];
        aa += ax[i] * ax[i];
    }
    *backward = aa + bb == 0 ? 0 : sqrt(rr) / (sqrt(aa) + sqrt(bb)); /* NaN stays NaN */
    return bb > 0 ? sqrt(rr / bb) : sqrt(rr);
}

/* u = T v + u0: a node's own variable plus its parent's displacement (ascending node order). */
static void field(kt_aug *A)
{
    const aug_stream *s = &A->s;
    const aug_rhs *r = &A->r;
    for (int i = 0; i < r->n; i++) {
        int a = i / 3, c = i % 3;
        if (a < s->nn0)
            A->u[i] = A->F.pos[i] >= 0 ? r->x[A->F.pos[i]] : s->g[i];
        else
            A->u[i] = r->x[r->nK + A->B.apos[i]] + A->u[3 * s->parent[a] + c];
    }
}

int kt_aug_solve_augmented(kt_aug *A, kt_err *e)
{
    aug_rhs *r = &A->r;
    double t0 = kt_now();
    if (rhs_size(r, A->F.nK, A->B.m, 3 * A->s.mesh.nn, e) || kt_aug_stream_loads(&A->s, e) ||
        lifted_loads(&A->s, r, e))
        return e->code;
    assemble_rhs(&A->s, &A->F, &A->B, r);
    if (substitute(A, r->b, r->x, e)) return e->code;
    double t1 = kt_now(), backward;
    A->row.iters = 0;
    A->row.rel_residual = residual(A, r->b, r->x, r->r, r->dx, &backward);
    if (!(backward <= A->o.tol)) { /* one step of iterative refinement */
        if (substitute(A, r->r, r->dx, e)) return e->code;
        for (int i = 0; i < r->nK + r->m; i++) r->x[i] += r->dx[i];
        A->row.rel_residual = residual(A, r->b, r->x, r->r, r->dx, &backward);
        A->row.iters = 1;
    }
    if (!(backward <= A->o.tol))
        return kt_fail(e, KT_ERUN, "step %d: the augmented solve's backward error %.3g exceeds "
                       "--tol %.3g after a step of iterative refinement (m = %d)", A->s.step,
                       backward, A->o.tol, A->B.m);
    field(A);
    A->react_valid = 0;
    A->row.t_step2 = kt_aug_ms(t1 - t0);
    A->row.t_step3 = kt_aug_ms(kt_now() - t1);
    return KT_OK;
}
