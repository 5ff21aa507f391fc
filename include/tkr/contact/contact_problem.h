// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_contact_contact_problem_h
#define tkr_contact_contact_problem_h

#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/timer.h>

#include <deal.II/distributed/shared_tria.h>

#include <deal.II/fe/mapping_q1.h>

#include <deal.II/lac/affine_constraints.h>

#include <tkr/contact/active_set_solver.h>
#include <tkr/elasticity/linear_elasticity.h>
#include <tkr/mortar/mortar_coupling.h>
#include <tkr/output/summary.h>
#include <tkr/parameters/parameters.h>

#include <memory>

namespace TKR::Contact
{
  /**
   * `Problem = contact`: one static, frictionless contact solve between the
   * femur (master, `femur_contact`) and the tibia (slave, `tibia_contact`).
   * The femur's fixation surface is moved by `Femur displacement`; the
   * tibia's inferior surface is clamped, or loaded by `Axial force` and
   * held in its plane by springs (then only contact holds it axially).
   * Optionally compares the result with Hertz's solution.
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
    const ContactState &
    get_state() const
    {
      return state;
    }

    /** The mortar coupling of the solve (D, M, normals, gaps). */
    const Mortar::MortarCoupling &
    get_coupling() const
    {
      return *coupling;
    }

  private:
    void
    make_grid();
    void
    setup_system();
    void
    check_initial_gaps() const;
    ContactStatistics
    solve();
    void
    report(const ContactStatistics &statistics);
    void
    compare_with_hertz(const ContactStatistics &statistics);
    void
    cross_check_with_ipopt();
    void
    output_results();

    const Parameters::AllParameters &parameters;
    const MPI_Comm                   mpi_communicator;
    dealii::ConditionalOStream       pcout;
    dealii::TimerOutput              timer;

    dealii::parallel::shared::Triangulation<3> triangulation;
    const dealii::MappingQ1<3>                 mapping;
    Elasticity::LinearElasticity               elasticity;
    std::unique_ptr<Mortar::ContactSurface>    slave, master;
    std::unique_ptr<Mortar::MortarCoupling>    coupling;
    std::unique_ptr<ActiveSetSolver>           solver;
    dealii::AffineConstraints<double>          dirichlet;
    Elasticity::BoundaryLoads                  loads;
    ContactState                               state;
    Output::Summary                            summary;
  };
} // namespace TKR::Contact

#endif
