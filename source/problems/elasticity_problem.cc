// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <deal.II/dofs/dof_tools.h>

#include <deal.II/numerics/vector_tools.h>

#include <tkr/base/result_schema.h>
#include <tkr/mesh/mesh.h>
#include <tkr/output/solution_output.h>
#include <tkr/problems/elasticity_problem.h>

namespace TKR::Problems
{
  namespace
  {
    // The elasticity problem's keys of summary.json (two_body_model.cc).
    // clang-format off
    [[maybe_unused]] const bool declared = ResultSchema::declare(
      "summary.json",
      70,
      {
        {"cg_iterations", "integer", "-", {"elasticity"}, "CG iterations: of the elasticity solve; of the AMG-CG active set (contact, only when it used CG) (a trace)", {}, true},
        {"max_displacement_femur_mm", "number", "mm", {"elasticity"}, "the femur's largest displacement"},
        {"max_displacement_tibia_mm", "number", "mm", {"elasticity"}, "the tibia's largest displacement"}});
    // clang-format on
  } // namespace

  using namespace dealii;

  ElasticityProblem::ElasticityProblem(
    const Parameters::AllParameters &parameters,
    const MPI_Comm                   mpi_communicator)
    : model(parameters, mpi_communicator, mpi_communicator)
  {}

  void
  ElasticityProblem::setup_system()
  {
    model.distribute_dofs();
    const auto &dof_handler = model.elasticity().get_dof_handler();

    // Every rank keeps the constraints of all DoFs (a shared triangulation
    // knows all cells); LinearElasticity::setup_system() relies on that.
    constraints.clear();
    DoFTools::make_hanging_node_constraints(dof_handler, constraints);
    for (const types::boundary_id id :
         {Mesh::BoundaryIds::femur_fixation, Mesh::BoundaryIds::tibia_inferior})
      VectorTools::interpolate_boundary_values(model.mapping(),
                                               dof_handler,
                                               id,
                                               Functions::ZeroFunction<3>(3),
                                               constraints);
    constraints.close();

    system = std::make_unique<Elasticity::ElasticSystem>(model.elasticity());
    system->setup(constraints);
    model.pcout() << "Degrees of freedom: " << dof_handler.n_dofs() << " (FE_Q("
                  << model.parameters().mesh.fe_degree << ")^3), MPI ranks: "
                  << Utilities::MPI::n_mpi_processes(model.communicator())
                  << std::endl;
  }

  void
  ElasticityProblem::assemble_system()
  {
    Elasticity::BoundaryLoads loads;
    loads.tractions = {{Mesh::BoundaryIds::femur_contact,
                        model.parameters().elasticity.femur_contact_traction},
                       {Mesh::BoundaryIds::tibia_contact,
                        model.parameters().elasticity.tibia_contact_traction}};
    system->assemble(model.mapping(), constraints, loads);
  }

  Elasticity::SolverStatistics
  ElasticityProblem::solve()
  {
    system->setup_preconditioner(model.mapping());
    const auto statistics = system->solve(constraints);
    model.pcout() << "CG "
                  << (statistics.converged ? "converged" : "did NOT converge");
    if (!model.parameters().output.testing)
      model.pcout() << " in " << statistics.iterations
                    << " iterations, relative residual "
                    << statistics.relative_residual;
    model.pcout() << std::endl;
    return statistics;
  }

  void
  ElasticityProblem::output_results()
  {
    TimerOutput::Scope scope(model.timer(), "output");
    Output::VtuSeries  series(model.parameters().output.directory,
                             "solution",
                             model.communicator());
    Output::write_solution(model.elasticity(),
                           system->solution(),
                           model.mapping(),
                           series,
                           0,
                           0.);
  }

  bool
  ElasticityProblem::run()
  {
    model.start("two-body linear elasticity without contact");
    model.make_grid();
    setup_system();
    assemble_system();
    const auto statistics = solve();

    const double max_femur =
      model.elasticity().max_displacement(system->solution(),
                                          Mesh::MaterialIds::femur);
    const double max_tibia =
      model.elasticity().max_displacement(system->solution(),
                                          Mesh::MaterialIds::tibia);
    model.pcout() << "Max displacement: femur " << 1e3 * max_femur
                  << " um, tibia " << 1e3 * max_tibia << " um" << std::endl;
    if (model.parameters().output.vtu_interval > 0)
      output_results();

    model.summary().set("cg_iterations", statistics.iterations);
    model.summary().set("max_displacement_femur_mm", max_femur);
    model.summary().set("max_displacement_tibia_mm", max_tibia);
    return model.finish(statistics.converged);
  }
} // namespace TKR::Problems
