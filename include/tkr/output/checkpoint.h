// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_output_checkpoint_h
#define tkr_output_checkpoint_h

#include <tkr/wear/wear_state.h>

#include <mpi.h>

#include <string>

namespace TKR::Output
{
  /** The checkpoint file of an output directory. */
  std::string
  checkpoint_file(const std::string &directory);

  /**
   * Write @p state as an HDF5 file (`checkpoint.h5` in @p directory, on
   * rank 0): attributes for the counters, datasets for the per-vertex
   * displacements and depth, the steps' warm starts and the history.
   * Written into a temporary file that is renamed when complete, so a
   * crash (or SIGKILL) never leaves a half-written checkpoint, only the
   * previous one.
   */
  void
  write_checkpoint(const std::string        &directory,
                   const Wear::WearRunState &state,
                   const MPI_Comm            mpi_communicator);

  /**
   * Read the checkpoint of @p directory (on every rank). Throws
   * ExcInputError naming the file if it does not exist, cannot be read, or
   * does not fit a mesh with @p n_vertices vertices and a gait of
   * @p n_steps steps.
   */
  Wear::WearRunState
  read_checkpoint(const std::string &directory,
                  const unsigned int n_vertices,
                  const unsigned int n_steps);
} // namespace TKR::Output

#endif
