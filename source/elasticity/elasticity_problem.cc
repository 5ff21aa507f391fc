// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <deal.II/base/timer.h>

#include <deal.II/dofs/dof_tools.h>

#include <deal.II/numerics/data_out.h>
#include <deal.II/numerics/vector_tools.h>

#include <tkr/elasticity/elasticity_problem.h>
#include <tkr/mesh/mesh.h>
#include <tkr/output/solution_output.h>

#include <iomanip>

namespace TKR::Elasticity
{
  using namespace dealii;

  ElasticityProblem::ElasticityProblem(
    const Parameters::AllParameters &parameters,
    const MPI_Comm                   mpi_communicator)
    : parameters(parameters)
    , mpi_communicator(mpi_communicator)
    , pcout(std::cout, Utilities::MPI::this_mpi_process(mpi_communicator) == 0)
    // Rank 0's times; the MPI variant of TimerOutput would print a warning
    // whenever an input error unwinds the stack.
    , timer(pcout,
            parameters.output.testing ? TimerOutput::never :
                                        TimerOutput::summary,
            TimerOutput::wall_times)
    , triangulation(mpi_communicator,
                    Triangulation<3>::none,
                    /*allow_artificial_cells=*/false,
                    parallel::shared::Triangulation<3>::partition_metis)
    , elasticity(triangulation,
                 parameters.materials,
                 parameters.linear_solver,
                 parameters.mesh.fe_degree,
                 mpi_communicator,
                 timer)
  {}

  void
  ElasticityProblem::make_grid()
  {
    TimerOutput::Scope scope(timer, "read mesh");
    Mesh::read_mesh(parameters.mesh, triangulation);
    Output::report_mesh(pcout,
                        summary,
                        Mesh::compute_statistics(triangulation),
                        parameters.mesh.file,
                        parameters.output.testing);
  }

  void
  ElasticityProblem::setup_system()
  {
    elasticity.distribute_dofs();
    const auto &dof_handler = elasticity.get_dof_handler();

    // Every rank keeps the constraints of all DoFs (a shared triangulation
    // knows all cells); LinearElasticity::setup_system() relies on that.
    constraints.clear();
    DoFTools::make_hanging_node_constraints(dof_handler, constraints);
    for (const types::boundary_id id :
         {Mesh::BoundaryIds::femur_fixation, Mesh::BoundaryIds::tibia_inferior})
      VectorTools::interpolate_boundary_values(mapping,
                                               dof_handler,
                                               id,
                                               Functions::ZeroFunction<3>(3),
                                               constraints);
    constraints.close();

    elasticity.setup_system(constraints);
    pcout << "Degrees of freedom: " << dof_handler.n_dofs() << " (FE_Q("
          << parameters.mesh.fe_degree << ")^3), MPI ranks: "
          << Utilities::MPI::n_mpi_processes(mpi_communicator) << std::endl;
    summary.set("dofs", static_cast<unsigned long long>(dof_handler.n_dofs()));
  }

  void
  ElasticityProblem::assemble_system()
  {
    BoundaryLoads loads;
    loads.tractions = {{Mesh::BoundaryIds::femur_contact,
                        parameters.elasticity.femur_contact_traction},
                       {Mesh::BoundaryIds::tibia_contact,
                        parameters.elasticity.tibia_contact_traction}};
    elasticity.assemble_system(mapping, constraints, loads);
  }

  SolverStatistics
  ElasticityProblem::solve()
  {
    elasticity.setup_preconditioner(mapping);
    const SolverStatistics statistics = elasticity.solve(constraints);
    pcout << "CG " << (statistics.converged ? "converged" : "did NOT converge");
    if (!parameters.output.testing)
      pcout << " in " << statistics.iterations
            << " iterations, relative residual "
            << statistics.relative_residual;
    pcout << std::endl;
    return statistics;
  }

  void
  ElasticityProblem::output_results()
  {
    TimerOutput::Scope scope(timer, "output");
    Output::VtuSeries  series(parameters.output.directory,
                             "solution",
                             mpi_communicator);
    Output::write_solution(elasticity, mapping, series, 0, 0.);
  }

  bool
  ElasticityProblem::run()
  {
    Timer wall_timer(mpi_communicator, /*sync_lap_times=*/true);
    pcout << "tkr-wear: two-body linear elasticity without contact "
          << "(Problem = elasticity)" << std::endl;
    Output::create_directory(parameters.output.directory, mpi_communicator);
    summary.set("problem", Parameters::to_string(parameters.problem));

    make_grid();
    setup_system();
    assemble_system();
    const SolverStatistics statistics = solve();

    const double max_femur =
      elasticity.max_displacement(Mesh::MaterialIds::femur);
    const double max_tibia =
      elasticity.max_displacement(Mesh::MaterialIds::tibia);
    pcout << "Max displacement: femur " << 1e3 * max_femur << " um, tibia "
          << 1e3 * max_tibia << " um" << std::endl;
    if (parameters.output.vtu_interval > 0)
      output_results();

    summary.set("converged", statistics.converged);
    summary.set("cg_iterations", statistics.iterations);
    summary.set("max_displacement_femur_mm", max_femur);
    summary.set("max_displacement_tibia_mm", max_tibia);
    Output::finish_run(summary,
                       parameters.output.directory,
                       mpi_communicator,
                       wall_timer.wall_time(),
                       pcout);
    return statistics.converged;
  }
} // namespace TKR::Elasticity
