/* bench_solves: the physical limit of the solves augsolve does. Factors the constrained
 * stiffness of a mesh (the mesh's own elimination order, as augsolve does by default; or AMD /
 * METIS) and times
 *   - a full solve with the supernodal LL^T factor and with the simplicial one it becomes,
 *   - closure-restricted solves (cholmod_solve2 with a Bset) from single nodes: those of a
 *     surface group (the set a cut or constraint starts from) and nodes spread over the mesh.
 * Each time is set against the bytes the solve must stream from memory: for a factor of
 * nnz stored entries, forward + backward substitution read every value (8 B) and, simplicial,
 * its row index (4 B): bytes(L) = 2 * 8 * xsize (supernodal), 2 * 12 * nnz (simplicial);
 * bytes(closure) = 2 * 12 * sum of the column counts of L over the closure.
 *
 *   bench_solves MESH SCENE [--ordering natural|amd|metis] [--set SURFACE] [--sample N]
 *                [--spread N] [--reps R] [--tag NAME]
 *
 * stdout, TSV with a header: one row per measured solve:
 *   tag kind node closure_dofs entries bytes time_ms
 * kind: factor (time = analyze + factorize, entries = nnz(L)), full-super, full-simpl,
 * closure-set, closure-spread. Times are the best of R repetitions. */
#define _POSIX_C_SOURCE 200809L
#include "bench.h"

typedef struct opts {
    const char *mesh, *scene, *ordering, *set, *tag;
    int sample, spread, reps;
} opts;

static int parse(int argc, char **argv, opts *o)
{
    *o = (opts){NULL, NULL, "natural", NULL, "-", 40, 40, 5};
    int pos = 0;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp(a, "--ordering") && v) o->ordering = argv[++i];
        else if (!strcmp(a, "--set") && v) o->set = argv[++i];
        else if (!strcmp(a, "--tag") && v) o->tag = argv[++i];
        else if (!strcmp(a, "--sample") && v && !kt_parse_int(v, &o->sample)) i++;
        else if (!strcmp(a, "--spread") && v && !kt_parse_int(v, &o->spread)) i++;
        else if (!strcmp(a, "--reps") && v && !kt_parse_int(v, &o->reps)) i++;
        else if (a[0] != '-' && pos == 0) o->mesh = a, pos++;
        else if (a[0] != '-' && pos == 1) o->scene = a, pos++;
        else return -1;
    }
    return o->mesh && o->scene && o->reps >= 1 ? 0 : -1;
}

static void row(const opts *o, const char *kind, int node, long cl, double entries, double bytes,
                double ms)
{
    printf("%s\t%s\t%d\t%ld\t%.0f\t%.0f\t%.6f\n", o->tag, kind, node, cl, entries, bytes, ms);
}

/* Best-of-reps full solve with the factor as it is now. */
static double time_full(cholmod_factor *L, cholmod_dense *B, int reps, cholmod_common *c)
{
    double best = INFINITY;
    for (int r = 0; r < reps; r++) {
        double t0 = kt_now();
        cholmod_dense *X = cholmod_solve(CHOLMOD_A, L, B, c);
        double t = kt_now() - t0;
        cholmod_free_dense(&X, c);
        if (t < best) best = t;
    }
    return 1e3 * best;
}

typedef struct ws {
    cholmod_dense *B, *X, *Y, *E;
    cholmod_sparse *Bset, *Xset;
    int *iperm;
} ws;

/* Closure solve from the three DOFs of node a: time (best of reps), closure size, L entries. */
static int closure_solve(cholmod_factor *L, ws *w, int a, int reps, double *ms, long *cl,
                         double *entries, cholmod_common *c, kt_err *e)
{
    int *Bp = w->Bset->p, *Bi = w->Bset->i;
    double *Bx = w->B->x;
    Bp[0] = 0;
    Bp[1] = 3;
    for (int k = 0; k < 3; k++) {
        Bi[k] = 3 * a + k;
        Bx[3 * a + k] = 1.0;
    }
    double best = INFINITY;
    for (int r = 0; r < reps; r++) {
        double t0 = kt_now();
        if (!cholmod_solve2(CHOLMOD_A, L, w->B, w->Bset, &w->X, &w->Xset, &w->Y, &w->E, c))
            return kt_fail(e, KT_ERUN, "cholmod_solve2 failed (status %d)", c->status);
        double t = kt_now() - t0;
        if (t < best) best = t;
    }
    for (int k = 0; k < 3; k++) Bx[3 * a + k] = 0.0;
    const int *Xp = w->Xset->p, *Xi = w->Xset->i, *Lnz = L->nz;
    double s = 0;
    for (int q = Xp[0]; q < Xp[1]; q++) s += Lnz[w->iperm ? w->iperm[Xi[q]] : Xi[q]];
    *ms = 1e3 * best;
    *cl = Xp[1] - Xp[0];
    *entries = s;
    return KT_OK;
}

