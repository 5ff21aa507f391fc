// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.
//
// WearCheckpoint: a wear run's checkpoint, read at a resume, written every
// Checkpoint interval blocks and at a stop signal.

#include <deal.II/base/timer.h>

#include <tkr/base/exceptions.h>
#include <tkr/output/checkpoint.h>
#include <tkr/problems/wear_run.h>

#include <algorithm>

namespace TKR::Problems
{
  using namespace dealii;

  WearCheckpoint::WearCheckpoint(WearRun &run)
    : run(run)
  {}

  void
  WearCheckpoint::resume()
  {
    const auto &parameters = run.model.parameters();
    const auto &directory  = parameters.output.directory;
    run.state              = Output::read_checkpoint(directory,
                                        run.model.triangulation().n_vertices(),
                                        run.n_steps(),
                                        parameters,
                                        run.model.world());
    run.model.geometry().set_vertex_displacements(
      run.state.displacement,
      run.state.stiffness_displacement);
    run.model.geometry().set_wear_depth(run.state.depth);
    AssertThrow(run.state.activity_volume.size() ==
                  (run.is_mix() ? run.activities.size() : 0),
                ExcInternalError());
    run.set_step_starts(run.state.step_starts);
    if (run.state.stiffness_block > 1)
      for (auto &c : run.cycles)
        c->setup_solver();
    const bool extrapolated =
      !run.state.step_starts.empty() &&
      std::all_of(run.state.step_starts.begin(),
                  run.state.step_starts.end(),
                  [](const Gait::StepStart &s) { return !s.previous.empty(); });
    run.model.pcout() << "Resumed from <" << Output::checkpoint_file(directory)
                      << ">: block " << run.state.block << ", "
                      << run.state.cycles << " cycles"
                      << (extrapolated ? ", warm starts extrapolated from the "
                                         "poses of the last two blocks" :
                                         "")
                      << std::endl;
  }

  void
  WearCheckpoint::write_if_due()
  {
    const auto &output = run.model.parameters().output;
    const bool  done   = run.state.cycles >= run.model.parameters().wear.cycles;
    if (output.checkpoint_interval == 0 ||
        (run.state.block % output.checkpoint_interval != 0 && !done))
      return;
    write();
  }

  void
  WearCheckpoint::stop(const std::string                  &signal,
                       const std::vector<Gait::StepStart> &starts)
  {
    const std::string file = run.model.parameters().parameter_file;
    std::string       kept =
      "before block 1 was done: there is nothing to continue; run <" + file +
      "> again";
    if (run.state.block > 0)
      {
        run.set_step_starts(starts);
        write();
        kept =
          "the checkpoint <" +
          Output::checkpoint_file(run.model.parameters().output.directory) +
          "> holds block " + std::to_string(run.state.block) + " (" +
          format_number(run.state.cycles, 6) + " cycles); tkr-wear --resume " +
          file + " continues the run";
      }
    AssertThrow(false,
                ExcStopped("Stopped by " + signal + " during block " +
                           std::to_string(run.state.block + 1) + ": " + kept +
                           "."));
  }

  void
  WearCheckpoint::write()
  {
    const auto        &output = run.model.parameters().output;
    TimerOutput::Scope scope(run.model.timer(), "checkpoint");
    run.state.displacement = run.model.geometry().vertex_displacements();
    run.state.stiffness_displacement =
      run.model.geometry().vertex_displacements(true);
    run.state.depth       = run.model.geometry().wear_depth();
    run.state.step_starts = run.step_starts();
    Output::write_checkpoint(output.directory,
                             run.state,
                             run.model.parameters(),
                             run.model.world());
    run.model.pcout() << "  checkpoint written after block " << run.state.block
                      << std::endl;
  }
} // namespace TKR::Problems
