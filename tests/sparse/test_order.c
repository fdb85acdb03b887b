/* test_order.c: orderings are permutations that honour the constrained set, and the factor
 * statistics agree with a dense symbolic elimination done independently here. */
#include <stdlib.h>
#include <string.h>

#include "grid.h"
#include "kt_test.h"
#include "order.h"

/* Independent reference: the DOF pattern of the permuted mesh as a dense boolean matrix,
 * eliminated column by column. Returns nnz(L), fills parent[] and the depth of each DOF. */
typedef struct ref {
    int n;
    double nnz, flops;
    int *parent, *depth;
} ref;

static void reference(const kt_mesh *m, const int *perm, const unsigned char *fixed, ref *r)
{
    int nn = m->nn, n = 3 * nn, nv = kt_tet_nv(m->order);
    int *inv = malloc(sizeof(int) * nn);
    for (int i = 0; i < nn; i++) inv[perm ? perm[i] : i] = i;
    unsigned char *A = calloc((size_t)n * n, 1);
    /* Coupled DOFs: any two DOFs of nodes sharing a tet, unless one of them is fixed. */
    for (int t = 0; t < m->ne; t++)
        for (int a = 0; a < nv; a++)
            for (int b = 0; b < nv; b++)
                for (int ca = 0; ca < 3; ca++)
                    for (int cb = 0; cb < 3; cb++) {
                        int u = m->tet[t * nv + a], v = m->tet[t * nv + b];
                        if (fixed && (fixed[3 * u + ca] || fixed[3 * v + cb])) continue;
                        A[(size_t)(3 * inv[u] + ca) * n + 3 * inv[v] + cb] = 1;
                    }
    for (int j = 0; j < n; j++) A[(size_t)j * n + j] = 1;
    r->n = n;
    r->nnz = r->flops = 0;
    r->parent = malloc(sizeof(int) * n);
    r->depth = malloc(sizeof(int) * n);
    for (int k = 0; k < n; k++) {
        int cnt = 0;
        r->parent[k] = -1;
        for (int i = k; i < n; i++)
            if (A[(size_t)i * n + k]) {
                cnt++;
                if (i > k && r->parent[k] < 0) r->parent[k] = i;
            }
        r->nnz += cnt;
        r->flops += (double)cnt * cnt;
        /* Fill: rows i, j > k both coupled to k become coupled. */
        for (int i = k + 1; i < n; i++)
            if (A[(size_t)i * n + k])
                for (int j = k + 1; j < n; j++)
                    if (A[(size_t)j * n + k]) A[(size_t)i * n + j] = 1;
    }
    for (int j = n - 1; j >= 0; j--) r->depth[j] = r->parent[j] < 0 ? 1 : r->depth[r->parent[j]] + 1;
    free(A);
    free(inv);
}

/* Closure of node v's DOFs by walking the reference tree with a visited set. */
static int ref_closure(const ref *r, const int *inv, int v, unsigned char *seen)
{
    memset(seen, 0, (size_t)r->n);
    int cnt = 0;
    for (int c = 0; c < 3; c++)
        for (int j = 3 * inv[v] + c; j >= 0 && !seen[j]; j = r->parent[j]) {
            seen[j] = 1;
            cnt++;
        }
    return cnt;
}

static void compare(const kt_mesh *m, const int *perm, const unsigned char *fixed, const int *set,
                    int nset, const char *what)
{
    kt_order_stats st;
    kt_err e = {0};
    CHECK(kt_order_analyze(m, perm, fixed, set, nset, &st, &e) == 0, "%s: %s", what, e.msg);
    ref r;
    reference(m, perm, fixed, &r);
    CHECK_NEAR(st.nnz_L, r.nnz, 0, what);
    CHECK_NEAR(st.flops, r.flops, 0, what);
    int height = 0;
    for (int j = 0; j < r.n; j++)
        if (r.depth[j] > height) height = r.depth[j];
    CHECK(st.height == height, "%s: height %d vs %d", what, st.height, height);
    int *inv = malloc(sizeof(int) * m->nn);
    for (int i = 0; i < m->nn; i++) inv[perm ? perm[i] : i] = i;
    unsigned char *seen = malloc((size_t)r.n), *all = calloc((size_t)r.n, 1);
    double sum = 0;
    int mx = 0, count = set ? nset : m->nn;
    long uni = 0;
    for (int k = 0; k < count; k++) {
        int v = set ? set[k] : k, cl = ref_closure(&r, inv, v, seen);
        sum += cl;
        if (cl > mx) mx = cl;
        for (int j = 0; j < r.n; j++)
            if (seen[j] && !all[j]) all[j] = 1, uni++;
    }
    CHECK_NEAR(st.closure_mean, sum / count, 1e-12, what);
    CHECK(st.closure_max == mx && st.closure_union == uni, "%s: closure max %d/%d union %ld/%ld", what,
          st.closure_max, mx, st.closure_union, uni);
    free(inv);
    free(seen);
    free(all);
    free(r.parent);
    free(r.depth);
}

static int is_perm(const int *p, int n)
{
    unsigned char *seen = calloc((size_t)n, 1);
    int ok = 1;
    for (int i = 0; i < n && ok; i++) {
        ok = p[i] >= 0 && p[i] < n && !seen[p[i]];
        if (ok) seen[p[i]] = 1;
    }
    free(seen);
    return ok;
}

