/* meshprep_run.c: mesh-prep's pipeline: build, group, check, order, renumber, write, summarize. */
#include "meshprep_run.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "build.h"
#include "eye.h"
#include "bind.h"
#include "msh.h"
#include "orderset.h"
#include "quality.h"
#include "refgeom.h"

/* ---- the run --------------------------------------------------------------------------------- */

static const char *model_name(int model)
{
    static const char *N[] = {"?", "eye", "box", "surface", "image"};
    return model >= 1 && model <= 4 ? N[model] : "?";
}

/* Counts of tets per region and triangles per surface, in group order. */
static void print_groups(FILE *f, const kt_mesh *m, int dim)
{
    fprintf(f, "%-13s", dim == 3 ? "regions" : "surfaces");
    int first = 1;
    for (int g = 0; g < m->ng; g++) {
        if (m->group[g].dim != dim) continue;
        long cnt = 0;
        int n = dim == 3 ? m->ne : m->nf;
        const int *tag = dim == 3 ? m->tet_tag : m->tri_tag;
        for (int i = 0; i < n; i++) cnt += tag[i] == m->group[g].tag;
        fprintf(f, "%s%s %ld", first ? "" : ", ", m->group[g].name, cnt);
        first = 0;
    }
    fprintf(f, " %s\n", dim == 3 ? "tets" : "triangles");
}

typedef struct run_info {
    const kt_prep_opts *o;
    int chosen_only;        /* KT_PREP_TABLE_CHOSEN */
    const kt_scene *s;
    int order, chosen, nfixed, nset, nsector;
    const char *set_label;
    double t_mesh, t_ref, t_write, t_total;
    int unloaded;           /* the stress-free geometry was computed */
    kt_refgeom_opts ro;
    kt_refgeom_stats rs;
    kt_quality q;
    int nrow;
    kt_prep_row row[6];
} run_info;

/* The eye's element sizes as meshed: the cornea and optical-zone ones follow the rule of
 * kt_eye_sizes, and a reduction is said, not hidden. */
static void print_sizes(FILE *f, const run_info *r)
{
    if (r->s->model != KT_MODEL_EYE) return;
    const kt_eye *eye = &r->s->eye;
    double hc, ho;
    kt_eye_sizes(eye, r->order, &hc, &ho);
    kt_err ge = {0};
    double tets = NAN;
    kt_eye_estimate_tets(eye, r->order, &tets, &ge);
    fprintf(f, "sizes        optical zone %g mm, incision %g mm, cornea %g mm, sclera %g mm\n"
               "             (about %.0f tets estimated before meshing; at most %d)\n", ho,
            eye->h_incision, hc, eye->h_sclera, tets, KT_EYE_MAX_TETS);
    if (eye->h_floor > 0)
        fprintf(f, "             incision floor %g mm within %g deg of the meridians %g and %g deg\n",
                eye->h_floor, eye->floor_sector > 0 && eye->floor_sector < 90 ? eye->floor_sector : 90,
                eye->floor_centre, fmod(eye->floor_centre + 180, 360));
    if (hc < eye->h_cornea || ho < eye->h_optical)
        fprintf(f, "             (eye.mesh_size asks for optical zone %g mm, cornea %g mm: element order %d "
                   "allows at most %.3g mm, central_thickness/%g)\n", eye->h_optical, eye->h_cornea, r->order,
                eye->t_central / kt_eye_layers(r->order), kt_eye_layers(r->order));
}

/* What the written coordinates are: the stress-free shape computed from the measured one, or
 * the scene's geometry as it is. */
