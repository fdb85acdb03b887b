/* test_eye.c: the parametric eye meshed with gmsh: groups, conforming incision rings (P1 and
 * P2), the exact toric anterior surface and its meridian curvatures, corneal thickness, valid
 * (also curved P2) elements, two elements through the cornea, meshes/eye.geo consistency and
 * rejection of inconsistent rings, and the refinement of a ring's floor
 * (eye.mesh_size.incision_floor). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gmshc.h>

#include "eye.h"
#include "kt_test.h"

#include "kt_test_gmsh.h"

#define DEG (KT_PI / 180.0)

/* A coarse eye with literature dimensions and 1.5 D of cylinder, steep meridian at 30 deg
 * (an oblique axis catches TABO orientation mistakes), one corneal and one limbal ring. */
static void coarse_eye(kt_eye *e)
{
    memset(e, 0, sizeof *e);
    double K = 337.5 / 7.8; /* keratometric index 1.3375 */
    e->r_ant_steep = 337.5 / (K + 0.75);
    e->r_ant_flat = 337.5 / (K - 0.75);
    e->steep_axis = 30;
    e->r_post = 6.7;
    e->t_central = 0.54;
    e->t_peripheral = 0.67;
    e->wtw = 11.7;
    e->limbus_width = 1.25;
    e->sclera_thickness = 0.5;
    e->globe_radius = 12;
    e->extent = 50;
    e->optical_zone = 6;
    e->h_optical = 0.3;
    e->h_incision = 0.25;
    e->h_cornea = 0.4; /* capped at t_central / 2.5 by the mesher */
    e->h_sclera = 1.5;
    e->nring = 2;
    strcpy(e->ring[0].name, "incision-ring-1");
    e->ring[0].diameter = 10.5;
    e->ring[0].depth_fraction = 0.9;
    strcpy(e->ring[1].name, "limbal-ring");
    e->ring[1].diameter = 12.6;
    e->ring[1].depth = 0.3;
}

static const int TET_FACE[4][3] = {{1, 2, 3}, {0, 2, 3}, {0, 1, 3}, {0, 1, 2}};
static const int TET_EDGE[6][2] = {{0, 1}, {1, 2}, {2, 0}, {3, 0}, {3, 2}, {3, 1}};
static const int TRI_EDGE[3][2] = {{0, 1}, {1, 2}, {2, 0}};

static void sort3(int *v)
{
    for (int i = 0; i < 2; i++)
        for (int j = 0; j < 2 - i; j++)
            if (v[j] > v[j + 1]) {
                int t = v[j];
                v[j] = v[j + 1];
                v[j + 1] = t;
            }
}

static long long face_key(int a, int b, int c)
{
    int v[3] = {a, b, c};
    sort3(v);
    return ((long long)v[0] << 42) | ((long long)v[1] << 21) | v[2];
}

typedef struct face_rec {
    long long key;
    int tet;
} face_rec;

static int cmp_face(const void *a, const void *b)
{
    long long x = ((const face_rec *)a)->key, y = ((const face_rec *)b)->key;
    return (x > y) - (x < y);
}

/* The tet's edge nodes on a triangle's edges are the triangle's mid-edge nodes. */
static int p2_edges_match(const int *q, const int *f)
{
    int bad = 0;
    for (int s = 0; s < 3; s++) {
        int a = f[TRI_EDGE[s][0]], b = f[TRI_EDGE[s][1]], found = 0;
        for (int j = 0; j < 6; j++) {
            int x = q[TET_EDGE[j][0]], y = q[TET_EDGE[j][1]];
            if ((x == a && y == b) || (x == b && y == a)) found = q[4 + j] == f[3 + s];
        }
        bad += !found;
    }
    return bad;
}

/* Every ring triangle is a face of exactly two tets; at order 2 the tets' edge nodes on that
 * face are the triangle's mid-edge nodes. Returns the number of violations. */
static int ring_conformity(const kt_mesh *m, int *nring_tri)
{
    int tv = kt_tet_nv(m->order), fv = kt_tri_nv(m->order), bad = 0;
    size_t nrec = 4 * (size_t)m->ne;
    face_rec *rec = malloc(sizeof *rec * nrec);
    for (int t = 0; t < m->ne; t++)
        for (int f = 0; f < 4; f++) {
            const int *q = m->tet + (size_t)t * tv;
            rec[4 * t + f].key = face_key(q[TET_FACE[f][0]], q[TET_FACE[f][1]], q[TET_FACE[f][2]]);
            rec[4 * t + f].tet = t;
        }
    qsort(rec, nrec, sizeof *rec, cmp_face);
    *nring_tri = 0;
    for (int i = 0; i < m->nf; i++) {
        if (m->tri_tag[i] < 11) continue;
        const int *f = m->tri + (size_t)i * fv;
        face_rec k = {face_key(f[0], f[1], f[2]), 0};
        face_rec *p = bsearch(&k, rec, nrec, sizeof k, cmp_face);
        int count = 0;
        (*nring_tri)++;
        if (p) {
            while (p > rec && p[-1].key == k.key) p--;
            for (; p < rec + nrec && p->key == k.key; p++, count++)
                if (m->order == 2) bad += p2_edges_match(m->tet + (size_t)p->tet * tv, f);
        }
        bad += count != 2;
    }
    free(rec);
    return bad;
}

