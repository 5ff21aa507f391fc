// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <deal.II/base/timer.h>

#include <tkr/base/exceptions.h>
#include <tkr/problems/wear_problem.h>
#include <tkr/wear/activity_mix.h>
#include <tkr/wear/sliding.h>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace TKR::Problems
{
  using namespace dealii;

  namespace
  {
    /** The shares of @p activities. */
    std::vector<double>
    shares(const std::vector<Parameters::Activity> &activities)
    {
      std::vector<double> values;
      for (const auto &activity : activities)
        values.push_back(activity.share);
      return values;
    }
  } // namespace

  WearProblem::WearProblem(const Parameters::AllParameters &parameters,
                           const MPI_Comm                   mpi_communicator,
                           const bool                       resume)
    : resume(resume)
    , wear_run(parameters, mpi_communicator)
    , motion(wear_run.model.geometry(),
             wear_run.groups.communicator,
             wear_run.model.timer())
    , report(wear_run)
    , files(wear_run)
    , checkpoint(wear_run)
  {}

  void
  WearProblem::start()
  {
    const auto &parameters = wear_run.model.parameters();
    if (!resume)
      {
        wear_run.state.cycles_per_block =
          parameters.wear.cycles_per_extrapolation_step;
        if (wear_run.is_mix())
          {
            wear_run.state.activity_depth.assign(
              wear_run.activities.size(),
              std::vector<double>(wear_run.model.triangulation().n_vertices(),
                                  0.));
            wear_run.state.activity_volume.assign(wear_run.activities.size(),
                                                  {});
          }
        wear_run.state.history.push_back(Wear::BlockResult());
        wear_run.state.history.back().activities = wear_run.activity_results();
        return;
      }
    checkpoint.resume();
  }

  void
  WearProblem::solve_cycles(const bool first, const bool last)
  {
    // What a checkpoint of the last block done keeps, should a stop
    // signal end this block's cycles (their steps overwrite them).
    const std::vector<Gait::StepStart> starts = wear_run.step_starts();
    for (unsigned int a = 0; a < wear_run.cycles.size(); ++a)
      {
        GaitCycle &c = *wear_run.cycles[a];
        if (first)
          wear_run.model.pcout()
            << (!wear_run.is_mix() ?
                  std::string() :
                  "Activity " + wear_run.activities[a].name + ", ")
            << "Gait cycle, " << c.n_steps() << " steps:" << std::endl;
        try
          {
            c.solve(first, last, first);
          }
        catch (const ExcStopped &exc)
          {
            checkpoint.stop(exception_message(exc), starts);
          }
      }
  }

  // The wear law over each activity's cycle sliding gives each
  // tibia_contact node's depth (of a mix: weighted by the shares); the
  // block's statistics come from the step reports (WearReport).
  void
  WearProblem::compute_wear()
  {
    wear_run.activity_wear.clear();
    for (const auto &c : wear_run.cycles)
      wear_run.activity_wear.push_back(
        wear_run.law->cycle_wear(Wear::CycleSliding(c->get_records())));
    wear_run.cycle_wear =
      Wear::mix_cycle_wear(wear_run.activity_wear, shares(wear_run.activities));
    report.add_cycles();
  }

  // The law turns the block of n cycles into a number of cycles at the
  // computed cycle's rate (n, unless the rate depends on the cycle count);
  // the depth grows by that many times the cycle's depth at every
  // tibia_contact node; the node moves inward along the worn surface's
  // nodal normal (Geometry::WornGeometry::worn_surface_measures()) by the
  // new depth, and MeshMotion extends that into the tibia.
  double
  WearProblem::extrapolate()
  {
    const auto &parameters = wear_run.model.parameters();
    const auto &wear       = parameters.wear;
    // The surface the cycle wore (moving it updates the geometry's).
    const auto  measures = wear_run.model.geometry().worn_surface_measures();
    const auto &surface  = wear_run.model.geometry().worn_surface().nodes();
    const auto &x        = wear_run.model.geometry().vertex_positions();
    std::vector<double> medial_lateral;
    for (const auto &node : surface)
      medial_lateral.push_back(x[node.vertex][0]);
    wear_run.sides = Wear::SurfaceSides(medial_lateral,
                                        parameters.gait.medial_direction,
                                        measures.area);
    const std::vector<Tensor<1, 3>> displacement =
      wear_run.model.geometry().vertex_displacements();
    for (;;)
      {
        const double n = std::min(wear_run.state.cycles_per_block,
                                  wear.cycles - wear_run.state.cycles);
        const double effective =
          wear_run.law->effective_cycles(wear_run.state.cycles, n);
        std::vector<Tensor<1, 3>> target = displacement;
        std::vector<double>       increment(
          wear_run.model.triangulation().n_vertices(),
          0.);
        for (unsigned int j = 0; j < surface.size(); ++j)
          {
            const unsigned int v = surface[j].vertex;
            increment[v]         = effective * wear_run.cycle_wear.depth[j];
            target[v] -= increment[v] * measures.normal[j];
          }
        const auto moved      = motion.extend(target);
        const auto distortion = motion.distortion(moved);
        if (distortion.min_ratio >= wear.distortion_limit)
          {
            wear_run.model.geometry().set_vertex_displacements(moved);
            wear_run.model.geometry().add_wear_depth(increment);
            wear_run.state.volume +=
              effective *
              Wear::measure_wear(wear_run.cycle_wear.depth, measures.area, 0.)
                .volume;
            for (unsigned int j = 0; j < surface.size(); ++j)
              (wear_run.sides.medial()[j] ? wear_run.state.volume_medial :
                                            wear_run.state.volume_lateral) +=
                effective * wear_run.cycle_wear.depth[j] * measures.area[j];
            wear_run.add_activity_wear(effective, measures.area);
            wear_run.state.cycles += n;
            ++wear_run.state.block;
            return n;
          }
        const std::string message =
          distortion_message(n, distortion, increment);
        AssertThrow(wear.halve_step_on_distortion && n > 1,
                    ExcInputError(message +
                                  " Reduce Wear/Cycles per extrapolation "
                                  "step, set Halve step on distortion = "
                                  "true, or refine the mesh where the "
                                  "insert wears."));
        wear_run.state.cycles_per_block = 0.5 * n;
        wear_run.model.pcout()
          << "Warning: " << message << " Halving the cycles per block to "
          << wear_run.state.cycles_per_block << " and retrying." << std::endl;
      }
  }

  std::string
  WearProblem::distortion_message(const double                n,
                                  const Geometry::Distortion &distortion,
                                  const std::vector<double>  &increment) const
  {
    double depth = 0;
    for (const unsigned int v : distortion.vertices)
      depth =
        std::max(depth,
                 wear_run.model.geometry().wear_depth()[v] + increment[v]);
    const Point<3>    &x = distortion.centre;
    std::ostringstream message;
    message << "Block " << wear_run.state.block + 1 << " (" << n
            << " cycles from cycle " << wear_run.state.cycles
            << "): the worn geometry would distort tibia cell "
            << distortion.cell << " (centre " << x[0] << ", " << x[1] << ", "
            << x[2] << "), where the wear depth reaches " << depth
            << " mm: its smallest Jacobian would drop to "
            << distortion.min_ratio
            << " of the unworn cell's, below the Distortion limit of "
            << wear_run.model.parameters().wear.distortion_limit << ".";
    return message.str();
  }

  std::function<void(MPI_Comm)> WearProblem::start_hook;

  bool
  WearProblem::run()
  {
    const auto &parameters = wear_run.model.parameters();
    const auto &wear       = parameters.wear;
    wear_run.model.start("knee-simulator wear test");
    if (start_hook)
      start_hook(wear_run.model.world());
    AssertThrow(parameters.mesh.fe_degree == 1,
                ExcInputError(
                  "Problem = wear needs Finite element degree = 1."));
    wear_run.model.make_grid();
    wear_run.model.distribute_dofs();
    for (unsigned int a = 0; a < wear_run.cycles.size(); ++a)
      wear_run.cycles[a]->setup(a == 0);
    motion.setup();
    start();
    wear_run.model.pcout()
      << "Extrapolation: " << wear.cycles << " cycles in blocks of "
      << wear_run.state.cycles_per_block << ", stiffness updated "
      << (wear.stiffness_update_interval == 0 ?
            std::string("never") :
            "every " + std::to_string(wear.stiffness_update_interval) +
              " block(s)")
      << ", warm starts " << (wear.warm_start ? "on" : "off") << std::endl;
    while (wear_run.state.cycles < wear.cycles)
      {
        Timer              block_timer;
        const unsigned int block = wear_run.state.block + 1;
        const unsigned int R     = wear.stiffness_update_interval;
        if (block > 1 && R > 0 && (block - 1) % R == 0 &&
            wear_run.state.stiffness_block != block)
          {
            wear_run.model.geometry().update_stiffness_geometry();
            for (auto &c : wear_run.cycles)
              c->setup_solver();
            wear_run.state.stiffness_block = block;
          }
        const bool first = (block == 1);
        const bool last =
          wear_run.state.cycles + wear_run.state.cycles_per_block >=
          wear.cycles;
        solve_cycles(first, last);
        {
          TimerOutput::Scope scope(wear_run.model.timer(), "wear");
          compute_wear();
          extrapolate();
        }
        const double block_wall_time = block_timer.wall_time();
        files.block(report);
        report.block(block_wall_time);
        checkpoint.write_if_due();
      }
    unsigned int window_misses = 0;
    for (const auto &c : wear_run.cycles)
      window_misses +=
        wear_run.groups.is_group_root ? c->n_window_misses() : 0u;
    if (parameters.contact_solver.coupling_window > 0 &&
        !parameters.output.testing)
      wear_run.model.pcout()
        << "Coupling window: "
        << Utilities::MPI::sum(window_misses, wear_run.model.world())
        << " contact solves repeated on the whole search distance" << std::endl;
    files.finish();
    const bool converged = wear_run.model.finish(wear_run.state.converged);
    if (!converged)
      report.failure();
    return converged;
  }
} // namespace TKR::Problems
