// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_base_mpi_h
#define tkr_base_mpi_h

#include <mpi.h>

#include <functional>
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

  /**
   * Run @p work on rank 0 of @p communicator only (e.g. writing a file)
   * and raise an ExcInputError it raised there on every rank: no rank may
   * go on to the next collective operation alone while the others stop.
   */
  void
  on_root(const std::function<void()> &work, const MPI_Comm communicator);

  /**
   * Run @p work on every rank of @p communicator, one rank after another
   * (e.g. opening a file that takes an exclusive lock, such as an HDF5 file
   * opened by deal.II's HDF5::File), and raise the first ExcInputError any
   * rank raised on every rank, so that an error on one rank alone cannot
   * leave the others waiting.
   */
  void
  in_turn(const std::function<void()> &work, const MPI_Comm communicator);

  /**
   * Whether every rank of @p communicator calls this within @p seconds (a
   * non-blocking barrier, polled). After an error on this rank it tells
   * whether the other ranks raised it too (an input error every rank reads
   * the same way) or wait for this one in a collective operation, which
   * only MPI_Abort() ends. @p communicator must be used for nothing else
   * (a duplicate of the world communicator made at start-up).
   */
  bool
  all_ranks_arrive(const MPI_Comm communicator, const double seconds);

  /**
   * How long a rank that raised an error waits for the other ranks to raise
   * it too (all_ranks_arrive()) before it ends the run with MPI_Abort():
   * ranks that read the same input fail within a fraction of a second of
   * each other.
   */
  constexpr double error_grace_seconds = 30;

  /**
   * The split of the ranks of a communicator into groups that share
   * independent work items, e.g. the steps of a gait cycle (rank r is in
   * group r * n_groups / n_ranks; group g does the items g, g + n_groups,
   * ...). Owns the group communicator.
   */
  struct StepGroups
  {
    /** @p requested_groups: 0 for one group per rank. */
    StepGroups(const MPI_Comm world, const unsigned int requested_groups);
    ~StepGroups();
    StepGroups(const StepGroups &) = delete;
    StepGroups &
    operator=(const StepGroups &) = delete;

    /** The items (of @p n_items) this group does. */
    std::vector<unsigned int>
    own_items(const unsigned int n_items) const;

    MPI_Comm     communicator;
    unsigned int n_groups;
    unsigned int index;
    /** Rank 0 of the group. */
    bool is_group_root;
  };
} // namespace TKR

#endif