static void print_reference(FILE *f, const run_info *r)
{
    if (r->unloaded) {
        fprintf(f, "reference    stress-free shape that the loads deform into the scene's (measured) geometry\n"
                   "             (loads.reference: loaded): %d solves, residual max |X0 + u(X0) - X_measured| = %.3g um\n"
                   "             (tolerance %.3g um; %.3g um with the measured shape taken as stress-free),\n"
                   "             nodes moved up to %.1f um (%.2f s)\n",
                r->rs.iters, 1000 * r->rs.residual, 1000 * r->ro.tol, 1000 * r->rs.initial, 1000 * r->rs.shift,
                r->t_ref);
    } else if (r->s->reference == KT_REFERENCE_PRESTRESSED) {
        fprintf(f, "reference    the scene's (measured) geometry under its loads, kept as it is: augsolve\n"
                   "             linearizes about it with the loads' prestress (loads.reference: prestressed)\n");
    } else if (r->s->reference == KT_REFERENCE_UNLOADED) {
        fprintf(f, "reference    the scene's geometry, taken as stress-free (loads.reference: unloaded)\n");
    } else {
        fprintf(f, "reference    the scene's geometry (no loads: it is stress-free)\n");
    }
}

static void print_summary(FILE *f, const kt_mesh *m, const run_info *r)
{
    fprintf(f, "scene        %s (model %s, element order %d)\n", r->o->scene, model_name(r->s->model), r->order);
    fprintf(f, "mesh         %d nodes, %d tets, %d surface triangles (%.2f s)\n", m->nn, m->ne, m->nf, r->t_mesh);
    print_groups(f, m, 3);
    print_groups(f, m, 2);
    print_sizes(f, r);
    print_reference(f, r);
    fprintf(f, "quality      dihedral angle min %.2f deg, max %.2f deg; radius ratio 3r_in/r_circ min %.3f (tet %d), mean %.3f\n",
            r->q.dihedral_min, r->q.dihedral_max, r->q.ratio_min, r->q.worst + 1, r->q.ratio_mean);
    fprintf(f, "dofs         %d, of which %d fixed (identity rows in the analysis)\n", 3 * m->nn, r->nfixed);
    fprintf(f, "closure set  %s: %d nodes\n", r->set_label, r->nrow ? r->row[0].st.nset : r->nset);
    fprintf(f, "orderings    %s(closures in DOFs: elimination-tree paths from a node's DOFs to the root)\n",
            r->chosen_only ? "the chosen one only, --chosen-only " : "");
    fprintf(f, "  %-12s %12s %12s %8s %13s %12s %12s %9s\n", "method", "nnz(L)", "flops", "height",
            "closure mean", "closure max", "|closure(S)|", "order s");
    for (int i = 0; i < r->nrow; i++) {
        const kt_prep_row *w = &r->row[i];
        fprintf(f, "%c %-12s %12.4g %12.4g %8d %13.1f %12d %12ld %9.3f\n", w->method == r->chosen ? '*' : ' ',
                kt_order_name(w->method), w->st.nnz_L, w->st.flops, w->st.height, w->st.closure_mean,
                w->st.closure_max, w->st.closure_union, w->t_order);
    }
    const kt_prep_row *best = NULL, *chosen = NULL;
    for (int i = 0; i < r->nrow; i++) {
        if (!best || r->row[i].st.flops < best->st.flops) best = &r->row[i];
        if (r->row[i].method == r->chosen) chosen = &r->row[i];
    }
    if (chosen && best && chosen->st.flops > 5 * best->st.flops)
        fprintf(f, "note         %s costs %.1fx the factor flops and %.1fx the nnz(L) of %s\n",
                kt_order_name(chosen->method), chosen->st.flops / best->st.flops,
                chosen->st.nnz_L / best->st.nnz_L, kt_order_name(best->method));
    if (r->nsector) {
        fprintf(f, "sector       the %d set nodes within 30 deg of meridian %g deg and its opposite (a paired\n"
                   "             60-degree LRI there); the set is swept from that meridian (ordering.centre)\n",
                r->nsector, r->s->ordering_centre);
        fprintf(f, "  %-12s %13s %12s %12s\n", "method", "closure mean", "closure max", "|closure|");
        for (int i = 0; i < r->nrow; i++) {
            const kt_prep_row *w = &r->row[i];
            fprintf(f, "%c %-12s %13.1f %12d %12ld\n", w->method == r->chosen ? '*' : ' ',
                    kt_order_name(w->method), w->sector.closure_mean, w->sector.closure_max,
                    w->sector.closure_union);
        }
    }
    fprintf(f, "output       %s (%s MSH 4.1, nodes numbered in %s order; written in %.2f s)\n",
            r->o->out, r->o->binary ? "binary" : "ASCII", kt_order_name(r->chosen), r->t_write);
    fprintf(f, "time         %.2f s in all\n", r->t_total);
}

