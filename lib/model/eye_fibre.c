/* eye_fibre.c: the lamellar frame field of the parametric eye: surface normal, the two
 * in-plane fibre directions (nasal-temporal and superior-inferior centrally, turning towards
 * radial/circumferential across the limbal band) and the limbal weight. */
#include <math.h>
#include <string.h>

#include "eye.h"
#include "eye_geom.h"

static void normalize(double *v)
{
    double n = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    for (int k = 0; k < 3; k++) v[k] /= n;
}

static void cross3(const double *u, const double *v, double *w)
{
    w[0] = u[1] * v[2] - u[2] * v[1];
    w[1] = u[2] * v[0] - u[0] * v[2];
    w[2] = u[0] * v[1] - u[1] * v[0];
}

/* Unit projection of axis vector ax onto the plane normal to n. */
static double project(const double *ax, const double *n, double *t)
{
    double d = ax[0] * n[0] + ax[1] * n[1] + ax[2] * n[2];
    for (int k = 0; k < 3; k++) t[k] = ax[k] - d * n[k];
    double len = sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]);
    if (len > 1e-6) normalize(t);
    return len;
}

/* The frame at point p; cornea: normal from the anterior sphere's centre, else from the globe's. */
static void frame_at(const kt_eye_geom *g, const kt_eye *eye, const double *p, int cornea, double *F)
{
    double n[3] = {p[0], p[1], p[2] - (cornea ? g->z_ca : 0.0)}, a1[3], a2[3], c[3];
    normalize(n);
    static const double X[3] = {1, 0, 0}, Y[3] = {0, 1, 0};
    if (project(X, n, a1) < 1e-6) {
        project(Y, n, a2);
        cross3(a2, n, a1);
    }
    cross3(n, a1, a2);
    double rho = hypot(p[0], p[1]);
    double w = 1.0;
    /* On an oval cornea: the edge in this meridian, and radial / circumferential are the normal /
     * tangent of the ellipse of the white-to-white's axes through p (kt_eye_fibre_frames). */
    double edge = g->rc, nx = p[0], ny = p[1];
    if (g->oval && rho > 1e-9) {
        edge = kt_eye_geom_edge_rho(g, p[0] / rho, p[1] / rho);
        nx = p[0] * g->rv * g->rv, ny = p[1] * g->rc * g->rc;
    }
    if (cornea) {
        double s = (rho - (edge - eye->fibre_band)) / eye->fibre_band;
        s = s < 0 ? 0 : s > 1 ? 1 : s;
        w = s * s * (3 - 2 * s);
    }
    if (rho > 1e-9) {
        double nr = g->oval ? hypot(nx, ny) : rho;
        double cz[3] = {-ny / nr, nx / nr, 0};
        project(cz, n, c);
    } else {
        memcpy(c, a2, sizeof c);
    }
    /* turn the pair about n, a1 towards a2, by w times the angle in the tangent plane from a1
     * to the radial direction c x n, reduced to [-45, 45] deg: at w = 1 radial/circumferential */
    double r[3];
    cross3(c, n, r);
    double phi = atan2(r[0] * a2[0] + r[1] * a2[1] + r[2] * a2[2], r[0] * a1[0] + r[1] * a1[1] + r[2] * a1[2]);
    double q = 0.5 * M_PI;
    double delta = phi - q * round(phi / q), th = w * delta;
    double b1[3], b2[3];
    for (int k = 0; k < 3; k++) b1[k] = cos(th) * a1[k] + sin(th) * a2[k];
    cross3(n, b1, b2);
    memcpy(F, b1, 3 * sizeof(double));
    memcpy(F + 3, b2, 3 * sizeof(double));
    memcpy(F + 6, n, 3 * sizeof(double));
    memcpy(F + 9, c, 3 * sizeof(double));
    F[12] = w;
}

int kt_eye_fibre_frames(const kt_eye *eye, const kt_mesh *m, double *F, kt_err *e)
{
    kt_eye_geom g;
    if (kt_eye_geom_init(eye, &g, e)) return e->code;
    const kt_group *cornea = kt_mesh_find_group(m, 3, "cornea");
    int nv = kt_tet_nv(m->order);
    for (int t = 0; t < m->ne; t++) {
        double p[3] = {0, 0, 0};
        for (int a = 0; a < 4; a++)
            for (int k = 0; k < 3; k++) p[k] += 0.25 * m->xyz[3 * (size_t)m->tet[(size_t)t * nv + a] + k];
        frame_at(&g, eye, p, cornea && m->tet_tag[t] == cornea->tag, F + 13 * (size_t)t);
    }
    return KT_OK;
}

int kt_eye_depth_fractions(const kt_eye *eye, const kt_mesh *m, double *S, kt_err *e)
{
    kt_eye_geom g;
    if (kt_eye_geom_init(eye, &g, e)) return e->code;
    int nv = kt_tet_nv(m->order);
    for (int t = 0; t < m->ne; t++) {
        double p[3] = {0, 0, 0};
        for (int a = 0; a < 4; a++)
            for (int k = 0; k < 3; k++) p[k] += 0.25 * m->xyz[3 * (size_t)m->tet[(size_t)t * nv + a] + k];
        double rho = hypot(p[0], p[1]), z0 = p[2];
        /* the warp moved a point of the mesh of revolution by w(rho, z0) delta in z: undo it
         * (w changes by about delta / thickness over the move: a contraction) */
        double delta = rho < g.rL ? kt_eye_geom_toric_z(&g, p[0], p[1]) - kt_eye_geom_sphere_z(&g, rho) : 0;
        if (isfinite(delta) && delta != 0)
            for (int it = 0; it < 50; it++) {
                double w = kt_eye_geom_weight(&g, rho, z0), z1 = p[2] - (w > 0 ? w * delta : 0);
                if (fabs(z1 - z0) < 1e-13) break;
                z0 = z1;
            }
        double h = kt_eye_geom_height(&g, rho, z0);
        S[t] = isnan(h) ? NAN : 1 - h;
    }
    return KT_OK;
}
