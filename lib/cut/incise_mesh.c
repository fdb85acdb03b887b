/* incise_mesh.c: the cutter's view of the mesh, shared by the driver (incise.c) and the
 * phases (incise_ring.c, incise_snap.c, incise_deform.c, incise_anchor.c): the current tets,
 * faces and their neighbours, node -> tets, the union-find, the order of a phase's faces. */
#include "incise_int.h"

#include <stdlib.h>
#include <string.h>

/* Vertices of face j (the face opposite vertex j) and tet10 edge numbering (gmsh order). */

int kt_incise_face_pos(int order, int j, int *pos)
{
    int n = 0;
    for (int k = 0; k < 3; k++) pos[n++] = kt_tet_face[j][k];
    if (order == 2)
        for (int k = 0; k < 6; k++)
            if (kt_tet_edge[k][0] != j && kt_tet_edge[k][1] != j) pos[n++] = 4 + k;
    return n;
}

/* Face table and neighbours across faces; a face in three tets is a broken mesh. */
static int build_faces(kt_incise *c, kt_err *e)
{
    const kt_mesh *m = c->m;
    int nf = 4 * m->ne;
    c->nbr = kt_calloc((size_t)nf, sizeof(int), e);
    if (!c->nbr || kt_mesh_tet_faces(m, &c->ftab, e)) return e->code;
    for (int i = 0; i < nf; i++) c->nbr[c->ftab[i].id] = -1;
    for (int i = 0; i + 1 < nf; i++) {
        if (kt_face_cmp_v(&c->ftab[i], &c->ftab[i + 1]) != 0) continue;
        if (i + 2 < nf && kt_face_cmp_v(&c->ftab[i], &c->ftab[i + 2]) == 0)
            return kt_fail(e, KT_EINPUT, "mesh: face (%d %d %d) is shared by more than two tets",
                           c->ftab[i].v[0] + 1, c->ftab[i].v[1] + 1, c->ftab[i].v[2] + 1);
        c->nbr[c->ftab[i].id] = c->ftab[i + 1].id;
        c->nbr[c->ftab[i + 1].id] = c->ftab[i].id;
    }
    c->nftab = nf;
    return KT_OK;
}

int kt_incise_find_face(const kt_incise *c, int a, int b, int d)
{
    int v[3] = {a, b, d};
    int k = kt_face_find(c->ftab, c->nftab, v);
    return k < 0 ? -1 : c->ftab[k].id;
}

/* Input node -> tets, every node of a tet (mid-edge nodes too). */
static int build_node_tets(kt_incise *c, kt_err *e)
{
    const kt_mesh *m = c->m;
    if (kt_mesh_node_tets(m, &c->n2t_p, &c->n2t_i, e)) return e->code;
    c->maxdeg = 0;
    for (int v = 0; v < m->nn; v++)
        if (c->n2t_p[v + 1] - c->n2t_p[v] > c->maxdeg) c->maxdeg = c->n2t_p[v + 1] - c->n2t_p[v];
    return KT_OK;
}

int kt_incise_tables(kt_incise *c, kt_err *e)
{
    const kt_mesh *m = c->m;
    c->nv = kt_tet_nv(m->order);
    c->nn = m->nn;
    c->cap = m->nn + 1024;
    c->cur = kt_calloc((size_t)m->ne * c->nv, sizeof(int), e);
    c->origin = kt_calloc((size_t)c->cap, sizeof(int), e);
    c->cut = kt_calloc((size_t)4 * m->ne, 1, e);
    c->side = kt_calloc((size_t)4 * m->ne, 1, e);
    if (e->code) return e->code;
    memcpy(c->cur, m->tet, (size_t)m->ne * c->nv * sizeof(int));
    for (int v = 0; v < m->nn; v++) c->origin[v] = v;
    if (build_faces(c, e) || build_node_tets(c, e)) return e->code;
    int d = c->maxdeg + 1;
    c->s_tet = kt_calloc((size_t)d, sizeof(int), e);
    c->s_loc = kt_calloc((size_t)d, sizeof(int), e);
    c->s_par = kt_calloc((size_t)d, sizeof(int), e);
    c->s_lab = kt_calloc((size_t)d, sizeof(int), e);
    c->st.nn = m->nn;
    c->st.ne = m->ne;
    return e->code;
}

int kt_incise_uf_find(int *par, int a)
{
    while (par[a] != a) a = par[a] = par[par[a]];
    return a;
}

static int cmp_cutface(const void *pa, const void *pb)
{
    const kt_cutface *a = pa, *b = pb;
    if (a->key != b->key) return (a->key > b->key) - (a->key < b->key);
    return (a->slot > b->slot) - (a->slot < b->slot);
}

void kt_incise_sort_faces(kt_phase *ph)
{
    qsort(ph->face, (size_t)ph->nface, sizeof *ph->face, cmp_cutface);
}

