/* aug_plan_step.c: one step of the planned method, top to bottom: the step's edits on the cut
 * mesh -> its loads (fem layer) -> the right-hand side of the released rows -> forward
 * substitution with the whole factor, the unreleased rows zeroed, back substitution -> the
 * displacement of the cut mesh and its reactions. */
#include "aug_plan.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "apply.h"
#include "chol.h"

void kt_plan_state_free(kt_plan_state *s)
{
    kt_mesh_free(&s->mesh);
    free(s->origin);
    free(s->force);
    free(s->f);
    free(s->tf);
    free(s->fe_rel);
    free(s->pown);
    free(s->pview.tet);
    free(s->v);
    free(s->u);
    free(s->react);
    free(s->b);
    free(s->x);
    free(s->r);
    free(s->ax);
    free(s->yf);
    free(s->bf);
    free(s->want);
    free(s->rwork);
    if (s->c_started) {
        cholmod_free_dense(&s->w[0], &s->c);
        cholmod_free_dense(&s->w[1], &s->c);
        cholmod_free_dense(&s->Y, &s->c);
        cholmod_free_dense(&s->E, &s->c);
        cholmod_finish(&s->c);
    }
    memset(s, 0, sizeof *s);
}

/* Each tet's prestress internal forces (fem layer), once: the loads of every step assemble them
 * in tet order on the cut mesh, as kt_fem_release_loads would, without the element integrals. */
static int release_forces(kt_plan_state *s, const kt_aug_problem *prob, kt_err *e)
{
    const kt_mesh *m = prob->mesh;
    if (!prob->mats->td || !prob->mats->td->sig) return KT_OK;
    size_t ld = 3 * (size_t)kt_tet_nv(m->order);
    if (!(s->fe_rel = kt_calloc((size_t)m->ne * ld, sizeof(double), e))) return e->code;
    for (int el = 0; el < m->ne; el++)
        if (kt_fem_element_release(m, prob->mats, el, s->fe_rel + el * ld, e)) return e->code;
    return KT_OK;
}

/* The tets a pressure can load: those with three corners on a pressure surface (a superset of
 * the tets whose face is a triangle of it; tets keep their numbers through cuts, and so do
 * the surfaces' triangles). The pressures of a step are those of the view of the cut mesh
 * with these tets only: every loaded triangle is still the face of exactly one of them, the
 * one it bounds, and the fem layer walks its faces in the same order, so the loads are
 * bitwise those of the whole mesh at a fraction of the search. */
static int pressure_tets(kt_plan_state *s, const kt_aug_problem *prob, kt_err *e)
{
    const kt_mesh *m = prob->mesh;
    int fv = kt_tri_nv(m->order), nv = kt_tet_nv(m->order);
    unsigned char *on = kt_calloc((size_t)m->nn, 1, e);
    if (!on) return e->code;
    for (int t = 0; t < m->nf; t++)
        for (int k = 0; k < prob->npress; k++)
            if (m->tri_tag[t] == prob->press[k].tag)
                for (int a = 0; a < 3; a++) on[m->tri[(size_t)t * fv + a]] = 1;
    for (int pass = 0; pass < 2 && !e->code; pass++) {
        s->npown = 0;
        for (int el = 0; el < m->ne; el++) {
            const int *t = m->tet + (size_t)el * nv;
            if (on[t[0]] + on[t[1]] + on[t[2]] + on[t[3]] < 3) continue;
            if (pass) s->pown[s->npown] = el;
            s->npown++;
        }
        if (!pass) {
            s->pown = kt_calloc((size_t)s->npown + 1, sizeof(int), e);
            s->pview.tet = kt_calloc(((size_t)s->npown + 1) * nv, sizeof(int), e);
        }
    }
    free(on);
    return e->code;
}

/* The view for this step: the current nodes of the pressure tets, the mesh's triangles. */
static void pressure_view(kt_plan_state *s)
{
    const kt_mesh *m = &s->mesh;
    int nv = kt_tet_nv(m->order);
    int *tet = s->pview.tet;
    s->pview = *m;
    s->pview.tet = tet;
    s->pview.tet_tag = NULL;
    s->pview.ne = s->npown;
    for (int k = 0; k < s->npown; k++)
        memcpy(tet + (size_t)k * nv, m->tet + (size_t)s->pown[k] * nv, (size_t)nv * sizeof(int));
}

