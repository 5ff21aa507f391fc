// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_output_progress_h
#define tkr_output_progress_h

#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/mpi.h>

#include <tkr/wear/wear_state.h>

#include <string>
#include <vector>

namespace TKR::Output
{
  /**
   * The progress of a long run, on the screen (rank 0 of the run) and
   * appended to `progress.log` in the output directory, so that a run in
   * the background can be followed with `tail -f` (doc/output.md).
   */
  class Progress
  {
  public:
    Progress(const std::string &directory, const MPI_Comm mpi_communicator);

    /** @p line on the screen and at the end of progress.log. */
    void
    say(const std::string &line) const;

    /**
     * The line of a finished block: block/blocks, cycles, mass loss, depth
     * and wear area of @p last, and (unless @p testing) the block's wall
     * time and the estimated time left at that pace.
     */
    void
    block(const unsigned int       block,
          const unsigned int       n_blocks,
          const double             cycles,
          const Wear::BlockResult &last,
          const double             block_wall_time,
          const bool               testing) const;

    /** The last line of a run whose @p failed steps make it fail. */
    void
    failure(const std::vector<Wear::FailedStep> &failed) const;

  private:
    const std::string          log_file;
    dealii::ConditionalOStream pcout;
  };
} // namespace TKR::Output

#endif
