/* order.c: node orderings (AMD, CAMD, METIS) and symbolic factor statistics via CHOLMOD. */
#include "order.h"

#include <amd.h>
#include <camd.h>
#include <cholmod.h>
#include <metis.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>

#include "chol.h"
#include "topology.h"

/* Node adjacency (no self loops, no repeats) in compressed form: neighbours of v are
 * adj[ptr[v] .. ptr[v+1]-1]. */
typedef struct graph {
    int n;
    int *ptr, *adj;
} graph;

static void graph_free(graph *g)
{
    free(g->ptr);
    free(g->adj);
    memset(g, 0, sizeof *g);
}

/* Neighbours of v through its tets, marking with stamp v; fills out (if not NULL), returns count. */
static int neighbours(const kt_mesh *m, const int *at, const int *tet_of, int v, int *mark, int *out)
{
    int nv = kt_tet_nv(m->order), cnt = 0;
    for (int k = at[v]; k < at[v + 1]; k++) {
        const int *t = m->tet + (size_t)tet_of[k] * nv;
        for (int j = 0; j < nv; j++)
            if (t[j] != v && mark[t[j]] != v) {
                mark[t[j]] = v;
                if (out) out[cnt] = t[j];
                cnt++;
            }
    }
    return cnt;
}

static int node_graph(const kt_mesh *m, graph *g, kt_err *e)
{
    memset(g, 0, sizeof *g);
    int *at = NULL, *tet_of = NULL;
    if (kt_mesh_node_tets(m, &at, &tet_of, e)) return e->code;
    int *mark = kt_calloc((size_t)m->nn, sizeof(int), e);
    g->n = m->nn;
    g->ptr = kt_calloc((size_t)m->nn + 1, sizeof(int), e);
    if (!mark || !g->ptr) goto fail;
    for (int v = 0; v < m->nn; v++) mark[v] = -1;
    for (int v = 0; v < m->nn; v++) g->ptr[v + 1] = g->ptr[v] + neighbours(m, at, tet_of, v, mark, NULL);
    g->adj = kt_calloc((size_t)g->ptr[m->nn], sizeof(int), e);
    if (!g->adj) goto fail;
    for (int v = 0; v < m->nn; v++) mark[v] = -1;
    for (int v = 0; v < m->nn; v++) neighbours(m, at, tet_of, v, mark, g->adj + g->ptr[v]);
    free(at);
    free(tet_of);
    free(mark);
    return KT_OK;
fail:
    free(at);
    free(tet_of);
    free(mark);
    graph_free(g);
    return e->code;
}

const char *kt_order_name(int method)
{
    switch (method) {
    case KT_ORDERING_AMD: return "amd";
    case KT_ORDERING_METIS: return "metis";
    case KT_ORDERING_CONSTRAINED: return "constrained";
    case KT_ORDERING_NATURAL: return "natural";
    case KT_ORDERING_METIS_LAST: return "metis-last";
    default: return "?";
    }
}

const char *kt_metis_status(int status)
{
    switch (status) {
    case METIS_OK: return "status 1, METIS_OK";
    case METIS_ERROR_INPUT: return "status -2, METIS_ERROR_INPUT: METIS refused its input";
    case METIS_ERROR_MEMORY: return "status -3, METIS_ERROR_MEMORY: out of memory (or SIGABRT while it ran)";
    case METIS_ERROR:
        return "status -4, METIS_ERROR: METIS catches a SIGTERM sent while it runs and returns this, "
               "so the process was most likely being stopped";
    default: return "an unknown METIS status";
    }
}

static int order_amd(const graph *g, int *perm, kt_err *e)
{
    int st = amd_order(g->n, g->ptr, g->adj, perm, NULL, NULL);
    if (st != AMD_OK && st != AMD_OK_BUT_JUMBLED) return kt_fail(e, KT_ERUN, "AMD ordering failed (status %d)", st);
    return KT_OK;
}

/* CAMD with constraint sets: the 'last' nodes in sets 1 + rank, after all others. */
static int order_camd(const graph *g, const int *last, const int *rank, int nlast, int *perm, kt_err *e)
{
    int *cset = kt_calloc((size_t)g->n, sizeof(int), e);
    if (!cset) return e->code;
    for (int k = 0; k < nlast; k++) cset[last[k]] = 1 + (rank ? rank[k] : 0);
    int st = camd_order(g->n, g->ptr, g->adj, perm, NULL, NULL, cset);
    free(cset);
    if (st != CAMD_OK && st != CAMD_OK_BUT_JUMBLED) return kt_fail(e, KT_ERUN, "CAMD ordering failed (status %d)", st);
    return KT_OK;
}

static pthread_mutex_t metis_lock = PTHREAD_MUTEX_INITIALIZER;

