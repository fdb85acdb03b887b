/* eye.c: the parametric eye meshed with the gmsh C API (OpenCASCADE kernel).
 *
 * The rotationally symmetric base eye (mean anterior sphere) is drawn as a profile in the
 * x-z half-plane and revolved about z; each incision ring is a revolved segment that starts
 * slightly outside the eye and runs along the local normal to its depth. A boolean fragment
 * makes the rings conforming internal faces of the volumes and the outside stubs are removed.
 * After meshing (and order elevation, curved to the geometry) an oval cornea's nodes are moved
 * in their meridians (kt_eye_warp_oval: the corneal edge onto the white-to-white ellipse, the
 * rings with it, the central zone untouched), then every node is mapped by a vertical
 * displacement that turns the anterior sphere into the exact toric surface and blends to zero
 * through the corneal thickness and across the limbus. */
#include "eye.h"

#include <gmshc.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "eye_geom.h"
#include "topology.h"

#define RING_STUB 0.1 /* mm: how far a ring's construction segment starts outside the eye */


/* State of one meshing run: geometry, gmsh's sticky error flag, entity classification. */
typedef struct eye_build {
    const kt_eye *eye;
    kt_eye_geom g;
    double top[KT_SCENE_MAX][2], dir[KT_SCENE_MAX][2], depth[KT_SCENE_MAX];
    int ierr;          /* set by any failing gmsh call */
    int nvtag, nstag;  /* sizes of the tag-indexed tables */
    int *vol_region;   /* volume entity tag -> region tag (0: none) */
    int *surf_group;   /* surface entity tag -> surface group tag (0: interface) */
    int nring_piece;   /* ring faces kept after the fragment */
    int aux[4], naux;  /* construction points (centres) to delete once the solids exist */
    double h_cornea, h_optical; /* sizes after the through-the-thickness rule (kt_eye_sizes) */
} eye_build;

static void gm(eye_build *b, int ierr) { if (ierr) b->ierr = 1; }

/* Turn gmsh's error flag or the first error in its log (this run's logger, which holds only
 * errors at the verbosity we set) into KT_ERUN naming the stage. */
static int gm_check(eye_build *b, const char *stage, kt_err *e)
{
    char **log = NULL;
    size_t nlog = 0;
    int ierr = 0;
    const char *first = NULL;
    gmshLoggerGet(&log, &nlog, &ierr);
    for (size_t i = 0; i < nlog && !first; i++)
        if (strncmp(log[i], "Error", 5) == 0) first = log[i];
    if (b->ierr || first)
        kt_fail(e, KT_ERUN, "eye: gmsh failed while %s: %s", stage, first ? first : "(no message)");
    for (size_t i = 0; i < nlog; i++) gmshFree(log[i]);
    gmshFree(log);
    return e->code ? e->code : KT_OK;
}

static int pt(eye_build *b, const double p[2])
{
    int ierr = 0, t = gmshModelOccAddPoint(p[0], 0, p[1], 0, -1, &ierr);
    gm(b, ierr);
    return t;
}

static int pt_axis(eye_build *b, double z)
{
    double p[2] = {0, z};
    return pt(b, p);
}

static int line(eye_build *b, int p, int q)
{
    int ierr = 0, t = gmshModelOccAddLine(p, q, -1, &ierr);
    gm(b, ierr);
    return t;
}

static int arc(eye_build *b, int p, int centre, int q)
{
    int ierr = 0, t = gmshModelOccAddCircleArc(p, centre, q, -1, &ierr);
    gm(b, ierr);
    return t;
}

static int face(eye_build *b, int c0, int c1, int c2, int c3)
{
    int ierr = 0, loop[4] = {c0, c1, c2, c3};
    int w = gmshModelOccAddCurveLoop(loop, 4, -1, &ierr);
    gm(b, ierr);
    int f = gmshModelOccAddPlaneSurface(&w, 1, -1, &ierr);
    gm(b, ierr);
    return f;
}

/* The posterior conic from the vertex Pv to Pp: an ellipse arc (a circle if k = 1). */
static int posterior_curve(eye_build *b, int pv, int pp)
{
    const kt_eye_geom *g = &b->g;
    double a = g->Rp / g->k, bb = g->Rp / sqrt(g->k), zc = g->z_pv - a;
    int centre = pt_axis(b, zc);
    b->aux[b->naux++] = centre;
    if (fabs(g->k - 1) < 1e-9) return arc(b, pv, centre, pp);
    int ierr = 0, major = g->k < 1 ? pv : pt(b, (double[2]){bb, zc});
    if (g->k > 1) b->aux[b->naux++] = major;
    int t = gmshModelOccAddEllipseArc(pv, centre, major, pp, -1, &ierr);
    gm(b, ierr);
    return t;
}

