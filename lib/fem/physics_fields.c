/* physics_fields.c: the per-tet inputs of the physics (material, lamellar frame, limbal weight,
 * constants, prestress) as VTK cell fields for augsolve's step files (keratome-vtk(5)). */
#include "physics.h"

#include <stdlib.h>
#include <string.h>

/* Append field `name` of ncomp values per tet, its values at *next in ph->cellv. */
static double *add(kt_physics *ph, const char *name, int ncomp, int is_int, size_t ne,
                   double **next)
{
    kt_vtk_field *f = &ph->cell[ph->ncell++];
    snprintf(f->name, sizeof f->name, "%s", name);
    f->ncomp = ncomp;
    f->on_cells = 1;
    f->is_int = is_int;
    f->v = *next;
    *next += (size_t)ncomp * ne;
    return f->v;
}

int kt_physics_cell_fields(kt_physics *ph, const kt_mesh *m, kt_err *e)
{
    static const char *const CST[5] = {"E_inplane", "E_inplane_2", "G_transverse", "nu",
                                       "E_circumferential"};
    static const char *const FRAME[4] = {"a1", "a2", "n", "c"};
    static const int VTK_ORDER[6] = {0, 1, 2, 5, 3, 4}; /* xx yy zz xy yz xz from Voigt */
    size_t ne = (size_t)m->ne, per = 1 + 5 + (ph->frame ? 13 : 0) + (ph->prestressed ? 6 : 0);
    free(ph->cellv);
    ph->ncell = 0;
    if (!(ph->cellv = kt_calloc(per * (ne ? ne : 1), sizeof(double), e))) return e->code;
    double *next = ph->cellv;
    double *lam = add(ph, "lamellar", 1, 1, ne, &next);
    for (size_t t = 0; t < ne; t++) lam[t] = ph->cst[KT_PHYSICS_NCST * t + 5];
    for (int k = 0; k < 5; k++) {
        double *v = add(ph, CST[k], 1, 0, ne, &next);
        for (size_t t = 0; t < ne; t++) v[t] = ph->cst[KT_PHYSICS_NCST * t + k];
    }
    if (ph->frame) {
        for (int k = 0; k < 4; k++) {
            double *v = add(ph, FRAME[k], 3, 0, ne, &next);
            for (size_t t = 0; t < ne; t++) memcpy(v + 3 * t, ph->frame + 13 * t + 3 * k, 3 * sizeof(double));
        }
        double *w = add(ph, "limbal_weight", 1, 0, ne, &next);
        for (size_t t = 0; t < ne; t++) w[t] = ph->frame[13 * t + 12];
    }
    if (ph->prestressed) {
        double *v = add(ph, "sigma0", 6, 0, ne, &next);
        kt_materials mats = {0, NULL, &ph->td, NULL};
        for (int t = 0; t < m->ne; t++) {
            double s[6];
            if (kt_fem_prestress_mean(m, &mats, t, s, e)) return e->code;
            for (int p = 0; p < 6; p++) v[6 * (size_t)t + p] = s[VTK_ORDER[p]];
        }
    }
    return KT_OK;
}