/* Gaussian elimination with partial pivoting; the solution overwrites b. */
static int solve(double *A, double *b, int n)
{
    for (int c = 0; c < n; c++) {
        int p = c;
        for (int r = c + 1; r < n; r++)
            if (fabs(A[r * n + c]) > fabs(A[p * n + c])) p = r;
        if (fabs(A[p * n + c]) < 1e-300) return -1;
        for (int k = 0; k < n; k++) {
            double t = A[c * n + k];
            A[c * n + k] = A[p * n + k];
            A[p * n + k] = t;
        }
        double t = b[c];
        b[c] = b[p];
        b[p] = t;
        for (int r = c + 1; r < n; r++) {
            double f = A[r * n + c] / A[c * n + c];
            for (int k = c; k < n; k++) A[r * n + k] -= f * A[c * n + k];
            b[r] -= f * b[c];
        }
    }
    for (int c = n - 1; c >= 0; c--) {
        for (int k = c + 1; k < n; k++) b[c] -= A[c * n + k] * b[k];
        b[c] /= A[c * n + c];
    }
    return 0;
}

/* Least-squares fit of z over the anterior nodes within rmax of the axis by a full quartic in
 * (x, y); returns the apex Hessian entries (zxx, zxy, zyy). */
static int fit_apex_hessian(const kt_mesh *m, const int *nodes, int count, double rmax,
                            double H[3], int *used)
{
    enum { NT = 15 };
    double A[NT * NT] = {0}, rhs[NT] = {0};
    *used = 0;
    for (int i = 0; i < count; i++) {
        const double *p = m->xyz + 3 * (size_t)nodes[i];
        if (hypot(p[0], p[1]) > rmax) continue;
        double phi[NT];
        int k = 0;
        for (int d = 0; d <= 4; d++)
            for (int j = 0; j <= d; j++) phi[k++] = pow(p[0], d - j) * pow(p[1], j);
        for (int r = 0; r < NT; r++) {
            rhs[r] += phi[r] * p[2];
            for (int c = 0; c < NT; c++) A[r * NT + c] += phi[r] * phi[c];
        }
        (*used)++;
    }
    if (solve(A, rhs, NT)) return -1;
    /* terms: 1 | x y | x^2 xy y^2 | ... */
    H[0] = 2 * rhs[3];
    H[1] = rhs[4];
    H[2] = 2 * rhs[5];
    return 0;
}

/* Moller-Trumbore: distance t along o + t d to triangle abc, or -1. */
static double ray_tri(const double *o, const double *d, const double *a, const double *b,
                      const double *c)
{
    double e1[3], e2[3], p[3], s[3], q[3];
    for (int i = 0; i < 3; i++) e1[i] = b[i] - a[i], e2[i] = c[i] - a[i], s[i] = o[i] - a[i];
    p[0] = d[1] * e2[2] - d[2] * e2[1];
    p[1] = d[2] * e2[0] - d[0] * e2[2];
    p[2] = d[0] * e2[1] - d[1] * e2[0];
    double det = e1[0] * p[0] + e1[1] * p[1] + e1[2] * p[2];
    if (fabs(det) < 1e-14) return -1;
    double u = (s[0] * p[0] + s[1] * p[1] + s[2] * p[2]) / det;
    if (u < -1e-12 || u > 1 + 1e-12) return -1;
    q[0] = s[1] * e1[2] - s[2] * e1[1];
    q[1] = s[2] * e1[0] - s[0] * e1[2];
    q[2] = s[0] * e1[1] - s[1] * e1[0];
    double v = (d[0] * q[0] + d[1] * q[1] + d[2] * q[2]) / det;
    if (v < -1e-12 || u + v > 1 + 1e-12) return -1;
    return (e2[0] * q[0] + e2[1] * q[1] + e2[2] * q[2]) / det;
}

/* Nearest hit of the line o + t d (t of either sign) with the triangles of group `tag`. */
static double line_hit(const kt_mesh *m, int tag, const double *o, const double *d)
{
    int fv = kt_tri_nv(m->order);
    double best = NAN;
    for (int i = 0; i < m->nf; i++) {
        if (m->tri_tag[i] != tag) continue;
        const int *f = m->tri + (size_t)i * fv;
        double nd[3] = {-d[0], -d[1], -d[2]};
        double t = ray_tri(o, d, m->xyz + 3 * f[0], m->xyz + 3 * f[1], m->xyz + 3 * f[2]);
        if (t < 0) {
            t = ray_tri(o, nd, m->xyz + 3 * f[0], m->xyz + 3 * f[1], m->xyz + 3 * f[2]);
            if (t >= 0) t = -t;
            else continue;
        }
        if (isnan(best) || fabs(t) < fabs(best)) best = t;
    }
    return best;
}