/* Profile faces of cornea, limbus and sclera in the x-z half-plane (x = rho). */
static void profile(eye_build *b, int f[3])
{
    const kt_eye_geom *g = &b->g;
    int a0 = pt_axis(b, g->z_apex), ca = pt_axis(b, g->z_ca), o = pt_axis(b, 0);
    int pv = pt_axis(b, g->z_pv), E = pt(b, g->E), Pp = pt(b, g->Pp);
    int Lo = pt(b, g->Lo), Li = pt(b, g->Li), So = pt(b, g->So), Si = pt(b, g->Si);
    b->aux[b->naux++] = ca;
    b->aux[b->naux++] = o;
    int c_ant = arc(b, a0, ca, E), c_edge = line(b, E, Pp);
    int c_post = posterior_curve(b, pv, Pp), c_axis = line(b, pv, a0);
    int c_lo = arc(b, E, o, Lo), c_ls = line(b, Lo, Li), c_li = line(b, Li, Pp);
    int c_so = arc(b, Lo, o, So), c_rim = line(b, So, Si), c_si = arc(b, Si, o, Li);
    f[0] = face(b, c_ant, c_edge, c_post, c_axis);
    f[1] = face(b, c_lo, c_ls, c_li, c_edge);
    f[2] = face(b, c_so, c_rim, c_si, c_ls);
}

/* Revolve dim-dimensional entity `tag` by a full turn; return the swept entity of dim+1. */
static int revolve(eye_build *b, int dim, int tag)
{
    int in[2] = {dim, tag}, *out = NULL, ierr = 0, res = -1;
    size_t nout = 0;
    gmshModelOccRevolve(in, 2, 0, 0, 0, 0, 0, 1, 2 * KT_PI, &out, &nout, NULL, 0, NULL, 0, 0,
                        &ierr);
    gm(b, ierr);
    for (size_t i = 0; i + 1 < nout; i += 2)
        if (out[i] == dim + 1 && res < 0) res = out[i + 1];
    gmshFree(out);
    if (res < 0) b->ierr = 1;
    /* The generator itself is not part of the model. */
    gmshModelOccRemove(in, 2, 1, &ierr);
    gm(b, ierr);
    return res;
}

/* A ring's construction segment, from RING_STUB outside the eye to its depth, revolved. */
static int ring_surface(eye_build *b, int i)
{
    double p[2], q[2];
    for (int c = 0; c < 2; c++) {
        p[c] = b->top[i][c] - RING_STUB * b->dir[i][c];
        q[c] = b->top[i][c] + b->depth[i] * b->dir[i][c];
    }
    return revolve(b, 1, line(b, pt(b, p), pt(b, q)));
}

static int grow_table(int **tab, int *n, int need, kt_err *e)
{
    if (need <= *n) return KT_OK;
    int *t = kt_realloc(*tab, (size_t)need, sizeof(int), e);
    if (!t) return e->code;
    memset(t + *n, 0, (size_t)(need - *n) * sizeof(int));
    *tab = t;
    *n = need;
    return KT_OK;
}

/* Ring pieces outside the eye (the stubs) lie above the ring's top point: remove them. */
static int keep_ring_pieces(eye_build *b, int k, const int *map, size_t nmap, kt_err *e)
{
    for (size_t j = 0; j + 1 < nmap; j += 2) {
        if (map[j] != 2) continue;
        int ierr = 0, tag = map[j + 1];
        double x, y, z;
        gmshModelOccGetCenterOfMass(2, tag, &x, &y, &z, &ierr);
        gm(b, ierr);
        if (z > b->top[k][1]) {
            int dt[2] = {2, tag};
            gmshModelOccRemove(dt, 2, 1, &ierr);
            gm(b, ierr);
            continue;
        }
        if (grow_table(&b->surf_group, &b->nstag, tag + 1, e)) return e->code;
        b->surf_group[tag] = KT_EYE_SURF_RING0 + k + 1;
        b->nring_piece++;
    }
    return KT_OK;
}

