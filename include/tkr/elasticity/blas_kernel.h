// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_elasticity_blas_kernel_h
#define tkr_elasticity_blas_kernel_h

#include <string>

namespace TKR::Elasticity::BlasKernel
{
  /** The vector instructions of a processor that OpenBLAS's kernels use. */
  struct Processor
  {
    bool avx    = false;
    bool avx2   = false; // with FMA
    bool avx512 = false; // F, VL, BW and DQ, with the OS's support
  };

  /** This processor's (GCC's __builtin_cpu_supports). */
  Processor
  this_processor();

  /**
   * The OpenBLAS core type (OPENBLAS_CORETYPE) to ask for on @p processor
   * when OpenBLAS chose @p core, or "" to keep it. OpenBLAS built with
   * DYNAMIC_ARCH (Debian's) picks its kernels by the processor's model
   * number; a processor newer than the library (Debian 12's OpenBLAS
   * 0.3.21 on a 5th-generation Xeon, model 207) falls back to the
   * Prescott kernels of 2004 (SSE3), whose dgemm is what CHOLMOD's
   * supernodal solves spend their time in. Only such a fallback (a core
   * of the Intel line without AVX: Prescott, Core2, Penryn, Dunnington,
   * Nehalem) on a processor with AVX is replaced, by the best of SkylakeX
   * (AVX-512), Haswell (AVX2 and FMA) and Sandybridge (AVX); any other
   * core (Sandybridge, Haswell, SkylakeX, Zen, Cooperlake, ...) is
   * OpenBLAS's informed choice and kept.
   */
  std::string
  better_core(const std::string &core, const Processor &processor);

  /**
   * Called first in main(), before MPI starts: if the BLAS is OpenBLAS,
   * OPENBLAS_CORETYPE is not set and better_core() names a core, set it
   * and execute the program again with the same arguments (OpenBLAS reads
   * the variable only when it is loaded). Returns if nothing is to be done
   * or the program cannot be executed again.
   */
  void
  select(char *argv[]);

  /**
   * What select() did, for the run's header: "" if it did nothing, else
   * e.g. "OpenBLAS's SkylakeX kernels (it chose Prescott on this
   * processor, which it does not know; OPENBLAS_CORETYPE overrides)".
   */
  std::string
  note();
} // namespace TKR::Elasticity::BlasKernel

#endif