int kt_plan_state_init(kt_plan_state *s, const kt_edits_plan *p, const kt_plan_factor *F,
                       const kt_aug_problem *prob, kt_err *e)
{
    memset(s, 0, sizeof *s);
    kt_chol_start(&s->c);
    s->c_started = 1;
    s->rwork = kt_calloc((size_t)F->maxrow, sizeof(double), e);
    s->yf = kt_calloc((size_t)F->nfree + 1, sizeof(double), e);
    s->bf = kt_calloc((size_t)F->nfree + 1, sizeof(double), e);
    size_t n = 3 * (size_t)p->nn;
    s->origin = kt_calloc((size_t)p->nn, sizeof(int), e);
    s->force = kt_calloc(n, sizeof(double), e);
    s->f = kt_calloc(n, sizeof(double), e);
    s->tf = kt_calloc(n, sizeof(double), e);
    s->v = kt_calloc(n, sizeof(double), e);
    s->u = kt_calloc(n, sizeof(double), e);
    s->react = kt_calloc(n, sizeof(double), e);
    s->b = kt_calloc(n, sizeof(double), e);
    s->x = kt_calloc(n, sizeof(double), e);
    s->r = kt_calloc(n, sizeof(double), e);
    s->ax = kt_calloc(n, sizeof(double), e);
    if (e->code || kt_mesh_copy(&s->mesh, prob->mesh, e)) return e->code;
    for (int a = 0; a < p->nn0; a++) s->origin[a] = a;
    if (pressure_tets(s, prob, e)) return e->code;
    return release_forces(s, prob, e);
}

int kt_plan_advance(kt_plan_state *s, const kt_edits_plan *p, kt_err *e)
{
    double t0 = kt_now();
    const kt_step *st = &p->step[s->step];
    int *touched = NULL, nt = 0, nn_old = s->mesh.nn;
    if (kt_cut_apply(&s->mesh, st, &touched, &nt, e)) return e->code;
    free(touched);
    for (int a = nn_old; a < s->mesh.nn; a++) s->origin[a] = s->origin[p->parent[a]];
    for (int i = 0; i < st->n; i++)
        if (st->edit[i].kind == KT_EDIT_FORCE)
            memcpy(s->force + 3 * (size_t)st->edit[i].node, st->edit[i].v, sizeof st->edit[i].v);
    s->step++;
    s->t_edits = kt_now() - t0;
    return KT_OK;
}

/* Applied loads on the cut mesh: the scene's pressures (fem layer), the prestress's internal
 * forces when the scene is prestressed (their release across cut faces; each tet's forces
 * from s->fe_rel on its current nodes), the edits' forces. */
static int loads(kt_plan_state *s, const kt_aug_problem *prob, kt_err *e)
{
    size_t n = 3 * (size_t)s->mesh.nn;
    memset(s->f, 0, n * sizeof(double));
    pressure_view(s);
    for (int k = 0; k < prob->npress; k++)
        if (kt_fem_pressure(&s->pview, prob->press[k].tag, prob->press[k].p, s->f, e))
            return e->code;
    if (s->fe_rel) {
        int nv = kt_tet_nv(s->mesh.order);
        for (int el = 0; el < s->mesh.ne; el++) {
            const int *t = s->mesh.tet + (size_t)el * nv;
            const double *fe = s->fe_rel + (size_t)el * 3 * nv;
            for (int a = 0; a < nv; a++)
                for (int c = 0; c < 3; c++) s->f[3 * (size_t)t[a] + c] += fe[3 * a + c];
        }
    }
    for (size_t i = 0; i < n; i++) s->f[i] += s->force[i];
    return KT_OK;
}

/* tf = T^T f (each variable sums its node's and descendants' loads); b = tf on the free
 * variables minus the lifting A(free, constrained) g of the variables present. */