/* Build volumes and rings, fragment them, record which entity is which. */
static int build_model(eye_build *b, kt_err *e)
{
    int f[3], nr = b->eye->nring;
    profile(b, f);
    int obj[6], tool[2 * KT_SCENE_MAX];
    for (int i = 0; i < 3; i++) obj[2 * i] = 3, obj[2 * i + 1] = revolve(b, 2, f[i]);
    for (int i = 0; i < nr; i++) tool[2 * i] = 2, tool[2 * i + 1] = ring_surface(b, i);
    for (int i = 0; i < b->naux; i++) {
        int ierr = 0, dt[2] = {0, b->aux[i]};
        gmshModelOccRemove(dt, 2, 0, &ierr);
        gm(b, ierr);
    }
    if (gm_check(b, "building the eye geometry", e)) return e->code;
    int *out = NULL, **map = NULL, ierr = 0;
    size_t nout = 0, *nmap = NULL, nnmap = 0;
    gmshModelOccFragment(obj, 6, tool, (size_t)2 * nr, &out, &nout, &map, &nmap, &nnmap, -1, 1,
                         1, &ierr);
    gm(b, ierr);
    int rc = KT_OK;
    if (!b->ierr && nnmap != (size_t)(3 + nr)) b->ierr = 1;
    for (size_t i = 0; i < nnmap && !b->ierr && rc == KT_OK; i++) {
        if (i >= 3) {
            rc = keep_ring_pieces(b, (int)i - 3, map[i], nmap[i], e);
            continue;
        }
        for (size_t j = 0; j + 1 < nmap[i] && rc == KT_OK; j += 2) {
            rc = grow_table(&b->vol_region, &b->nvtag, map[i][j + 1] + 1, e);
            if (rc == KT_OK) b->vol_region[map[i][j + 1]] = (int)i + 1;
        }
    }
    for (size_t i = 0; i < nnmap; i++) gmshFree(map[i]);
    gmshFree(map);
    gmshFree(nmap);
    gmshFree(out);
    if (rc) return rc;
    gmshModelOccSynchronize(&ierr);
    gm(b, ierr);
    if (gm_check(b, "fragmenting the volumes with the incision rings", e)) return e->code;
    for (int i = 0; i < nr; i++) {
        int found = 0;
        for (int t = 0; t < b->nstag; t++) found |= b->surf_group[t] == KT_EYE_SURF_RING0 + i + 1;
        if (!found)
            return kt_fail(e, KT_ERUN, "eye: ring '%s' was lost in the boolean fragment",
                           b->eye->ring[i].name);
    }
    return KT_OK;
}

/* A point inside a model surface (its parametric midpoint). */
static void surface_point(eye_build *b, int tag, double p[3])
{
    double *lo = NULL, *hi = NULL, *xyz = NULL;
    size_t nlo = 0, nhi = 0, nxyz = 0;
    int ierr = 0;
    gmshModelGetParametrizationBounds(2, tag, &lo, &nlo, &hi, &nhi, &ierr);
    gm(b, ierr);
    if (nlo == 2 && nhi == 2) {
        double uv[2] = {0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1])};
        gmshModelGetValue(2, tag, uv, 2, &xyz, &nxyz, &ierr);
        gm(b, ierr);
    }
    if (nxyz == 3) memcpy(p, xyz, 3 * sizeof(double));
    else b->ierr = 1, p[0] = p[1] = p[2] = NAN;
    gmshFree(lo);
    gmshFree(hi);
    gmshFree(xyz);
}

/* Boundary face of one region: which group it belongs to, from where it lies. */
static int boundary_group(const kt_eye_geom *g, int region, const double p[3])
{
    double tol = 1e-6 * g->Rg;
    double r0 = sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
    double ra = sqrt(p[0] * p[0] + p[1] * p[1] + (p[2] - g->z_ca) * (p[2] - g->z_ca));
    if (region == KT_EYE_REG_CORNEA) return fabs(ra - g->Ra) < tol ? KT_EYE_SURF_ANTERIOR : KT_EYE_SURF_INNER;
    if (fabs(r0 - g->Rg) < tol) return KT_EYE_SURF_OUTER;
    if (region == KT_EYE_REG_LIMBUS || fabs(r0 - g->Ri) < tol) return KT_EYE_SURF_INNER;
    return KT_EYE_SURF_FIXED;
}

static int classify_surfaces(eye_build *b, kt_err *e)
{
    int *st = NULL, ierr = 0;
    size_t nst = 0;
    gmshModelGetEntities(&st, &nst, 2, &ierr);
    gm(b, ierr);
    for (size_t i = 0; i + 1 < nst && !b->ierr; i += 2) {
        int tag = st[i + 1];
        if (grow_table(&b->surf_group, &b->nstag, tag + 1, e)) break;
        if (b->surf_group[tag] >= KT_EYE_SURF_RING0) continue;
        int *up = NULL, *down = NULL;
        size_t nup = 0, ndown = 0;
        gmshModelGetAdjacencies(2, tag, &up, &nup, &down, &ndown, &ierr);
        gm(b, ierr);
        if (nup == 1 && up[0] < b->nvtag && b->vol_region[up[0]]) {
            double p[3];
            surface_point(b, tag, p);
            b->surf_group[tag] = boundary_group(&b->g, b->vol_region[up[0]], p);
        } else if (nup != 2) {
            kt_fail(e, KT_ERUN, "eye: model surface %d bounds %zu volumes", tag, nup);
        }
        gmshFree(up);
        gmshFree(down);
    }
    gmshFree(st);
    if (e->code) return e->code;
    return gm_check(b, "classifying the eye's surfaces", e);
}