/* Number of cornea tets that the segment o..o+len*d passes through (interval > 1e-6 mm). */
static int tets_crossed(const kt_mesh *m, const double *o, const double *d, double len)
{
    int tv = kt_tet_nv(m->order), n = 0;
    for (int t = 0; t < m->ne; t++) {
        if (m->tet_tag[t] != 1) continue;
        const int *q = m->tet + (size_t)t * tv;
        double lo = 0, hi = len;
        for (int f = 0; f < 4 && lo < hi; f++) {
            const double *a = m->xyz + 3 * q[TET_FACE[f][0]], *b = m->xyz + 3 * q[TET_FACE[f][1]],
                         *c = m->xyz + 3 * q[TET_FACE[f][2]], *v = m->xyz + 3 * q[f];
            double u[3], w[3], nrm[3];
            for (int i = 0; i < 3; i++) u[i] = b[i] - a[i], w[i] = c[i] - a[i];
            nrm[0] = u[1] * w[2] - u[2] * w[1];
            nrm[1] = u[2] * w[0] - u[0] * w[2];
            nrm[2] = u[0] * w[1] - u[1] * w[0];
            double side = 0, num = 0, den = 0;
            for (int i = 0; i < 3; i++) {
                side += nrm[i] * (v[i] - a[i]);
                num += nrm[i] * (o[i] - a[i]);
                den += nrm[i] * d[i];
            }
            if (side < 0) num = -num, den = -den; /* inside: num + t den >= 0 */
            if (fabs(den) < 1e-15) {
                if (num < 0) hi = -1;
            } else if (den > 0) {
                lo = fmax(lo, -num / den);
            } else {
                hi = fmin(hi, -num / den);
            }
        }
        n += hi - lo > 1e-6;
    }
    return n;
}

/* Jacobian determinant of a P2 tet's quadratic map at barycentric point L. */
static double p2_detj(const kt_mesh *m, const int *q, const double L[4])
{
    static const double dL[3][4] = {{-1, 1, 0, 0}, {-1, 0, 1, 0}, {-1, 0, 0, 1}};
    double J[3][3] = {{0}};
    for (int r = 0; r < 3; r++) {
        for (int a = 0; a < 4; a++) {
            double dn = (4 * L[a] - 1) * dL[r][a];
            for (int c = 0; c < 3; c++) J[r][c] += dn * m->xyz[3 * q[a] + c];
        }
        for (int j = 0; j < 6; j++) {
            int a = TET_EDGE[j][0], b = TET_EDGE[j][1];
            double dn = 4 * (L[a] * dL[r][b] + L[b] * dL[r][a]);
            for (int c = 0; c < 3; c++) J[r][c] += dn * m->xyz[3 * q[4 + j] + c];
        }
    }
    return J[0][0] * (J[1][1] * J[2][2] - J[1][2] * J[2][1]) -
           J[0][1] * (J[1][0] * J[2][2] - J[1][2] * J[2][0]) +
           J[0][2] * (J[1][0] * J[2][1] - J[1][1] * J[2][0]);
}

static int count_tag(const int *tags, int n, int tag)
{
    int c = 0;
    for (int i = 0; i < n; i++) c += tags[i] == tag;
    return c;
}

static void check_groups(const kt_mesh *m, const kt_eye *eye, int with_fixed)
{
    static const char *reg[3] = {"cornea", "limbus", "sclera"};
    static const char *srf[4] = {"anterior", "inner", "fixed", "outer"};
    for (int i = 0; i < 3; i++) {
        const kt_group *g = kt_mesh_find_group(m, 3, reg[i]);
        CHECK(g && g->tag == i + 1, "region %s with tag %d", reg[i], i + 1);
        CHECK(g && count_tag(m->tet_tag, m->ne, g->tag) > 0, "region %s has tets", reg[i]);
    }
    for (int i = 0; i < 4; i++) {
        const kt_group *g = kt_mesh_find_group(m, 2, srf[i]);
        if (i == 2 && !with_fixed) {
            CHECK(g == NULL, "whole globe: no 'fixed' group");
            continue;
        }
        CHECK(g && g->tag == i + 1, "surface %s with tag %d", srf[i], i + 1);
        CHECK(g && count_tag(m->tri_tag, m->nf, g->tag) > 0, "surface %s has triangles", srf[i]);
    }
    for (int k = 0; k < eye->nring; k++) {
        const kt_group *g = kt_mesh_find_group(m, 2, eye->ring[k].name);
        CHECK(g && g->tag == 11 + k, "ring %s with tag %d", eye->ring[k].name, 11 + k);
        CHECK(g && count_tag(m->tri_tag, m->nf, g->tag) > 0, "ring %s has triangles",
              eye->ring[k].name);
    }
}

/* Anterior nodes (vertices and, at P2, mid-edge nodes) on the toric surface. */
static double anterior_error(const kt_mesh *m, const kt_eye *eye, int *count)
{
    const kt_group *g = kt_mesh_find_group(m, 2, "anterior");
    int *nodes = NULL, n = 0;
    kt_err e = {0};
    double worst = INFINITY;
    if (g && kt_mesh_group_nodes(m, g, &nodes, &n, &e) == KT_OK) {
        worst = 0;
        for (int i = 0; i < n; i++) {
            const double *p = m->xyz + 3 * (size_t)nodes[i];
            worst = fmax(worst, fabs(p[2] - kt_eye_anterior_z(eye, p[0], p[1])));
        }
    }
    free(nodes);
    *count = n;
    return worst;
}

