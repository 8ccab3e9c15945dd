/* The numerical libraries' run-time settings the program chooses for itself (numerics.c). */
#ifndef CAIRN_CLI_NUMERICS_H
#define CAIRN_CLI_NUMERICS_H

/* The sparse factorisations on one thread (OpenMP and the BLAS pool). */
void cli_numerics_one_thread(void);

/* When OpenBLAS chose a kernel below what the processor runs (a processor newer than the
 * library), or started a pool of several threads the user did not ask for, starts the program
 * again from its beginning with the kernel named in OPENBLAS_CORETYPE and OPENBLAS_NUM_THREADS
 * at 1; returns when it does nothing (or when that fails). Call first in main. */
void cli_blas_kernel(char **argv);

#endif