static int field(eye_build *b, const char *type)
{
    int ierr = 0, t = gmshModelMeshFieldAdd(type, -1, &ierr);
    gm(b, ierr);
    return t;
}

static void fnum(eye_build *b, int f, const char *opt, double v)
{
    int ierr = 0;
    gmshModelMeshFieldSetNumber(f, opt, v, &ierr);
    gm(b, ierr);
}

static int threshold(eye_build *b, int in, double hmin, double hmax, double dmin, double dmax)
{
    int t = field(b, "Threshold");
    fnum(b, t, "InField", in);
    fnum(b, t, "SizeMin", hmin);
    fnum(b, t, "SizeMax", hmax);
    fnum(b, t, "DistMin", dmin);
    fnum(b, t, "DistMax", dmax);
    return t;
}

/* Threshold that reaches h_mid at distance dmin + len and keeps that slope up to h_max, so
 * that in a Min field it only refines (h_max is the coarsest size anywhere). */
static int graded(eye_build *b, int in, double hmin, double dmin, double len, double hmid,
                  double hmax)
{
    if (hmin >= hmid) return -1; /* nothing to refine: the base field is finer already */
    return threshold(b, in, hmin, hmax, dmin, dmin + len * (hmax - hmin) / (hmid - hmin));
}

static int matheval(eye_build *b, const char *expr)
{
    int ierr = 0, t = field(b, "MathEval");
    gmshModelMeshFieldSetString(t, "F", expr, &ierr);
    gm(b, ierr);
    return t;
}

/* Distance (mm) from a point to ring i's floor, the circle the ring's bottom edge sweeps (the
 * crack front of an incision cut along it), restricted to the arcs within floor_sector of the
 * meridian floor_centre and its opposite: sqrt(dr^2 + dz^2 + (rho_f * angle beyond the
 * sector)^2), the angle folded into [0, 90] deg. Written as a gmsh MathEval expression; every
 * number is parenthesized, since its parser refuses a sign after an operator ("x*-0.5"), which a
 * centre above 90 deg gives. */
static int floor_distance(eye_build *b, int i, char *expr, size_t len)
{
    const kt_eye *eye = b->eye;
    double rho = b->top[i][0] + b->depth[i] * b->dir[i][0];
    double z = b->top[i][1] + b->depth[i] * b->dir[i][1];
    double sector = eye->floor_sector > 0 && eye->floor_sector < 90 ? eye->floor_sector : 90;
    double ca = cos(eye->floor_centre * KT_PI / 180), sa = sin(eye->floor_centre * KT_PI / 180);
    int n = snprintf(expr, len,
                     "sqrt((sqrt(x*x+y*y)-(%.17g))^2 + (z-(%.17g))^2 + ((%.17g)*0.5*("
                     "acos(Fabs(x*(%.17g)+y*(%.17g))/(sqrt(x*x+y*y)+1e-12))-(%.17g) + "
                     "Fabs(acos(Fabs(x*(%.17g)+y*(%.17g))/(sqrt(x*x+y*y)+1e-12))-(%.17g))))^2)",
                     rho, z, rho, ca, sa, sector * KT_PI / 180, ca, sa, sector * KT_PI / 180);
    return n > 0 && (size_t)n < len ? matheval(b, expr) : (b->ierr = 1, -1);
}

/* Where on the mesh of revolution the oval warp's outer surface point lands at *dist in the
 * meridian t: *dist becomes its pre-image (bisection; the warp is monotone along a meridian),
 * *rad grows by how much more the outer surface moves there than the inner one. Unchanged on
 * a round eye. */
static void site_preimage(const kt_eye_geom *g, double t, double *dist, double *rad)
{
    double c = cos(t), s = sin(t), lo = 0, hi = g->rL;
    if (!g->oval || !(*dist < g->rL)) return;
    for (int it = 0; it < 100; it++) {
        double mid = 0.5 * (lo + hi);
        if (kt_eye_geom_oval_rho(g, mid, c, s) < *dist) lo = mid;
        else hi = mid;
    }
    double xi = 0.5 * (lo + hi);
    *rad += fabs(kt_eye_geom_oval_shift(g, xi, 1, c, s) - kt_eye_geom_oval_shift(g, xi, 0, c, s));
    *dist = xi;
}