/* The biconic written out independently: meridian curvature check and apex height. */
static void check_curvature(const kt_mesh *m, const kt_eye *eye)
{
    const kt_group *g = kt_mesh_find_group(m, 2, "anterior");
    int *nodes = NULL, n = 0, used = 0;
    kt_err e = {0};
    double H[3] = {0, 0, 0};
    if (!g || kt_mesh_group_nodes(m, g, &nodes, &n, &e)) {
        CHECK(0, "anterior nodes");
        return;
    }
    int rc = fit_apex_hessian(m, nodes, n, 1.5, H, &used);
    free(nodes);
    CHECK(rc == 0 && used >= 30, "quartic fit over %d anterior nodes within 1.5 mm", used);
    double ts = eye->steep_axis * DEG, tf = ts + KT_PI / 2;
    double ks = H[0] * cos(ts) * cos(ts) + 2 * H[1] * cos(ts) * sin(ts) + H[2] * sin(ts) * sin(ts);
    double kf = H[0] * cos(tf) * cos(tf) + 2 * H[1] * cos(tf) * sin(tf) + H[2] * sin(tf) * sin(tf);
    printf("P1 eye: fitted radii %.4f (steep, expect %.4f) %.4f (flat, expect %.4f) mm\n",
           -1 / ks, eye->r_ant_steep, -1 / kf, eye->r_ant_flat);
    CHECK(fabs(-1 / ks - eye->r_ant_steep) < 0.01 * eye->r_ant_steep,
          "steep meridian radius %.4f vs %.4f mm", -1 / ks, eye->r_ant_steep);
    CHECK(fabs(-1 / kf - eye->r_ant_flat) < 0.01 * eye->r_ant_flat,
          "flat meridian radius %.4f vs %.4f mm", -1 / kf, eye->r_ant_flat);
    /* principal direction of the steepest (most negative) curvature, TABO degrees */
    double ang = 0.5 * atan2(2 * H[1], H[0] - H[2]) / DEG; /* extremal direction */
    double k1 = H[0] * pow(cos(ang * DEG), 2) + 2 * H[1] * cos(ang * DEG) * sin(ang * DEG) +
                H[2] * pow(sin(ang * DEG), 2);
    if (k1 > 0.5 * (H[0] + H[2])) ang += 90;
    ang = fmod(ang + 360, 180);
    CHECK(fabs(ang - eye->steep_axis) < 1.0, "steep meridian found at %.2f deg, expected %.2f",
          ang, eye->steep_axis);
}

/* Thickness along a normal line of the base sphere at radial distance r, meridian theta:
 * distance between the anterior and inner surfaces of the mesh. */
static double mesh_thickness(const kt_mesh *m, const kt_eye *eye, double r, double theta)
{
    double Ra = 2.0 / (1 / eye->r_ant_steep + 1 / eye->r_ant_flat);
    double phi = asin(r / Ra), c = cos(theta * DEG), s = sin(theta * DEG);
    double z = kt_eye_anterior_z(eye, r * c, r * s);
    double o[3] = {r * c, r * s, z}, d[3] = {-sin(phi) * c, -sin(phi) * s, -cos(phi)};
    double ta = line_hit(m, 1, o, d), ti = line_hit(m, 2, o, d);
    return ti - ta;
}

/* Ring geometry: top edge shared with the outer surface at radial distance diameter/2, and
 * the bottom edge where depth along the base normal puts it (the warp keeps x and y). */
static void check_ring_shape(const kt_mesh *m, const kt_eye *eye)
{
    double Ra = 2.0 / (1 / eye->r_ant_steep + 1 / eye->r_ant_flat);
    char *outer = calloc((size_t)m->nn, 1);
    int fv = kt_tri_nv(m->order);
    for (int i = 0; i < m->nf; i++)
        if (m->tri_tag[i] == 1 || m->tri_tag[i] == 4)
            for (int j = 0; j < fv; j++) outer[m->tri[(size_t)i * fv + j]] = 1;
    for (int k = 0; k < eye->nring; k++) {
        double r = 0.5 * eye->ring[k].diameter, t = kt_eye_thickness(eye, r);
        double depth = eye->ring[k].depth_fraction > 0 ? eye->ring[k].depth_fraction * t
                                                       : eye->ring[k].depth;
        double sinphi = r < 0.5 * eye->wtw ? r / Ra : r / eye->globe_radius;
        double rmin = INFINITY, top_err = 0;
        int ntop = 0;
        for (int i = 0; i < m->nf; i++) {
            if (m->tri_tag[i] != 11 + k) continue;
            for (int j = 0; j < fv; j++) {
                const double *p = m->xyz + 3 * (size_t)m->tri[(size_t)i * fv + j];
                double rho = hypot(p[0], p[1]);
                rmin = fmin(rmin, rho);
                if (outer[m->tri[(size_t)i * fv + j]]) {
                    ntop++;
                    top_err = fmax(top_err, fabs(rho - r));
                    top_err = fmax(top_err, fabs(p[2] - kt_eye_anterior_z(eye, p[0], p[1])));
                }
            }
        }
        CHECK(ntop >= 20 && top_err < 1e-7, "ring %s: %d top nodes on the surface at r %.3f "
              "(%.3g mm off)", eye->ring[k].name, ntop, r, top_err);
        CHECK(fabs(rmin - (r - depth * sinphi)) < 1e-7, "ring %s bottom at r %.6f, expected "
              "%.6f (depth %.4f mm)", eye->ring[k].name, rmin, r - depth * sinphi, depth);
    }
    free(outer);
}

/* meshes/eye.geo, opened by gmsh with this eye's dimensions, must describe the same solid:
 * every physical group's exact (OpenCASCADE) measure against the P1 mesh's. */
static const char *GEO_GROUPS[8] = {"anterior", "inner", "fixed", "outer", "incision-ring-1",
                                    "cornea", "limbus", "sclera"};

