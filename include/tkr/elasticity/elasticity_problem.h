// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_elasticity_elasticity_problem_h
#define tkr_elasticity_elasticity_problem_h

#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/timer.h>

#include <deal.II/distributed/shared_tria.h>

#include <deal.II/fe/mapping_q1.h>

#include <deal.II/lac/affine_constraints.h>

#include <tkr/elasticity/linear_elasticity.h>
#include <tkr/output/summary.h>
#include <tkr/parameters/parameters.h>

namespace TKR::Elasticity
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
    make_grid();
    void
    setup_system();
    void
    assemble_system();
    SolverStatistics
    solve();
    void
    output_results();

    const Parameters::AllParameters &parameters;
    const MPI_Comm                   mpi_communicator;
    dealii::ConditionalOStream       pcout;
    dealii::TimerOutput              timer;

    dealii::parallel::shared::Triangulation<3> triangulation;
    const dealii::MappingQ1<3>                 mapping;
    LinearElasticity                           elasticity;
    dealii::AffineConstraints<double>          constraints;
    Output::Summary                            summary;
  };
} // namespace TKR::Elasticity

#endif
