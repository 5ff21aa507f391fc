// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_contact_contact_solver_h
#define tkr_contact_contact_solver_h

#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/timer.h>

#include <deal.II/fe/mapping.h>

#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/trilinos_vector.h>

#include <tkr/contact/contact_state.h>
#include <tkr/contact/pose_newton.h>
#include <tkr/elasticity/linear_elasticity.h>
#include <tkr/mortar/mortar_coupling.h>
#include <tkr/parameters/parameters.h>

#include <mpi.h>

#include <memory>
#include <string>
#include <vector>

namespace TKR::Contact
{
  /**
   * What every contact solver offers (DESIGN.md sections 4.4 and 4.5): the
   * frictionless mortar contact problem between the two linear-elastic
   * bodies of a LinearElasticity object, coupled by a MortarCoupling, for
   * given Dirichlet constraints and boundary loads. The implementations
   * (ActiveSetSolver, CondensedActiveSetSolver, IpoptSolver) solve the same
   * discrete problem; create them with create_contact_solver().
   *
   * The calling sequence: setup() once the Dirichlet constraints and the
   * springs are known (they must stay the same for every later solve;
   * the direct solver factorises the stiffness here); add_observation()
   * for linear functionals of the displacement to be evaluated after
   * every solve; then, after every MortarCoupling::reinit(), solve().
   */
  class ContactSolver
  {
  public:
    ContactSolver(const Elasticity::LinearElasticity &elasticity,
                  const Mortar::MortarCoupling       &coupling,
                  const Parameters::ContactSolver    &parameters,
                  const double                        slave_youngs_modulus,
                  const MPI_Comm                      mpi_communicator,
                  const dealii::ConditionalOStream   &pcout,
                  dealii::TimerOutput                &timer,
                  const bool                          testing = false);

    virtual ~ContactSolver() = default;

    /**
     * The Dirichlet constraints @p dirichlet and the springs of @p loads,
     * on the geometry of @p mapping, for every later solve.
     */
    virtual void
    setup(const dealii::Mapping<3>                &mapping,
          const dealii::AffineConstraints<double> &dirichlet,
          const Elasticity::BoundaryLoads         &loads);

    /**
     * Solve the contact problem on the current coupling for the loads
     * @p loads (whose springs must be those given to setup()). @p state
     * holds the initial active set (empty: the nodes whose gap exceeds the
     * smallest gap by at most @p initial_distance mm) and returns the
     * final state.
     */
    virtual ContactStatistics
    solve(const dealii::Mapping<3>        &mapping,
          const Elasticity::BoundaryLoads &loads,
          const double                     initial_distance,
          ContactState                    &state) = 0;

    /**
     * Declare that the tractions of later solves are linear combinations
     * of those of @p basis (the springs stay those of setup()), and solve
     * with solve(mapping, coefficients, ...). The condensed solver keeps
     * K^{-1} of every basis load, so that such a solve needs no back
     * substitution; the others assemble the combination.
     */
    virtual void
    set_load_basis(const dealii::Mapping<3>                     &mapping,
                   const std::vector<Elasticity::BoundaryLoads> &basis);

    /**
     * Solve for the tractions sum_i @p coefficients[i] basis[i] of
     * set_load_basis() and the springs of setup(); otherwise as solve().
     */
    virtual ContactStatistics
    solve(const dealii::Mapping<3>  &mapping,
          const std::vector<double> &coefficients,
          const double               initial_distance,
          ContactState              &state);

    /**
     * The analytic derivatives of the pose equations of @p system for the
     * pose Newton (PoseNewton), or none (nullptr: use FiniteDifferencePose).
     * The condensed active set has them (it keeps the compliance columns
     * of the contact nodes).
     */
    virtual std::unique_ptr<PoseDerivatives>
    pose_derivatives(PoseSystem &system, const double initial_distance)
    {
      (void)system;
      (void)initial_distance;
      return nullptr;
    }

    /**
     * Precompute what the solves after a setup() will probably need, from
     * what the solves before it used, sharing the work with the solvers of
     * @p peers (one rank of each other step group, whose solvers have the
     * same stiffness; collective on @p peers). The condensed solver
     * computes the compliance columns of the last stiffness's contact
     * nodes in full batches; the others need nothing.
     */
    virtual void
    prefetch(const MPI_Comm peers)
    {
      (void)peers;
    }

