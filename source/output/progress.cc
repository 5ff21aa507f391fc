// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <tkr/output/progress.h>

#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>

namespace TKR::Output
{
  using namespace dealii;

  Progress::Progress(const std::string &directory,
                     const MPI_Comm     mpi_communicator)
    : log_file(directory + "/progress.log")
    , pcout(std::cout, Utilities::MPI::this_mpi_process(mpi_communicator) == 0)
  {}

  void
  Progress::say(const std::string &line) const
  {
    pcout << line << std::endl;
    if (pcout.is_active())
      {
        std::ofstream log(log_file, std::ios::app);
        log << line << std::endl;
      }
  }

  void
  Progress::block(const unsigned int       block,
                  const unsigned int       n_blocks,
                  const double             cycles,
                  const Wear::BlockResult &last,
                  const double             block_wall_time,
                  const bool               testing) const
  {
    std::ostringstream line;
    line << "Block " << std::setw(4) << block << "/" << n_blocks << ": "
         << std::setw(9) << cycles << " cycles, mass loss " << last.mass
         << " mg, max depth " << 1e3 * last.max_depth << " um, wear area "
         << last.wear_area_percent << " %";
    if (!testing)
      {
        const double remaining = (n_blocks - block) * block_wall_time;
        line << ", " << std::fixed << std::setprecision(1) << block_wall_time
             << " s/block, ETA " << std::setprecision(0) << remaining / 60.
             << " min";
      }
    say(line.str());
  }

  void
  Progress::failure(const std::vector<Wear::FailedStep> &failed) const
  {
    std::ostringstream line;
    line << "tkr-wear: " << failed.size()
         << " gait step(s) over the blocks did not converge or failed their "
            "load balance (summary.json lists them as unconverged_steps, "
            "the first in block "
         << (failed.empty() ? 0 : failed[0].block) << ", step "
         << (failed.empty() ? 0 : failed[0].step)
         << "): these results are not converged, exit code 1.";
    say(line.str());
  }
} // namespace TKR::Output
