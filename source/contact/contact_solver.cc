// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <tkr/base/exceptions.h>
#include <tkr/base/mpi.h>
#include <tkr/contact/active_set_solver.h>
#include <tkr/contact/condensed_solver.h>
#include <tkr/contact/contact_solver.h>
#include <tkr/contact/ipopt_solver.h>

namespace TKR::Contact
{
  using namespace dealii;

  ContactSolver::ContactSolver(const Elasticity::LinearElasticity &elasticity,
                               const Mortar::MortarCoupling       &coupling,
                               const Parameters::ContactSolver    &parameters,
                               const double              slave_youngs_modulus,
                               const MPI_Comm            mpi_communicator,
                               const ConditionalOStream &pcout,
                               TimerOutput              &timer,
                               const bool                testing)
    : elasticity(elasticity)
    , coupling(coupling)
    , parameters(parameters)
    , slave_youngs_modulus(slave_youngs_modulus)
    , mpi_communicator(mpi_communicator)
    , pcout(pcout)
    , trace(pcout.get_stream(), pcout.is_active() && !testing)
    , timer(timer)
  {}

  void
  ContactSolver::setup(const Mapping<3> &,
                       const AffineConstraints<double> &dirichlet_constraints,
                       const Elasticity::BoundaryLoads &loads)
  {
    springs               = Elasticity::BoundaryLoads();
    springs.springs       = loads.springs;
    springs.spring_fields = loads.spring_fields;
    dirichlet.clear();
    dirichlet.copy_from(dirichlet_constraints);
    observation_weights.clear();
    observed.clear();
  }

  void
  ContactSolver::set_load_basis(
    const Mapping<3> &,
    const std::vector<Elasticity::BoundaryLoads> &basis)
  {
    load_basis = basis;
  }

  ContactStatistics
  ContactSolver::solve(const Mapping<3>          &mapping,
                       const std::vector<double> &coefficients,
                       const double               initial_distance,
                       ContactState              &state)
  {
    return solve(mapping,
                 Elasticity::linear_combination(load_basis,
                                                coefficients,
                                                springs),
                 initial_distance,
                 state);
  }

  unsigned int
  ContactSolver::add_observation(const TrilinosWrappers::MPI::Vector &weights)
  {
    for (const auto &line : dirichlet.get_lines())
      AssertThrow(line.inhomogeneity == 0.,
                  ExcMessage("Observations need homogeneous constraints."));
    observation_weights.push_back(weights);
    observed.push_back(0.);
    return observation_weights.size() - 1;
  }

  // w . u over the locally owned entries, summed over the ranks. The
  // weights were assembled with the (homogeneous) Dirichlet constraints,
  // so they vanish on constrained rows and carry their share to the DoFs
  // these depend on: w . u then equals the functional of the full
  // displacement.
  void
  ContactSolver::observe_solution(const TrilinosWrappers::MPI::Vector &u)
  {
    for (unsigned int m = 0; m < observation_weights.size(); ++m)
      {
        double value = 0;
        for (const auto i : elasticity.locally_owned_dofs())
          value += observation_weights[m][i] * u[i];
        observed[m] = Utilities::MPI::sum(value, mpi_communicator);
      }
  }

  Parameters::ContactAlgorithm
  resolve_algorithm(const Parameters::ContactAlgorithm algorithm,
                    const Parameters::ProblemType      problem)
  {
    if (algorithm != Parameters::ContactAlgorithm::automatic)
      return algorithm;
    return problem == Parameters::ProblemType::wear ?
             Parameters::ContactAlgorithm::condensed_active_set :
             Parameters::ContactAlgorithm::active_set;
  }

  std::unique_ptr<ContactSolver>
  create_contact_solver(const Parameters::AllParameters    &parameters,
                        const Elasticity::LinearElasticity &elasticity,
                        const Mortar::MortarCoupling       &coupling,
                        const MPI_Comm                      mpi_communicator,
                        const ConditionalOStream           &pcout,
                        TimerOutput                        &timer)
  {
    const auto algorithm =
      resolve_algorithm(parameters.contact_solver.algorithm,
                        parameters.problem);
    const double E_slave = parameters.materials.tibia.youngs_modulus;
    switch (algorithm)
      {
        case Parameters::ContactAlgorithm::ipopt:
          AssertThrow(parameters.problem != Parameters::ProblemType::wear,
                      ExcInputError(
                        "Problem = wear cannot use Contact solver/Solver = "
                        "ipopt (a reference for single contact solves); "
                        "use auto, active set or condensed active set."));
          return std::make_unique<IpoptSolver>(elasticity,
                                               coupling,
                                               parameters.contact_solver,
                                               E_slave,
                                               mpi_communicator,
                                               pcout,
                                               timer);
        case Parameters::ContactAlgorithm::condensed_active_set:
          return std::make_unique<CondensedActiveSetSolver>(
            elasticity,
            coupling,
            parameters.contact_solver,
            E_slave,
            mpi_communicator,
            pcout,
            timer,
            parameters.output.testing);
        default:
          return std::make_unique<ActiveSetSolver>(elasticity,
                                                   coupling,
                                                   parameters.contact_solver,
                                                   E_slave,
                                                   mpi_communicator,
                                                   pcout,
                                                   timer,
                                                   parameters.output.testing);
      }
  }
} // namespace TKR::Contact
