// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_problems_contact_problem_h
#define tkr_problems_contact_problem_h

#include <deal.II/lac/affine_constraints.h>

#include <tkr/contact/contact_solver.h>
#include <tkr/mortar/mortar_coupling.h>
#include <tkr/problems/two_body_model.h>

#include <memory>

namespace TKR::Problems
{
  /**
   * `Problem = contact`: one static, frictionless contact solve between the
   * femur (master, `femur_contact`) and the tibia (slave, `tibia_contact`).
   * The femur's fixation surface is moved by `Femur displacement`; the
   * tibia's inferior surface is clamped, or loaded by `Axial force` and
   * held in its plane by springs (then only contact holds it axially).
   * Optionally compares the result with Hertz's solution and with Ipopt.
   */
  class ContactProblem
  {
  public:
    ContactProblem(const Parameters::AllParameters &parameters,
                   const MPI_Comm                   mpi_communicator);

    /** Run; returns true if the contact solve converged. */
    bool
    run();

    /** Active set, pressures and gaps of the last solve (per slave node). */
    const Contact::ContactState &
    get_state() const
    {
      return state;
    }

    /** The mortar coupling of the solve (D, M, normals, gaps). */
    const Mortar::MortarCoupling &
    get_coupling() const
    {
      return model.coupling();
    }

  private:
    /** The Dirichlet constraints of Static contact (femur fixation,
     *  clamped tibia, rollers). */
    void
    setup_constraints();

    /** The loaded tibia's traction and springs (none if clamped). */
    void
    setup_loads();

    void
    setup_system();
    void
    check_initial_gaps() const;
    double
    closure_at(const unsigned int node) const;
    double
    initial_contact_distance() const;
    Contact::ContactStatistics
    solve();
    void
    check_contact_found(const Contact::ContactStatistics &statistics) const;
    void
    report(const Contact::ContactStatistics &statistics);
    void
    compare_with_hertz(const Contact::ContactStatistics &statistics);
    void
    cross_check_with_ipopt();
    void
    output_results();

    TwoBodyModel                            model;
    std::unique_ptr<Contact::ContactSolver> solver;
    dealii::AffineConstraints<double>       dirichlet;
    Elasticity::BoundaryLoads               loads;
    Contact::ContactState                   state;
    /** The displacement of the solve (ghosted). */
    dealii::TrilinosWrappers::MPI::Vector solution;
  };
} // namespace TKR::Problems

#endif