/* Size fields: h_incision near the rings, h_floor at the rings' floor (within the sector),
 * h_optical in the central zone, h_cornea elsewhere in cornea and limbus, h_sclera in the
 * sclera; the background size is their minimum. */
static int size_fields(eye_build *b, kt_err *e)
{
    const kt_eye *eye = b->eye;
    const kt_eye_geom *g = &b->g;
    double fl[4 + KT_SCENE_MAX];
    int n = 0, f;
    char expr[1024];
    /* Optical zone: radial distance from the axis, switched off below the corneal edge. */
    snprintf(expr, sizeof expr, "sqrt(x*x+y*y) + 100*(((%.17g) - z) + Fabs((%.17g) - z))",
             g->Pp[1], g->Pp[1]);
    double hc = b->h_cornea, hmax = fmax(eye->h_sclera, hc);
    if ((f = graded(b, matheval(b, expr), b->h_optical, 0.5 * eye->optical_zone, 2 * hc, hc, hmax)) > 0)
        fl[n++] = f;
    /* Sclera: polar angle about the globe centre, coarsening beyond the limbus. */
    fl[n++] = threshold(b, matheval(b, "acos(z/sqrt(x*x+y*y+z*z+1e-12))"), hc, eye->h_sclera,
                        g->alphaL, g->alphaL + 3 * eye->h_sclera / g->Rg);
    if (eye->nring > 0) {
        double *tags = kt_calloc((size_t)b->nring_piece, sizeof(double), e);
        if (!tags) return e->code;
        int k = 0, ierr = 0;
        for (int t = 0; t < b->nstag; t++)
            if (b->surf_group[t] >= KT_EYE_SURF_RING0) tags[k++] = t;
        int d = field(b, "Distance");
        gmshModelMeshFieldSetNumbers(d, "SurfacesList", tags, (size_t)k, &ierr);
        gm(b, ierr);
        free(tags);
        /* Sample the ring faces (spacing = bounding-box diagonal / N) at about h_incision / 5. */
        fnum(b, d, "NumPointsPerCurve", ceil(3 * 2 * g->rL / eye->h_incision));
        if ((f = graded(b, d, eye->h_incision, 0.5 * eye->h_incision, 2 * hc, hc, hmax)) > 0)
            fl[n++] = f;
    }
    if (eye->site_radius > 0) {
        /* The site: horizontal distance from its axis (every number parenthesized, see above),
         * on the mesh of revolution where the oval warp takes it. */
        double dist = eye->site_distance, rad = eye->site_radius;
        site_preimage(g, eye->site_meridian * KT_PI / 180, &dist, &rad);
        double cx = dist * cos(eye->site_meridian * KT_PI / 180);
        double cy = dist * sin(eye->site_meridian * KT_PI / 180);
        snprintf(expr, sizeof expr, "sqrt((x-(%.17g))^2 + (y-(%.17g))^2)", cx, cy);
        if ((f = graded(b, matheval(b, expr), eye->h_incision, rad, 2 * hc, hc, hmax)) > 0) fl[n++] = f;
    }
    double hring = fmin(eye->h_incision, hc);
    for (int i = 0; i < eye->nring && eye->h_floor > 0; i++) {
        int dist = floor_distance(b, i, expr, sizeof expr);
        double len = (hring - eye->h_floor) / kt_eye_floor_slope(eye);
        if (dist > 0 && (f = graded(b, dist, eye->h_floor, 0.5 * eye->h_floor, len, hring, hmax)) > 0)
            fl[n++] = f;
    }
    int ierr = 0, mn = field(b, "Min");
    gmshModelMeshFieldSetNumbers(mn, "FieldsList", fl, (size_t)n, &ierr);
    gm(b, ierr);
    gmshModelMeshFieldSetAsBackgroundMesh(mn, &ierr);
    gm(b, ierr);
    return gm_check(b, "setting the mesh size fields", e);
}

static void opt(eye_build *b, const char *name, double v)
{
    int ierr = 0;
    gmshOptionSetNumber(name, v, &ierr);
    gm(b, ierr);
}

/* Frontal-Delaunay surfaces and Delaunay volumes, on one thread: the same scene gives the same
 * mesh, to the byte, on every run and machine thread count (mesh-prep(1), REPRODUCIBILITY).
 * HXT, the parallel 3D mesher used before, orders the surface nodes it starts from by their
 * heap addresses, so its mesh changed with every run even on one thread (64,566 / 64,574 /
 * 64,500 nodes of the default eye). On the default eye Delaunay costs 1.2-1.5x HXT's CPU time
 * in mesh-prep and gives 10% more nodes (70,958 against ~64,500); its worst tets are slivers
 * whose four corners all lie on the boundary (min dihedral 8.5 deg against HXT's 11-12; mean
 * radius ratio 0.727 against 0.692). The optimizer's threshold 0.5 (gmsh's default 0.3)
 * improves the mean quality for no measurable time. */
