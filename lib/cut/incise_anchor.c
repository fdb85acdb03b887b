/* incise_anchor.c: a cut must not sever a piece of the body from everything that holds it in
 * place: the piece would float free and the stiffness of every later step would be singular.
 * Checked after each cut step on the tets' current nodes. Nor, in a prestressed scene, leave a
 * tet hanging by one face (its other three cut or on the boundary): the prestress's stress
 * stiffness can outweigh the material stiffness of the one tet that holds it (the lamellar
 * cornea is soft in transverse shear), and the tangent is then not positive definite. */
#include <stdlib.h>

#include "bind.h"
#include "incise_int.h"

/* held[v]: input node v has a DOF fixed by the scene. */
int kt_incise_anchor_init(kt_incise *c, kt_err *e)
{
    int nn = c->m->nn;
    unsigned char *fixed = kt_calloc((size_t)3 * nn, 1, e);
    c->held = kt_calloc((size_t)nn, 1, e);
    if (fixed && c->held && kt_fem_dirichlet(&c->plan->scene, c->m, fixed, NULL, NULL, e) == KT_OK)
        for (int v = 0; v < nn; v++) {
            c->held[v] = fixed[3 * v] | fixed[3 * v + 1] | fixed[3 * v + 2];
            c->nheld += c->held[v];
        }
    free(fixed);
    return e->code;
}

/* KT_EINPUT when a tet with at most two faces on the mesh's boundary now has three or more cut
 * or on the boundary (prestressed scenes only). */
static int hanging(kt_incise *c, const kt_phase *ph, int step, kt_err *e)
{
    if (c->plan->scene.reference != KT_REFERENCE_PRESTRESSED) return KT_OK;
    for (int t = 0; t < c->m->ne; t++) {
        int bound = 0, shut = 0;
        for (int j = 0; j < 4; j++) {
            int s = 4 * t + j;
            bound += c->nbr[s] < 0;
            shut += c->nbr[s] < 0 || c->cut[s];
        }
        if (bound > 2 || shut < 3) continue;
        double x[3] = {0, 0, 0};
        for (int k = 0; k < 4; k++)
            for (int q = 0; q < 3; q++) x[q] += 0.25 * c->m->xyz[3 * (size_t)c->m->tet[(size_t)t * c->nv + k] + q];
        return kt_fail(e, KT_EINPUT, "%s:%d:%d: %s: step %d leaves an element hanging by one face (at %.3g %.3g %.3g "
                       "mm): under the prestress its stiffness would not be positive definite; move or shorten "
                       "the cut, or mesh finer there", c->plan->path, ph->at.line, ph->at.col, ph->name, step,
                       x[0], x[1], x[2]);
    }
    return KT_OK;
}

int kt_incise_anchor_check(kt_incise *c, const kt_phase *ph, int step, kt_err *e)
{
    if (c->nheld == 0) return KT_OK; /* nothing is fixed anywhere: augsolve reports that */
    int nn = c->nn, ne = c->m->ne, nv = c->nv;
    int *par = kt_calloc((size_t)nn, sizeof(int), e);
    int *count = kt_calloc((size_t)nn, sizeof(int), e);
    unsigned char *ok = kt_calloc((size_t)nn, 1, e);
    if (e->code) goto done;
    for (int v = 0; v < nn; v++) par[v] = v;
    for (int t = 0; t < ne; t++) {
        const int *tv = c->cur + (size_t)t * nv;
        int a = kt_incise_uf_find(par, tv[0]);
        for (int l = 1; l < nv; l++) {
            int b = kt_incise_uf_find(par, tv[l]);
            if (b != a) par[b] = a;
        }
    }
    for (int v = 0; v < nn; v++) {
        int r = kt_incise_uf_find(par, v);
        count[r]++;
        ok[r] |= c->held[c->origin[v]];
    }
    for (int v = 0; v < nn; v++) {
        int r = kt_incise_uf_find(par, v);
        if (ok[r]) continue;
        const double *x = c->m->xyz + 3 * (size_t)c->origin[v];
        kt_fail(e, KT_EINPUT, "%s:%d:%d: %s: step %d cuts off a piece of %d nodes (node %d at "
                "%.3g %.3g %.3g mm among them) from every node the scene fixes: it would float "
                "free and the stiffness would be singular; shorten or move the cut",
                c->plan->path, ph->at.line, ph->at.col, ph->name, step, count[r], v + 1, x[0],
                x[1], x[2]);
        break;
    }
done:
    free(par);
    free(count);
    free(ok);
    return e->code ? e->code : hanging(c, ph, step, e);
}
