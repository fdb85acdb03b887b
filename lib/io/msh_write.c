/* msh_write.c: gmsh MSH 4.1 writer (ASCII and binary), one entity per group. */
#include "msh.h"

#include <stdint.h>
#include <stdlib.h>
#include <errno.h>
#include <string.h>

#include "g17.h"

typedef struct wr {
    FILE *f;
    int bin;
} wr;

static void put_i(wr *w, int v, char sep)
{
    if (w->bin) {
        int32_t x = v;
        fwrite(&x, 4, 1, w->f);
    } else {
        fprintf(w->f, "%d%c", v, sep);
    }
}

static void put_z(wr *w, size_t v, char sep)
{
    if (w->bin) {
        uint64_t x = v;
        fwrite(&x, 8, 1, w->f);
    } else {
        fprintf(w->f, "%zu%c", v, sep);
    }
}

static void put_d(wr *w, double v, char sep)
{
    char t[KT_G17_MAX + 1];
    if (w->bin) {
        fwrite(&v, 8, 1, w->f);
    } else {
        int n = kt_g17(v, t);
        t[n] = sep;
        fwrite(t, 1, (size_t)n + 1, w->f);
    }
}

/* Section end: binary data is followed by a newline before the $End line. */
static void end_section(wr *w, const char *name)
{
    fprintf(w->f, "%s$End%s\n", w->bin ? "\n" : "", name);
}

/* Bounding box of the nodes of the elements of a group. */
static void group_box(const kt_mesh *m, const kt_group *g, double box[6])
{
    int nv = g->dim == 3 ? kt_tet_nv(m->order) : kt_tri_nv(m->order);
    int n = g->dim == 3 ? m->ne : m->nf;
    const int *el = g->dim == 3 ? m->tet : m->tri, *tag = g->dim == 3 ? m->tet_tag : m->tri_tag;
    int any = 0;
    for (int i = 0; i < n; i++) {
        if (tag[i] != g->tag) continue;
        for (int j = 0; j < nv; j++) {
            const double *x = m->xyz + 3 * (size_t)el[(size_t)nv * i + j];
            for (int c = 0; c < 3; c++) {
                if (!any || x[c] < box[c]) box[c] = x[c];
                if (!any || x[c] > box[3 + c]) box[3 + c] = x[c];
            }
            any = 1;
        }
    }
    if (!any) memset(box, 0, 6 * sizeof(double));
}

static int check_writable(const kt_mesh *m, kt_err *e)
{
    if (m->order != 1 && m->order != 2)
        return kt_fail(e, KT_EINPUT, "mesh order %d: expected 1 or 2", m->order);
    for (int i = 0; i < m->ne; i++)
        if (!kt_mesh_find_tag(m, 3, m->tet_tag[i]))
            return kt_fail(e, KT_EINPUT, "tetrahedron %d has region tag %d, which is no dimension-3 group",
                           i, m->tet_tag[i]);
    for (int i = 0; i < m->nf; i++)
        if (!kt_mesh_find_tag(m, 2, m->tri_tag[i]))
            return kt_fail(e, KT_EINPUT, "triangle %d has surface tag %d, which is no dimension-2 group",
                           i, m->tri_tag[i]);
    int nvol = 0;
    for (int g = 0; g < m->ng; g++) {
        if (m->group[g].dim != 2 && m->group[g].dim != 3)
            return kt_fail(e, KT_EINPUT, "group '%s' has dimension %d: expected 2 or 3",
                           m->group[g].name, m->group[g].dim);
        if (strchr(m->group[g].name, '"'))
            return kt_fail(e, KT_EINPUT, "group name '%s' contains '\"'", m->group[g].name);
        nvol += m->group[g].dim == 3;
    }
    if (m->nn > 0 && nvol == 0)
        return kt_fail(e, KT_EINPUT, "mesh has no dimension-3 group to hold its nodes");
    return KT_OK;
}

static void write_entities(wr *w, const kt_mesh *m, int nsurf, int nvol)
{
    fprintf(w->f, "$Entities\n");
    put_z(w, 0, ' ');
    put_z(w, 0, ' ');
    put_z(w, (size_t)nsurf, ' ');
    put_z(w, (size_t)nvol, '\n');
    for (int dim = 2; dim <= 3; dim++)
        for (int g = 0; g < m->ng; g++) {
            if (m->group[g].dim != dim) continue;
            double box[6];
            group_box(m, &m->group[g], box);
            put_i(w, m->group[g].tag, ' ');
            for (int c = 0; c < 6; c++) put_d(w, box[c], ' ');
            put_z(w, 1, ' ');
            put_i(w, m->group[g].tag, ' ');
            put_z(w, 0, '\n');
        }
    end_section(w, "Entities");
}

