/* scene_write.c: an eye scene as YAML, every field explicit (%.17g: read back exactly). */
#include "scene_write.h"
#include "yml.h"

#include "scene_int.h"

#include <math.h>

#include "yml.h"

static const char *const ORDER_NAMES[] = {"amd", "metis", "constrained", "natural", "metis-last"};
static const char *const REF_NAMES[] = {"loaded", "unloaded", "prestressed"};

/* A length c (mm) in um, in the fewest digits (15 to 17) that read back (kt_yml_parse_quantity)
 * as c exactly, trying the nearest doubles to 1000 c; in mm (%.17g: exact) when none does. */
static void write_um(FILE *f, double c)
{
    char buf[64];
    for (int k = 0; k < 9; k++) {
        double u = c * 1e3;
        for (int s = 0; s < (k + 1) / 2; s++) u = nextafter(u, k % 2 ? INFINITY : -INFINITY);
        for (int p = 15; p <= 17; p++) {
            double back;
            snprintf(buf, sizeof buf, "%.*g um", p, u);
            if (kt_yml_parse_quantity(buf, KT_UNIT_LENGTH, &back) == 0 && back == c) {
                fputs(buf, f);
                return;
            }
        }
    }
    fprintf(f, "%.17g mm", c);
}

/* A measured surface's departure (eye_depart.h), one radial order a line. */
static void write_departure(FILE *f, const char *key, const kt_eye_departure *d)
{
    if (d->order <= 0) return;
    fprintf(f, "  %s:\n", key);
    if (d->conic != 0) fprintf(f, "    asphericity: %.17g\n", d->conic);
    fprintf(f, "    zernike_order: %d\n    radius: %.17g mm\n    taper: %.17g mm\n", d->order, d->radius, d->taper);
    fprintf(f, "    # OSA/ANSI j = 0 ... %d, normalized (each the term's RMS over the zone); a line per radial order\n",
            kt_zern_nterms(d->order) - 1);
    fprintf(f, "    coefficients: [");
    for (int n = 0, j = 0; n <= d->order; n++) {
        fprintf(f, "\n      ");
        for (int m = 0; m <= n; m++, j++) {
            write_um(f, d->coef[j]);
            if (j + 1 < kt_zern_nterms(d->order)) fputs(m < n ? ", " : ",", f);
        }
    }
    fprintf(f, "]\n");
}

static void write_eye(FILE *f, const kt_eye *y)
{
    fprintf(f, "eye:\n");
    fprintf(f, "  anterior_radius_steep: %.17g mm\n  anterior_radius_flat: %.17g mm\n", y->r_ant_steep, y->r_ant_flat);
    fprintf(f, "  steep_axis: %.17g deg\n", y->steep_axis);
    if (y->r_post_steep != y->r_post_flat)
        fprintf(f, "  posterior_radius_steep: %.17g mm\n  posterior_radius_flat: %.17g mm\n  posterior_steep_axis: %.17g deg\n",
                y->r_post_steep, y->r_post_flat, y->post_axis);
    else fprintf(f, "  posterior_radius: %.17g mm\n", y->r_post);
    fprintf(f, "  central_thickness: %.17g mm\n  peripheral_thickness: %.17g mm\n", y->t_central, y->t_peripheral);
    fprintf(f, "  white_to_white: {horizontal: %.17g mm, vertical: %.17g mm}\n  limbus_width: %.17g mm\n", y->wtw,
            y->wtw_v == 0 ? y->wtw : y->wtw_v, y->limbus_width);
    fprintf(f, "  sclera_thickness: %.17g mm\n  globe_radius: %.17g mm\n", y->sclera_thickness, y->globe_radius);
    fprintf(f, "  extent: %.17g deg\n  optical_zone: %.17g mm\n", y->extent, y->optical_zone);
    fprintf(f, "  fibres: {limbal_band: %.17g mm, limbal_density: %.17g}\n", y->fibre_band, y->fibre_density);
    fprintf(f, "  mesh_size:\n    optical_zone: %.17g mm\n    incision: %.17g mm\n", y->h_optical, y->h_incision);
    if (y->h_floor > 0) fprintf(f, "    incision_floor: %.17g mm\n", y->h_floor);
    if (y->h_floor > 0) fprintf(f, "    floor_grading: %.17g\n", kt_eye_floor_slope(y));
    fprintf(f, "    cornea: %.17g mm\n    sclera: %.17g mm\n", y->h_cornea, y->h_sclera);
    if (y->site_radius > 0)
        fprintf(f, "    site: {meridian: %.17g deg, distance: %.17g mm, radius: %.17g mm}\n", y->site_meridian,
                y->site_distance, y->site_radius);
    fprintf(f, y->nring ? "  incision_rings:\n" : "  incision_rings: []\n");
    for (int i = 0; i < y->nring; i++) {
        const kt_ring *r = &y->ring[i];
        fprintf(f, "    - name: %s\n      diameter: %.17g mm\n", r->name, r->diameter);
        if (r->depth_fraction > 0) fprintf(f, "      depth_fraction: %.17g\n", r->depth_fraction);
        else fprintf(f, "      depth: %.17g mm\n", r->depth);
    }
    write_departure(f, "anterior_departure", &y->dep_ant);
    write_departure(f, "posterior_departure", &y->dep_post);
}

