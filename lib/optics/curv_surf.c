/* curv_surf.c: the anterior corneal surface of a step mesh: nodes descending from the input
 * mesh's "anterior" group, deformed, and the boundary triangles between them. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "curv.h"
#include "topology.h"

/* ---------------------------------------------------------------- anterior surface */

int kt_curv_anterior_mask(const kt_mesh *m, const char *what, unsigned char **mask, kt_err *e)
{
    *mask = NULL;
    const kt_group *g = kt_mesh_find_group(m, 2, "anterior");
    if (!g)
        return kt_fail(e, KT_EINPUT,
                       "%s: no surface group \"anterior\": expected the anterior corneal surface "
                       "as a physical group of triangles (lib/model/eye.h)", what);
    int *nodes = NULL, cnt = 0;
    if (kt_mesh_group_nodes(m, g, &nodes, &cnt, e) != KT_OK) return e->code;
    if (cnt == 0) {
        free(nodes);
        return kt_fail(e, KT_EINPUT, "%s: surface group \"anterior\" has no triangles", what);
    }
    unsigned char *mk = kt_calloc(m->nn, 1, e);
    if (!mk) {
        free(nodes);
        return e->code;
    }
    for (int i = 0; i < cnt; i++) mk[nodes[i]] = 1;
    free(nodes);
    *mask = mk;
    return KT_OK;
}

void kt_surf_free(kt_surf *s)
{
    free(s->xyz), free(s->disp), free(s->node), free(s->origin), free(s->tri);
    memset(s, 0, sizeof *s);
}

/* A boundary-face candidate: kt_face with id = 4 * cell + the corner it is opposite. */

/* VTK_QUADRATIC_TETRA mid-edge node positions: edges 01 12 02 03 13 23 -> 4..9. */
static int mid_of(int a, int b)
{
    static const int mid[4][4] = {{-1, 4, 6, 7}, {4, -1, 5, 8}, {6, 5, -1, 9}, {7, 8, 9, -1}};
    return mid[a][b];
}

/* Faces of the tets whose three corners are all anterior (sl[pt] >= 0). */
static int collect_faces(const kt_vtk *v, const int *sl, kt_face **out, int *nout, kt_err *e)
{
    int cap = 64, n = 0;
    kt_face *f = kt_calloc(cap, sizeof(kt_face), e);
    if (!f) return e->code;
    for (int c = 0; c < v->ncell; c++) {
        int type = v->cell_type[c];
        if (type != 10 && type != 24) continue;
        const int *t = v->conn + v->cell_ptr[c];
        for (int opp = 0; opp < 4; opp++) {
            int k[3], j = 0;
            for (int q = 0; q < 4; q++)
                if (q != opp) k[j++] = t[q];
            if (sl[k[0]] < 0 || sl[k[1]] < 0 || sl[k[2]] < 0) continue;
            if (n == cap) {
                kt_face *g = kt_realloc(f, cap *= 2, sizeof(kt_face), e);
                if (!g) {
                    free(f);
                    return e->code;
                }
                f = g;
            }
            kt_sort3(k);
            memcpy(f[n].v, k, sizeof k);
            f[n].id = 4 * c + opp;
            n++;
        }
    }
    qsort(f, n, sizeof(kt_face), kt_face_cmp);
    *out = f, *nout = n;
    return KT_OK;
}

static int add_tri(kt_surf *s, int *cap, int a, int b, int c, kt_err *e)
{
    if (s->ntri == *cap) {
        int *t = kt_realloc(s->tri, (size_t)(*cap *= 2) * 3, sizeof(int), e);
        if (!t) return e->code;
        s->tri = t;
    }
    s->tri[3 * s->ntri] = a, s->tri[3 * s->ntri + 1] = b, s->tri[3 * s->ntri + 2] = c;
    s->ntri++;
    return KT_OK;
}

/* One boundary face of cell c (opposite corner opp) as 1 or 4 outward triangles. */
static int emit_face(const kt_vtk *v, int c, int opp, const int *sl, kt_surf *s, int *cap, kt_err *e)
{
    const int *t = v->conn + v->cell_ptr[c];
    int q[3], j = 0;
    for (int i = 0; i < 4; i++)
        if (i != opp) q[j++] = i;
    const double *A = v->xyz + 3 * t[q[0]], *B = v->xyz + 3 * t[q[1]], *C = v->xyz + 3 * t[q[2]],
                 *O = v->xyz + 3 * t[opp];
    double u[3], w[3], nrm[3];
    for (int k = 0; k < 3; k++) u[k] = B[k] - A[k], w[k] = C[k] - A[k];
    nrm[0] = u[1] * w[2] - u[2] * w[1];
    nrm[1] = u[2] * w[0] - u[0] * w[2];
    nrm[2] = u[0] * w[1] - u[1] * w[0];
    if (nrm[0] * (O[0] - A[0]) + nrm[1] * (O[1] - A[1]) + nrm[2] * (O[2] - A[2]) > 0) {
        int tmp = q[1]; /* outward: away from the opposite corner */
        q[1] = q[2], q[2] = tmp;
    }
    int a = sl[t[q[0]]], b = sl[t[q[1]]], cc = sl[t[q[2]]];
    if (v->cell_type[c] == 24) {
        int mab = sl[t[mid_of(q[0], q[1])]], mbc = sl[t[mid_of(q[1], q[2])]],
            mca = sl[t[mid_of(q[2], q[0])]];
        if (mab >= 0 && mbc >= 0 && mca >= 0) {
            if (add_tri(s, cap, a, mab, mca, e) || add_tri(s, cap, mab, b, mbc, e) ||
                add_tri(s, cap, mca, mbc, cc, e) || add_tri(s, cap, mab, mbc, mca, e))
                return e->code;
            return KT_OK;
        }
    }
    return add_tri(s, cap, a, b, cc, e);
}

