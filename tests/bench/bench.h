/* bench.h: what the benchmark programs share: a mesh with its scene's materials, physics and
 * Dirichlet data, and the constrained stiffness matrix, built with the library's own calls (the
 * same ones augsolve uses: kt_physics_problem). Header-only (static functions) so that each bench program stays a
 * single-file program. */
#ifndef KT_BENCH_H
#define KT_BENCH_H

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cholmod.h>

#include "bind.h"
#include "chol.h"
#include "msh.h"
#include "physics.h"
#include "scene.h"

typedef struct bench_problem {
    kt_mesh mesh;
    kt_scene scene;
    kt_fem_problem fem;   /* the scene on the mesh (owns what the three below point to) */
    kt_physics phys;      /* fibre matrices, prestress: fem.mats.td points into it */
    kt_materials mats;
    unsigned char *fixed; /* 3*nn: Dirichlet DOFs of the scene */
    double *g;            /* 3*nn: their values, mm */
} bench_problem;

static inline void bench_problem_free(bench_problem *p)
{
    kt_fem_problem_free(&p->fem);
    kt_physics_free(&p->phys);
    kt_mesh_free(&p->mesh);
    memset(p, 0, sizeof *p);
}

/* Mesh + scene -> the problem augsolve solves: materials, physics (for a prestressed scene the
 * stiffness about the loaded measured geometry, and zero prescribed values: the steps are
 * increments) and Dirichlet data. */
static inline int bench_problem_load(bench_problem *p, const char *mesh, const char *scene, kt_err *e)
{
    memset(p, 0, sizeof *p);
    if (kt_msh_read(mesh, &p->mesh, e) || kt_scene_load(scene, &p->scene, e) ||
        kt_physics_problem(&p->scene, &p->mesh, &p->fem, &p->phys, e))
        return e->code;
    p->mats = p->fem.mats;
    p->fixed = p->fem.fixed;
    p->g = p->fem.g;
    return KT_OK;
}

/* The free-DOF block of the constrained stiffness (lower triangle, stype -1): the matrix whose
 * condition number matters (identity rows of fixed DOFs would only add eigenvalues of 1).
 * map[i] = compact index of DOF i or -1; *nfree its size. */
static inline cholmod_sparse *bench_free_block(const bench_problem *p, int **map, int *nfree,
                                        cholmod_common *c, kt_err *e)
{
    cholmod_sparse *K = kt_fem_assemble(&p->mesh, &p->mats, p->fixed, c, e);
    if (!K) return NULL;
    int n = (int)K->ncol, nf = 0;
    int *mp = kt_calloc((size_t)n, sizeof(int), e);
    if (!mp) {
        cholmod_free_sparse(&K, c);
        return NULL;
    }
    for (int i = 0; i < n; i++) mp[i] = p->fixed[i] ? -1 : nf++;
    const int *Kp = K->p, *Ki = K->i;
    const double *Kx = K->x;
    size_t nz = 0;
    for (int j = 0; j < n; j++)
        if (mp[j] >= 0)
            for (int q = Kp[j]; q < Kp[j + 1]; q++) nz += Ki[q] >= j && mp[Ki[q]] >= 0;
    cholmod_sparse *F = cholmod_allocate_sparse(nf, nf, nz, 1, 1, -1, CHOLMOD_REAL, c);
    if (!F) {
        kt_fail(e, KT_ERUN, "out of memory for the free block (%zu nonzeros)", nz);
        free(mp);
        cholmod_free_sparse(&K, c);
        return NULL;
    }
    int *Fp = F->p, *Fi = F->i;
    double *Fx = F->x;
    nz = 0;
    for (int j = 0; j < n; j++) {
        if (mp[j] < 0) continue;
        Fp[mp[j]] = (int)nz;
        for (int q = Kp[j]; q < Kp[j + 1]; q++)
            if (Ki[q] >= j && mp[Ki[q]] >= 0) {
                Fi[nz] = mp[Ki[q]];
                Fx[nz++] = Kx[q];
            }
    }
    Fp[nf] = (int)nz;
    F->sorted = 0;
    cholmod_sort(F, c);
    cholmod_free_sparse(&K, c);
    *map = mp;
    *nfree = nf;
    return F;
}

/* Keep the given (mesh-prep) ordering exactly, or let CHOLMOD use AMD / METIS. */
static inline cholmod_factor *bench_analyze(cholmod_sparse *K, const char *ordering, int supernodal,
                                     cholmod_common *c, kt_err *e)
{
    c->nmethods = 1;
    c->method[0].ordering = !strcmp(ordering, "amd")     ? CHOLMOD_AMD
                            : !strcmp(ordering, "metis") ? CHOLMOD_METIS
                                                         : CHOLMOD_NATURAL;
    c->postorder = strcmp(ordering, "natural") != 0;
    c->supernodal = supernodal ? CHOLMOD_SUPERNODAL : CHOLMOD_SIMPLICIAL;
    c->final_ll = 0;
    cholmod_factor *L = cholmod_analyze(K, c);
    if (!L) kt_fail(e, KT_ERUN, "CHOLMOD analyze failed (status %d)", c->status);
    return L;
}

static inline int bench_factorize(cholmod_sparse *K, cholmod_factor *L, cholmod_common *c, kt_err *e)
{
    return kt_chol_factor(K, L, c, "bench", e);
}

/* Stored entries of L: supernodal values (padding included) or simplicial column counts. */
static inline double bench_factor_entries(const cholmod_factor *L)
{
    if (L->is_super) return (double)L->xsize;
    const int *Lnz = L->nz;
    double s = 0;
    for (size_t j = 0; j < L->n; j++) s += Lnz[j];
    return s;
}

static inline int bench_cmp_double(const void *x, const void *y)
{
    double a = *(const double *)x, b = *(const double *)y;
    return (a > b) - (a < b);
}

#endif