static void rhs(kt_plan_state *s, const kt_edits_plan *p, const kt_plan_factor *F)
{
    int n = 3 * s->mesh.nn;
    memset(s->tf, 0, (size_t)n * sizeof(double));
    for (int i = 0; i < n; i++)
        for (int a = i / 3; a >= 0; a = p->parent[a]) s->tf[3 * a + i % 3] += s->f[i];
    memset(s->b, 0, (size_t)F->nfree * sizeof(double));
    for (int v = 0; v < n; v++)
        if (F->pos[v] >= 0) s->b[F->pos[v]] = s->tf[v];
    for (int l = 0; l < F->nlift; l++) {
        int r = F->lrow[l], c = F->lcol[l];
        if (r < n && c < n && F->pos[r] >= 0 && F->pos[c] < 0)
            s->b[F->pos[r]] -= F->lval[l] * p->gv[c];
    }
}

static int solve_sys(kt_plan_state *s, const kt_plan_factor *F, int sys, cholmod_dense *in,
                     cholmod_dense **out, kt_err *e)
{
    if (!cholmod_solve2(sys, F->L, in, NULL, out, NULL, &s->Y, &s->E, &s->c))
        return kt_fail(e, KT_ERUN, "CHOLMOD solve failed (status %d)", s->c.status);
    return KT_OK;
}

/* Whether rows 0..nf-1 of P b are those the plan's forward substitution consumed, up to
 * rounding: within SAME_ROUNDING x eps x scale (scale: the largest load a variable sums,
 * |T^T f|). Mathematically they are the same whenever the loads move with the tets (pressures,
 * prestress release): a variable sums its node's and its descendants' loads, which a cut only
 * regroups (an increment released earlier already summed the loads of the tets its unreleased
 * descendants will take); the sums in another order differ by rounding. The substitution then
 * solves for a right-hand side off by that much, which the backward-error check of the step
 * (against the step's own b) counts. */
enum { SAME_ROUNDING = 64 };
static int same_rows(const kt_plan_state *s, const kt_plan_factor *F, const double *b,
                     double scale)
{
    const int *Perm = F->L->Perm;
    double tol = SAME_ROUNDING * DBL_EPSILON * scale;
    for (int q = 0; q < s->nf; q++)
        if (!(fabs(b[Perm[q]] - s->bf[q]) <= tol)) return 0;
    return 1;
}

/* y = L^-1 P b on the first N rows (s->w[1]; later rows are not meaningful). A step's
 * right-hand side (plan = 1) continues the plan's forward substitution s->yf over the rows it
 * releases (the columns nf..N-1 only) when the rows already consumed agree with b's, else starts
 * it over; a refinement's (plan = 0) is a forward substitution of its own. */
static int forward(kt_plan_state *s, const kt_plan_factor *F, int N, const double *b, int plan,
                   double scale, kt_err *e)
{
    if (!s->w[1] && !(s->w[1] = cholmod_zeros(F->nfree, 1, CHOLMOD_REAL, &s->c)))
        return kt_fail(e, KT_ERUN, "CHOLMOD out of memory");
    double *y = s->w[1]->x;
    const int *Perm = F->L->Perm;
    if (!plan) {
        for (int q = 0; q < F->nfree; q++) y[q] = q < N ? b[Perm[q]] : 0;
        kt_plan_forward(F, s->rwork, 0, N, y);
        return KT_OK;
    }
    if (s->nf > 0 && s->nf <= N && same_rows(s, F, b, scale)) {
        s->ncont++;
    } else {
        s->nf = 0;
        memset(s->yf, 0, (size_t)F->nfree * sizeof(double));
    }
    for (int q = s->nf; q < N; q++) {
        s->bf[q] = b[Perm[q]];
        s->yf[q] += s->bf[q];
    }
    kt_plan_forward(F, s->rwork, s->nf, N, s->yf);
    s->nf = N;
    memcpy(y, s->yf, (size_t)N * sizeof(double));
    return KT_OK;
}

/* x = A_k^-1 b on the first N free positions, 0 after: forward (plan: continuing the plan's),
 * the rows of the unreleased increments zeroed, L^T (D L^T for LDL^T), P^T. t[0..1] +=
 * forward, back (s). */