int kt_metis_nodend(int n, const int *xadj, const int *adj, int *options, int *perm, int *iperm)
{
    _Static_assert(sizeof(idx_t) == sizeof(int), "METIS built with 32-bit indices");
    idx_t nn = n;
    pthread_mutex_lock(&metis_lock);
    int st = METIS_NodeND(&nn, (idx_t *)xadj, (idx_t *)adj, NULL, (idx_t *)options, (idx_t *)perm,
                          (idx_t *)iperm);
    pthread_mutex_unlock(&metis_lock);
    return st;
}

/* METIS nested dissection. Its 'perm' output is our perm (new node i = old perm[i]): checked
 * by fill and tree height on the beams, where the other reading is far worse (height 19092 vs
 * 744 DOFs on 5x5x1024). */
static int order_metis(const graph *g, int *perm, kt_err *e)
{
    if (g->n < 3 || g->ptr[g->n] == 0) {
        for (int i = 0; i < g->n; i++) perm[i] = i;
        return KT_OK;
    }
    idx_t n = g->n, options[METIS_NOPTIONS];
    METIS_SetDefaultOptions(options);
    options[METIS_OPTION_NUMBERING] = 0;
    idx_t *mperm = kt_calloc((size_t)n, sizeof(idx_t), e);
    idx_t *miperm = kt_calloc((size_t)n, sizeof(idx_t), e);
    if (!mperm || !miperm) {
        free(mperm);
        free(miperm);
        return e->code;
    }
    int st = kt_metis_nodend(g->n, g->ptr, g->adj, (int *)options, (int *)mperm, (int *)miperm);
    for (int i = 0; i < g->n; i++) perm[i] = (int)mperm[i];
    free(mperm);
    free(miperm);
    if (st != METIS_OK) return kt_fail(e, KT_ERUN, "METIS_NodeND failed (%s)", kt_metis_status(st));
    return KT_OK;
}

/* Move the 'last' nodes to the end of perm by a stable counting sort on 1 + rank (0 for the
 * others): every part keeps its relative order. */
static int move_last(int n, const int *last, const int *rank, int nlast, int *perm, kt_err *e)
{
    int *key = kt_calloc((size_t)n, sizeof(int), e), *tmp = kt_calloc((size_t)n, sizeof(int), e);
    int kmax = 1;
    for (int k = 0; k < nlast; k++)
        if (rank && rank[k] + 1 > kmax) kmax = rank[k] + 1;
    int *start = kt_calloc((size_t)kmax + 2, sizeof(int), e);
    if (!key || !tmp || !start) {
        free(key);
        free(tmp);
        free(start);
        return e->code;
    }
    for (int k = 0; k < nlast; k++) key[last[k]] = 1 + (rank ? rank[k] : 0);
    for (int i = 0; i < n; i++) start[key[i] + 1]++;
    for (int k = 0; k <= kmax; k++) start[k + 1] += start[k];
    for (int i = 0; i < n; i++) tmp[start[key[perm[i]]]++] = perm[i];
    memcpy(perm, tmp, sizeof(int) * (size_t)n);
    free(key);
    free(tmp);
    free(start);
    return KT_OK;
}

static int check_set(const kt_mesh *m, const int *set, int nset, kt_err *e)
{
    unsigned char *seen = kt_calloc((size_t)m->nn, 1, e);
    if (!seen) return e->code;
    for (int k = 0; k < nset; k++) {
        if (set[k] < 0 || set[k] >= m->nn || seen[set[k]]) {
            free(seen);
            return kt_fail(e, KT_ERUN, "ordering set: node %d out of range or repeated", set[k]);
        }
        seen[set[k]] = 1;
    }
    free(seen);
    return KT_OK;
}

int kt_order_nodes(const kt_mesh *m, int method, const int *last, int nlast, int *perm, kt_err *e)
{
    return kt_order_nodes_ranked(m, method, last, NULL, nlast, perm, e);
}

int kt_order_nodes_ranked(const kt_mesh *m, int method, const int *last, const int *rank,
                          int nlast, int *perm, kt_err *e)
{
    if (method == KT_ORDERING_NATURAL) {
        for (int i = 0; i < m->nn; i++) perm[i] = i;
        return KT_OK;
    }
    if (method < KT_ORDERING_AMD || method > KT_ORDERING_METIS_LAST)
        return kt_fail(e, KT_ERUN, "unknown ordering method %d", method);
    int uses_set = method == KT_ORDERING_CONSTRAINED || method == KT_ORDERING_METIS_LAST;
    if (uses_set && check_set(m, last, nlast, e)) return e->code;
    for (int k = 0; uses_set && rank && k < nlast; k++)
        if (rank[k] < 0 || rank[k] > m->nn - 2)
            return kt_fail(e, KT_ERUN, "ordering set: rank %d out of range", rank[k]);
    graph g;
    if (node_graph(m, &g, e)) return e->code;
    int rc;
    if (method == KT_ORDERING_AMD) rc = order_amd(&g, perm, e);
    else if (method == KT_ORDERING_CONSTRAINED) rc = order_camd(&g, last, rank, nlast, perm, e);
    else rc = order_metis(&g, perm, e);
    if (!rc && method == KT_ORDERING_METIS_LAST) rc = move_last(m->nn, last, rank, nlast, perm, e);
    graph_free(&g);
    return rc;
}

