/* lp_mesh.c: the patient's mesh (lp_mesh.h): mesh-prep's pipeline on the chosen ordering only. */
#include "lp_mesh.h"

#include <stdlib.h>
#include <string.h>

#include "bind.h"
#include "build.h"
#include "order.h"
#include "orderset.h"
#include "refgeom.h"

/* The geometry is the measured shape under the loads: replace it by the stress-free one. */
static int unload(const kt_scene *s, int quiet, kt_mesh *m, kt_err *e)
{
    if (s->reference != KT_REFERENCE_LOADED) return KT_OK;
    for (int i = 0; i < s->nmat; i++)
        if (s->mat[i].fibre)
            return kt_fail(e, KT_EINPUT, "%s: materials.%s: model fibre needs loads.reference prestressed or unloaded "
                           "(the stress-free iteration is isotropic only)", s->path, s->mat[i].region);
    kt_refgeom_opts ro;
    kt_refgeom_stats rs;
    kt_refgeom_opts_default(s, &ro);
    ro.quiet = quiet;
    if (kt_refgeom_unload(s, m, &ro, &rs, e)) return e->code;
    return kt_mesh_check(m, "stress-free geometry", e);
}

/* The scene's ordering of the mesh (the ordering set last, swept from the centre meridian),
 * the nodes renumbered in it. */
static int order(const kt_scene *s, kt_mesh *m, kt_err *e)
{
    int *set = NULL, *rank = NULL, nset = 0, *perm = kt_calloc((size_t)m->nn, sizeof(int), e);
    char label[160];
    if (perm && !kt_orderset_nodes(s, m, &set, &nset, label, e) && !kt_orderset_ranks(s, m, set, nset, &rank, e) &&
        !kt_order_nodes_ranked(m, s->ordering, set, rank, nset, perm, e))
        kt_mesh_permute(m, perm, e);
    free(set), free(rank), free(perm);
    return e->code;
}

int kt_lp_mesh_make(const kt_scene *s, int quiet, kt_lp_mesh *mh, kt_err *e)
{
    memset(mh, 0, sizeof *mh);
    double t0 = kt_now(), c0 = kt_cpu_now();
    kt_log(quiet, "lri-plan: meshing the patient's eye\n");
    if (kt_build_mesh(s, s->order, quiet, &mh->m, e) || kt_mesh_check(&mh->m, "the patient's mesh", e) ||
        kt_fem_check_scene(s, &mh->m, NULL, e) || unload(s, quiet, &mh->m, e) || order(s, &mh->m, e)) {
        kt_lp_mesh_free(mh);
        return e->code;
    }
    mh->hash = kt_mesh_hash(&mh->m);
    mh->seconds = kt_now() - t0, mh->cpu = kt_cpu_now() - c0;
    kt_log(quiet, "lri-plan: meshed in %.1f s (CPU %.1f s): %d nodes\n", mh->seconds, mh->cpu, mh->m.nn);
    return KT_OK;
}

void kt_lp_mesh_free(kt_lp_mesh *mh)
{
    kt_mesh_free(&mh->m);
}
