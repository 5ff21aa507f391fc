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
    : prm(parameters)
    , world_communicator(world)
    , model_communicator(communicator)
    , screen(std::cout, Utilities::MPI::this_mpi_process(world) == 0)
    // Rank 0's times; the MPI variant of TimerOutput would print a warning
    // whenever an input error unwinds the stack.
    , timer_output(screen,
                   parameters.output.testing ? TimerOutput::never :
                                               TimerOutput::summary,
                   TimerOutput::wall_times)
    , wall_timer(world, /*sync_lap_times=*/true)
    , tria(communicator,
           Triangulation<3>::none,
           /*allow_artificial_cells=*/false,
           parallel::shared::Triangulation<3>::partition_metis)
    , worn_geometry(tria, communicator)
    , two_bodies(tria,
                 parameters.materials,
                 parameters.linear_solver,
                 parameters.mesh.fe_degree,
                 communicator,
                 timer_output)
  {}

  void
  TwoBodyModel::start(const std::string &title)
  {
    screen << "tkr-wear: " << title
           << " (Problem = " << Parameters::to_string(prm.problem) << ")"
           << std::endl;
    Output::create_directory(prm.output.directory, world_communicator);
    run_summary.set("problem", Parameters::to_string(prm.problem));
  }

  void
  TwoBodyModel::make_grid(const std::function<void(Triangulation<3> &)> &adjust)
  {
    TimerOutput::Scope scope(timer_output, "read mesh");
    Mesh::read_mesh(prm.mesh, tria);
    if (adjust)
      adjust(tria);
    Output::report_mesh(screen,
                        run_summary,
                        Mesh::compute_statistics(tria),
                        prm.mesh.file,
                        prm.mesh.contact_cell_quality,
                        prm.output.testing);
    worn_geometry.initialize();
  }

  void
  TwoBodyModel::distribute_dofs()
  {
    two_bodies.distribute_dofs();
    run_summary.set("dofs",
                    static_cast<unsigned long long>(
                      two_bodies.get_dof_handler().n_dofs()));
  }

  void
  TwoBodyModel::setup_contact_surfaces()
  {
    if (mortar_coupling)
      return;
    const auto &dof_handler = two_bodies.get_dof_handler();
    // The geometry's worn surface on the elasticity's DoFs: one numbering
    // of the tibia_contact nodes for the coupling and the wear.
    slave = std::make_unique<Mortar::ContactSurface>(
      worn_geometry.worn_surface().with_dofs_of(dof_handler));
    master = std::make_unique<Mortar::ContactSurface>(
      dof_handler,
      Mesh::BoundaryIds::femur_contact);
    mortar_coupling = std::make_unique<Mortar::MortarCoupling>(*slave, *master);
  }

  bool
  TwoBodyModel::finish(const bool converged)
  {
    run_summary.set("converged", converged);
    Output::finish_run(run_summary,
                       prm.output.directory,
                       world_communicator,
                       wall_timer.wall_time(),
                       prm.output.testing,
                       screen);
    return converged;
  }
} // namespace TKR::Problems