static int closures(const opts *o, const bench_problem *p, cholmod_factor *L, cholmod_common *c,
                    kt_err *e)
{
    int n = (int)L->n;
    ws w = {0};
    w.B = cholmod_zeros(n, 1, CHOLMOD_REAL, c);
    w.Bset = cholmod_allocate_sparse(n, 1, 3, 1, 1, 0, CHOLMOD_PATTERN, c);
    if (!w.B || !w.Bset) return kt_fail(e, KT_ERUN, "out of memory");
    if (L->ordering != CHOLMOD_NATURAL) {
        /* Xset comes back in the original numbering; L's columns are permuted */
        w.iperm = kt_calloc((size_t)n, sizeof(int), e);
        if (!w.iperm) return e->code;
        for (int k = 0; k < n; k++) w.iperm[((int *)L->Perm)[k]] = k;
    }
    /* the first Bset call converts a supernodal factor to simplicial: not timed */
    double ms, ent;
    long cl;
    closure_solve(L, &w, 0, 1, &ms, &cl, &ent, c, e);
    int *set = NULL, nset = 0;
    if (!e->code && o->set) {
        const kt_group *g = kt_mesh_find_group(&p->mesh, 2, o->set);
        if (!g) kt_fail(e, KT_EINPUT, "%s: no surface group '%s'", o->mesh, o->set);
        else kt_mesh_group_nodes(&p->mesh, g, &set, &nset, e);
    }
    int ns = o->sample < nset ? o->sample : nset;
    for (int k = 0; k < ns && !e->code; k++) {
        int a = set[(long)k * nset / ns];
        if (closure_solve(L, &w, a, o->reps, &ms, &cl, &ent, c, e) == KT_OK)
            row(o, "closure-set", a + 1, cl, ent, 24.0 * ent, ms);
    }
    int nn = p->mesh.nn;
    for (int k = 0; k < o->spread && !e->code; k++) {
        int a = (int)((long)k * nn / o->spread);
        if (closure_solve(L, &w, a, o->reps, &ms, &cl, &ent, c, e) == KT_OK)
            row(o, "closure-spread", a + 1, cl, ent, 24.0 * ent, ms);
    }
    /* simplicial full solve, now that the factor has been converted */
    if (!e->code) {
        ent = bench_factor_entries(L);
        row(o, "full-simpl", 0, n, ent, 24.0 * ent, time_full(L, w.B, o->reps, c));
    }
    free(set);
    free(w.iperm);
    cholmod_free_dense(&w.B, c);
    cholmod_free_dense(&w.X, c);
    cholmod_free_dense(&w.Y, c);
    cholmod_free_dense(&w.E, c);
    cholmod_free_sparse(&w.Bset, c);
    cholmod_free_sparse(&w.Xset, c);
    return e->code;
}

int main(int argc, char **argv)
{
    opts o;
    if (parse(argc, argv, &o)) {
        fprintf(stderr, "usage: bench_solves MESH SCENE [--ordering natural|amd|metis] "
                        "[--set SURFACE] [--sample N] [--spread N] [--reps R] [--tag NAME]\n");
        return 2;
    }
    kt_err e = {0};
    bench_problem p;
    cholmod_common c;
    cholmod_start(&c);
    cholmod_sparse *K = NULL;
    cholmod_factor *L = NULL;
    cholmod_dense *B = NULL;
    if (bench_problem_load(&p, o.mesh, o.scene, &e)) goto done;
    K = kt_fem_assemble(&p.mesh, &p.mats, p.fixed, &c, &e);
    if (!K) goto done;
    double t0 = kt_now();
    if (!(L = bench_analyze(K, o.ordering, 1, &c, &e)) || bench_factorize(K, L, &c, &e)) goto done;
    double tf = kt_now() - t0;
    printf("tag\tkind\tnode\tclosure_dofs\tentries\tbytes\ttime_ms\n");
    row(&o, "factor", 0, (long)K->ncol, c.lnz, 0, 1e3 * tf);
    B = cholmod_ones(K->nrow, 1, CHOLMOD_REAL, &c);
    if (!B) {
        kt_fail(&e, KT_ERUN, "out of memory");
        goto done;
    }
    double ent = bench_factor_entries(L);
    row(&o, "full-super", 0, (long)K->ncol, ent, 16.0 * ent, time_full(L, B, o.reps, &c));
    closures(&o, &p, L, &c, &e);
done:
    if (e.code) fprintf(stderr, "bench_solves: %s\n", e.msg);
    cholmod_free_dense(&B, &c);
    cholmod_free_factor(&L, &c);
    cholmod_free_sparse(&K, &c);
    bench_problem_free(&p);
    cholmod_finish(&c);
    return e.code;
}