static void set_options(eye_build *b)
{
    opt(b, "General.Terminal", 0);
    opt(b, "General.Verbosity", 1);
    opt(b, "General.AbortOnError", 0);
    opt(b, "General.NumThreads", 1);
    opt(b, "Mesh.MaxNumThreads3D", 1);
    opt(b, "Mesh.Algorithm3D", 1);
    opt(b, "Mesh.OptimizeThreshold", 0.5);
    opt(b, "Mesh.MeshSizeExtendFromBoundary", 0);
    opt(b, "Mesh.MeshSizeFromPoints", 0);
    opt(b, "Mesh.MeshSizeFromCurvature", 0);
    opt(b, "Mesh.MeshSizeMax", fmax(b->eye->h_sclera, b->h_cornea));
}

/* ---- extraction into kt_mesh ---------------------------------------------------------- */

typedef struct node_map {
    size_t *tags;   /* gmsh node tags */
    double *xyz;    /* their coordinates */
    size_t n;
    int *index;     /* gmsh tag -> compact 0-based index, -1 unused */
    size_t maxtag;
} node_map;

static void node_map_free(node_map *nm)
{
    gmshFree(nm->tags);
    gmshFree(nm->xyz);
    free(nm->index);
    memset(nm, 0, sizeof *nm);
}

static int read_nodes(eye_build *b, node_map *nm, kt_err *e)
{
    double *par = NULL;
    size_t ncoord = 0, npar = 0;
    int ierr = 0;
    gmshModelMeshGetNodes(&nm->tags, &nm->n, &nm->xyz, &ncoord, &par, &npar, -1, -1, 0, 0, &ierr);
    gmshFree(par);
    gm(b, ierr);
    if (b->ierr || ncoord != 3 * nm->n) return kt_fail(e, KT_ERUN, "eye: gmsh returned no nodes");
    for (size_t i = 0; i < nm->n; i++)
        if (nm->tags[i] > nm->maxtag) nm->maxtag = nm->tags[i];
    nm->index = kt_calloc(nm->maxtag + 1, sizeof(int), e);
    if (!nm->index) return e->code;
    for (size_t i = 0; i <= nm->maxtag; i++) nm->index[i] = -1;
    return KT_OK;
}

/* Elements of one gmsh type on one entity, appended to conn/tag (node tags kept as gmsh tags
 * in a size_t scratch until compaction). */
static int append_elements(eye_build *b, int type, int ent, int nv, int group, size_t **conn,
                           int **tags, int *count, kt_err *e)
{
    size_t *et = NULL, *nt = NULL, net = 0, nnt = 0;
    int ierr = 0;
    gmshModelMeshGetElementsByType(type, &et, &net, &nt, &nnt, ent, 0, 1, &ierr);
    gm(b, ierr);
    int rc = KT_OK;
    if (!b->ierr && net > 0 && nnt == net * (size_t)nv) {
        size_t *c = kt_realloc(*conn, ((size_t)*count + net) * nv, sizeof(size_t), e);
        if (c) *conn = c;
        int *t = c ? kt_realloc(*tags, (size_t)*count + net, sizeof(int), e) : NULL;
        if (t) {
            *tags = t;
            memcpy(c + (size_t)*count * nv, nt, nnt * sizeof(size_t));
            for (size_t i = 0; i < net; i++) t[*count + i] = group;
            *count += (int)net;
        }
        rc = e->code;
    }
    gmshFree(et);
    gmshFree(nt);
    return rc;
}

/* Give every node used by a tet a compact index, in gmsh tag order. */
static int compact_nodes(node_map *nm, const size_t *conn, size_t len, kt_mesh *m, kt_err *e)
{
    for (size_t i = 0; i < len; i++) {
        if (conn[i] > nm->maxtag) return kt_fail(e, KT_ERUN, "eye: element names unknown node");
        nm->index[conn[i]] = 1;
    }
    int nn = 0;
    for (size_t t = 0; t <= nm->maxtag; t++) nm->index[t] = nm->index[t] > 0 ? nn++ : -1;
    m->nn = nn;
    m->xyz = kt_calloc(3 * (size_t)nn, sizeof(double), e);
    if (!m->xyz) return e->code;
    for (size_t i = 0; i < nm->n; i++) {
        int k = nm->index[nm->tags[i]];
        if (k >= 0) memcpy(m->xyz + 3 * (size_t)k, nm->xyz + 3 * i, 3 * sizeof(double));
    }
    return KT_OK;
}