static int substitute(kt_plan_state *s, const kt_plan_factor *F, int N, const double *b,
                      double *x, int plan, double scale, double *t, kt_err *e)
{
    double t0 = kt_now();
    if (forward(s, F, N, b, plan, scale, e)) return e->code;
    double *y = s->w[1]->x;
    memset(y + N, 0, (size_t)(F->nfree - N) * sizeof(double)); /* P keeps them in place */
    double t1 = kt_now();
    if (F->L->is_super) { /* the released prefix, and the wanted supernodes */
        kt_plan_back(F, s->want, s->rwork, N, y);
        const int *Perm = F->L->Perm;
        for (int q = 0; q < F->nfree; q++) x[Perm[q]] = y[q];
    } else {
        if (solve_sys(s, F, F->L->is_ll ? CHOLMOD_Lt : CHOLMOD_DLt, s->w[1], &s->w[0], e) ||
            solve_sys(s, F, CHOLMOD_Pt, s->w[0], &s->w[1], e))
            return e->code;
        memcpy(x, s->w[1]->x, (size_t)F->nfree * sizeof(double));
    }
    t[0] += t1 - t0;
    t[1] += kt_now() - t1;
    return KT_OK;
}

/* r = b - A_k x on the first N positions; returns ||r|| / ||b|| and sets *backward to the
 * normwise backward error ||r|| / (||A_k||_F ||x|| + ||b||) (2-norms, ||A_k||_F = fro from
 * F->fro_at). It bounds the componentwise form ||r|| / (|| |A_k| |x| || + ||b||) from below by
 * at most ||A_k||_F ||x|| / || |A_k| |x| || and costs one pass over A's lower triangle. */
static double residual(const kt_plan_factor *F, int N, double fro, const double *b,
                       const double *x, double *r, double *backward)
{
    const int *Ap = F->A->p, *Ai = F->A->i;
    const double *Ax = F->A->x;
    memcpy(r, b, (size_t)N * sizeof(double));
    for (int j = 0; j < N; j++) {
        double xj = x[j], sj = 0;
        for (int q = Ap[j]; q < Ap[j + 1]; q++) {
            int i = Ai[q];
            if (i >= N) continue;
            sj += Ax[q] * x[i];
            if (i != j) r[i] -= Ax[q] * xj;
        }
        r[j] -= sj;
    }
    double rr = 0, bb = 0, xx = 0;
    for (int i = 0; i < N; i++) {
        rr += r[i] * r[i];
        bb += b[i] * b[i];
        xx += x[i] * x[i];
    }
    double den = fro * sqrt(xx) + sqrt(bb);
    *backward = den == 0 ? 0 : sqrt(rr) / den; /* NaN stays NaN: the check must fail on it */
    return bb > 0 ? sqrt(rr / bb) : sqrt(rr);
}

/* The variables, the displacement u_c = u_parent + d_c, and K u - f at constrained DOFs
 * (each constrained variable's row of A gives the sum over the DOF and its constrained
 * descendants; its children's sums come off). */
static void field(kt_plan_state *s, const kt_edits_plan *p, const kt_plan_factor *F)
{
    int nn = s->mesh.nn, n = 3 * nn;
    for (int v = 0; v < n; v++) s->v[v] = F->pos[v] >= 0 ? s->x[F->pos[v]] : p->gv[v];
    for (int a = 0; a < nn; a++)
        for (int c = 0; c < 3; c++)
            s->u[3 * a + c] = s->v[3 * a + c] + (p->parent[a] >= 0 ? s->u[3 * p->parent[a] + c] : 0);
    memset(s->react, 0, (size_t)n * sizeof(double));
    for (int l = 0; l < F->nlift; l++) {
        int r = F->lrow[l], c = F->lcol[l];
        if (r < n && c < n && F->pos[r] < 0) s->react[r] += F->lval[l] * s->v[c];
    }
    for (int v = 0; v < n; v++)
        if (F->pos[v] < 0) s->react[v] -= s->tf[v];
    for (int a = p->nn0; a < nn; a++) /* ascending: a child's own children come off later */
        for (int c = 0; c < 3; c++)
            if (F->pos[3 * a + c] < 0) s->react[3 * p->parent[a] + c] -= s->react[3 * a + c];
}

