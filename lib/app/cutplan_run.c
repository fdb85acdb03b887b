/* cutplan_run.c: the cutplan tool's work: plan + mesh -> edits stream. */
#define _XOPEN_SOURCE 700
#include "cutplan_run.h"

#include "incise.h"

#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "msh.h"

/* The absolute path of an existing file ("-" and failures give the path as it is); one that
 * does not fit the header's 1023 bytes is refused (cut, it would name another file). */
static int abs_path(const char *path, char *buf, size_t size, kt_err *e)
{
    char tmp[PATH_MAX];
    const char *src = strcmp(path, "-") != 0 && realpath(path, tmp) ? tmp : path;
    size_t n = strlen(src);
    if (n >= size)
        return kt_fail(e, KT_EINPUT, "expected a path of at most %zu bytes for the edits header "
                       "(keratome-edits(5)), found %zu: %s", size - 1, n, path);
    memcpy(buf, src, n + 1);
    return KT_OK;
}

/* Write the snapped mesh the edits apply to; snapping without a place for it is an error. */
static int write_snapped(const kt_cutplan_opts *o, const kt_mesh *m, int snapped, kt_err *e)
{
    if (snapped == 0) {
        if (o->mesh_out) return kt_msh_write(o->mesh_out, m, o->binary, e);
        return KT_OK;
    }
    if (!o->mesh_out)
        return kt_fail(e, KT_EINPUT, "snapping moved %d nodes of %s onto the cutting "
                       "surface: give --mesh-out FILE for the snapped mesh the edits apply to",
                       snapped, o->mesh);
    return kt_msh_write(o->mesh_out, m, o->binary, e);
}

static int stream(const kt_cutplan_opts *o, const kt_plan *p, kt_incise *c, const kt_mesh *m,
                  kt_err *e)
{
    kt_edits_header h;
    memset(&h, 0, sizeof h);
    if (abs_path(p->scene_path, h.scene, sizeof h.scene, e) ||
        (strcmp(p->path, "-") != 0 && abs_path(p->path, h.plan, sizeof h.plan, e)) ||
        abs_path(o->mesh_out ? o->mesh_out : o->mesh, h.mesh, sizeof h.mesh, e))
        return e->code;
    h.nn = m->nn;
    h.ne = m->ne;
    h.hash = kt_mesh_hash(m); /* after snapping: the mesh the edits apply to */
    h.has_hash = 1;
    kt_out out;
    if (kt_out_open(&out, o->out, e)) return e->code;
    kt_step s = {0};
    kt_progress pr;
    const kt_incise_stats *st = kt_incise_stats_get(c);
    kt_progress_start(&pr, "cutplan", st->work, o->quiet);
    kt_err we = {0}; /* the writer's errors: a failed write is named by its file (kt_out_failed) */
    int rc = kt_edits_write_header(out.f, &h, &we);
    while (rc == KT_OK) {
        int more = kt_incise_next(c, &s, e);
        if (more <= 0) {
            rc = more < 0 ? e->code : KT_OK;
            break;
        }
        rc = kt_edits_write_step(out.f, &s, &we);
        kt_progress_update(&pr, st->work_done);
    }
    kt_step_free(&s);
    if (rc == KT_OK && st->steps == 0)
        rc = kt_fail(e, KT_EINPUT, "%s: the plan makes no step on %s (nothing to cut)", o->plan,
                     o->mesh);
    if (rc == KT_OK) rc = kt_edits_write_done(out.f, st->steps, &we);
    if (we.code && (out.is_stdout || kt_out_failed(&out, e) == KT_OK))
        kt_fail(e, we.code, "%s: %s", out.is_stdout ? "<stdout>" : o->out, we.msg);
    if (rc == KT_OK) rc = kt_out_commit(&out, e);
    else kt_out_abort(&out);
    rc = e->code;
    kt_progress_end(&pr);
    return rc;
}

int kt_cutplan_run(const kt_cutplan_opts *o, kt_err *e)
{
    double t0 = kt_now();
    kt_plan *p = kt_calloc(1, sizeof *p, e);
    kt_mesh m = {0};
    kt_incise *c = NULL;
    if (!p || kt_out_check(o->out, e) || (o->mesh_out && kt_out_check(o->mesh_out, e)) ||
        kt_plan_load(o->plan, p, e))
        goto done;
    const char *in[] = {o->plan, o->mesh, p->scene_path};
    if (kt_out_distinct(o->out, in, 3, e) || (o->mesh_out && kt_out_distinct(o->mesh_out, in, 3, e)) ||
        kt_msh_read(o->mesh, &m, e))
        goto done;
    if (kt_plan_check_mesh(p, &m, o->mesh, e)) goto done;
    double t1 = kt_now();
    if (kt_incise_begin(&c, p, &m, o->quiet, e)) goto done;
    const kt_incise_stats *st = kt_incise_stats_get(c);
    if (write_snapped(o, &m, st->snapped, e)) goto done;
    double t2 = kt_now();
    /* the mesh goes first (a reader down the pipe opens it at once); a failed cut takes it back */
    if (stream(o, p, c, &m, e)) {
        struct stat st; /* a device or FIFO written to directly is never removed */
        if (o->mesh_out && strcmp(o->mesh_out, "-") != 0 && lstat(o->mesh_out, &st) == 0 &&
            S_ISREG(st.st_mode))
            remove(o->mesh_out);
        goto done;
    }
    kt_log(o->quiet, "cutplan: %d steps, %ld nodes duplicated, %ld faces cut, %ld constraints, "
           "%ld forces; mesh %d nodes %d tets; load %.2f s, prepare %.2f s, steps %.2f s\n",
           st->steps, st->dups, st->faces, st->fixes, st->forces, m.nn, m.ne, t1 - t0, t2 - t1,
           kt_now() - t2);
done:
    kt_incise_end(c);
    kt_mesh_free(&m);
    free(p);
    return e->code;
}