static int geo_measures(const kt_eye *eye, double out[8])
{
    char v[7][32];
    const char *names[7] = {"r_steep", "r_flat", "lw", "sclera", "extent", "ring_d", "ring_f"};
    double vals[7] = {eye->r_ant_steep, eye->r_ant_flat, eye->limbus_width,
                      eye->sclera_thickness, eye->extent, eye->ring[0].diameter,
                      eye->ring[0].depth_fraction};
    char *argv[1 + 3 * 7];
    int argc = 0, ierr = 0;
    argv[argc++] = "gmsh";
    for (int i = 0; i < 7; i++) {
        snprintf(v[i], sizeof v[i], "%.17g", vals[i]);
        argv[argc++] = "-setnumber";
        argv[argc++] = (char *)names[i];
        argv[argc++] = v[i];
    }
    gmshInitialize(argc, argv, 0, &ierr);
    gmshOptionSetNumber("General.Terminal", 0, &ierr);
    gmshOpen("meshes/eye.geo", &ierr);
    int rc = ierr;
    int *pg = NULL;
    size_t npg = 0;
    gmshModelGetPhysicalGroups(&pg, &npg, -1, &ierr);
    for (int g = 0; g < 8; g++) out[g] = NAN;
    for (size_t i = 0; i + 1 < npg && rc == 0; i += 2) {
        char *name = NULL;
        gmshModelGetPhysicalName(pg[i], pg[i + 1], &name, &ierr);
        int *ent = NULL;
        size_t nent = 0;
        gmshModelGetEntitiesForPhysicalGroup(pg[i], pg[i + 1], &ent, &nent, &ierr);
        double sum = 0, mass = 0;
        for (size_t k = 0; k < nent; k++) {
            gmshModelOccGetMass(pg[i], ent[k], &mass, &ierr);
            sum += mass;
        }
        for (int g = 0; g < 8; g++)
            if (name && strcmp(name, GEO_GROUPS[g]) == 0) out[g] = sum;
        gmshFree(name);
        gmshFree(ent);
    }
    gmshFree(pg);
    gmshFinalize(&ierr);
    return rc;
}

static double mesh_measure(const kt_mesh *m, const kt_group *g)
{
    double sum = 0;
    if (g->dim == 3) {
        for (int t = 0; t < m->ne; t++) {
            const int *q = m->tet + 4 * (size_t)t;
            if (m->tet_tag[t] == g->tag)
                sum += kt_tet_volume(m->xyz + 3 * q[0], m->xyz + 3 * q[1], m->xyz + 3 * q[2],
                                     m->xyz + 3 * q[3]);
        }
        return sum;
    }
    for (int i = 0; i < m->nf; i++) {
        if (m->tri_tag[i] != g->tag) continue;
        const int *f = m->tri + 3 * (size_t)i;
        const double *a = m->xyz + 3 * f[0], *b = m->xyz + 3 * f[1], *c = m->xyz + 3 * f[2];
        double u[3], w[3];
        for (int k = 0; k < 3; k++) u[k] = b[k] - a[k], w[k] = c[k] - a[k];
        sum += 0.5 * sqrt(pow(u[1] * w[2] - u[2] * w[1], 2) + pow(u[2] * w[0] - u[0] * w[2], 2) +
                          pow(u[0] * w[1] - u[1] * w[0], 2));
    }
    return sum;
}

static void check_geo_script(const kt_mesh *m, const kt_eye *eye)
{
    double geo[8];
    CHECK(geo_measures(eye, geo) == 0, "gmsh opens meshes/eye.geo");
    for (int g = 0; g < 8; g++) {
        const kt_group *grp = kt_mesh_find_group(m, g < 5 ? 2 : 3, GEO_GROUPS[g]);
        double mm = grp ? mesh_measure(m, grp) : NAN;
        CHECK(fabs(mm - geo[g]) < 0.005 * geo[g], "eye.geo group %s: %.4f (gmsh, exact) vs "
              "%.4f (kt_eye_mesh, P1)", GEO_GROUPS[g], geo[g], mm);
    }
}

/* At least two elements through the corneal thickness: no cornea tet has a vertex on the
 * anterior surface and another on the inner one. */
static int tets_spanning_cornea(const kt_mesh *m)
{
    char *on = calloc((size_t)m->nn, 1);
    int fv = kt_tri_nv(m->order), tv = kt_tet_nv(m->order), n = 0;
    for (int i = 0; i < m->nf; i++)
        if (m->tri_tag[i] == 1 || m->tri_tag[i] == 2)
            for (int j = 0; j < fv; j++) on[m->tri[(size_t)i * fv + j]] |= m->tri_tag[i];
    for (int t = 0; t < m->ne; t++) {
        int mask = 0;
        for (int j = 0; j < 4 && m->tet_tag[t] == 1; j++) mask |= on[m->tet[(size_t)t * tv + j]];
        n += mask == 3;
    }
    free(on);
    return n;
}

