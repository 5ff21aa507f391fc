// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_output_checkpoint_h
#define tkr_output_checkpoint_h

#include <tkr/parameters/parameters.h>
#include <tkr/wear/wear_state.h>

#include <mpi.h>

#include <map>
#include <string>

namespace TKR::Output
{
  /** The checkpoint file of an output directory. */
  std::string
  checkpoint_file(const std::string &directory);

  /**
   * The entries of @p parameters that determine the state of a wear run,
   * "Subsection/Entry" -> value: the mesh (its contents' checksum rather
   * than its path, which may move), its degree and groups, the materials,
   * the gait protocol with its waveform (checksum) and every Gait entry
   * but the step groups, and the Wear entries but Cycles (a run may be
   * resumed to go further) and the distortion handling (which may be
   * changed to get past a refused block); of the models' own subsections
   * only those of the run's law and protocol, their input files by
   * checksum.
   */
  std::map<std::string, std::string>
  state_parameters(const Parameters::AllParameters &parameters);

  /** state_parameters() as the "entry = value" lines a checkpoint keeps. */
  std::string
  state_parameters_text(const Parameters::AllParameters &parameters);

  /**
   * Refuse (ExcInputError naming @p filename and the entry) a checkpoint
   * whose @p recorded state parameters ("entry = value" lines, as written)
   * differ from the state_parameters() of @p parameters; entries recorded
   * under their paths before they moved into a model's subsection
   * (Parameters::moved_entries()) count under their new paths.
   */
  void
  check_state_parameters(const std::string               &filename,
                         const std::string               &recorded,
                         const Parameters::AllParameters &parameters);

  /**
   * Write @p state as an HDF5 file (`checkpoint.h5` in @p directory, on
   * rank 0): attributes for the counters and for the
   * state_parameters() of @p parameters, datasets for the per-vertex
   * displacements and depth, the steps' warm starts and the history.
   * Written into a temporary file that is renamed when complete, so a
   * crash (or SIGKILL) never leaves a half-written checkpoint, only the
   * previous one.
   */
  void
  write_checkpoint(const std::string               &directory,
                   const Wear::WearRunState        &state,
                   const Parameters::AllParameters &parameters,
                   const MPI_Comm                   mpi_communicator);

  /**
   * Read the checkpoint of @p directory on every rank of
   * @p mpi_communicator, one rank after another (deal.II opens an HDF5
   * file for reading and writing, under an exclusive lock: ranks that open
   * it at once fail). Throws ExcInputError on every rank, naming the file,
   * if it does not exist, cannot be opened or read,
   * does not fit a mesh with @p n_vertices vertices and a gait of
   * @p n_steps steps, or was written with other state_parameters() than
   * those of @p parameters (naming the first entry that differs).
   */
  Wear::WearRunState
  read_checkpoint(const std::string               &directory,
                  const unsigned int               n_vertices,
                  const unsigned int               n_steps,
                  const Parameters::AllParameters &parameters,
                  const MPI_Comm                   mpi_communicator);
} // namespace TKR::Output

#endif
