// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <deal.II/base/exceptions.h>

#include <tkr/base/mpi.h>

namespace TKR
{
  void
  sum_over_ranks(std::vector<double> &values, const MPI_Comm communicator)
  {
    const int ierr = MPI_Allreduce(MPI_IN_PLACE,
                                   values.data(),
                                   values.size(),
                                   MPI_DOUBLE,
                                   MPI_SUM,
                                   communicator);
    AssertThrowMPI(ierr);
  }
} // namespace TKR