static void check_p1(const kt_eye *eye)
{
    kt_mesh m;
    kt_err e = {0};
    double t0 = kt_now();
    int rc = kt_eye_mesh(eye, 1, 1, &m, &e);
    CHECK(rc == KT_OK, "P1 eye meshed: %s", e.msg);
    if (rc) return;
    printf("P1 eye: %d nodes, %d tets, %.1f s\n", m.nn, m.ne, kt_now() - t0);
    CHECK(m.order == 1 && m.ne > 1000, "P1 tets: %d", m.ne);
    kt_err e2 = {0};
    CHECK(kt_mesh_check(&m, "eye", &e2) == KT_OK, "all tets positive: %s", e2.msg);
    check_groups(&m, eye, 1);
    int nrt = 0, bad = ring_conformity(&m, &nrt);
    CHECK(nrt > 0 && bad == 0, "P1: %d of %d ring triangles not shared by exactly two tets",
          bad, nrt);
    int na = 0;
    double err = anterior_error(&m, eye, &na);
    CHECK(na > 100 && err <= 1e-9, "P1 anterior nodes on the toric surface: %d nodes, %.3g mm",
          na, err);
    check_curvature(&m, eye);
    check_ring_shape(&m, eye);
    check_geo_script(&m, eye);
    double tc = mesh_thickness(&m, eye, 0, 0);
    CHECK(fabs(tc - eye->t_central) < 0.02 * eye->t_central, "apex thickness %.4f vs %.4f mm",
          tc, eye->t_central);
    /* Meridian 45 deg off the principal ones: the toric and base surfaces nearly agree. */
    double t3 = mesh_thickness(&m, eye, 3.0, eye->steep_axis + 45), tk = kt_eye_thickness(eye, 3.0);
    CHECK(fabs(t3 - tk) < 0.02 * tk, "thickness at r = 3 mm: mesh %.4f vs %.4f mm", t3, tk);
    double te = kt_eye_thickness(eye, 0.5 * eye->wtw);
    CHECK(fabs(te - eye->t_peripheral) < 1e-9, "thickness at the limbus %.6f vs %.6f mm", te,
          eye->t_peripheral);
    double o[3] = {0, 0, kt_eye_anterior_z(eye, 0, 0)}, d[3] = {0, 0, -1};
    int spanning = tets_spanning_cornea(&m);
    CHECK(spanning == 0, "%d cornea tets reach from the anterior to the inner surface", spanning);
    int layers = tets_crossed(&m, o, d, tc);
    CHECK(layers >= 2, "%d tets through the apex thickness", layers);
    printf("P1 eye: apex thickness %.4f mm, %d tets crossed; thickness at r = 3: %.4f mm "
           "(kt_eye_thickness %.4f)\n", tc, layers, t3, tk);
    kt_mesh_free(&m);
}

static void check_p2(const kt_eye *eye)
{
    kt_mesh m;
    kt_err e = {0};
    double t0 = kt_now();
    int rc = kt_eye_mesh(eye, 2, 1, &m, &e);
    CHECK(rc == KT_OK, "P2 eye meshed: %s", e.msg);
    if (rc) return;
    printf("P2 eye: %d nodes, %d tets, %.1f s\n", m.nn, m.ne, kt_now() - t0);
    CHECK(m.order == 2 && kt_tet_nv(m.order) == 10, "10-node tets");
    check_groups(&m, eye, 1);
    int nrt = 0, bad = ring_conformity(&m, &nrt);
    CHECK(nrt > 0 && bad == 0, "P2: %d violations over %d ring triangles", bad, nrt);
    int na = 0;
    double err = anterior_error(&m, eye, &na);
    CHECK(na > 100 && err <= 1e-9, "P2 anterior nodes (with mid-edge) on the toric surface: "
          "%d nodes, %.3g mm", na, err);
    /* Mid-edge nodes are curved: anterior ones off their chord, outer sclera ones on the globe. */
    double off_ant = 0, off_out = 0, on_globe = 0;
    for (int i = 0; i < m.nf; i++) {
        const int *f = m.tri + 6 * (size_t)i;
        for (int s = 0; s < 3; s++) {
            const double *a = m.xyz + 3 * f[TRI_EDGE[s][0]], *b = m.xyz + 3 * f[TRI_EDGE[s][1]],
                         *c = m.xyz + 3 * f[3 + s];
            double dev = 0;
            for (int k = 0; k < 3; k++) dev = fmax(dev, fabs(c[k] - 0.5 * (a[k] + b[k])));
            if (m.tri_tag[i] == 1) off_ant = fmax(off_ant, dev);
            if (m.tri_tag[i] == 4 && hypot(c[0], c[1]) > 0.5 * eye->wtw + eye->limbus_width) {
                off_out = fmax(off_out, dev);
                on_globe = fmax(on_globe, fabs(sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]) -
                                               eye->globe_radius));
            }
        }
    }
    CHECK(off_ant > 1e-4, "anterior mid-edge nodes curved (max %.3g mm off the chord)", off_ant);
    CHECK(off_out > 1e-3 && on_globe < 1e-8,
          "outer scleral mid-edge nodes on the globe (%.3g mm; %.3g mm off the chord)", on_globe,
          off_out);
    static const double pts[5][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1},
                                     {0.25, 0.25, 0.25, 0.25}};
    int neg = 0;
    for (int t = 0; t < m.ne; t++)
        for (int k = 0; k < 5; k++) neg += !(p2_detj(&m, m.tet + 10 * (size_t)t, pts[k]) > 0);
    CHECK(neg == 0, "P2 Jacobian positive at corners and centroid (%d bad)", neg);
    kt_mesh_free(&m);
}

