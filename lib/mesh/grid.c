/* grid.c: structured box meshes, each cell split into six tets around its main diagonal. */
#include "grid.h"

#include <stdlib.h>
#include <string.h>

/* The six tets of a cell: walk from corner 0 to corner 7 adding one axis at a time. */
static const int PERM[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};

static int node_id(int i, int j, int k, int nx, int ny) { return i + nx * (j + ny * k); }

/* Two triangles of a boundary quad a,b,c,d (in cyclic order), split along diagonal a-c to
 * match the tets (which all contain the diagonal through the cell's corner 0). */
static void quad(int *tri, int *tag, int *nf, int a, int b, int c, int d, int t)
{
    int *q = tri + 3 * (*nf);
    q[0] = a; q[1] = b; q[2] = c;
    q[3] = a; q[4] = c; q[5] = d;
    tag[*nf] = tag[*nf + 1] = t;
    *nf += 2;
}

int kt_grid_box(kt_mesh *m, int nx, int ny, int nz, double lx, double ly, double lz, kt_err *e)
{
    memset(m, 0, sizeof *m);
    if (nx < 2 || ny < 2 || nz < 2 || !(lx > 0) || !(ly > 0) || !(lz > 0))
        return kt_fail(e, KT_EINPUT, "grid needs at least 2 nodes and a positive length per axis");
    m->order = 1;
    m->nn = nx * ny * nz;
    int cx = nx - 1, cy = ny - 1, cz = nz - 1;
    m->ne = 6 * cx * cy * cz;
    m->nf = 4 * (cy * cz + cx * cz + cx * cy);
    m->xyz = kt_calloc(3 * (size_t)m->nn, sizeof(double), e);
    m->tet = kt_calloc(4 * (size_t)m->ne, sizeof(int), e);
    m->tet_tag = kt_calloc(m->ne, sizeof(int), e);
    m->tri = kt_calloc(3 * (size_t)m->nf, sizeof(int), e);
    m->tri_tag = kt_calloc(m->nf, sizeof(int), e);
    if (e->code) {
        kt_mesh_free(m);
        return e->code;
    }
    for (int k = 0; k < nz; k++)
        for (int j = 0; j < ny; j++)
            for (int i = 0; i < nx; i++) {
                double *x = m->xyz + 3 * (size_t)node_id(i, j, k, nx, ny);
                x[0] = lx * i / cx;
                x[1] = ly * j / cy;
                x[2] = lz * k / cz;
            }
    int t = 0;
    for (int k = 0; k < cz; k++)
        for (int j = 0; j < cy; j++)
            for (int i = 0; i < cx; i++)
                for (int p = 0; p < 6; p++) {
                    int c[3] = {i, j, k};
                    int *q = m->tet + 4 * (size_t)t;
                    q[0] = node_id(c[0], c[1], c[2], nx, ny);
                    for (int s = 0; s < 3; s++) {
                        c[PERM[p][s]]++;
                        q[s + 1] = node_id(c[0], c[1], c[2], nx, ny);
                    }
                    const double *X = m->xyz;
                    if (kt_tet_volume(X + 3 * q[0], X + 3 * q[1], X + 3 * q[2], X + 3 * q[3]) < 0) {
                        int s = q[2]; q[2] = q[3]; q[3] = s;
                    }
                    m->tet_tag[t++] = 1;
                }
    int nf = 0;
    for (int k = 0; k < cz; k++)
        for (int j = 0; j < cy; j++) {
            quad(m->tri, m->tri_tag, &nf, node_id(0, j, k, nx, ny), node_id(0, j + 1, k, nx, ny),
                 node_id(0, j + 1, k + 1, nx, ny), node_id(0, j, k + 1, nx, ny), 1);
            quad(m->tri, m->tri_tag, &nf, node_id(cx, j, k, nx, ny), node_id(cx, j + 1, k, nx, ny),
                 node_id(cx, j + 1, k + 1, nx, ny), node_id(cx, j, k + 1, nx, ny), 2);
        }
    for (int k = 0; k < cz; k++)
        for (int i = 0; i < cx; i++) {
            quad(m->tri, m->tri_tag, &nf, node_id(i, 0, k, nx, ny), node_id(i + 1, 0, k, nx, ny),
                 node_id(i + 1, 0, k + 1, nx, ny), node_id(i, 0, k + 1, nx, ny), 3);
            quad(m->tri, m->tri_tag, &nf, node_id(i, cy, k, nx, ny), node_id(i + 1, cy, k, nx, ny),
                 node_id(i + 1, cy, k + 1, nx, ny), node_id(i, cy, k + 1, nx, ny), 4);
        }
    for (int j = 0; j < cy; j++)
        for (int i = 0; i < cx; i++) {
            quad(m->tri, m->tri_tag, &nf, node_id(i, j, 0, nx, ny), node_id(i + 1, j, 0, nx, ny),
                 node_id(i + 1, j + 1, 0, nx, ny), node_id(i, j + 1, 0, nx, ny), 5);
            quad(m->tri, m->tri_tag, &nf, node_id(i, j, cz, nx, ny), node_id(i + 1, j, cz, nx, ny),
                 node_id(i + 1, j + 1, cz, nx, ny), node_id(i, j + 1, cz, nx, ny), 6);
        }
    static const char *NAMES[6] = {"xmin", "xmax", "ymin", "ymax", "zmin", "zmax"};
    if (kt_mesh_add_group(m, 3, 1, "body", e)) goto fail;
    for (int g = 0; g < 6; g++)
        if (kt_mesh_add_group(m, 2, g + 1, NAMES[g], e)) goto fail;
    return KT_OK;
fail:
    kt_mesh_free(m);
    return e->code;
}
