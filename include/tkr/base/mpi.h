// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_base_mpi_h
#define tkr_base_mpi_h

#include <deal.II/base/exceptions.h>
#include <deal.II/base/utilities.h>

#include <mpi.h>

#include <functional>
#include <type_traits>
#include <utility>
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
   * Displacements of MPI_Allgatherv from the per-rank @p counts, and the
   * total as the last entry; refused beyond what an int counts.
   */
  std::vector<int>
  offsets_of(const std::vector<int> &counts);

  /**
   * Every rank's @p local values (double, int, 64-bit integers or char),
   * concatenated in the order of the ranks of @p communicator. @p offsets,
   * if given, receives where each rank's values start (offsets_of()).
   */
  template <typename T>
  std::vector<T>
  all_gather_values(const std::vector<T> &local,
                    const MPI_Comm        communicator,
                    std::vector<int>     *offsets = nullptr)
  {
    static_assert(std::is_same_v<T, double> || std::is_same_v<T, int> ||
                    std::is_same_v<T, char> ||
                    (std::is_integral_v<T> && sizeof(T) == 8),
                  "all_gather_values() knows no MPI type for T.");
    const MPI_Datatype type    = std::is_same_v<T, double> ? MPI_DOUBLE :
                                 std::is_same_v<T, int>    ? MPI_INT :
                                 std::is_same_v<T, char>   ? MPI_CHAR :
                                                             MPI_INT64_T;
    int                n_ranks = 1;
    int                ierr    = MPI_Comm_size(communicator, &n_ranks);
    AssertThrowMPI(ierr);
    std::vector<int> counts(n_ranks);
    const int        n_local = local.size();
    ierr                     = MPI_Allgather(&n_local,
                         1,
                         MPI_INT,
                         counts.data(),
                         1,
                         MPI_INT,
                         communicator);
    AssertThrowMPI(ierr);
    std::vector<int> displacements = offsets_of(counts);
    std::vector<T>   all(displacements.back());
    ierr = MPI_Allgatherv(local.data(),
                          n_local,
                          type,
                          all.data(),
                          counts.data(),
                          displacements.data(),
                          type,
                          communicator);
    AssertThrowMPI(ierr);
    if (offsets != nullptr)
      *offsets = std::move(displacements);
    return all;
  }

  /**
   * Every rank's @p object (anything dealii::Utilities::pack() takes), in
   * the order of the ranks: dealii::Utilities::MPI::all_gather() without
   * its zlib pass, which took most of the exchange of a gait cycle's step
   * results (issue 34).
   */
  template <typename T>
  std::vector<T>
  all_gather_objects(const MPI_Comm communicator, const T &object)
  {
    std::vector<int>        offsets;
    const std::vector<char> all =
      all_gather_values(dealii::Utilities::pack(object, false),
                        communicator,
                        &offsets);
    std::vector<T> objects;
    for (std::size_t r = 0; r + 1 < offsets.size(); ++r)
      objects.push_back(
        dealii::Utilities::unpack<T>(all.cbegin() + offsets[r],
                                     all.cbegin() + offsets[r + 1],
                                     false));
    return objects;
  }

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
   * From now on, SIGTERM and SIGUSR1 (what SLURM and PBS send before a
   * job's time limit) set a flag instead of ending the process; the wear
   * run and the study check it (stop_requested()) at safe points and stop
   * with a consistent checkpoint (doc/cluster.md).
   */
  void
  install_stop_handlers();

  /**
   * The signal one of the ranks of @p communicator received (SIGTERM,
   * SIGUSR1), or 0 if none did. Collective.
   */
  int
  stop_requested(const MPI_Comm communicator);

  /** "SIGTERM", "SIGUSR1" or "signal N". */
  std::string
  signal_name(const int signal);

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

    MPI_Comm communicator;
    /**
     * The ranks with this rank's place in every group (one per group) if
     * the groups are of equal size, else this rank alone: what a group
     * computed for all groups reaches each of its ranks' peers.
     */
    MPI_Comm     peers;
    unsigned int n_groups;
    unsigned int index;
    /** Rank 0 of the group. */
    bool is_group_root;
  };
} // namespace TKR

#endif
