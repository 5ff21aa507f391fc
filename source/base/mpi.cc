// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <deal.II/base/exceptions.h>
#include <deal.II/base/mpi.h>

#include <tkr/base/exceptions.h>
#include <tkr/base/mpi.h>

#include <chrono>
#include <climits>
#include <csignal>
#include <string>
#include <thread>

namespace TKR
{
  namespace
  {
    /** The stop signal received (0: none), set by the handler. */
    volatile std::sig_atomic_t received_signal = 0;

    extern "C" void
    record_stop_signal(int signal)
    {
      received_signal = signal;
    }
  } // namespace

  void
  install_stop_handlers()
  {
    std::signal(SIGTERM, record_stop_signal);
    std::signal(SIGUSR1, record_stop_signal);
  }

  int
  stop_requested(const MPI_Comm communicator)
  {
    return dealii::Utilities::MPI::max(static_cast<int>(received_signal),
                                       communicator);
  }

  std::string
  signal_name(const int signal)
  {
    return signal == SIGTERM ? "SIGTERM" :
           signal == SIGUSR1 ? "SIGUSR1" :
                               "signal " + std::to_string(signal);
  }

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

  std::vector<int>
  offsets_of(const std::vector<int> &counts)
  {
    std::vector<int> offsets(counts.size() + 1, 0);
    for (std::size_t r = 0; r < counts.size(); ++r)
      {
        AssertThrow(static_cast<long long>(offsets[r]) + counts[r] <= INT_MAX,
                    dealii::ExcMessage("Too many values for one MPI call."));
        offsets[r + 1] = offsets[r] + counts[r];
      }
    return offsets;
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

  void
  in_turn(const std::function<void()> &work, const MPI_Comm communicator)
  {
    const unsigned int n_ranks =
      dealii::Utilities::MPI::n_mpi_processes(communicator);
    const unsigned int rank =
      dealii::Utilities::MPI::this_mpi_process(communicator);
    std::string error;
    for (unsigned int turn = 0; turn < n_ranks; ++turn)
      {
        if (turn == rank)
          try
            {
              work();
            }
          catch (const ExcInputError &exc)
            {
              error = exception_message(exc);
            }
        const int ierr = MPI_Barrier(communicator);
        AssertThrowMPI(ierr);
      }
    for (const auto &message :
         dealii::Utilities::MPI::all_gather(communicator, error))
      AssertThrow(message.empty(), ExcInputError(message));
  }

  bool
  all_ranks_arrive(const MPI_Comm communicator, const double seconds)
  {
    MPI_Request request;
    int         ierr = MPI_Ibarrier(communicator, &request);
    AssertThrowMPI(ierr);
    const auto start = std::chrono::steady_clock::now();
    for (;;)
      {
        int arrived = 0;
        ierr        = MPI_Test(&request, &arrived, MPI_STATUS_IGNORE);
        AssertThrowMPI(ierr);
        if (arrived)
          return true;
        const std::chrono::duration<double> waited =
          std::chrono::steady_clock::now() - start;
        if (waited.count() > seconds)
          return false;
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
      }
  }

  StepGroups::StepGroups(const MPI_Comm world, const unsigned int requested)
  {
    const unsigned int n_ranks = dealii::Utilities::MPI::n_mpi_processes(world);
    const unsigned int rank = dealii::Utilities::MPI::this_mpi_process(world);
    n_groups = (requested == 0 ? n_ranks : std::min(requested, n_ranks));
    index    = rank * n_groups / n_ranks;
    int ierr = MPI_Comm_split(world, index, rank, &communicator);
    AssertThrowMPI(ierr);
    const unsigned int place =
      dealii::Utilities::MPI::this_mpi_process(communicator);
    is_group_root = place == 0;
    ierr          = MPI_Comm_split(world,
                          n_ranks % n_groups == 0 ? place : n_groups + rank,
                          index,
                          &peers);
    AssertThrowMPI(ierr);
  }

  StepGroups::~StepGroups()
  {
    MPI_Comm_free(&peers);
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