/* Fail early, before meshing, if the output cannot be created. */
static int probe_output(const char *path, kt_err *e)
{
    struct stat st;
    if (strcmp(path, "-") == 0) return KT_OK;
    if (kt_out_check(path, e)) return e->code;
    if (stat(path, &st) == 0 && !S_ISREG(st.st_mode)) return KT_OK; /* written to directly */
    kt_out o;
    if (kt_out_open(&o, path, e)) return e->code;
    kt_out_abort(&o);
    return KT_OK;
}

/* Compare the orderings on the unpermuted mesh; *perm gets the chosen one. metis-last is
 * METIS's order with the set moved last: METIS is deterministic on one graph, so the metis row's
 * order is reused (its time is METIS's plus the move). One symbolic analysis per ordering gives
 * the figures of the set and of the sector. */
static int compare_orderings(const kt_mesh *m, const unsigned char *fixed, const int *set,
                             const int *rank, int nset, const int *sector, int nsector,
                             run_info *r, int *perm, kt_err *e)
{
    int methods[] = {KT_ORDERING_AMD, KT_ORDERING_METIS, KT_ORDERING_CONSTRAINED,
                     KT_ORDERING_METIS_LAST, KT_ORDERING_NATURAL};
    int *p = kt_calloc((size_t)m->nn, sizeof(int), e), *pm = kt_calloc((size_t)m->nn, sizeof(int), e);
    if (!p || !pm) {
        free(p), free(pm);
        return e->code;
    }
    double t_metis = -1;
    r->nrow = 0;
    for (int i = 0; i < 5; i++) {
        int meth = methods[i];
        if ((meth == KT_ORDERING_NATURAL || r->chosen_only) && r->chosen != meth) continue;
        kt_prep_row *w = &r->row[r->nrow++];
        w->method = meth;
        double t0 = kt_now();
        if (meth == KT_ORDERING_METIS_LAST && t_metis >= 0) {
            memcpy(p, pm, sizeof(int) * (size_t)m->nn);
            if (kt_order_move_last(m, set, rank, nset, p, e)) break;
            w->t_order = t_metis + (kt_now() - t0);
        } else {
            if (kt_order_nodes_ranked(m, meth, set, rank, nset, p, e)) break;
            w->t_order = kt_now() - t0;
        }
        if (meth == KT_ORDERING_METIS) {
            memcpy(pm, p, sizeof(int) * (size_t)m->nn);
            t_metis = w->t_order;
        }
        const int *sets[2] = {set, sector};
        int nsets[2] = {nset, nsector};
        kt_order_stats st[2];
        if (kt_order_analyze_sets(m, p, fixed, nsector ? 2 : 1, sets, nsets, st, e)) break;
        w->st = st[0];
        if (nsector) w->sector = st[1];
        if (meth == r->chosen) memcpy(perm, p, sizeof(int) * (size_t)m->nn);
        kt_log(r->o->quiet, "mesh-prep: ordering %s: nnz(L) %.4g\n", kt_order_name(meth), w->st.nnz_L);
    }
    free(p);
    free(pm);
    return e->code;
}

/* The geometry is the measured shape under the loads: replace it by the stress-free one. */
static int unload(const kt_prep_opts *o, const kt_scene *s, run_info *r, kt_mesh *m, kt_err *e)
{
    if (s->reference != KT_REFERENCE_LOADED) return KT_OK;
    for (int i = 0; i < s->nmat; i++)
        if (s->mat[i].fibre)
            return kt_fail(e, KT_EINPUT, "%s: materials.%s: model fibre needs loads.reference "
                           "prestressed or unloaded (the stress-free iteration is isotropic only)",
                           s->path, s->mat[i].region);
    double t0 = kt_now();
    kt_refgeom_opts_default(s, &r->ro);
    r->ro.quiet = o->quiet;
    if (kt_refgeom_unload(s, m, &r->ro, &r->rs, e)) return e->code;
    r->unloaded = r->rs.iters > 0;
    r->t_ref = kt_now() - t0;
    return kt_mesh_check(m, "stress-free geometry", e);
}

