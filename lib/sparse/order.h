/* order.h: node orderings of a tet mesh (AMD, METIS, constrained, natural) and the sparsity of
 * the resulting Cholesky factor: nnz(L), flops, elimination-tree height and closures.
 *
 * The node graph joins every two nodes of a tetrahedron (all 4 or 10). An ordering is a node
 * permutation perm (new node i = old node perm[i], as kt_mesh_permute takes it); since DOF
 * 3*node + c, the DOF order follows the node order with a node's three DOFs consecutive. */
#ifndef KT_ORDER_H
#define KT_ORDER_H

#include "mesh.h"

/* Methods (a scene's ordering: names them): amd, metis, constrained, natural; as KT_ORDERING_METIS_LAST the scene's KT_ORDERING_* (amd, metis, constrained = CAMD with the set last,
 * natural), and METIS nested dissection with the set then moved last, order kept. */
enum { KT_ORDERING_AMD = 1, KT_ORDERING_METIS, KT_ORDERING_CONSTRAINED, KT_ORDERING_NATURAL };
#define KT_ORDERING_METIS_LAST 5

/* Name of a method ("amd", "metis", "constrained", "natural", "metis-last"). */
const char *kt_order_name(int method);

/* What a METIS 5 return status means, for messages: "status -4, METIS_ERROR: ...". METIS 5.1
 * traps SIGTERM (and SIGABRT) while it runs and returns METIS_ERROR (METIS_ERROR_MEMORY) instead
 * of letting the signal end the process: a job stopped while it orders shows up as
 * METIS_ERROR, and no ordering was made. */
const char *kt_metis_status(int status);

/* METIS_NodeND of the graph (n vertices, CSR xadj/adj, no weights; options NULL: METIS's
 * defaults) into perm and iperm, its status returned. The one door to METIS: METIS seeds and
 * draws from the C library's one rand() stream at every call, so two calls at once (lri-plan's
 * families on their threads) would interleave their draws and change each other's orderings;
 * they take turns here, under the one lock of the library (a file-scope mutex, with the
 * allocation-failure test's counter the only mutable state at file scope). */
int kt_metis_nodend(int n, const int *xadj, const int *adj, int *options, int *perm, int *iperm);

/* Compute a node permutation. last (nlast nodes, any order, no repeats) is the set that the
 * constrained and metis-last methods put at the end; the other methods ignore it. With
 * nlast == 0 the constrained method is plain AMD. perm has m->nn entries. */
int kt_order_nodes(const kt_mesh *m, int method, const int *last, int nlast, int *perm, kt_err *e);

/* Same, with a rank >= 0 for each 'last' node (rank[k] for last[k]): within the set, nodes of
 * higher rank come later (CAMD constraint sets; a stable sort for metis-last), so the nodes to
 * be cut first can sit nearest the root. rank NULL: all equal. */
int kt_order_nodes_ranked(const kt_mesh *m, int method, const int *last, const int *rank,
                          int nlast, int *perm, kt_err *e);

/* Sparsity of the factor of the 3*nn DOF matrix in the mesh's current (or a given) order. */
typedef struct kt_order_stats {
    int n;                  /* DOFs (3*nn) */
    double nnz_A;           /* entries in the lower triangle of the DOF matrix, with diagonal */
    double nnz_L;           /* entries of L, diagonal included */
    double flops;           /* sum over columns of colcount^2 */
    int height;             /* elimination-tree height: DOFs on the longest leaf-to-root path */
    int nset;               /* nodes in the measured set */
    double closure_mean;    /* mean over set nodes of |closure| of the node's DOFs */
    int closure_max;        /* largest such closure */
    long closure_union;     /* |closure| of all DOFs of the set together */
} kt_order_stats;

/* Symbolic analysis (CHOLMOD, simplicial, the given order kept: one method, no postorder) of
 * the DOF matrix after renumbering nodes by perm (NULL: the current order). fixed (3*nn, by
 * current DOF number; NULL: none) marks Dirichlet DOFs, which get identity rows and columns.
 * set (nset nodes, current numbering; NULL: every node) is the node set whose closures are
 * measured: closure of a node = union of the elimination-tree paths from its DOFs to the root. */
int kt_order_analyze(const kt_mesh *m, const int *perm, const unsigned char *fixed, const int *set,
                   int nset, kt_order_stats *st, kt_err *e);

/* The same for nk sets at once (sets[k] of nsets[k] nodes, NULL: every node; st[k] its
 * figures): one symbolic analysis, each set's closures on its elimination tree. */
int kt_order_analyze_sets(const kt_mesh *m, const int *perm, const unsigned char *fixed, int nk,
                          const int *const *sets, const int *nsets, kt_order_stats *st, kt_err *e);

/* What the metis-last method does after METIS: move the 'last' nodes (ranked as in
 * kt_order_nodes_ranked, rank NULL: all equal) to the end of perm by a stable sort, every part
 * keeping its relative order. METIS is deterministic on one graph, so a METIS perm moved here
 * is kt_order_nodes_ranked(KT_ORDERING_METIS_LAST)'s perm, without a second METIS run. */
int kt_order_move_last(const kt_mesh *m, const int *last, const int *rank, int nlast, int *perm,
                       kt_err *e);

#endif