static int to_index(const node_map *nm, const size_t *conn, size_t len, int **out, kt_err *e)
{
    int *o = kt_calloc(len, sizeof(int), e);
    if (!o) return e->code;
    for (size_t i = 0; i < len; i++) {
        o[i] = conn[i] <= nm->maxtag ? nm->index[conn[i]] : -1;
        if (o[i] < 0) {
            free(o);
            return kt_fail(e, KT_ERUN, "eye: a surface triangle uses a node no tet has");
        }
    }
    *out = o;
    return KT_OK;
}

static int add_groups(eye_build *b, kt_mesh *m, kt_err *e)
{
    static const char *regions[3] = {"cornea", "limbus", "sclera"};
    static const char *surfs[4] = {"anterior", "inner", "fixed", "outer"};
    for (int i = 0; i < 3; i++)
        if (kt_mesh_add_group(m, 3, i + 1, regions[i], e)) return e->code;
    for (int i = 0; i < 4; i++)
        if (!(i + 1 == KT_EYE_SURF_FIXED && b->g.whole) && kt_mesh_add_group(m, 2, i + 1, surfs[i], e))
            return e->code;
    for (int k = 0; k < b->eye->nring; k++) {
        char name[KT_NAME_MAX];
        if (b->eye->ring[k].name[0]) snprintf(name, sizeof name, "%s", b->eye->ring[k].name);
        else snprintf(name, sizeof name, "incision-ring-%d", k + 1);
        if (kt_mesh_add_group(m, 2, KT_EYE_SURF_RING0 + k + 1, name, e)) return e->code;
    }
    return KT_OK;
}

/* gmsh can log nothing and still leave a region or a ring without elements. */
static int check_counts(const kt_mesh *m, kt_err *e)
{
    for (int g = 0; g < m->ng; g++) {
        const kt_group *gr = &m->group[g];
        int n = 0, nel = gr->dim == 3 ? m->ne : m->nf;
        const int *tag = gr->dim == 3 ? m->tet_tag : m->tri_tag;
        for (int i = 0; i < nel && n == 0; i++) n += tag[i] == gr->tag;
        if (n == 0)
            return kt_fail(e, KT_ERUN, "eye: gmsh produced no %s in '%s'",
                           gr->dim == 3 ? "tetrahedra" : "triangles", gr->name);
    }
    return KT_OK;
}

static int extract(eye_build *b, int order, kt_mesh *m, kt_err *e)
{
    node_map nm = {0};
    size_t *tetc = NULL, *tric = NULL;
    int tv = kt_tet_nv(order), fv = kt_tri_nv(order);
    int ttype = order == 2 ? 11 : 4, ftype = order == 2 ? 9 : 2;
    memset(m, 0, sizeof *m);
    m->order = order;
    int rc = read_nodes(b, &nm, e);
    for (int v = 0; v < b->nvtag && rc == KT_OK; v++)
        if (b->vol_region[v])
            rc = append_elements(b, ttype, v, tv, b->vol_region[v], &tetc, &m->tet_tag, &m->ne, e);
    for (int s = 0; s < b->nstag && rc == KT_OK; s++)
        if (b->surf_group[s])
            rc = append_elements(b, ftype, s, fv, b->surf_group[s], &tric, &m->tri_tag, &m->nf, e);
    if (rc == KT_OK && m->ne == 0) rc = kt_fail(e, KT_ERUN, "eye: gmsh produced no tetrahedra");
    if (rc == KT_OK) rc = compact_nodes(&nm, tetc, (size_t)m->ne * tv, m, e);
    if (rc == KT_OK) rc = to_index(&nm, tetc, (size_t)m->ne * tv, &m->tet, e);
    if (rc == KT_OK) rc = to_index(&nm, tric, (size_t)m->nf * fv, &m->tri, e);
    if (rc == KT_OK) rc = add_groups(b, m, e);
    if (rc == KT_OK) rc = check_counts(m, e);
    free(tetc);
    free(tric);
    node_map_free(&nm);
    if (rc) kt_mesh_free(m);
    return rc;
}

/* ---- driver ---------------------------------------------------------------------------- */

static int mesh_model(eye_build *b, int order, int quiet, kt_err *e)
{
    int ierr = 0;
    double t0 = kt_now();
    kt_log(quiet, "eye: meshing with gmsh (surfaces Frontal-Delaunay, volumes Delaunay)\n");
    gmshModelMeshGenerate(3, &ierr);
    gm(b, ierr);
    if (gm_check(b, "meshing the eye", e)) return e->code;
    if (order == 2) {
        gmshModelMeshSetOrder(2, &ierr);
        gm(b, ierr);
        if (gm_check(b, "making the mesh second order", e)) return e->code;
    }
    kt_log(quiet, "eye: meshed in %.1f s\n", kt_now() - t0);
    return KT_OK;
}

