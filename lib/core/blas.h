/* blas.h: the BLAS thread count, pinned so that an answer does not depend on the machine, and
 * the BLAS's work buffer, taken at a tool's start so that no later allocation failure can hang
 * inside the BLAS. */
#ifndef KT_BLAS_H
#define KT_BLAS_H

/* Run the BLAS on one thread, whatever OPENBLAS_NUM_THREADS or OMP_NUM_THREADS say: OpenBLAS
 * splits its level-3 kernels (the supernodal Cholesky's dsyrk, dgemm, dpotrf) by thread count,
 * which changes the order of the sums and so the last digits of a solution (1e-12 here); and
 * under a limit on address space (ulimit -v) a worker thread whose buffer allocation fails
 * retries it forever, so the process would hang instead of failing. Every tool calls this
 * first (kt_tool_start), before any BLAS call. Returns 1 when OpenBLAS was found and pinned, 0
 * for another BLAS (its own thread setting applies then: see augsolve(1), ENVIRONMENT). */
int kt_blas_pin(void);

/* OpenBLAS's work buffer for the calling thread (KT_BLAS_BUFFER bytes of address space, touched
 * only as used), mapped now by one small level-3 call. Debian's OpenBLAS 0.3.21 maps a thread's
 * buffer on its first level-3 or LAPACK call and keeps it to the process's end; when that mmap
 * fails (ulimit -v) it tries again in a loop with no end (driver/others/memory.c,
 * blas_memory_alloc), so a solve that ran out of address space after CHOLMOD's factor was
 * allocated hung with no message. Taken first, while the process is small, the buffer is never
 * asked for again on that thread (the tools call the BLAS from one thread). Returns
 * KT_BLAS_WARM_OK, KT_BLAS_WARM_NONE for another BLAS (nothing done), or KT_BLAS_WARM_NOROOM
 * when the address space left (ulimit -v) cannot hold the buffer: then nothing was called, and
 * a BLAS call would hang; kt_tool_start ends the tool with exit 1 and a message. */
enum { KT_BLAS_WARM_OK, KT_BLAS_WARM_NONE, KT_BLAS_WARM_NOROOM };
#define KT_BLAS_BUFFER ((size_t)128 << 20) /* OpenBLAS's BUFFER_SIZE on x86_64 (32 << 22) */
int kt_blas_warm(void);

#endif
