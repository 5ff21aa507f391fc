// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <deal.II/numerics/data_out.h>

#include <tkr/base/exceptions.h>
#include <tkr/output/solution_output.h>
#include <tkr/output/wear_output.h>
#include <tkr/problems/wear_problem.h>
#include <tkr/wear/archard.h>

#include <algorithm>

namespace TKR::Problems
{
  using namespace dealii;

  WearProblem::WearProblem(const Parameters::AllParameters &parameters,
                           const MPI_Comm                   mpi_communicator)
    : groups(mpi_communicator, parameters.gait.step_groups)
    , model(parameters, mpi_communicator, groups.communicator)
    , cycle(model, groups)
  {}

  // Archard's law integrated over the cycle gives each tibia_contact
  // node's depth; volume = sum of depth x D_jj, mass = density x volume.
  // The wear area counts the nodes whose depth, extrapolated linearly to
  // the Cycles of the parameter file, exceeds the wear-area threshold.
  // Quantities are printed per million cycles, so that the regression
  // tests compare O(1) numbers.
  void
  WearProblem::compute_wear()
  {
    const auto &parameters = model.parameters;
    const auto &wear       = parameters.wear;
    // k is given in mm^3/(N m); slips are in mm.
    wear_depth          = Wear::cycle_wear_depth(cycle.get_records(),
                                        1e-3 * wear.wear_coefficient,
                                        &slip);
    const double volume = Wear::worn_volume(wear_depth, cycle.get_coupling());
    const double mass   = parameters.materials.tibia.density * volume;
    const auto  &nodes  = cycle.get_coupling().slave_nodes();
    double       max_depth = 0, area = 0, worn_area = 0;
    for (unsigned int j = 0; j < wear_depth.size(); ++j)
      {
        max_depth = std::max(max_depth, wear_depth[j]);
        area += nodes[j].D;
        if (wear_depth[j] * wear.cycles > wear.wear_area_threshold)
          worn_area += nodes[j].D;
      }
    unsigned int n_newton = 0, n_solves = 0, n_converged = 0;
    double       max_pressure = 0, max_area = 0;
    for (const auto &r : cycle.get_reports())
      {
        n_newton += r.newton_iterations;
        n_solves += r.pose_updates + 1;
        n_converged += r.converged;
        max_pressure = std::max(max_pressure, r.max_pressure);
        max_area     = std::max(max_area, r.contact_area);
      }
    const unsigned int n_steps = cycle.n_steps();

    model.pcout << "Wear of one cycle (Archard, k = " << wear.wear_coefficient
                << " mm^3/(N m)):" << std::endl
                << "  volume loss:       " << 1e6 * volume
                << " mm^3 per million cycles" << std::endl
                << "  mass loss:         " << 1e6 * mass
                << " mg per million cycles" << std::endl
                << "  max wear depth:    " << 1e9 * max_depth
                << " um per million cycles" << std::endl
                << "  peak pressure:     " << max_pressure
                << " MPa (over the cycle)" << std::endl
                << "  max contact area:  " << max_area << " mm^2" << std::endl
                << "  wear area:         " << 100. * worn_area / area
                << " % of tibia_contact (depth x " << wear.cycles
                << " cycles > " << wear.wear_area_threshold << " mm)"
                << std::endl
                << "  linear extrapolation to " << wear.cycles
                << " cycles without geometry update: " << mass * wear.cycles
                << " mg" << std::endl
                << "  steps: " << n_steps << ", converged: " << n_converged
                << ", contact solves: " << n_solves
                << ", Newton iterations per step: "
                << double(n_newton) / n_steps << std::endl;

    auto &summary = model.summary;
    summary.set("cycles", 1);
    summary.set("mass_loss_mg", mass);
    summary.set("volume_loss_mm3", volume);
    summary.set("max_wear_depth_mm", max_depth);
    summary.set("wear_area_percent", 100. * worn_area / area);
    summary.set("wear_area_threshold_mm", wear.wear_area_threshold);
    summary.set("max_pressure_MPa", max_pressure);
    summary.set("max_contact_area_mm2", max_area);
    summary.set("steps", n_steps);
    summary.set("converged_steps", n_converged);
    summary.set("contact_solves", n_solves);
    summary.set("mean_newton_iterations", double(n_newton) / n_solves);
    summary.set("linear_extrapolation_cycles", wear.cycles);
    summary.set("linear_extrapolation_mass_loss_mg", mass * wear.cycles);

    Output::WearHistory history(parameters.output.directory,
                                parameters.output.testing,
                                model.world);
    history.append({1,
                    1.,
                    volume,
                    mass,
                    max_depth,
                    100. * worn_area / area,
                    max_pressure,
                    max_area,
                    model.wall_timer.wall_time()});
  }

  void
  WearProblem::output_results()
  {
    const auto &parameters = model.parameters;
    Output::write_steps_csv(parameters.output.directory,
                            cycle.get_reports(),
                            model.world);
    if (parameters.output.vtu_interval == 0)
      return;
    cycle.output_steps();
    if (groups.index != 0)
      return;
    // The wear of the cycle on the tibia (group 0 writes it).
    TimerOutput::Scope  scope(model.timer, "output");
    std::vector<double> depth_nm(wear_depth.size());
    for (unsigned int j = 0; j < wear_depth.size(); ++j)
      depth_nm[j] = 1e6 * wear_depth[j];
    Output::VtuSeries series(parameters.output.directory,
                             "wear",
                             groups.communicator);
    Output::write_solution(model.elasticity,
                           model.mapping(),
                           series,
                           0,
                           0.,
                           {{&cycle.get_coupling().slave_surface(),
                             {"wear_depth_nm", "slip_mm", "unused"},
                             {depth_nm, slip}}});
  }

  bool
  WearProblem::run()
  {
    model.start("ISO 14243-1 gait cycle and Archard wear");
    AssertThrow(model.parameters.mesh.fe_degree == 1,
                ExcInputError(
                  "Problem = wear needs Finite element degree = 1."));
    model.make_grid();
    model.distribute_dofs();
    cycle.setup();

    model.pcout << "Gait cycle, " << cycle.n_steps() << " steps:" << std::endl;
    const bool converged = cycle.solve();
    compute_wear();
    output_results();
    model.summary.set("step_groups", groups.n_groups);
    return model.finish(converged);
  }
} // namespace TKR::Problems
