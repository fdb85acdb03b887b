/* kt_test_gmsh.h: for a test program that meshes with gmsh. gmsh 4.8 keeps a few allocations
 * of its surface mesher (meshGFace) to the end: inside libgmsh, not ours to report. The
 * sanitizer build's LeakSanitizer reads these hooks, so only leaks from libgmsh itself are
 * ignored, silently. Include it in one file of the program. */
#ifndef KT_TEST_GMSH_H
#define KT_TEST_GMSH_H

const char *__lsan_default_suppressions(void);
const char *__lsan_default_suppressions(void) { return "leak:libgmsh.so\n"; }
const char *__lsan_default_options(void);
const char *__lsan_default_options(void) { return "print_suppressions=0"; }

#endif
