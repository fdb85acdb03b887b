/* incise.c: mesh topology for cutting, node splitting, and the step generator. */
#include "incise_int.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Does face j of a tet hold the node at local position l? */
static int face_has(int j, int l)
{
    if (l < 4) return l != j;
    return kt_tet_edge[l - 4][0] != j && kt_tet_edge[l - 4][1] != j;
}

/* ---- splitting ---- */

/* The tets currently holding node v, with v's local position in each. */
static int star(kt_incise *c, int v)
{
    int o = c->origin[v], n = 0;
    for (int p = c->n2t_p[o]; p < c->n2t_p[o + 1]; p++) {
        int t = c->n2t_i[p];
        const int *tv = c->cur + (size_t)t * c->nv;
        for (int l = 0; l < c->nv; l++)
            if (tv[l] == v) {
                c->s_tet[n] = t;
                c->s_loc[n++] = l;
                break;
            }
    }
    return n;
}

static int star_index(const kt_incise *c, int n, int t)
{
    for (int i = 0; i < n; i++)
        if (c->s_tet[i] == t) return i;
    return -1;
}

static int new_node(kt_incise *c, int v, kt_err *e)
{
    if (c->nn == c->cap) {
        int cap = 2 * c->cap;
        int *o = kt_realloc(c->origin, (size_t)cap, sizeof(int), e);
        if (!o) return -1;
        c->origin = o;
        c->cap = cap;
    }
    c->origin[c->nn] = c->origin[v];
    return c->nn++;
}

/* Move the tets of component root r (of the n star tets) from v to a new node. */
static int move_component(kt_incise *c, int v, int n, int r, kt_step *s, kt_err *e)
{
    int *el = kt_calloc((size_t)n, sizeof(int), e);
    if (!el) return e->code;
    int w = new_node(c, v, e), nel = 0;
    if (w < 0) {
        free(el);
        return e->code;
    }
    for (int i = 0; i < n; i++)
        if (kt_incise_uf_find(c->s_par, i) == r) {
            el[nel++] = c->s_tet[i];
            c->cur[(size_t)c->s_tet[i] * c->nv + c->s_loc[i]] = w;
        }
    kt_edit ed = {0};
    ed.kind = KT_EDIT_DUP;
    ed.node = v;
    ed.new_node = w;
    ed.nel = nel;
    ed.el = el;
    kt_step_add(s, &ed, e);
    free(el);
    return e->code;
}

/* Split node v along the cut faces through it; *nsplit counts the new nodes. Components of its
 * star (tets joined across uncut faces) are labelled by the sides of the cut faces they touch:
 * the first component on the stay side keeps v, every other labelled one gets a new node. */
static int split_node(kt_incise *c, int v, kt_step *s, int *nsplit, kt_err *e)
{
    int n = star(c, v);
    for (int i = 0; i < n; i++) {
        c->s_par[i] = i;
        c->s_lab[i] = 0;
    }
    for (int i = 0; i < n; i++) {
        int t = c->s_tet[i], l = c->s_loc[i];
        for (int j = 0; j < 4; j++) {
            if (!face_has(j, l)) continue;
            int slot = 4 * t + j;
            if (c->cut[slot]) {
                c->s_lab[i] |= c->side[slot] > 0 ? 2 : 1;
                continue;
            }
            if (c->nbr[slot] < 0) continue;
            int k = star_index(c, n, c->nbr[slot] / 4);
            if (k >= 0) c->s_par[kt_incise_uf_find(c->s_par, i)] = kt_incise_uf_find(c->s_par, k);
        }
    }
    /* label of each root: the union of its tets' labels */
    for (int i = 0; i < n; i++) {
        int r = kt_incise_uf_find(c->s_par, i);
        if (r != i) c->s_lab[r] |= c->s_lab[i];
    }
    int keep = -1, best = 99;
    static const int RANK[4] = {1, 0, 3, 2}; /* prefer stay side, then unlabelled, conflict, move */
    for (int i = 0; i < n; i++)
        if (kt_incise_uf_find(c->s_par, i) == i && RANK[c->s_lab[i]] < best) {
            best = RANK[c->s_lab[i]];
            keep = i;
        }
    for (int i = 0; i < n; i++) {
        if (kt_incise_uf_find(c->s_par, i) != i || i == keep || c->s_lab[i] == 0) continue;
        if (move_component(c, v, n, i, s, e)) return e->code;
        (*nsplit)++;
    }
    return KT_OK;
}

static int cmp_int(const void *a, const void *b)
{
    int x = *(const int *)a, y = *(const int *)b;
    return (x > y) - (x < y);
}

