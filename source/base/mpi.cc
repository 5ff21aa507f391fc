// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <deal.II/base/exceptions.h>
#include <deal.II/base/mpi.h>

#include <tkr/base/exceptions.h>
#include <tkr/base/mpi.h>

#include <string>

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

  void
  on_root(const std::function<void()> &work, const MPI_Comm communicator)
  {
    std::string error;
    if (dealii::Utilities::MPI::this_mpi_process(communicator) == 0)
      try
        {
          work();
        }
      catch (const ExcInputError &exc)
        {
          error = exception_message(exc);
        }
    error = dealii::Utilities::MPI::broadcast(communicator, error, 0);
    AssertThrow(error.empty(), ExcInputError(error));
  }

  StepGroups::StepGroups(const MPI_Comm world, const unsigned int requested)
  {
    const unsigned int n_ranks = dealii::Utilities::MPI::n_mpi_processes(world);
    const unsigned int rank = dealii::Utilities::MPI::this_mpi_process(world);
    n_groups       = (requested == 0 ? n_ranks : std::min(requested, n_ranks));
    index          = rank * n_groups / n_ranks;
    const int ierr = MPI_Comm_split(world, index, rank, &communicator);
    AssertThrowMPI(ierr);
    is_group_root = dealii::Utilities::MPI::this_mpi_process(communicator) == 0;
  }

  StepGroups::~StepGroups()
  {
    MPI_Comm_free(&communicator);
  }

  std::vector<unsigned int>
  StepGroups::own_items(const unsigned int n_items) const
  {
    std::vector<unsigned int> items;
    for (unsigned int i = index; i < n_items; i += n_groups)
      items.push_back(i);
    return items;
  }
} // namespace TKR