int kt_scene_write_eye(FILE *f, const kt_scene *s, const char *header, kt_err *e)
{
    if (s->model != KT_MODEL_EYE) return kt_fail(e, KT_EINPUT, "scene '%s': only eye scenes are written", s->name);
    if (header) kt_yml_put_comment(f, header);
    fprintf(f, "name: %s\nmodel: eye\norder: %d\n", s->name, s->order);
    write_eye(f, &s->eye);
    fprintf(f, "ordering:\n  method: %s\n", ORDER_NAMES[s->ordering - 1]);
    if (s->ordering_set[0]) fprintf(f, "  last: %s\n", s->ordering_set);
    if (s->ordering_halo >= 0) fprintf(f, "  halo: %d\n", s->ordering_halo);
    if (!isnan(s->ordering_centre)) fprintf(f, "  centre: %.17g deg\n", s->ordering_centre);
    if (!isnan(s->ordering_sector)) fprintf(f, "  sector: %.17g deg\n", s->ordering_sector);
    fprintf(f, "materials:\n");
    for (int i = 0; i < s->nmat; i++) {
        const kt_region_mat *m = &s->mat[i];
        if (m->fibre && m->gt_profile[0] > 0)
            fprintf(f, "  %s: {model: fibre, E_inplane: %.17g MPa, E_inplane_2: %.17g MPa, G_transverse: %.17g MPa, nu: %.17g, "
                       "G_transverse_profile: [%.17g MPa, %.17g MPa, %.17g MPa]}\n",
                    m->region, m->E1, m->E2, m->Gt, m->nu, m->gt_profile[0], m->gt_profile[1], m->gt_profile[2]);
        else if (m->fibre)
            fprintf(f, "  %s: {model: fibre, E_inplane: %.17g MPa, E_inplane_2: %.17g MPa, G_transverse: %.17g MPa, nu: %.17g}\n",
                    m->region, m->E1, m->E2, m->Gt, m->nu);
        else
            fprintf(f, "  %s: {model: isotropic, E: %.17g MPa, nu: %.17g}\n", m->region, m->E, m->nu);
    }
    fprintf(f, "loads:\n  reference: %s\n  reference_tolerance: %.17g mm\n  pressure:\n", REF_NAMES[s->reference],
            s->reference_tol);
    for (int i = 0; i < s->npressure; i++)
        fprintf(f, "    - {surface: %s, value: %.17g MPa}\n", s->pressure[i].surface, s->pressure[i].p);
    fprintf(f, "fixation:\n");
    for (int i = 0; i < s->nfix; i++) {
        const kt_fixation *x = &s->fix[i];
        char comp[4];
        int k = 0;
        for (int c = 0; c < 3; c++)
            if (x->mask & (1u << c)) comp[k++] = "xyz"[c];
        comp[k] = '\0';
        fprintf(f, "  - {surface: %s, components: %s, value: [%.17g mm, %.17g mm, %.17g mm]}\n", x->surface, comp,
                x->value[0], x->value[1], x->value[2]);
    }
    /* the uncertainty section when it differs from the defaults (an age-scaled scene) */
    int head = 0;
    for (int q = 0; q < KT_UQ_N; q++) {
        const kt_uncertainty *u = &s->unc;
        int age = q == KT_UQ_AGE_SLOPE && isfinite(u->age);
        if (u->sd[q] == kt_uq_default_sd(q) && u->dist[q] == KT_UQ_NORMAL && !age) continue;
        if (!head++) fprintf(f, "uncertainty:\n");
        fprintf(f, "  %s: {sd: %.17g%s", kt_uq_name(q), u->sd[q],
                u->dist[q] == KT_UQ_UNIFORM ? ", distribution: uniform" : "");
        if (age) fprintf(f, ", age: %.17g", u->age);
        fprintf(f, "}\n");
    }
    if (s->unc.nontissue_cv != KT_UQ_NONTISSUE_CV) {
        if (!head++) fprintf(f, "uncertainty:\n");
        fprintf(f, "  nontissue_cv: %.17g\n", s->unc.nontissue_cv);
    }
    kt_scene_write_wound(f, &s->wound);
    if (ferror(f)) return kt_fail(e, KT_ERUN, "writing the scene '%s' failed", s->name);
    return KT_OK;
}