static int add_cand(kt_incise *c, int v, kt_err *e)
{
    if (c->ncand == c->capcand) {
        int cap = c->capcand ? 2 * c->capcand : 256;
        int *p = kt_realloc(c->s_cand, (size_t)cap, sizeof(int), e);
        if (!p) return e->code;
        c->s_cand = p;
        c->capcand = cap;
    }
    c->s_cand[c->ncand++] = v;
    return KT_OK;
}

int kt_incise_cut(kt_incise *c, kt_phase *ph, const kt_cutface *f, int n, kt_step *s,
                  int *ndup, kt_err *e)
{
    c->ncand = 0;
    c->st.work_done += n;
    int pos[6];
    for (int i = 0; i < n; i++) {
        int slot = f[i].slot, other = c->nbr[slot];
        if (c->cut[slot]) {
            ph->skipped++;
            continue;
        }
        c->cut[slot] = c->cut[other] = 1;
        c->side[slot] = (signed char)(f[i].side > 0 ? 1 : -1);
        c->side[other] = (signed char)-c->side[slot];
        c->st.faces++;
        int np = kt_incise_face_pos(c->m->order, slot % 4, pos);
        for (int k = 0; k < np; k++)
            if (add_cand(c, c->cur[(size_t)(slot / 4) * c->nv + pos[k]], e)) return e->code;
        np = kt_incise_face_pos(c->m->order, other % 4, pos);
        for (int k = 0; k < np; k++)
            if (add_cand(c, c->cur[(size_t)(other / 4) * c->nv + pos[k]], e)) return e->code;
    }
    qsort(c->s_cand, (size_t)c->ncand, sizeof(int), cmp_int);
    int nsplit = 0;
    for (int i = 0; i < c->ncand; i++) {
        if (i > 0 && c->s_cand[i] == c->s_cand[i - 1]) continue;
        if (split_node(c, c->s_cand[i], s, &nsplit, e)) return e->code;
    }
    *ndup += nsplit;
    c->st.dups += nsplit;
    return KT_OK;
}

/* ---- pull-apart forces of a planar cut ---- */

static int add_pair(kt_phase *ph, int a, int b, kt_err *e)
{
    if (ph->npair == ph->cappair) {
        int cap = ph->cappair ? 2 * ph->cappair : 64;
        int *p = kt_realloc(ph->pair, (size_t)cap, 2 * sizeof(int), e);
        if (!p) return e->code;
        ph->pair = p;
        ph->cappair = cap;
    }
    ph->pair[2 * ph->npair] = a;
    ph->pair[2 * ph->npair + 1] = b;
    ph->npair++;
    return KT_OK;
}

/* After a step's duplications: pull the new pairs on the pull surface (or, without one, the
 * first step's pairs) apart; every pulled node's force is re-emitted so each side's total stays
 * pull_force. */
static int pull_forces(kt_incise *c, kt_phase *ph, kt_step *s, int first_edit, kt_err *e)
{
    if (ph->pull_force <= 0.0) return KT_OK;
    int before = ph->npair;
    for (int i = first_edit; i < s->n; i++) {
        const kt_edit *ed = &s->edit[i];
        if (ed->kind != KT_EDIT_DUP) continue;
        int on = ph->pull_node ? ph->pull_node[c->origin[ed->node]] : ph->k == 1;
        if (on && add_pair(ph, ed->node, ed->new_node, e)) return e->code;
    }
    if (ph->npair == before) return KT_OK;
    double f = ph->pull_force / ph->npair;
    for (int i = 0; i < ph->npair; i++)
        for (int sgn = -1; sgn <= 1; sgn += 2) {
            kt_edit ed = {0};
            ed.kind = KT_EDIT_FORCE;
            ed.node = ph->pair[2 * i + (sgn > 0)];
            for (int k = 0; k < 3; k++) ed.v[k] = sgn * f * ph->pull_dir[k] + 0.0; /* no -0 */
            if (kt_step_add(s, &ed, e)) return e->code;
            c->st.forces++;
        }
    return KT_OK;
}

/* ---- steps ---- */

static void label_range(const kt_phase *ph, double a, double b, kt_step *s)
{
    if (ph->key_unit == KT_KEY_DEG)
        snprintf(s->label, sizeof s->label, "arc %.4g-%.4g deg (%s)", a, b, ph->name);
    else
        snprintf(s->label, sizeof s->label, "front %.4g-%.4g mm (%s)", a, b, ph->name);
}

/* One step of a cut: the next degrees_per_step of travel (a portion that splits no node merges
 * into the next one), or groups of faces of equal travel until nodes_per_step nodes split. */
