// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <tkr/mesh/mesh.h>
#include <tkr/output/solution_output.h>
#include <tkr/problems/two_body_model.h>

namespace TKR::Problems
{
  using namespace dealii;

  TwoBodyModel::TwoBodyModel(const Parameters::AllParameters &parameters,
                             const MPI_Comm                   world,
                             const MPI_Comm                   communicator)
    : parameters(parameters)
    , world(world)
    , communicator(communicator)
    , pcout(std::cout, Utilities::MPI::this_mpi_process(world) == 0)
    // Rank 0's times; the MPI variant of TimerOutput would print a warning
    // whenever an input error unwinds the stack.
    , timer(pcout,
            parameters.output.testing ? TimerOutput::never :
                                        TimerOutput::summary,
            TimerOutput::wall_times)
    , wall_timer(world, /*sync_lap_times=*/true)
    , triangulation(communicator,
                    Triangulation<3>::none,
                    /*allow_artificial_cells=*/false,
                    parallel::shared::Triangulation<3>::partition_metis)
    , geometry(triangulation, communicator)
    , elasticity(triangulation,
                 parameters.materials,
                 parameters.linear_solver,
                 parameters.mesh.fe_degree,
                 communicator,
                 timer)
  {}

  void
  TwoBodyModel::start(const std::string &title)
  {
    pcout << "tkr-wear: " << title
          << " (Problem = " << Parameters::to_string(parameters.problem) << ")"
          << std::endl;
    Output::create_directory(parameters.output.directory, world);
    summary.set("problem", Parameters::to_string(parameters.problem));
  }

  void
  TwoBodyModel::make_grid(const std::function<void(Triangulation<3> &)> &adjust)
  {
    TimerOutput::Scope scope(timer, "read mesh");
    Mesh::read_mesh(parameters.mesh, triangulation);
    if (adjust)
      adjust(triangulation);
    Output::report_mesh(pcout,
                        summary,
                        Mesh::compute_statistics(triangulation),
                        parameters.mesh.file,
                        parameters.output.testing);
    geometry.initialize();
  }

  void
  TwoBodyModel::distribute_dofs()
  {
    elasticity.distribute_dofs();
    summary.set("dofs",
                static_cast<unsigned long long>(
                  elasticity.get_dof_handler().n_dofs()));
  }

  void
  TwoBodyModel::setup_contact_surfaces()
  {
    const auto &dof_handler = elasticity.get_dof_handler();
    slave                   = std::make_unique<Mortar::ContactSurface>(
      dof_handler,
      Mesh::BoundaryIds::tibia_contact);
    master = std::make_unique<Mortar::ContactSurface>(
      dof_handler,
      Mesh::BoundaryIds::femur_contact);
    coupling = std::make_unique<Mortar::MortarCoupling>(*slave, *master);
  }

  bool
  TwoBodyModel::finish(const bool converged)
  {
    summary.set("converged", converged);
    Output::finish_run(summary,
                       parameters.output.directory,
                       world,
                       wall_timer.wall_time(),
                       parameters.output.testing,
                       pcout);
    return converged;
  }
} // namespace TKR::Problems
