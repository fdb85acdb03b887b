/* cgalmesh_none.c: the CGAL entry points of a build configured with KT_WITH_CGAL=OFF. */
#include "cgalmesh.h"

int kt_cgal_mesh_surface(const char *path, double facet_size, double facet_distance,
                         double cell_size, kt_mesh *m, kt_err *e)
{
    (void)facet_size, (void)facet_distance, (void)cell_size, (void)m;
    return kt_fail(e, KT_ERUN, "%s: this build has no CGAL (configure with -DKT_WITH_CGAL=ON)",
                   path);
}

int kt_cgal_mesh_image(const char *path, double facet_size, double facet_distance,
                       double cell_size, kt_mesh *m, kt_err *e)
{
    return kt_cgal_mesh_surface(path, facet_size, facet_distance, cell_size, m, e);
}