static void check_whole_globe(void)
{
    kt_eye eye;
    coarse_eye(&eye);
    eye.extent = 180;
    eye.nring = 0;
    eye.h_sclera = 2.0;
    kt_mesh m;
    kt_err e = {0};
    int rc = kt_eye_mesh(&eye, 1, 1, &m, &e);
    CHECK(rc == KT_OK, "whole globe meshed: %s", e.msg);
    if (rc) return;
    check_groups(&m, &eye, 0);
    double zmin = INFINITY;
    for (int i = 0; i < m.nn; i++) zmin = fmin(zmin, m.xyz[3 * i + 2]);
    CHECK_NEAR(zmin, -eye.globe_radius, 1e-6, "posterior pole reached");
    kt_mesh_free(&m);
}

static void check_rejects(void)
{
    struct { double diameter, depth, fraction; const char *why; } bad[] = {
        {14.5, 0, 0.9, "outside the cornea and limbus"},
        {4.0, 0, 0.9, "inside the optical zone"},
        {10.5, 0.9, 0, "deeper than the local thickness"},
        {11.7, 0, 0.5, "on the corneal edge"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        kt_eye eye;
        coarse_eye(&eye);
        eye.nring = 1;
        strcpy(eye.ring[0].name, "bad-ring");
        eye.ring[0].diameter = bad[i].diameter;
        eye.ring[0].depth = bad[i].depth;
        eye.ring[0].depth_fraction = bad[i].fraction;
        kt_mesh m;
        kt_err e = {0};
        int rc = kt_eye_mesh(&eye, 1, 1, &m, &e);
        CHECK(rc == KT_EINPUT && strstr(e.msg, "bad-ring"), "ring %s rejected: rc %d '%s'",
              bad[i].why, rc, e.msg);
        CHECK(m.nn == 0 && m.xyz == NULL, "no mesh on rejection");
    }
    kt_eye eye;
    coarse_eye(&eye);
    eye.t_peripheral = 3.0;
    kt_mesh m;
    kt_err e = {0};
    CHECK(kt_eye_mesh(&eye, 1, 1, &m, &e) == KT_EINPUT, "impossible thickness profile: %s",
          e.msg);
}

/* Angle (deg, folded into [0, 90]) between the direction of (x, y) and the meridian c. */
static double meridian_angle(double x, double y, double c)
{
    double d = fmod(fabs(atan2(y, x) / DEG - c), 180.0);
    return d > 90 ? 180 - d : d;
}

static int cmp_ll(const void *a, const void *b)
{
    long long x = *(const long long *)a, y = *(const long long *)b;
    return (x > y) - (x < y);
}

/* Lengths along ring 1's floor (tag 11): its triangles' boundary edges that touch no anterior
 * node. in_sector: mean length of the floor edges within `inside` deg of the floor's meridians
 * (and count), out_sector: mean of those beyond `outside` deg. near: mean length of the tet
 * edges that touch a floor node within `inside` deg. */
typedef struct floor_sizes { double in_sector, out_sector, near; int n_in, n_out, n_near; } floor_sizes;

static floor_sizes floor_edge_sizes(const kt_mesh *m, double centre, double inside, double outside)
{
    int fv = kt_tri_nv(m->order), tv = kt_tet_nv(m->order), ne = 0;
    floor_sizes r = {0};
    long long *key = malloc(sizeof *key * 3 * (size_t)m->nf);
    char *anterior = calloc((size_t)m->nn, 1), *floor = calloc((size_t)m->nn, 1);
    for (int i = 0; i < m->nf; i++) {
        const int *f = m->tri + (size_t)i * fv;
        for (int s = 0; s < 3; s++) {
            if (m->tri_tag[i] == 1) anterior[f[s]] = 1;
            int a = f[TRI_EDGE[s][0]], b = f[TRI_EDGE[s][1]];
            if (m->tri_tag[i] == 11)
                key[ne++] = ((long long)(a < b ? a : b) << 32) | (a < b ? b : a);
        }
    }
    qsort(key, (size_t)ne, sizeof *key, cmp_ll);
    for (int i = 0; i < ne; i++) {
        if ((i > 0 && key[i - 1] == key[i]) || (i + 1 < ne && key[i + 1] == key[i])) continue;
        int a = (int)(key[i] >> 32), b = (int)(key[i] & 0xffffffff);
        if (anterior[a] || anterior[b]) continue;
        const double *p = m->xyz + 3 * (size_t)a, *q = m->xyz + 3 * (size_t)b;
        double len = sqrt((p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) +
                          (p[2] - q[2]) * (p[2] - q[2]));
        double ang = meridian_angle(0.5 * (p[0] + q[0]), 0.5 * (p[1] + q[1]), centre);
        if (ang <= inside) r.in_sector += len, r.n_in++, floor[a] = floor[b] = 1;
        if (ang >= outside) r.out_sector += len, r.n_out++;
    }
    for (int t = 0; t < m->ne; t++)
        for (int j = 0; j < 6; j++) {
            int a = m->tet[(size_t)t * tv + TET_EDGE[j][0]], b = m->tet[(size_t)t * tv + TET_EDGE[j][1]];
            if (!floor[a] && !floor[b]) continue;
            const double *p = m->xyz + 3 * (size_t)a, *q = m->xyz + 3 * (size_t)b;
            r.near += sqrt((p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) +
                           (p[2] - q[2]) * (p[2] - q[2]));
            r.n_near++;
        }
    r.in_sector /= r.n_in > 0 ? r.n_in : 1;
    r.out_sector /= r.n_out > 0 ? r.n_out : 1;
    r.near /= r.n_near > 0 ? r.n_near : 1;
    free(key);
    free(anterior);
    free(floor);
    return r;
}

/* eye.mesh_size.incision_floor: the floor of ring 1 is meshed at about h_floor inside the
 * sector (along the floor and in the tets around it), at the ring's size outside it, and the
 * node count grows like a graded refinement of a curve (not of the ring's whole surface). */
static void check_floor(void)
{
    kt_eye eye;
    coarse_eye(&eye);
    eye.nring = 1;
    kt_mesh plain, fine;
    kt_err e = {0};
    int rc = kt_eye_mesh(&eye, 1, 1, &plain, &e);
    CHECK(rc == KT_OK, "eye without floor refinement meshed: %s", e.msg);
    if (rc) return;
    eye.h_floor = 0.06;
    eye.floor_centre = eye.steep_axis;
    eye.floor_sector = 40;
    rc = kt_eye_mesh(&eye, 1, 1, &fine, &e);
    CHECK(rc == KT_OK, "eye with floor refinement meshed: %s", e.msg);
    if (rc) {
        kt_mesh_free(&plain);
        return;
    }
    floor_sizes a = floor_edge_sizes(&plain, eye.floor_centre, 35, 60);
    floor_sizes b = floor_edge_sizes(&fine, eye.floor_centre, 35, 60);
    printf("floor: %d -> %d nodes; floor edges in the sector %.3f -> %.3f mm (%d -> %d), "
           "outside %.3f -> %.3f mm; tet edges at the floor %.3f -> %.3f mm (requested %.3f)\n",
           plain.nn, fine.nn, a.in_sector, b.in_sector, a.n_in, b.n_in, a.out_sector,
           b.out_sector, a.near, b.near, eye.h_floor);
    CHECK(b.n_in > 0 && b.in_sector <= 1.5 * eye.h_floor, "floor edges in the sector %.3f mm",
          b.in_sector);
    /* The tets at the floor reach out into the graded zone (size + 0.5 per unit distance). */
    CHECK(b.near <= 2 * eye.h_floor, "tet edges at the floor %.3f mm", b.near);
    CHECK(a.in_sector > 2.5 * eye.h_floor, "without the field the floor is coarse: %.3f mm",
          a.in_sector);
    CHECK(b.out_sector > 2.5 * eye.h_floor, "outside the sector the floor is coarse: %.3f mm",
          b.out_sector);
    CHECK(fine.nn > plain.nn && fine.nn < 1.5 * plain.nn, "node count %d -> %d", plain.nn, fine.nn);
    /* eye.mesh_size.floor_grading: the same floor size, growing twice as fast away from it: the
     * floor itself as fine, the nodes the field adds fewer (a graded tube's nodes go like
     * 1 / grading^2; the ring's own size and the sector's ends bound it here). */
    kt_mesh steep;
    eye.floor_grading = 2 * KT_EYE_FLOOR_GRADING;
    rc = kt_eye_mesh(&eye, 1, 1, &steep, &e);
    CHECK(rc == KT_OK, "eye with a steeper floor grading meshed: %s", e.msg);
    if (rc == KT_OK) {
        floor_sizes c = floor_edge_sizes(&steep, eye.floor_centre, 35, 60);
        printf("floor grading %g -> %g: %d -> %d nodes (%d added -> %d), floor edges %.3f mm\n", KT_EYE_FLOOR_GRADING,
               eye.floor_grading, fine.nn, steep.nn, fine.nn - plain.nn, steep.nn - plain.nn, c.in_sector);
        CHECK(c.n_in > 0 && c.in_sector <= 1.5 * eye.h_floor, "steeper grading: floor edges %.3f mm", c.in_sector);
        CHECK(steep.nn > plain.nn && steep.nn - plain.nn < 0.75 * (fine.nn - plain.nn),
              "steeper grading: nodes added %d, against %d", steep.nn - plain.nn, fine.nn - plain.nn);
        kt_mesh_free(&steep);
    }
    kt_mesh_free(&plain);
    kt_mesh_free(&fine);
}

/* The geometry functions against closed forms: apex, meridian circles, thickness. */
static void check_geometry(const kt_eye *eye)
{
    double za = kt_eye_anterior_z(eye, 0, 0), ts = eye->steep_axis * DEG;
    for (int k = 1; k <= 5; k++) {
        double r = k, Rs = eye->r_ant_steep, Rf = eye->r_ant_flat;
        double zs = kt_eye_anterior_z(eye, r * cos(ts), r * sin(ts));
        double zf = kt_eye_anterior_z(eye, -r * sin(ts), r * cos(ts));
        CHECK_NEAR(za - zs, Rs - sqrt(Rs * Rs - r * r), 1e-12, "steep meridian is a circle");
        CHECK_NEAR(za - zf, Rf - sqrt(Rf * Rf - r * r), 1e-12, "flat meridian is a circle");
    }
    CHECK_NEAR(kt_eye_thickness(eye, 0), eye->t_central, 1e-12, "central thickness");
    double prev = 0;
    int mono = 1;
    for (int k = 0; k <= 20; k++) {
        double t = kt_eye_thickness(eye, 0.5 * eye->wtw * k / 20);
        mono &= t >= prev - 1e-12;
        prev = t;
    }
    CHECK(mono, "thickness rises from centre to limbus");
}

int main(void)
{
    kt_eye eye;
    coarse_eye(&eye);
    check_geometry(&eye);
    check_rejects();
    check_p1(&eye);
    check_p2(&eye);
    check_whole_globe();
    check_floor();
    return kt_test_done("test_eye");
}
