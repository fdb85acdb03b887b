/* edits.h: the edits stream (man5 keratome-edits): progressive node duplications, Dirichlet
 * constraints and nodal forces, grouped by step. Line-oriented text, streamable:
 *
 *   keratome-edits 1
 *   scene "plans/eye.yaml"             (the scene the mesh was built from)
 *   plan "plans/lri-paired-60.yaml"    (optional: the plan, for curvature's target)
 *   hash 3f1c0d5e9a2b7c41             (optional: kt_mesh_hash of that mesh, 16 hex digits)
 *   mesh "eye.msh" 20411 98231        (file, node count, tet count the edits apply to)
 *   step 1 "arc 0-5 deg"
 *   dup 1204 20412 3 88 91 1502       (node, new node, count, the tets that move to it)
 *   fix 17 xyz 0 0 0.1                (node, components, values in mm)
 *   force 17 0 0 -0.01                (node, nodal force in N, replacing any earlier one)
 *   end
 *   done 1                            (the last record: the number of steps)
 *
 * Node and tet numbers are 1-based, as in the MSH file; a new node takes the next free number.
 * '#' starts a comment (outside a quoted string). Paths and labels are double-quoted with
 * backslash escapes (bare ones are read too). A stream without its 'done' record, or whose
 * count differs from the steps read, is cut short: an error (KT_EINPUT). */
#ifndef KT_EDITS_H
#define KT_EDITS_H

#include <stdint.h>
#include <stdio.h>

#include "util.h"

enum { KT_EDIT_DUP = 1, KT_EDIT_FIX, KT_EDIT_FORCE };

/* Bounds the reader enforces (keratome-edits(5), LIMITS), besides the mesh's own
 * (KT_MESH_MAX_NODES, KT_MESH_MAX_TETS, for the header's counts and the nodes dups add). */
#define KT_EDITS_MAX_LINE (1 << 20)    /* bytes in one line */
#define KT_EDITS_MAX_DUP_TETS 10000    /* tets moved by one dup (a node has far fewer) */
#define KT_EDITS_MAX_STEPS 1000000     /* steps in a stream */

/* One edit; numbers here are 0-based. */
typedef struct kt_edit {
    int kind;
    int node;        /* the node edited */
    int new_node;    /* DUP: the new node's number */
    int nel;         /* DUP: how many tets move to the new node */
    int *el;         /* DUP: those tets (owned) */
    unsigned mask;   /* FIX: components fixed (bit c) */
    double v[3];     /* FIX: displacement, mm; FORCE: force, N */
    long line;       /* where the reader found it (0: not read from a stream) */
    int col;         /* DUP: column of its first tet number */
} kt_edit;

typedef struct kt_step {
    int index;       /* 1, 2, ... */
    char label[128];
    int n, cap;
    kt_edit *edit;   /* owned */
} kt_step;

typedef struct kt_edits_header {
    char scene[1024];
    char plan[1024];   /* may be empty */
    char mesh[1024];
    int nn, ne;      /* counts of the mesh the edits apply to */
    int has_hash;    /* 1: hash holds the content hash (kt_mesh_hash) of that mesh; 0: an older
                        header without one, checked by the counts alone */
    uint64_t hash;
} kt_edits_header;

typedef struct kt_edits_reader {
    FILE *f;
    const char *name; /* for messages */
    long line;
    int last_step;
    int nn_cur;      /* node count after the dups read so far (for range checks) */
    int done;        /* the 'done' record was read */
    kt_edits_header h;
} kt_edits_reader;

/* Read the header. */
int kt_edits_open(kt_edits_reader *r, FILE *f, const char *name, kt_err *e);
/* Read the next step into s (cleared first); returns 1 for a step, 0 after the stream's 'done'
 * record (its count checked, nothing after it), or -1 with e set: the end of the input before
 * 'done' is an error (a stream cut short, or a header alone). */
int kt_edits_next(kt_edits_reader *r, kt_step *s, kt_err *e);

void kt_step_clear(kt_step *s);  /* keep the allocation, drop the edits */
void kt_step_free(kt_step *s);
/* Append an edit (copies el). */
int kt_step_add(kt_step *s, const kt_edit *ed, kt_err *e);

int kt_edits_write_header(FILE *f, const kt_edits_header *h, kt_err *e);
/* Write one step and flush, so a reader downstream can start. */
int kt_edits_write_step(FILE *f, const kt_step *s, kt_err *e);
/* Write the last record, "done N" (N >= 1, the steps written), and flush. */
int kt_edits_write_done(FILE *f, int nsteps, kt_err *e);

#endif