static int cut_step(kt_incise *c, kt_phase *ph, kt_step *s, kt_err *e)
{
    int ndup = 0, first = s->n;
    double from = ph->done;
    ph->k++;
    while (ph->pos < ph->nface && (ph->nps > 0 ? ndup < ph->nps : ndup == 0)) {
        int end = ph->pos;
        if (ph->dps > 0) {
            double thr = fmin(ph->done + ph->dps, ph->total);
            while (end < ph->nface && ph->face[end].key <= thr + 1e-9) end++;
            ph->done = thr;
        } else {
            double key = ph->face[end].key, tol = 1e-12 * (1.0 + fabs(key));
            while (end < ph->nface && ph->face[end].key <= key + tol) end++;
            ph->done = key;
        }
        if (kt_incise_cut(c, ph, ph->face + ph->pos, end - ph->pos, s, &ndup, e)) return e->code;
        ph->pos = end;
    }
    if (ph->pos >= ph->nface) ph->done = ph->total;
    label_range(ph, from, ph->done, s);
    return pull_forces(c, ph, s, first, e);
}

static int phase_done(const kt_phase *ph)
{
    if (ph->kind == KT_PHASE_CUT) return ph->pos >= ph->nface;
    return ph->k >= ph->nsteps;
}

int kt_incise_next(kt_incise *c, kt_step *s, kt_err *e)
{
    kt_step_clear(s);
    while (c->iphase < c->nphase) {
        kt_phase *ph = &c->phase[c->iphase];
        if (phase_done(ph)) {
            if (ph->skipped)
                kt_log(c->quiet, "cutplan: note: %s: %ld faces already cut by an earlier incision "
                       "were skipped\n", ph->name, ph->skipped);
            c->st.skipped += ph->skipped;
            c->iphase++;
            continue;
        }
        int rc = ph->kind == KT_PHASE_CUT ? cut_step(c, ph, s, e) : kt_incise_deform_step(c, ph, s, e);
        if (rc) return -1;
        if (s->n == 0) continue; /* an overlap that split nothing: no step */
        s->index = ++c->st.steps;
        if (ph->kind == KT_PHASE_CUT && kt_incise_anchor_check(c, ph, s->index, e)) return -1;
        return 1;
    }
    return 0;
}

/* ---- setup of the phases ---- */

static int add_phases(kt_incise *c, kt_err *e)
{
    const kt_plan *p = c->plan;
    int n = p->ndeform + p->ntunnel + p->ninc + (p->planar.set ? 1 : 0);
    c->phase = kt_calloc((size_t)n, sizeof *c->phase, e);
    if (!c->phase) return e->code;
    c->maxphase = n;
    for (int i = 0; i < p->ndeform; i++, c->nphase++)
        if (kt_incise_deform_phase(c, &p->deform[i], i, &c->phase[c->nphase], e)) return e->code;
    for (int i = 0; i < p->ntunnel; i++, c->nphase++) /* the main incisions first */
        if (kt_incise_tunnel_phase(c, &p->tunnel[i], i, &c->phase[c->nphase], e)) return e->code;
    for (int i = 0; i < p->ninc; i++, c->nphase++) {
        const kt_incision *inc = &p->inc[i];
        kt_phase *ph = &c->phase[c->nphase];
        int rc = inc->surface[0] ? kt_incise_ring_phase(c, inc, i, ph, e)
                                 : kt_incise_cylinder_phase(c, inc, i, ph, e);
        if (rc) return e->code;
        ph->at = inc->at;
    }
    if (p->planar.set) {
        if (kt_incise_planar_phase(c, &c->phase[c->nphase], e)) return e->code;
        c->phase[c->nphase++].at = p->planar.at;
    }
    for (int i = 0; i < c->nphase; i++)
        c->st.work += c->phase[i].kind == KT_PHASE_CUT ? c->phase[i].nface : c->phase[i].nsteps;
    return KT_OK;
}

int kt_incise_begin(kt_incise **cp, const kt_plan *p, kt_mesh *m, int quiet, kt_err *e)
{
    *cp = NULL;
    kt_incise *c = kt_calloc(1, sizeof *c, e);
    if (!c) return e->code;
    c->plan = p;
    c->m = m;
    c->quiet = quiet;
    if (kt_incise_tables(c, e) || kt_incise_anchor_init(c, e) || add_phases(c, e)) {
        kt_incise_end(c);
        return e->code;
    }
    *cp = c;
    return KT_OK;
}

const kt_incise_stats *kt_incise_stats_get(const kt_incise *c) { return &c->st; }

void kt_incise_end(kt_incise *c)
{
    if (!c) return;
    for (int i = 0; c->phase && i < c->maxphase; i++) {
        free(c->phase[i].face);
        free(c->phase[i].pull_node);
        free(c->phase[i].pair);
        free(c->phase[i].nodes);
    }
    free(c->phase);
    free(c->cur);
    free(c->held);
    free(c->origin);
    free(c->nbr);
    free(c->cut);
    free(c->side);
    free(c->n2t_p);
    free(c->n2t_i);
    free(c->ftab);
    free(c->s_tet);
    free(c->s_loc);
    free(c->s_par);
    free(c->s_lab);
    free(c->s_cand);
    free(c);
}
