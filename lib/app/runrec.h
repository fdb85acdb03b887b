/* runrec.h: the provenance block of an augsolve run's run.yaml: what was solved (the scene's
 * bytes as a hash and as text, its materials and loads as read), by which tools (keratome,
 * CHOLMOD, METIS, the compiler), and the solver's figures from the run's steps.tsv (largest
 * factor, largest residual, time). The mesh is named once, at run.yaml's top level (mesh,
 * mesh_hash, mesh_nodes, mesh_tets), not here. augsolve(1) documents the keys. */
#ifndef KT_RUNREC_H
#define KT_RUNREC_H

#include <stdio.h>

#include "scene.h"

/* The 64-bit FNV-1a hash of a file's bytes (*nbytes: its size); KT_EINPUT when unreadable. */
int kt_runrec_file_hash(const char *path, uint64_t *hash, long *nbytes, kt_err *e);

/* Append the `provenance:` mapping to run.yaml being written on f: sc is the scene as loaded,
 * run_dir the folder whose steps.tsv is complete.
 * Fails (KT_ERUN) only when the scene file can no longer be read or a write fails, and
 * (KT_EINPUT, "file:line:col: expected ...") when steps.tsv holds a field that is not a number. */
int kt_runrec_write(FILE *f, const char *run_dir, const kt_scene *sc, kt_err *e);

#endif