/* ---- symbolic statistics ------------------------------------------------------------------ */

/* Upper triangle of the permuted DOF pattern (stype 1); fixed DOFs keep only their diagonal. */
static cholmod_sparse *dof_pattern(const graph *g, const int *perm, const int *inv,
                                   const unsigned char *fixed, cholmod_common *c, kt_err *e)
{
    int nn = g->n;
    size_t nz = 0;
    for (int J = 0; J < nn; J++) {
        int v = perm[J];
        for (int k = g->ptr[v]; k < g->ptr[v + 1]; k++)
            if (inv[g->adj[k]] < J) nz += 9;
        nz += 6;
    }
    if (nz > 2147483647u) {
        kt_fail(e, KT_ERUN, "DOF matrix too large for 32-bit indices (%zu entries)", nz);
        return NULL;
    }
    cholmod_sparse *A = cholmod_allocate_sparse(3 * (size_t)nn, 3 * (size_t)nn, nz, 0, 1, 1, CHOLMOD_PATTERN, c);
    if (!A) {
        kt_fail(e, KT_ERUN, "CHOLMOD could not allocate the DOF pattern (%zu entries)", nz);
        return NULL;
    }
    int *Ap = A->p, *Ai = A->i, p = 0;
    for (int J = 0; J < nn; J++) {
        int v = perm[J];
        for (int cj = 0; cj < 3; cj++) {
            int col = 3 * J + cj;
            Ap[col] = p;
            int col_fixed = fixed && fixed[3 * (size_t)v + cj];
            for (int k = g->ptr[v]; k < g->ptr[v + 1] && !col_fixed; k++) {
                int u = g->adj[k], U = inv[u];
                if (U > J) continue;
                for (int ci = 0; ci < 3; ci++)
                    if (!(fixed && fixed[3 * (size_t)u + ci])) Ai[p++] = 3 * U + ci;
            }
            for (int ci = 0; ci < cj && !col_fixed; ci++)
                if (!(fixed && fixed[3 * (size_t)v + ci])) Ai[p++] = 3 * J + ci;
            Ai[p++] = col;
        }
    }
    Ap[3 * nn] = p;
    return A;
}

/* Number of DOFs on the union of etree paths from a node's DOFs, marking with stamp. */
static int walk(const int *parent, int *mark, int stamp, int j)
{
    int cnt = 0;
    for (; j != -1 && mark[j] != stamp; j = parent[j]) {
        mark[j] = stamp;
        cnt++;
    }
    return cnt;
}

/* |closure| of node J's DOFs 3J..3J+2. Inside the node's block the paths are walked with
 * marks; where they leave it, a single common exit adds its depth (the usual case: a free
 * node's DOFs form a chain), several distinct exits are merged by walking. */
static int node_closure(const int *parent, const int *depth, int *mark, int stamp, int J)
{
    int lo = 3 * J, hi = 3 * J + 2, cl = 0, exit[3], nexit = 0;
    for (int c = 0; c < 3; c++) {
        int j = lo + c;
        for (; j != -1 && j <= hi && mark[j] != stamp; j = parent[j]) {
            mark[j] = stamp;
            cl++;
        }
        if (j > hi) {
            int seen = 0;
            for (int k = 0; k < nexit; k++) seen |= exit[k] == j;
            if (!seen) exit[nexit++] = j;
        }
    }
    if (nexit == 1) return cl + depth[exit[0]];
    for (int k = 0; k < nexit; k++) cl += walk(parent, mark, stamp, exit[k]);
    return cl;
}

static void closures(const int *parent, const int *depth, const int *inv, const int *set, int nset,
                     int nn, int *mark, kt_order_stats *st)
{
    int n = 3 * nn;
    for (int j = 0; j < n; j++) mark[j] = -1;
    double sum = 0;
    int count = set ? nset : nn;
    st->nset = count;
    st->closure_max = 0;
    for (int k = 0; k < count; k++) {
        int cl = node_closure(parent, depth, mark, k, inv[set ? set[k] : k]);
        sum += cl;
        if (cl > st->closure_max) st->closure_max = cl;
    }
    st->closure_mean = count ? sum / count : 0;
    for (int j = 0; j < n; j++) mark[j] = -1;
    st->closure_union = 0;
    for (int k = 0; k < count; k++) {
        int J = inv[set ? set[k] : k];
        for (int c = 0; c < 3; c++) st->closure_union += walk(parent, mark, 0, 3 * J + c);
    }
}