    /**
     * The next solves will probably need what the rows of the present
     * coupling's slave nodes @p slave_nodes touch: the next prefetch()
     * precomputes that too (for a cycle with no cycle before it to go by,
     * see wants_expectations()). The condensed solver notes the surface
     * nodes of the rows; the others need nothing.
     */
    virtual void
    expect(const std::vector<unsigned int> &slave_nodes)
    {
      (void)slave_nodes;
    }

    /**
     * Whether expect() and a prefetch() would help the next solves: the
     * condensed solver holds no columns (the first cycle, with no cycle
     * before it to go by). The others never need it.
     */
    virtual bool
    wants_expectations() const
    {
      return false;
    }

    /**
     * A gait cycle begins: what prefetch() precomputes at the next setup()
     * is what the solves from here on use (the condensed solver's columns).
     * The others need nothing.
     */
    virtual void
    new_cycle()
    {}

    /**
     * The full displacement of the last solve (ghosted: every locally
     * relevant entry). The condensed solver computes only the contact
     * surfaces and the observations in solve(); this costs it one more
     * back substitution.
     */
    virtual dealii::TrilinosWrappers::MPI::Vector
    compute_solution() = 0;

    /**
     * Add a linear functional of the displacement, w . u, that every solve
     * evaluates: @p weights is a right-hand side assembled with the
     * Dirichlet constraints of setup() (e.g. by
     * LinearElasticity::assemble_rhs() for a traction whose work is the
     * functional; LinearElasticity::load_vector()), which must be
     * homogeneous. Returns the functional's index for observation().
     */
    virtual unsigned int
    add_observation(const dealii::TrilinosWrappers::MPI::Vector &weights);

    /** Value of functional @p i for the displacement of the last solve. */
    double
    observation(const unsigned int i) const
    {
      return observed.at(i);
    }

    /** A short name for the screen ("active set"). */
    virtual std::string
    name() const = 0;

    /** The name with the method ("active set, AMG-preconditioned CG"). */
    virtual std::string
    description() const = 0;

  protected:
    /** The observations of the full displacement @p u (ghosted). */
    void
    observe_solution(const dealii::TrilinosWrappers::MPI::Vector &u);

    const Elasticity::LinearElasticity &elasticity;
    const Mortar::MortarCoupling       &coupling;
    const Parameters::ContactSolver     parameters;
    const double                        slave_youngs_modulus;
    const MPI_Comm                      mpi_communicator;
    const dealii::ConditionalOStream    pcout;
    /**
     * The solver's iteration trace: pcout, but silent with
     * `Output/Testing` (solver internals stay out of compared output).
     */
    const dealii::ConditionalOStream  trace;
    dealii::TimerOutput              &timer;
    dealii::AffineConstraints<double> dirichlet;
    /** The springs of setup() and the load basis of set_load_basis(). */
    Elasticity::BoundaryLoads              springs;
    std::vector<Elasticity::BoundaryLoads> load_basis;

    /** Weights of the observed functionals and their last values. */
    std::vector<dealii::TrilinosWrappers::MPI::Vector> observation_weights;
    std::vector<double>                                observed;
  };

  /**
   * The algorithm `Contact solver/Solver` stands for in @p problem:
   * `auto` is the condensed active set for Problem = wear (one
   * factorisation of the constant stiffness serves the whole gait cycle)
   * and the AMG-CG active set otherwise.
   */
  Parameters::ContactAlgorithm
  resolve_algorithm(const Parameters::ContactAlgorithm algorithm,
                    const Parameters::ProblemType      problem);

  /**
   * The contact solver of `Contact solver/Solver` (resolved for
   * `Problem`, see resolve_algorithm()). Throws ExcInputError for a solver
   * that cannot do the problem (Ipopt for the gait).
   */
  std::unique_ptr<ContactSolver>
  create_contact_solver(const Parameters::AllParameters    &parameters,
                        const Elasticity::LinearElasticity &elasticity,
                        const Mortar::MortarCoupling       &coupling,
                        const MPI_Comm                      mpi_communicator,
                        const dealii::ConditionalOStream   &pcout,
                        dealii::TimerOutput                &timer);
} // namespace TKR::Contact

#endif
