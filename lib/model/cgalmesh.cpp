/* cgalmesh.cpp: CGAL Mesh_3 tetrahedralization behind the C interface of cgalmesh.h.
 * Kept to one small translation unit: it alone costs 85-190 s of CPU and 3.9 GB of compiler
 * memory at -O2, 6.5 GB with -g (two domain types, so two instantiations of the mesher). */

/* ImageIO reads .inr.gz through zlib only with this defined; zlib is linked via PNG::PNG. */
#define CGAL_USE_ZLIB 1

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/IO/polygon_soup_io.h>
#include <CGAL/Image_3.h>
#include <CGAL/Labeled_mesh_domain_3.h>
#include <CGAL/Mesh_complex_3_in_triangulation_3.h>
#include <CGAL/Mesh_criteria_3.h>
#include <CGAL/Mesh_triangulation_3.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Polyhedral_mesh_domain_3.h>
#include <CGAL/Random.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/boost/graph/helpers.h>
#include <CGAL/make_mesh_3.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <new>
#include <set>
#include <string>
#include <unordered_map>
#include <vector>

extern "C" {
#include "cgalmesh.h"
}

namespace {

typedef CGAL::Exact_predicates_inexact_constructions_kernel K;
typedef CGAL::Surface_mesh<K::Point_3> Surface;
typedef CGAL::Polyhedral_mesh_domain_3<Surface, K> Poly_domain;
typedef CGAL::Labeled_mesh_domain_3<K> Image_domain;

/* Sequential meshing: the parallel mesher's output depends on thread timing. */
typedef CGAL::Sequential_tag Seq;
typedef CGAL::Mesh_triangulation_3<Poly_domain, CGAL::Default, Seq>::type Poly_tr;
typedef CGAL::Mesh_complex_3_in_triangulation_3<Poly_tr> Poly_c3t3;
typedef CGAL::Mesh_triangulation_3<Image_domain, CGAL::Default, Seq>::type Image_tr;
typedef CGAL::Mesh_complex_3_in_triangulation_3<Image_tr> Image_c3t3;

/* Seed of CGAL's default generator: any fixed value makes runs repeatable. */
const unsigned KT_CGAL_SEED = 20240607u;

/* Checked before CGAL's readers, which only print "File doesn't exist." on stderr. */
int check_input(const char *path, double fs, double fd, double cs, kt_err *e)
{
    std::FILE *f = std::fopen(path, "rb");
    if (!f) return kt_fail(e, KT_EINPUT, "%s: cannot open: %s", path, std::strerror(errno));
    std::fclose(f);
    if (!(fs > 0 && std::isfinite(fs)) || !(fd > 0 && std::isfinite(fd)) ||
        !(cs > 0 && std::isfinite(cs)))
        return kt_fail(e, KT_EINPUT,
                       "%s: mesh sizes must be positive (facet_size %g, facet_distance %g, "
                       "cell_size %g)", path, fs, fd, cs);
    return KT_OK;
}

/* Reads OFF/STL (any format CGAL knows) and insists on a closed, oriented manifold triangle
 * surface free of self-intersections: Mesh_3 decides inside/outside by ray parity, which is
 * only meaningful for such a surface (the input contract of Polyhedral_mesh_domain_3). */
int read_closed_surface(const char *path, Surface &sm, kt_err *e)
{
    std::vector<K::Point_3> pts;
    std::vector<std::vector<std::size_t>> polys;
    if (!CGAL::IO::read_polygon_soup(std::string(path), pts, polys) || polys.empty())
        return kt_fail(e, KT_EINPUT, "%s: cannot read a triangle surface (OFF or STL expected)",
                       path);
    for (std::size_t i = 0; i < polys.size(); i++)
        if (polys[i].size() != 3)
            return kt_fail(e, KT_EINPUT, "%s: face %zu has %zu vertices (triangles expected)",
                           path, i + 1, polys[i].size());
    namespace PMP = CGAL::Polygon_mesh_processing;
    if (!PMP::is_polygon_soup_a_polygon_mesh(polys))
        return kt_fail(e, KT_EINPUT,
                       "%s: faces do not form an oriented manifold surface (an edge shared by "
                       "more than two faces, a non-manifold vertex, or inconsistent orientation)",
                       path);
    PMP::polygon_soup_to_polygon_mesh(pts, polys, sm);
    if (!CGAL::is_closed(sm)) {
        std::size_t border = 0;
        for (auto h : sm.halfedges())
            if (sm.is_border(h)) border++;
        return kt_fail(e, KT_EINPUT, "%s: surface is not closed (%zu border edges: it has holes)",
                       path, border);
    }
    if (PMP::does_self_intersect(sm))
        return kt_fail(e, KT_EINPUT, "%s: surface intersects itself", path);
    return KT_OK;
}

/* The mesh under construction: nodes numbered in order of first use by a tet. */
template <class C3t3> struct Extract {
    typedef typename C3t3::Vertex_handle Vh;
    std::unordered_map<Vh, int> id;
    std::vector<double> xyz;
    std::vector<int> tet, tet_tag, tri;
    std::set<int> labels;

    int node(Vh v)
    {
        auto it = id.find(v);
        if (it != id.end()) return it->second;
        int k = (int)id.size();
        id.emplace(v, k);
        const auto &p = v->point();
        xyz.push_back(CGAL::to_double(p.x()));
        xyz.push_back(CGAL::to_double(p.y()));
        xyz.push_back(CGAL::to_double(p.z()));
        return k;
    }
    const double *at(int k) const { return &xyz[3 * (std::size_t)k]; }
};

/* Tets with kt_tet_volume > 0 (CGAL's positive orientation is the same convention, checked
 * rather than assumed); a flat tet is a run-time failure. */
template <class C3t3> int extract_tets(const C3t3 &c3t3, Extract<C3t3> &x, const char *path,
                                       kt_err *e)
{
    for (auto c = c3t3.cells_in_complex_begin(); c != c3t3.cells_in_complex_end(); ++c) {
        int v[4];
        for (int i = 0; i < 4; i++) v[i] = x.node(c->vertex(i));
        double vol = kt_tet_volume(x.at(v[0]), x.at(v[1]), x.at(v[2]), x.at(v[3]));
        if (vol < 0) std::swap(v[0], v[1]);
        if (!(vol != 0))
            return kt_fail(e, KT_ERUN, "%s: CGAL produced a flat tet (volume %g)", path, vol);
        int label = (int)c3t3.subdomain_index(c);
        x.tet.insert(x.tet.end(), v, v + 4);
        x.tet_tag.push_back(label);
        x.labels.insert(label);
    }
    return KT_OK;
}

/* Facets of the complex, each once, with the normal pointing out of the side with the
 * smaller nonzero label (so out of the body on the outer boundary). */
template <class C3t3> void extract_facets(const C3t3 &c3t3, Extract<C3t3> &x)
{
    for (auto f = c3t3.facets_in_complex_begin(); f != c3t3.facets_in_complex_end(); ++f) {
        auto c = f->first;
        int i = f->second;
        auto mirror = c3t3.triangulation().mirror_facet(*f);
        int a = (int)c3t3.subdomain_index(c), b = (int)c3t3.subdomain_index(mirror.first);
        if (a == 0 || (b != 0 && b < a)) {
            c = mirror.first;
            i = mirror.second;
        }
        int t[3], k = 0;
        for (int j = 0; j < 4; j++)
            if (j != i) t[k++] = x.node(c->vertex(j));
        int d = x.node(c->vertex(i));
        if (kt_tet_volume(x.at(t[0]), x.at(t[1]), x.at(t[2]), x.at(d)) > 0) std::swap(t[0], t[1]);
        x.tri.insert(x.tri.end(), t, t + 3);
    }
}

/* Copies into a C mesh; on failure m is left empty. */
template <class C3t3> int fill_mesh(const Extract<C3t3> &x, bool one_body, kt_mesh *m, kt_err *e)
{
    kt_mesh r;
    std::memset(&r, 0, sizeof r);
    r.order = 1;
    r.nn = (int)(x.xyz.size() / 3);
    r.ne = (int)x.tet_tag.size();
    r.nf = (int)(x.tri.size() / 3);
    r.xyz = (double *)kt_calloc(x.xyz.size(), sizeof(double), e);
    r.tet = (int *)kt_calloc(x.tet.size(), sizeof(int), e);
    r.tet_tag = (int *)kt_calloc(x.tet_tag.size(), sizeof(int), e);
    r.tri = (int *)kt_calloc(x.tri.size(), sizeof(int), e);
    r.tri_tag = (int *)kt_calloc((std::size_t)r.nf, sizeof(int), e);
    if (e->code) {
        kt_mesh_free(&r);
        return e->code;
    }
    std::copy(x.xyz.begin(), x.xyz.end(), r.xyz);
    std::copy(x.tet.begin(), x.tet.end(), r.tet);
    for (int i = 0; i < r.ne; i++) r.tet_tag[i] = one_body ? 1 : x.tet_tag[i];
    std::copy(x.tri.begin(), x.tri.end(), r.tri);
    for (int i = 0; i < r.nf; i++) r.tri_tag[i] = 1;
    if (one_body) {
        kt_mesh_add_group(&r, 3, 1, "body", e);
    } else {
        for (int l : x.labels) {
            char name[KT_NAME_MAX];
            std::snprintf(name, sizeof name, "label-%d", l);
            if (kt_mesh_add_group(&r, 3, l, name, e)) break;
        }
    }
    kt_mesh_add_group(&r, 2, 1, "boundary", e);
    if (e->code) {
        kt_mesh_free(&r);
        return e->code;
    }
    *m = r;
    return KT_OK;
}

/* Targets of the sliver perturbation and exudation, as minimum dihedral angles in degrees.
 * Both run without a time limit: CGAL's default limit is the refinement's own run time, which
 * would make the output depend on machine load. Measured on the bunny (20k nodes, uniform
 * sizes): perturbing to 10 degrees reaches it in about 7 s; a 15-degree target took 128 s, and
 * strongly graded sizes (facet_size << cell_size) slow the perturber down several times. */
const double KT_CGAL_PERTURB_DEG = 10.0;
const double KT_CGAL_EXUDE_DEG = 15.0;
/* Shape bounds of the refinement: minimum facet angle (degrees) and maximum cell
 * radius-edge ratio. CGAL's manual guarantees termination for angle <= 30 and ratio >= 2;
 * 25 and 3 are the values of its own examples. */
const double KT_CGAL_FACET_ANGLE = 25.0;
const double KT_CGAL_RADIUS_EDGE = 3.0;

/* Delaunay refinement (no global smoothing), then sliver perturbation and exudation. */
template <class C3t3, class Domain>
C3t3 run_mesher(const Domain &domain, double fs, double fd, double cs)
{
    namespace P = CGAL::parameters;
    typedef CGAL::Mesh_criteria_3<typename C3t3::Triangulation> Criteria;
    Criteria criteria(P::facet_angle = KT_CGAL_FACET_ANGLE, P::facet_size = fs,
                      P::facet_distance = fd, P::cell_radius_edge_ratio = KT_CGAL_RADIUS_EDGE,
                      P::cell_size = cs);
    CGAL::get_default_random() = CGAL::Random(KT_CGAL_SEED);
    return CGAL::make_mesh_3<C3t3>(
        domain, criteria, P::no_odt(), P::no_lloyd(),
        P::perturb(P::time_limit = 0, P::sliver_bound = KT_CGAL_PERTURB_DEG),
        P::exude(P::time_limit = 0, P::sliver_bound = KT_CGAL_EXUDE_DEG));
}

template <class C3t3> int finish(const C3t3 &c3t3, bool one_body, const char *path, kt_mesh *m,
                                 kt_err *e)
{
    Extract<C3t3> x;
    if (extract_tets(c3t3, x, path, e)) return e->code;
    if (x.tet.empty())
        return kt_fail(e, KT_ERUN, "%s: CGAL produced no tetrahedra (sizes too large?)", path);
    extract_facets(c3t3, x);
    return fill_mesh(x, one_body, m, e);
}

int mesh_surface(const char *path, double fs, double fd, double cs, kt_mesh *m, kt_err *e)
{
    Surface sm;
    if (read_closed_surface(path, sm, e)) return e->code;
    Poly_domain domain(sm);
    Poly_c3t3 c3t3 = run_mesher<Poly_c3t3>(domain, fs, fd, cs);
    return finish(c3t3, true, path, m, e);
}

int mesh_image(const char *path, double fs, double fd, double cs, kt_mesh *m, kt_err *e)
{
    CGAL::Image_3 image;
    if (!image.read(path))
        return kt_fail(e, KT_EINPUT, "%s: cannot read a 3D image (INR, optionally gzipped)",
                       path);
    if (image.xdim() < 2 || image.ydim() < 2 || image.zdim() < 2)
        return kt_fail(e, KT_EINPUT, "%s: image is %zux%zux%zu (3D labels expected)", path,
                       image.xdim(), image.ydim(), image.zdim());
    Image_domain domain = Image_domain::create_labeled_image_mesh_domain(image);
    Image_c3t3 c3t3 = run_mesher<Image_c3t3>(domain, fs, fd, cs);
    return finish(c3t3, false, path, m, e);
}

/* Runs one entry point, turning any C++ exception into a KT_ERUN error. */
template <class F> int guarded(const char *path, kt_err *e, F body)
{
    try {
        return body();
    } catch (const std::bad_alloc &) {
        return kt_fail(e, KT_ERUN, "%s: out of memory while meshing", path);
    } catch (const std::exception &ex) {
        return kt_fail(e, KT_ERUN, "%s: CGAL failed: %s", path, ex.what());
    } catch (...) {
        return kt_fail(e, KT_ERUN, "%s: CGAL failed with an unknown exception", path);
    }
}

} // namespace

extern "C" int kt_cgal_mesh_surface(const char *path, double facet_size, double facet_distance,
                                    double cell_size, kt_mesh *m, kt_err *e)
{
    std::memset(m, 0, sizeof *m);
    if (check_input(path, facet_size, facet_distance, cell_size, e)) return e->code;
    return guarded(path, e, [&] {
        return mesh_surface(path, facet_size, facet_distance, cell_size, m, e);
    });
}

extern "C" int kt_cgal_mesh_image(const char *path, double facet_size, double facet_distance,
                                  double cell_size, kt_mesh *m, kt_err *e)
{
    std::memset(m, 0, sizeof *m);
    if (check_input(path, facet_size, facet_distance, cell_size, e)) return e->code;
    return guarded(path, e, [&] {
        return mesh_image(path, facet_size, facet_distance, cell_size, m, e);
    });
}