/* The documented sizing rule (keratome-scene(5), eye.h): a thin shell in bending with a single
 * linear tet through its thickness is far too stiff, so with order 1 the cornea and optical-zone
 * sizes are at most t_central / 2.5 (at t_central / 2 gmsh still left ~20 tets touching both
 * surfaces of the default eye, at / 2.5 none). A 10-node tet represents bending through the
 * thickness on its own: with order 2 they are at most t_central. */
#define CORNEA_LAYERS_P1 2.5
#define CORNEA_LAYERS_P2 1.0

double kt_eye_layers(int order) { return order == 2 ? CORNEA_LAYERS_P2 : CORNEA_LAYERS_P1; }

void kt_eye_sizes(const kt_eye *eye, int order, double *h_cornea, double *h_optical)
{
    double cap = eye->t_central / kt_eye_layers(order);
    *h_cornea = fmin(eye->h_cornea, cap);
    *h_optical = fmin(eye->h_optical, cap);
}

static void cap_sizes(eye_build *b, int order, int quiet)
{
    kt_eye_sizes(b->eye, order, &b->h_cornea, &b->h_optical);
    if (b->h_cornea < b->eye->h_cornea || b->h_optical < b->eye->h_optical)
        kt_log(quiet, "eye: cornea/optical-zone element size reduced to %.3g mm (central thickness / %g "
               "for order %d: keratome-scene(5), mesh_size)\n", fmin(b->h_cornea, b->h_optical),
               kt_eye_layers(order), order);
}

static int validate_rings(eye_build *b, kt_err *e)
{
    if (b->eye->nring < 0 || b->eye->nring > KT_SCENE_MAX)
        return kt_fail(e, KT_EINPUT, "eye.rings: expected at most %d rings", KT_SCENE_MAX);
    for (int i = 0; i < b->eye->nring; i++)
        if (kt_eye_geom_ring(&b->g, b->eye, i, b->top[i], b->dir[i], &b->depth[i], e))
            return e->code;
    return KT_OK;
}

int kt_eye_mesh(const kt_eye *eye, int order, int quiet, kt_mesh *m, kt_err *e)
{
    eye_build b = {0};
    b.eye = eye;
    memset(m, 0, sizeof *m);
    if (order != 1 && order != 2)
        return kt_fail(e, KT_EINPUT, "eye: element order %d (expected 1 or 2)", order);
    if (kt_eye_geom_init(eye, &b.g, e) || validate_rings(&b, e)) return e->code;
    cap_sizes(&b, order, quiet);
    int ierr = 0, rc;
    gmshInitialize(0, NULL, 0, &ierr);
    if (ierr) return kt_fail(e, KT_ERUN, "eye: gmsh failed to initialise");
    gmshLoggerStart(&ierr);
    set_options(&b);
    gmshModelAdd("eye", &ierr);
    gm(&b, ierr);
    rc = gm_check(&b, "setting up gmsh", e);
    if (rc == KT_OK) rc = build_model(&b, e);
    if (rc == KT_OK) rc = classify_surfaces(&b, e);
    if (rc == KT_OK) rc = size_fields(&b, e);
    if (rc == KT_OK) rc = mesh_model(&b, order, quiet, e);
    if (rc == KT_OK) rc = extract(&b, order, m, e);
    gmshLoggerStop(&ierr);
    gmshFinalize(&ierr);
    free(b.vol_region);
    free(b.surf_group);
    /* The oval warp first (it keeps every surface of revolution on itself), then the toric one
     * with the measured surfaces' departures evaluated where the nodes now are. */
    if (rc == KT_OK) rc = kt_eye_warp_oval(&b.g, m, e);
    if (rc == KT_OK) rc = kt_eye_warp_measured(&b.g, eye, m, e);
    if (rc == KT_OK) rc = kt_mesh_check(m, "eye (after the toric map)", e);
    int nstraight = 0;
    if (rc == KT_OK) rc = kt_eye_straighten_inverted(m, &nstraight, e);
    if (rc == KT_OK && nstraight > 0)
        kt_log(quiet, "eye: %d mid-edge nodes of inverted curved tets put back on their chords\n",
               nstraight);
    if (rc == KT_OK) rc = kt_eye_check_curved(m, e);
    if (rc) kt_mesh_free(m);
    else kt_log(quiet, "eye: %d nodes, %d tets (order %d)\n", m->nn, m->ne, order);
    return rc;
}
