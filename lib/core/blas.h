/* blas.h: the BLAS thread count, pinned so that an answer does not depend on the machine. */
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

#endif
