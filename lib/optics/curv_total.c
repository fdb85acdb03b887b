/* curv_total.c: posterior corneal power and the thick-lens total corneal power. */
#include <math.h>
#include <stdlib.h>

#include "curv_total.h"

#define DEG KT_CURV_DEG

void kt_cornea_n_default(kt_cornea_n *n)
{
    n->air = KT_N_AIR, n->cornea = KT_N_CORNEA, n->aqueous = KT_N_AQUEOUS;
}

/* Zone-averaged axial curvature of meridian t, 1/mm. */
static double curvature(const kt_fit *f, double t) { return kt_curv_meridian_k(f, t) / KT_CURV_N_KERATO; }

static double total_of(double ka, double kp, double d, const kt_cornea_n *n)
{
    double pa = 1000 * (n->cornea - n->air) * ka, pp = 1000 * (n->aqueous - n->cornea) * kp;
    return pa + pp - d / 1000 / n->cornea * pa * pp;
}

double kt_curv_total_meridian(const kt_fit *ant, const kt_fit *post, const kt_cornea_n *n, double t)
{
    return total_of(curvature(ant, t), curvature(post, t), ant->az - post->az, n);
}

void kt_curv_total(const kt_fit *ant, const kt_fit *post, const kt_cornea_n *n, kt_total *o)
{
    double kp[KT_CURV_NMERID];
    o->thickness = ant->az - post->az;
    for (int i = 0; i < KT_CURV_NMERID; i++) {
        double t = i * 180.0 / KT_CURV_NMERID;
        kp[i] = curvature(post, t);
        o->pmer[i] = total_of(curvature(ant, t), kp[i], o->thickness, n);
    }
    double dn = 1000 * (n->aqueous - n->cornea);
    o->post_axis = kt_curv_harmonic_axis(kp);
    o->post_steep = dn * curvature(post, o->post_axis);
    o->post_flat = dn * curvature(post, o->post_axis + 90);
    o->post_cyl = fabs(o->post_steep) - fabs(o->post_flat);
    o->tot_axis = kt_curv_harmonic_axis(o->pmer);
    o->tot_steep = kt_curv_total_meridian(ant, post, n, o->tot_axis);
    o->tot_flat = kt_curv_total_meridian(ant, post, n, o->tot_axis + 90);
    o->tot_cyl = o->tot_steep - o->tot_flat;
    o->tot_mean = 0.5 * (o->tot_steep + o->tot_flat);
}

void kt_curv_total_none(kt_total *o)
{
    o->thickness = o->post_steep = o->post_flat = o->post_axis = o->post_cyl = NAN;
    o->tot_steep = o->tot_flat = o->tot_axis = o->tot_cyl = o->tot_mean = NAN;
    for (int i = 0; i < KT_CURV_NMERID; i++) o->pmer[i] = NAN;
}

int kt_curv_posterior_mask(const kt_mesh *m, unsigned char **mask, kt_err *e)
{
    *mask = NULL;
    const kt_group *inner = kt_mesh_find_group(m, 2, "inner"), *cornea = kt_mesh_find_group(m, 3, "cornea");
    if (!inner || !cornea) return KT_OK;
    int *ni = NULL, *nc = NULL, ci = 0, cc = 0;
    unsigned char *mk = NULL;
    int rc = kt_mesh_group_nodes(m, inner, &ni, &ci, e);
    if (rc == KT_OK) rc = kt_mesh_group_nodes(m, cornea, &nc, &cc, e);
    if (rc == KT_OK && !(mk = kt_calloc(m->nn, 1, e))) rc = e->code;
    if (rc == KT_OK) {
        for (int i = 0; i < ci; i++) mk[ni[i]] = 1;
        for (int i = 0; i < cc; i++) mk[nc[i]] |= 2;
        int any = 0;
        for (int i = 0; i < m->nn; i++) any |= (mk[i] = mk[i] == 3);
        if (any) *mask = mk;
        else free(mk);
    }
    free(ni), free(nc);
    return rc;
}