static int run_mesh(const kt_prep_opts *o, const kt_scene *s, run_info *r, kt_mesh *m, FILE *summary, kt_err *e)
{
    double t0 = kt_now();
    if (kt_build_mesh(s, r->order, o->quiet, m, e)) return e->code;
    r->t_mesh = kt_now() - t0;
    if (kt_mesh_check(m, o->scene, e)) return e->code;
    unsigned char *fixed = kt_calloc(3 * (size_t)m->nn, 1, e);
    int *set = NULL, *rank = NULL, *sector = NULL, *perm = kt_calloc((size_t)m->nn, sizeof(int), e);
    char label[160];
    if (!fixed || !perm || kt_fem_check_scene(s, m, fixed, e) || unload(o, s, r, m, e))
        goto done;
    kt_mesh_quality(m, &r->q);
    if (kt_orderset_nodes(s, m, &set, &r->nset, label, e) ||
        kt_orderset_ranks(s, m, set, r->nset, &rank, e) ||
        kt_orderset_sector(s, m, set, r->nset, &sector, &r->nsector, e))
        goto done;
    r->set_label = label;
    for (size_t k = 0; k < 3 * (size_t)m->nn; k++) r->nfixed += fixed[k];
    if (compare_orderings(m, fixed, set, rank, r->nset, sector, r->nsector, r, perm, e) ||
        kt_mesh_permute(m, perm, e))
        goto done;
    double t1 = kt_now();
    if (kt_msh_write(o->out, m, o->binary, e)) goto done;
    r->t_write = kt_now() - t1;
    r->t_total = kt_now() - t0;
    if (summary) print_summary(summary, m, r);
done:
    free(fixed);
    free(set);
    free(rank);
    free(sector);
    free(perm);
    return e->code;
}

/* The scene reader bounds the eye's tets at the scene's order; --order can ask for another. */
static int check_budget(const kt_prep_opts *o, const kt_scene *s, int order, kt_err *e)
{
    if (s->model != KT_MODEL_EYE || order == s->order) return KT_OK;
    kt_err ge = {0};
    double tets;
    if (kt_eye_estimate_tets(&s->eye, order, &tets, &ge) || tets <= KT_EYE_MAX_TETS) return KT_OK;
    return kt_fail(e, KT_EINPUT, "%s: eye.mesh_size: expected sizes that ask for at most %d tets "
                   "at order %d (--order), these ask for about %.3g million (keratome-scene(5), "
                   "LIMITS)", o->scene, KT_EYE_MAX_TETS, order, tets / 1e6);
}

int kt_prep_run(const kt_prep_opts *o, FILE *summary, kt_err *e)
{
    return kt_prep_run_table(o, KT_PREP_TABLE_ALL, summary, e);
}

int kt_prep_run_table(const kt_prep_opts *o, int table, FILE *summary, kt_err *e)
{
    kt_scene *s = kt_calloc(1, sizeof *s, e);
    if (!s) return e->code;
    run_info r;
    memset(&r, 0, sizeof r);
    kt_mesh m;
    memset(&m, 0, sizeof m);
    if (kt_scene_load(o->scene, s, e)) goto done;
    const char *in[] = {o->scene, s->cgal.path};
    if (kt_out_distinct(o->out, in, 2, e) || probe_output(o->out, e)) goto done;
    r.o = o;
    r.chosen_only = table == KT_PREP_TABLE_CHOSEN;
    r.s = s;
    r.order = o->order ? o->order : s->order;
    r.chosen = o->ordering ? o->ordering : s->ordering;
    if (check_budget(o, s, r.order, e)) goto done;
    run_mesh(o, s, &r, &m, summary, e);
done:
    kt_mesh_free(&m);
    free(s);
    return e->code;
}