static int surface_triangles(const kt_vtk *v, const int *sl, kt_surf *s, kt_err *e)
{
    kt_face *f = NULL;
    int nf = 0, cap = 64;
    if (collect_faces(v, sl, &f, &nf, e) != KT_OK) return e->code;
    s->tri = kt_calloc((size_t)cap * 3, sizeof(int), e);
    int rc = s->tri ? KT_OK : e->code;
    for (int i = 0; i < nf && rc == KT_OK;) {
        int j = i + 1;
        while (j < nf && kt_face_cmp_v(f + i, f + j) == 0) j++;
        if (j - i == 1) rc = emit_face(v, f[i].id / 4, f[i].id % 4, sl, s, &cap, e); /* boundary */
        i = j;
    }
    free(f);
    return rc;
}

/* s's points: the nn points whose slot sl[i] >= 0 (n of them), deformed xyz + disp, their
 * input-mesh node (org1, 1-based). */
static int fill_points(int nn, const double *xyz, const double *disp, const int *org1, const int *sl, int n,
                       kt_surf *s, kt_err *e)
{
    s->n = n;
    s->xyz = kt_calloc((size_t)3 * n, sizeof(double), e);
    s->disp = kt_calloc((size_t)3 * n, sizeof(double), e);
    s->node = kt_calloc(n, sizeof(int), e);
    s->origin = kt_calloc(n, sizeof(int), e);
    if (!s->xyz || !s->disp || !s->node || !s->origin) return e->code;
    for (int i = 0; i < nn; i++) {
        int k = sl[i];
        if (k < 0) continue;
        s->node[k] = i;
        s->origin[k] = org1[i];
        for (int c = 0; c < 3; c++) {
            s->disp[3 * k + c] = disp[3 * i + c];
            s->xyz[3 * k + c] = xyz[3 * i + c] + disp[3 * i + c];
        }
    }
    return KT_OK;
}

int kt_curv_extract(const kt_vtk *v, const char *what, const unsigned char *mask, int mesh_nn,
                    kt_surf *s, kt_err *e)
{
    memset(s, 0, sizeof *s);
    if (v->is_polydata)
        return kt_fail(e, KT_EINPUT, "%s: expected an UNSTRUCTURED_GRID of tets, found POLYDATA", what);
    const kt_vtk_field *disp = kt_vtk_find(v, "displacement", 0);
    const kt_vtk_field *orig = kt_vtk_find(v, "origin", 0);
    if (!disp || disp->ncomp != 3)
        return kt_fail(e, KT_EINPUT, "%s: expected POINT_DATA field \"displacement\" (3 components)", what);
    if (!orig || orig->ncomp != 1)
        return kt_fail(e, KT_EINPUT, "%s: expected POINT_DATA field \"origin\" (input-mesh node, 1-based)", what);
    int *sl = kt_calloc(v->nn, sizeof(int), e), *org1 = kt_calloc(v->nn, sizeof(int), e);
    if (!sl || !org1) {
        free(sl), free(org1);
        return e->code;
    }
    int n = 0;
    for (int i = 0; i < v->nn; i++) {
        double o = orig->v[i];
        if (!(o >= 1 && o <= mesh_nn && o == floor(o))) {
            free(sl), free(org1);
            return kt_fail(e, KT_EINPUT, "%s: origin of point %d is %g: expected a node of the mesh, 1..%d",
                           what, i, o, mesh_nn);
        }
        org1[i] = (int)o;
        sl[i] = mask[(int)o - 1] ? n++ : -1;
    }
    if (n == 0) {
        free(sl), free(org1);
        return kt_fail(e, KT_EINPUT, "%s: no point descends from an anterior-surface node", what);
    }
    int rc = fill_points(v->nn, v->xyz, disp->v, org1, sl, n, s, e);
    if (rc == KT_OK) rc = surface_triangles(v, sl, s, e);
    free(sl), free(org1);
    if (rc != KT_OK) kt_surf_free(s);
    return rc;
}

int kt_curv_points(const kt_mesh *m, const double *u, const int *origin, const unsigned char *mask, int mesh_nn,
                   kt_surf *s, kt_err *e)
{
    memset(s, 0, sizeof *s);
    int *sl = kt_calloc(m->nn, sizeof(int), e), *org1 = kt_calloc(m->nn, sizeof(int), e);
    int n = 0, rc = sl && org1 ? KT_OK : e->code;
    for (int i = 0; rc == KT_OK && i < m->nn; i++) {
        if (!(origin[i] >= 0 && origin[i] < mesh_nn)) {
            rc = kt_fail(e, KT_ERUN, "node %d descends from node %d: expected a node of the mesh, 0..%d", i, origin[i],
                         mesh_nn - 1);
            break;
        }
        org1[i] = origin[i] + 1;
        sl[i] = mask[origin[i]] ? n++ : -1;
    }
    if (rc == KT_OK && n == 0) rc = kt_fail(e, KT_ERUN, "no node descends from a node of the surface");
    if (rc == KT_OK) rc = fill_points(m->nn, m->xyz, u, org1, sl, n, s, e);
    free(sl), free(org1);
    if (rc != KT_OK) kt_surf_free(s);
    return rc;
}