static int analyze(const cholmod_sparse *A, int *parent, kt_order_stats *st, cholmod_common *c, kt_err *e)
{
    c->nmethods = 1;
    c->method[0].ordering = CHOLMOD_NATURAL;
    c->postorder = 0;
    c->supernodal = CHOLMOD_SIMPLICIAL;
    cholmod_factor *L = cholmod_analyze((cholmod_sparse *)A, c);
    if (!L || c->status < CHOLMOD_OK) {
        cholmod_free_factor(&L, c);
        return kt_fail(e, KT_ERUN, "CHOLMOD symbolic analysis failed (status %d)", c->status);
    }
    const int *cc = L->ColCount, *P = L->Perm;
    st->nnz_L = st->flops = 0;
    for (size_t j = 0; j < L->n; j++) {
        if (P[j] != (int)j) {
            cholmod_free_factor(&L, c);
            return kt_fail(e, KT_ERUN, "CHOLMOD did not keep the given order");
        }
        st->nnz_L += cc[j];
        st->flops += (double)cc[j] * cc[j];
    }
    cholmod_free_factor(&L, c);
    if (!cholmod_etree((cholmod_sparse *)A, parent, c))
        return kt_fail(e, KT_ERUN, "CHOLMOD elimination tree failed (status %d)", c->status);
    return KT_OK;
}

int kt_order_move_last(const kt_mesh *m, const int *last, const int *rank, int nlast, int *perm,
                       kt_err *e)
{
    if (check_set(m, last, nlast, e)) return e->code;
    for (int k = 0; rank && k < nlast; k++)
        if (rank[k] < 0 || rank[k] > m->nn - 2)
            return kt_fail(e, KT_ERUN, "ordering set: rank %d out of range", rank[k]);
    return move_last(m->nn, last, rank, nlast, perm, e);
}

int kt_order_analyze(const kt_mesh *m, const int *perm, const unsigned char *fixed, const int *set,
                   int nset, kt_order_stats *st, kt_err *e)
{
    const int *sets[1] = {set};
    int nsets[1] = {nset};
    return kt_order_analyze_sets(m, perm, fixed, 1, sets, nsets, st, e);
}

int kt_order_analyze_sets(const kt_mesh *m, const int *perm, const unsigned char *fixed, int nk,
                          const int *const *sets, const int *nsets, kt_order_stats *st, kt_err *e)
{
    int nn = m->nn, n = 3 * nn;
    for (int k = 0; k < nk; k++) {
        memset(&st[k], 0, sizeof st[k]);
        st[k].n = n;
        if (sets[k] && check_set(m, sets[k], nsets[k], e)) return e->code;
    }
    graph g;
    if (node_graph(m, &g, e)) return e->code;
    int *own = kt_calloc((size_t)nn, sizeof(int), e), *inv = kt_calloc((size_t)nn, sizeof(int), e);
    int *parent = kt_calloc((size_t)n, sizeof(int), e), *depth = kt_calloc((size_t)n, sizeof(int), e);
    int *mark = kt_calloc((size_t)n, sizeof(int), e);
    cholmod_common c;
    kt_chol_start(&c);
    cholmod_sparse *A = NULL;
    if (e->code) goto done;
    if (!perm) {
        for (int i = 0; i < nn; i++) own[i] = i;
        perm = own;
    }
    for (int i = 0; i < nn; i++) inv[perm[i]] = i;
    A = dof_pattern(&g, perm, inv, fixed, &c, e);
    if (!A) goto done;
    st[0].nnz_A = (double)((int *)A->p)[n];
    if (analyze(A, parent, &st[0], &c, e)) goto done;
    /* Depth = path length to the root; parents come after their children. */
    for (int j = n - 1; j >= 0; j--) {
        depth[j] = parent[j] < 0 ? 1 : depth[parent[j]] + 1;
        if (depth[j] > st[0].height) st[0].height = depth[j];
    }
    /* one factor: the same sparsity figures for every set, each its own closures */
    for (int k = 0; k < nk; k++) {
        if (k) {
            st[k].nnz_A = st[0].nnz_A, st[k].nnz_L = st[0].nnz_L;
            st[k].flops = st[0].flops, st[k].height = st[0].height;
        }
        closures(parent, depth, inv, sets[k], nsets[k], nn, mark, &st[k]);
    }
done:
    cholmod_free_sparse(&A, &c);
    cholmod_finish(&c);
    graph_free(&g);
    free(own);
    free(inv);
    free(parent);
    free(depth);
    free(mark);
    return e->code;
}