int main(void)
{
    kt_err e = {0};
    kt_mesh m;
    CHECK(kt_grid_box(&m, 3, 4, 6, 2.0, 3.0, 5.0, &e) == 0, "%s", e.msg);
    const kt_group *top = kt_mesh_find_group(&m, 2, "zmax"), *bottom = kt_mesh_find_group(&m, 2, "zmin");
    int *set = NULL, nset = 0, *fixn = NULL, nfix = 0;
    kt_mesh_group_nodes(&m, top, &set, &nset, &e);
    kt_mesh_group_nodes(&m, bottom, &fixn, &nfix, &e);
    unsigned char *fixed = calloc(3 * (size_t)m.nn, 1);
    for (int k = 0; k < nfix; k++) fixed[3 * fixn[k]] = fixed[3 * fixn[k] + 2] = 1; /* x and z */

    compare(&m, NULL, NULL, NULL, 0, "natural, all nodes");
    compare(&m, NULL, fixed, set, nset, "natural, fixed, set");

    int methods[] = {KT_ORDERING_AMD, KT_ORDERING_METIS, KT_ORDERING_CONSTRAINED, KT_ORDERING_METIS_LAST,
                     KT_ORDERING_NATURAL};
    int *perm = malloc(sizeof(int) * m.nn), *metis = malloc(sizeof(int) * m.nn);
    for (int i = 0; i < 5; i++) {
        const char *name = kt_order_name(methods[i]);
        CHECK(kt_order_nodes(&m, methods[i], set, nset, perm, &e) == 0, "%s: %s", name, e.msg);
        CHECK(is_perm(perm, m.nn), "%s: not a permutation", name);
        compare(&m, perm, fixed, set, nset, name);
        compare(&m, perm, NULL, NULL, 0, name);
        if (methods[i] == KT_ORDERING_METIS) memcpy(metis, perm, sizeof(int) * m.nn);
        if (methods[i] == KT_ORDERING_CONSTRAINED || methods[i] == KT_ORDERING_METIS_LAST) {
            /* The set occupies the last positions, so its closure is its own DOFs. */
            unsigned char *in = calloc((size_t)m.nn, 1);
            for (int k = 0; k < nset; k++) in[set[k]] = 1;
            int tail = 1;
            for (int k = m.nn - nset; k < m.nn; k++) tail &= in[perm[k]];
            CHECK(tail, "%s: set not last", name);
            kt_order_stats st;
            kt_order_analyze(&m, perm, NULL, set, nset, &st, &e);
            CHECK(st.closure_union == 3 * nset, "%s: |closure(S)| %ld for %d nodes", name, st.closure_union, nset);
            if (methods[i] == KT_ORDERING_METIS_LAST) {
                /* Others keep METIS's relative order. */
                int a = 0, stable = 1;
                for (int k = 0; k < m.nn; k++)
                    if (!in[metis[k]]) stable &= perm[a++] == metis[k];
                CHECK(stable, "metis-last changed the order of the other nodes");
            }
            free(in);
        }
    }

    /* Ranks within the set: CAMD and metis-last order the set by non-decreasing rank. */
    int *rank = malloc(sizeof(int) * nset);
    for (int k = 0; k < nset; k++) rank[k] = (int)(m.xyz[3 * set[k]] + 2 * m.xyz[3 * set[k] + 1]);
    int *rank_of = calloc((size_t)m.nn, sizeof(int));
    for (int k = 0; k < nset; k++) rank_of[set[k]] = rank[k];
    int ranked[] = {KT_ORDERING_CONSTRAINED, KT_ORDERING_METIS_LAST};
    for (int i = 0; i < 2; i++) {
        CHECK(kt_order_nodes_ranked(&m, ranked[i], set, rank, nset, perm, &e) == 0, "%s", e.msg);
        CHECK(is_perm(perm, m.nn), "ranked %s: not a permutation", kt_order_name(ranked[i]));
        int sorted = 1, inset = 1;
        for (int k = m.nn - nset; k < m.nn; k++) {
            inset &= m.xyz[3 * perm[k] + 2] == 5.0;
            if (k > m.nn - nset) sorted &= rank_of[perm[k - 1]] <= rank_of[perm[k]];
        }
        CHECK(inset && sorted, "ranked %s: set last %d, sorted by rank %d", kt_order_name(ranked[i]), inset, sorted);
        compare(&m, perm, fixed, set, nset, "ranked");
    }
    free(rank);
    free(rank_of);

    /* Fill-reducing orderings beat the natural one on a long beam; METIS's tree is far
     * shallower than AMD's banded one. */
    kt_mesh beam;
    CHECK(kt_grid_box(&beam, 5, 5, 200, 4, 4, 199, &e) == 0, "%s", e.msg);
    int *bp = malloc(sizeof(int) * beam.nn);
    kt_order_stats nat, amd, met;
    kt_order_analyze(&beam, NULL, NULL, NULL, 0, &nat, &e);
    kt_order_nodes(&beam, KT_ORDERING_AMD, NULL, 0, bp, &e);
    kt_order_analyze(&beam, bp, NULL, NULL, 0, &amd, &e);
    kt_order_nodes(&beam, KT_ORDERING_METIS, NULL, 0, bp, &e);
    kt_order_analyze(&beam, bp, NULL, NULL, 0, &met, &e);
    CHECK(amd.nnz_L < nat.nnz_L, "amd %g vs natural %g", amd.nnz_L, nat.nnz_L);
    CHECK(met.height < amd.height / 4, "metis height %d vs amd %d", met.height, amd.height);
    CHECK(e.code == 0, "%s", e.msg);

    /* A repeated node in the set is a programming error, reported. */
    int badset[2] = {1, 1};
    kt_err e2 = {0};
    CHECK(kt_order_nodes(&m, KT_ORDERING_CONSTRAINED, badset, 2, perm, &e2) == KT_ERUN, "repeated set node");

    free(bp);
    kt_mesh_free(&beam);
    free(perm);
    free(metis);
    free(fixed);
    free(set);
    free(fixn);
    kt_mesh_free(&m);
    return kt_test_done("test_order");
}
