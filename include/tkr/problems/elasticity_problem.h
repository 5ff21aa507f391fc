// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_problems_elasticity_problem_h
#define tkr_problems_elasticity_problem_h

#include <deal.II/lac/affine_constraints.h>

#include <tkr/elasticity/elastic_system.h>
#include <tkr/problems/two_body_model.h>

#include <memory>

namespace TKR::Problems
{
  /**
   * `Problem = elasticity`: the two bodies of the mesh, each clamped on its
   * fixation (femur) or inferior (tibia) surface and loaded by a uniform
   * traction on its contact surface, solved without contact. It exercises
   * the whole chain (parameters, mesh, two materials, parallel assembly,
   * AMG, output) and is the demonstration run of the program.
   */
  class ElasticityProblem
  {
  public:
    ElasticityProblem(const Parameters::AllParameters &parameters,
                      const MPI_Comm                   mpi_communicator);

    /** Run; returns true if the linear solve converged. */
    bool
    run();

  private:
    void
    setup_system();
    void
    assemble_system();
    Elasticity::SolverStatistics
    solve();
    void
    output_results();

    TwoBodyModel                      model;
    dealii::AffineConstraints<double> constraints;
    /** The linear system of the two bodies (set up in setup_system()). */
    std::unique_ptr<Elasticity::ElasticSystem> system;
  };
} // namespace TKR::Problems

#endif