static void write_nodes(wr *w, const kt_mesh *m, int vol_tag)
{
    size_t nn = (size_t)m->nn;
    fprintf(w->f, "$Nodes\n");
    put_z(w, nn ? 1 : 0, ' ');
    put_z(w, nn, ' ');
    put_z(w, nn ? 1 : 0, ' ');
    put_z(w, nn, '\n');
    if (nn) {
        put_i(w, 3, ' ');
        put_i(w, vol_tag, ' ');
        put_i(w, 0, ' ');
        put_z(w, nn, '\n');
        for (size_t i = 0; i < nn; i++) put_z(w, i + 1, '\n');
        if (w->bin) fwrite(m->xyz, sizeof(double), 3 * nn, w->f);
        else
            for (size_t i = 0; i < nn; i++) {
                put_d(w, m->xyz[3 * i], ' ');
                put_d(w, m->xyz[3 * i + 1], ' ');
                put_d(w, m->xyz[3 * i + 2], '\n');
            }
    }
    end_section(w, "Nodes");
}

/* One block per group of dimension dim: elements with that tag, element tags first+i. */
static void write_blocks(wr *w, const kt_mesh *m, int dim, size_t first)
{
    int nv = dim == 3 ? kt_tet_nv(m->order) : kt_tri_nv(m->order);
    int n = dim == 3 ? m->ne : m->nf, type = dim == 3 ? (m->order == 2 ? 11 : 4) : (m->order == 2 ? 9 : 2);
    const int *el = dim == 3 ? m->tet : m->tri, *tag = dim == 3 ? m->tet_tag : m->tri_tag;
    for (int g = 0; g < m->ng; g++) {
        if (m->group[g].dim != dim) continue;
        size_t cnt = 0;
        for (int i = 0; i < n; i++) cnt += tag[i] == m->group[g].tag;
        if (!cnt) continue;
        put_i(w, dim, ' ');
        put_i(w, m->group[g].tag, ' ');
        put_i(w, type, ' ');
        put_z(w, cnt, '\n');
        for (int i = 0; i < n; i++) {
            if (tag[i] != m->group[g].tag) continue;
            put_z(w, first + (size_t)i, ' ');
            for (int j = 0; j < nv; j++) put_z(w, (size_t)el[(size_t)nv * i + j] + 1, j + 1 < nv ? ' ' : '\n');
        }
    }
}

static int count_blocks(const kt_mesh *m, int dim)
{
    int nb = 0, n = dim == 3 ? m->ne : m->nf;
    const int *tag = dim == 3 ? m->tet_tag : m->tri_tag;
    for (int g = 0; g < m->ng; g++) {
        if (m->group[g].dim != dim) continue;
        for (int i = 0; i < n; i++)
            if (tag[i] == m->group[g].tag) {
                nb++;
                break;
            }
    }
    return nb;
}

static void write_elements(wr *w, const kt_mesh *m)
{
    size_t total = (size_t)m->ne + (size_t)m->nf;
    fprintf(w->f, "$Elements\n");
    put_z(w, (size_t)(count_blocks(m, 3) + count_blocks(m, 2)), ' ');
    put_z(w, total, ' ');
    put_z(w, total ? 1 : 0, ' ');
    put_z(w, total, '\n');
    write_blocks(w, m, 3, 1);
    write_blocks(w, m, 2, (size_t)m->ne + 1);
    end_section(w, "Elements");
}

int kt_msh_write_file(FILE *f, const kt_mesh *m, int binary, kt_err *e)
{
    if (check_writable(m, e)) return e->code;
    wr w = {f, 0};
    fprintf(f, "$MeshFormat\n4.1 %d 8\n", binary ? 1 : 0);
    if (binary) {
        int32_t one = 1;
        fwrite(&one, 4, 1, f);
        fputc('\n', f);
    }
    fprintf(f, "$EndMeshFormat\n");
    int named = 0, nsurf = 0, nvol = 0, vol_tag = 0;
    for (int g = 0; g < m->ng; g++) {
        named += m->group[g].name[0] != '\0';
        nsurf += m->group[g].dim == 2;
        if (m->group[g].dim == 3 && nvol++ == 0) vol_tag = m->group[g].tag;
    }
    if (named) {
        fprintf(f, "$PhysicalNames\n%d\n", named);
        for (int g = 0; g < m->ng; g++)
            if (m->group[g].name[0])
                fprintf(f, "%d %d \"%s\"\n", m->group[g].dim, m->group[g].tag, m->group[g].name);
        fprintf(f, "$EndPhysicalNames\n");
    }
    w.bin = binary;
    write_entities(&w, m, nsurf, nvol);
    write_nodes(&w, m, vol_tag);
    write_elements(&w, m);
    if (fflush(f) != 0 || ferror(f))
        return kt_fail(e, KT_ERUN, "write failed: %s", errno ? kt_io_cause(errno) : "output lost");
    return KT_OK;
}

int kt_msh_write(const char *path, const kt_mesh *m, int binary, kt_err *e)
{
    kt_out o;
    if (kt_out_open(&o, path, e)) return e->code;
    kt_err we = {0};
    if (kt_msh_write_file(o.f, m, binary, &we)) { /* a failed write is named by its file */
        if (o.is_stdout || kt_out_failed(&o, e) == KT_OK)
            kt_fail(e, we.code, "%s: %s", o.is_stdout ? "<stdout>" : path, we.msg);
        kt_out_abort(&o);
        return e->code;
    }
    return kt_out_commit(&o, e);
}
