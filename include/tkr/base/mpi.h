// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_base_mpi_h
#define tkr_base_mpi_h

#include <mpi.h>

#include <vector>

namespace TKR
{
  /**
   * Replace every entry of @p values by its sum over the ranks of
   * @p communicator (in place). The pattern of every "each rank fills what
   * it owns, one sum gives everybody everything" exchange in tkr-wear.
   */
  void
  sum_over_ranks(std::vector<double> &values, const MPI_Comm communicator);
} // namespace TKR

#endif