/* The current step's loads and right-hand side s->b; *scale gets the largest load a variable
 * sums. */
static int step_rhs(kt_plan_state *s, const kt_edits_plan *p, const kt_plan_factor *F,
                    const kt_aug_problem *prob, double *scale, kt_err *e)
{
    if (loads(s, prob, e)) return e->code;
    rhs(s, p, F);
    *scale = 0;
    for (int v = 0; v < 3 * s->mesh.nn; v++) *scale = kt_nanmax(*scale, fabs(s->tf[v]));
    if (!isfinite(*scale))
        return kt_fail(e, KT_EINPUT, "step %d: the loads sum to a value that is not finite "
                       "(an edits force or a pressure too large)", s->step);
    return KT_OK;
}

int kt_plan_continue(kt_plan_state *s, const kt_edits_plan *p, const kt_plan_factor *F,
                     const kt_aug_problem *prob, kt_err *e)
{
    double scale = 0;
    if (step_rhs(s, p, F, prob, &scale, e)) return e->code;
    return forward(s, F, F->nfree_at[s->step], s->b, 1, scale, e);
}

int kt_plan_solve(kt_plan_state *s, const kt_edits_plan *p, const kt_plan_factor *F,
                  const kt_aug_problem *prob, double tol, kt_err *e)
{
    double t0 = kt_now(), ts[2] = {0, 0}, scale = 0;
    kt_aug_row *w = &s->row;
    int N = F->nfree_at[s->step];
    if (step_rhs(s, p, F, prob, &scale, e)) return e->code;
    double t1 = kt_now();
    if (substitute(s, F, N, s->b, s->x, 1, scale, ts, e)) return e->code;
    double t2 = kt_now(), backward = 0, rel = NAN;
    if (!s->want) rel = residual(F, N, F->fro_at[s->step], s->b, s->x, s->r, &backward);
    s->row.iters = 0;
    if (!(backward <= tol)) { /* one step of iterative refinement */
        memset(s->r + N, 0, (size_t)(F->nfree - N) * sizeof(double));
        if (substitute(s, F, N, s->r, s->ax, 0, scale, ts, e)) return e->code;
        for (int i = 0; i < N; i++) s->x[i] += s->ax[i];
        rel = residual(F, N, F->fro_at[s->step], s->b, s->x, s->r, &backward);
        s->row.iters = 1;
    }
    if (!(backward <= tol))
        return kt_fail(e, KT_ERUN, "step %d: the planned solve's backward error %.3g exceeds "
                       "--tol %.3g after a step of iterative refinement", s->step, backward, tol);
    double t3 = kt_now();
    field(s, p, F);
    w->closure_max = s->want ? s->want_cols : 0;
    double t4 = kt_now();
    w->step = s->step;
    w->n_dofs = 3 * s->mesh.nn;
    w->m = N - F->nK;
    w->new_dofs = s->step ? 3 * (p->nn_at[s->step] - p->nn_at[s->step - 1]) : 0;
    w->t_update = 1e3 * (s->t_edits + t1 - t0);
    w->t_step1 = 1e3 * ts[0];
    w->t_step2 = 1e3 * (t3 - t2);
    w->t_step3 = 1e3 * (ts[1] + t4 - t3);
    w->t_total = w->t_update + 1e3 * (t4 - t1);
    w->rel_residual = rel;
    w->verify_rel_diff = w->t_verify = NAN;
    w->nnz_L = F->nnzL;
    return KT_OK;
}

int kt_plan_fresh(const kt_plan_state *s, const kt_edits_plan *p, const kt_aug_problem *prob,
                  double *u, double *t, kt_err *e)
{
    double t0 = kt_now();
    cholmod_common c;
    kt_chol_start(&c);
    c.nmethods = 1; /* what a user would run instead: METIS, postordered */
    c.method[0].ordering = CHOLMOD_METIS;
    c.postorder = 1;
    kt_fem_solve(&s->mesh, prob->mats, p->fixed, p->g, s->f, u, &c, e);
    cholmod_finish(&c);
    *t = kt_now() - t0;
    return e->code;
}
