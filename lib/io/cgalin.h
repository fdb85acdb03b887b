/* cgalin.h: the CGAL mesher's input files (a closed surface: OFF, STL, OBJ, PLY; a labelled
 * image: INR, optionally gzipped) checked before CGAL reads them, whose readers size their
 * arrays from the counts a header declares. */
#ifndef KT_CGALIN_H
#define KT_CGALIN_H

#include "util.h"

/* The largest input file, bytes (1 GiB). */
#define KT_CGALIN_MAX_BYTES ((long long)1 << 30)

/* KT_OK when path is a regular file of at most KT_CGALIN_MAX_BYTES whose header's counts
 * (an OFF's vertices and faces; a plain INR's voxels) the rest of the file can hold: at least
 * 6 bytes a vertex and 2 a face in text OFF, 12 and 16 in binary, one voxel of PIXSIZE bits
 * each in INR. Else KT_EINPUT: "path: expected ..." (a device, a FIFO or a directory, too
 * large, counts beyond the file). Other formats and a gzipped INR: the file checks only. */
int kt_cgalin_check(const char *path, kt_err *e);

#endif
