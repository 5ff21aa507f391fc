// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <tkr/base/result_schema.h>
#include <tkr/mesh/mesh.h>
#include <tkr/output/solution_output.h>
#include <tkr/problems/two_body_model.h>

namespace TKR::Problems
{
  namespace
  {
    // The keys of every run's summary.json (the wear run's go from 20,
    // the contact problem's from 60, the elasticity problem's from 70).
    // clang-format off
    [[maybe_unused]] const bool declared =
      ResultSchema::declare(
        "summary.json",
        10,
        {
        {"problem", "string", "-", {"wear", "contact", "elasticity"}, "the run's `Problem`: `wear`, `contact` or `elasticity`"},
        {"contact_cell_quality_tibia", "number", "-", {"wear", "contact", "elasticity"}, "the smallest scaled Jacobian of the cells with a face on `tibia_contact` (doc/geometry.md; a warning below `Mesh/Contact cell quality`)"},
        {"contact_cell_quality_femur", "number", "-", {"wear", "contact", "elasticity"}, "the same for `femur_contact`"},
        {"cells", "integer", "-", {"wear", "contact", "elasticity"}, "cells of the mesh, femur and tibia"},
        {"femur_volume_mm3", "number", "mm^3", {"wear", "contact", "elasticity"}, "the femur's volume in the mesh as read"},
        {"tibia_volume_mm3", "number", "mm^3", {"wear", "contact", "elasticity"}, "the tibia's (insert's) volume in the mesh as read"},
        {"dofs", "integer", "-", {"wear", "contact", "elasticity"}, "degrees of freedom of the two-body displacement"}}) &&
      ResultSchema::declare(
        "summary.json",
        90,
        {
        {"converged", "boolean", "-", {"wear", "contact", "elasticity"}, "wear: every step of every block converged; contact: the active set; elasticity: the linear solver"},
        {"mpi_ranks", "integer", "-", {"wear", "contact", "elasticity"}, "MPI processes of the run (in a study: of the case's group)"},
        {"wall_time_s", "number", "s", {"wear", "contact", "elasticity"}, "wall time of the run; absent under `Output/Testing = true`"}});
    // clang-format on
  } // namespace

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
    , run_summary("summary.json")
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
