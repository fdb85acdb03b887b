/* vtkio.c: bench_vtkio STEP.vtk [OUTDIR]: the cost of a step file in each encoding. Reads the
 * step, writes it back as ASCII and as BINARY legacy VTK (kt_vtk_write_tets, with every point
 * and cell field of the input), reads each back, and prints per encoding the bytes, the CPU
 * seconds to write and to read, and whether every value came back bit for bit. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>

#include "vtk.h"

static double cpu(void)
{
    struct timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return t.tv_sec + 1e-9 * t.tv_nsec;
}

/* The tets of v as a mesh (VTK tet10 order back to gmsh's: swap the last two nodes). */
static int as_mesh(const kt_vtk *v, kt_mesh *m, kt_err *e)
{
    memset(m, 0, sizeof *m);
    int nv = v->ncell ? v->cell_ptr[1] - v->cell_ptr[0] : 4;
    if (nv != 4 && nv != 10) return kt_fail(e, KT_EINPUT, "expected tets, found cells of %d nodes", nv);
    const kt_vtk_field *reg = kt_vtk_find(v, "region", 1);
    m->order = nv == 10 ? 2 : 1, m->nn = v->nn, m->ne = v->ncell, m->xyz = v->xyz;
    m->tet = calloc((size_t)nv * m->ne, sizeof(int));
    m->tet_tag = calloc((size_t)m->ne, sizeof(int));
    if (!m->tet || !m->tet_tag) return kt_fail(e, KT_ERUN, "out of memory");
    for (int i = 0; i < m->ne; i++) {
        for (int j = 0; j < nv; j++) m->tet[(size_t)nv * i + j] = v->conn[v->cell_ptr[i] + (nv == 10 && j >= 8 ? 17 - j : j)];
        m->tet_tag[i] = reg ? (int)reg->v[i] : 1;
    }
    return KT_OK;
}

static int same(const kt_vtk *a, const kt_vtk *b)
{
    if (a->nn != b->nn || a->ncell != b->ncell || a->nfield != b->nfield) return 0;
    if (memcmp(a->xyz, b->xyz, 3 * sizeof(double) * (size_t)a->nn)) return 0;
    for (int k = 0; k < a->nfield; k++) {
        const kt_vtk_field *f = &a->field[k], *g = kt_vtk_find(b, f->name, f->on_cells);
        size_t n = (size_t)f->ncomp * (f->on_cells ? a->ncell : a->nn);
        if (!g || g->ncomp != f->ncomp) return 0;
        for (size_t i = 0; i < n; i++) /* NaN == NaN here: bits */
            if (memcmp(&f->v[i], &g->v[i], 8) && !(f->v[i] != f->v[i] && g->v[i] != g->v[i])) return 0;
    }
    return 1;
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: bench_vtkio STEP.vtk [OUTDIR]\n");
        return 2;
    }
    const char *dir = argc > 2 ? argv[2] : "/tmp";
    kt_err e = {0};
    kt_vtk v;
    memset(&v, 0, sizeof v);
    double t0 = cpu();
    if (kt_vtk_read(argv[1], &v, &e)) {
        fprintf(stderr, "bench_vtkio: %s\n", e.msg);
        return 1;
    }
    printf("read %s: %d points, %d cells, %d fields, %.3f s CPU\n", argv[1], v.nn, v.ncell, v.nfield, cpu() - t0);
    kt_mesh m;
    if (as_mesh(&v, &m, &e)) {
        fprintf(stderr, "bench_vtkio: %s\n", e.msg);
        return 1;
    }
    kt_vtk_field *f = calloc((size_t)v.nfield + 1, sizeof *f);
    int nf = 0;
    for (int k = 0; k < v.nfield; k++)
        if (!(v.field[k].on_cells && strcmp(v.field[k].name, "region") == 0)) f[nf++] = v.field[k];
    printf("%-8s %12s %10s %10s %s\n", "encoding", "bytes", "write s", "read s", "bit for bit");
    for (int bin = 0; bin < 2; bin++) {
        char path[4096];
        snprintf(path, sizeof path, "%s/bench_vtkio.%s.vtk", dir, bin ? "binary" : "ascii");
        double a = cpu();
        if (kt_vtk_write_tets(path, &m, f, nf, bin, &e)) {
            fprintf(stderr, "bench_vtkio: %s\n", e.msg);
            return 1;
        }
        double b = cpu();
        kt_vtk w;
        memset(&w, 0, sizeof w);
        if (kt_vtk_read(path, &w, &e)) {
            fprintf(stderr, "bench_vtkio: %s\n", e.msg);
            return 1;
        }
        double c = cpu();
        struct stat st;
        stat(path, &st);
        printf("%-8s %12lld %10.3f %10.3f %s\n", bin ? "binary" : "ascii", (long long)st.st_size, b - a, c - b,
               same(&v, &w) ? "yes" : "NO");
        kt_vtk_free(&w);
        remove(path);
    }
    free(f);
    free(m.tet);
    free(m.tet_tag);
    kt_vtk_free(&v);
    return 0;
}
