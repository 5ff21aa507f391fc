// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.
//
// Elasticity::BlasKernel::better_core(): which OpenBLAS core a processor
// gets. A fallback of the Intel line without AVX (Prescott ... Nehalem) is
// replaced by the best core the instructions allow (SkylakeX with AVX-512,
// Haswell with AVX2 and FMA, Sandybridge with AVX); a core with AVX that
// OpenBLAS chose, a core of another line, or a processor without AVX keeps
// OpenBLAS's choice.
// The names are compared without case. select() keeps a user's
// OPENBLAS_CORETYPE (it returns).

#include <tkr/elasticity/blas_kernel.h>

#include <cstdlib>

#include "../tests.h"

int
main()
{
  initlog();
  using namespace TKR::Elasticity::BlasKernel;
  const Processor                                      none{};
  const Processor                                      avx{true, false, false};
  const Processor                                      avx2{true, true, false};
  const Processor                                      avx512{true, true, true};
  const std::vector<std::pair<std::string, Processor>> cases = {
    {"Prescott", avx512},
    {"Prescott", avx2},
    {"Prescott", avx},
    {"Prescott", none},
    {"prescott", avx512},
    {"Core2", avx2},
    {"Nehalem", avx512},
    {"Sandybridge", avx},
    {"Sandybridge", avx2},
    {"Haswell", avx2},
    {"Haswell", avx512},
    {"SkylakeX", avx512},
    {"Cooperlake", avx512},
    {"SapphireRapids", avx512},
    {"Zen", avx2},
    {"Atom", avx2},
    {"", avx512}};
  for (const auto &[core, processor] : cases)
    {
      const std::string better = better_core(core, processor);
      deallog << "core '" << core << "', avx " << processor.avx << " avx2 "
              << processor.avx2 << " avx512 " << processor.avx512 << ": "
              << (better.empty() ? "keep" : better) << std::endl;
    }

  // select() leaves a set OPENBLAS_CORETYPE alone (else it would have run
  // this test again before initlog()).
  setenv("OPENBLAS_CORETYPE", "Haswell", 1);
  char  name[] = "blas_kernel_01";
  char *argv[] = {name, nullptr};
  select(argv);
  deallog << "select() with OPENBLAS_CORETYPE set: returned, note '" << note()
          << "'" << std::endl;

  deallog << "OK" << std::endl;
}
