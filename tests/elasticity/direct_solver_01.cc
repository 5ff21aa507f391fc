// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.
//
// Elasticity::DirectSolver (CHOLMOD) on the two-body patch mesh, on 1 and 2
// ranks: the stiffness with the femur clamped on femur_fixation and the
// tibia clamped on tibia_inferior (inhomogeneous values) is factorised and
// solved for several right-hand sides at once and for one; the residuals are at
// round-off. The two bodies are factorised as two blocks: a unit load on the
// tibia gives exactly zero on the femur, unit loads in a batch give the same
// bits as beside a random column (the forward solve's skipped supernodes), the
// same matrix again keeps both factors, a stiffer tibia keeps the femur's.
// Without the tibia's clamp the tibia floats: the factorisation must refuse
// with the sentence about rigid-body motion.

#include <deal.II/base/function.h>

#include <deal.II/distributed/shared_tria.h>

#include <deal.II/fe/mapping_q1.h>

#include <deal.II/numerics/vector_tools.h>

#include <tkr/base/exceptions.h>
#include <tkr/elasticity/direct_solver.h>
#include <tkr/elasticity/elastic_system.h>
#include <tkr/elasticity/linear_elasticity.h>
#include <tkr/mesh/mesh.h>

#include "../tests.h"

#include <algorithm>

namespace
{
  double
  max_relative_residual(const TrilinosWrappers::SparseMatrix &K,
                        const Epetra_MultiVector             &X,
                        const Epetra_MultiVector             &B)
  {
    Epetra_MultiVector R(B.Map(), B.NumVectors());
    K.trilinos_matrix().Multiply(false, X, R);
    R.Update(-1., B, 1.);
    std::vector<double> r(B.NumVectors()), b(B.NumVectors());
    R.Norm2(r.data());
    B.Norm2(b.data());
    double worst = 0;
    for (int c = 0; c < B.NumVectors(); ++c)
      worst = std::max(worst, r[c] / b[c]);
    return worst;
  }
} // namespace

int
main(int argc, char **argv)
{
  using namespace TKR;
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  initlog();
  const MPI_Comm comm = MPI_COMM_WORLD;

  parallel::shared::Triangulation<3> triangulation(
    comm,
    Triangulation<3>::none,
    false,
    parallel::shared::Triangulation<3>::partition_metis);
  Mesh::read_mesh(Parameters::Mesh::with_default_groups(
                    std::string(SOURCE_DIR) +
                    "/../../meshes/verification/patch-coarse.msh"),
                  triangulation);
  Parameters::Materials materials;
  materials.femur = {220000., 0.31, 8.3};
  materials.tibia = {1100., 0.42, 0.935};
  const Parameters::LinearSolver linear{1e-10, 1000, true, 0.02, 2};
  TimerOutput                    timer(comm,
                    std::cout,
                    TimerOutput::never,
                    TimerOutput::wall_times);
  MappingQ1<3>                   mapping;
  Elasticity::LinearElasticity   elasticity(triangulation,
                                          materials,
                                          linear,
                                          1,
                                          comm,
                                          timer);
  elasticity.distribute_dofs();
  deallog << "DoFs: " << elasticity.get_dof_handler().n_dofs() << std::endl;

  Elasticity::BoundaryLoads loads;
  loads.tractions[Mesh::BoundaryIds::femur_contact] =
    Tensor<1, 3>({0.5, -1., 2.});
  for (const bool clamp_tibia : {true, false})
    {
      AffineConstraints<double> constraints;
      VectorTools::interpolate_boundary_values(
        mapping,
        elasticity.get_dof_handler(),
        Mesh::BoundaryIds::femur_fixation,
        Functions::ZeroFunction<3>(3),
        constraints);
      if (clamp_tibia)
        VectorTools::interpolate_boundary_values(
          mapping,
          elasticity.get_dof_handler(),
          Mesh::BoundaryIds::tibia_inferior,
          Functions::ConstantFunction<3>(std::vector<double>{0.01, 0., -0.02}),
          constraints);
      constraints.close();
      TKR::Elasticity::ElasticSystem system(elasticity);
      system.setup(constraints);
      system.assemble(mapping, constraints, loads);
      const auto &K = system.matrix();

      Elasticity::DirectSolver solver;
      try
        {
          solver.factorize(K);
        }
      catch (const ExcInputError &e)
        {
          const std::string message = exception_message(e);
          deallog << "tibia clamped: " << yes_no(clamp_tibia)
                  << ", refused: " << message.substr(0, message.find(" ("))
                  << " ... " << message.substr(message.find("): ") + 3)
                  << std::endl;
          continue;
        }
      deallog << "tibia clamped: " << yes_no(clamp_tibia)
              << ", factorised: " << yes_no(solver.is_factorized())
              << ", blocks: " << solver.n_blocks() << std::endl;

      // Seven random right-hand sides at once (on 2 ranks: 3 and 4
      // columns per rank), then the load vector alone.
      Epetra_MultiVector B(solver.row_map(), 7), X(solver.row_map(), 7);
      B.Random();
      solver.solve(X, B);
      deallog << "7 right-hand sides, residual below 1e-12: "
              << yes_no(max_relative_residual(K, X, B) < 1e-12) << std::endl;

      // A unit load on one body: the other body's values are exactly zero.
      {
        Epetra_MultiVector b(solver.row_map(), 1), x(solver.row_map(), 1);
        const auto        &dofs = elasticity.get_dof_handler();
        std::vector<types::global_dof_index> cell_dofs(
          dofs.get_fe().n_dofs_per_cell());
        types::global_dof_index tibia_dof = numbers::invalid_dof_index;
        IndexSet                femur_dofs(dofs.n_dofs());
        for (const auto &cell : dofs.active_cell_iterators())
          {
            cell->get_dof_indices(cell_dofs);
            if (cell->material_id() == Mesh::MaterialIds::femur)
              femur_dofs.add_indices(cell_dofs.begin(), cell_dofs.end());
            else if (!constraints.is_constrained(cell_dofs[0]))
              tibia_dof = cell_dofs[0];
          }
        const int local = b.Map().LID(static_cast<int>(tibia_dof));
        if (local >= 0)
          b[0][local] = 1.;
        solver.solve(x, b);
        double on_femur = 0;
        for (const auto i : femur_dofs)
          {
            const int l = x.Map().LID(static_cast<int>(i));
            if (l >= 0)
              on_femur = std::max(on_femur, std::abs(x[0][l]));
          }
        deallog << "unit load on the tibia: residual below 1e-12: "
                << yes_no(max_relative_residual(K, x, b) < 1e-12)
                << ", largest value on the femur: "
                << Utilities::MPI::max(on_femur, comm) << std::endl;

        // Unit loads in a batch (the forward substitution visits only the
        // supernodes above their rows): the same solutions to the last
        // bit as with a random column in the batch, which visits all of
        // them (on 2 ranks the random column is the second rank's third).
        std::vector<types::global_dof_index> tibia_dofs;
        for (const auto &cell : dofs.active_cell_iterators())
          if (cell->material_id() != Mesh::MaterialIds::femur)
            {
              cell->get_dof_indices(cell_dofs);
              for (const auto dof : cell_dofs)
                if (!constraints.is_constrained(dof) &&
                    std::find(tibia_dofs.begin(), tibia_dofs.end(), dof) ==
                      tibia_dofs.end() &&
                    tibia_dofs.size() < 4)
                  tibia_dofs.push_back(dof);
            }
        Epetra_MultiVector units(solver.row_map(), 4),
          solved(solver.row_map(), 4), mixed(solver.row_map(), 5),
          mixed_solved(solver.row_map(), 5);
        mixed.Random();
        for (unsigned int c = 0; c < 4; ++c)
          {
            *mixed(c)       = *units(c);
            const int local = units.Map().LID(static_cast<int>(tibia_dofs[c]));
            if (local >= 0)
              units[c][local] = mixed[c][local] = 1.;
          }
        solver.solve(solved, units);
        solver.solve(mixed_solved, mixed);
        bool same = true;
        for (unsigned int c = 0; c < 4; ++c)
          for (int i = 0; i < solved.MyLength(); ++i)
            same = same && solved[c][i] == mixed_solved[c][i];
        deallog << "4 unit loads at once: residual below 1e-12: "
                << yes_no(max_relative_residual(K, solved, units) < 1e-12)
                << ", the same bits as beside a random column: "
                << yes_no(Utilities::MPI::min(same ? 1 : 0, comm) == 1)
                << std::endl;
      }

      // The same matrix again: every block kept. Then the tibia twice as
      // stiff: the femur's block kept, the tibia's factorised again.
      solver.factorize(K);
      deallog << "the same matrix again: " << solver.n_kept_blocks() << " of "
              << solver.n_blocks() << " blocks kept" << std::endl;
      {
        Parameters::Materials stiffer = materials;
        stiffer.tibia.youngs_modulus *= 2;
        Elasticity::LinearElasticity stiffer_elasticity(triangulation,
                                                        stiffer,
                                                        linear,
                                                        1,
                                                        comm,
                                                        timer);
        stiffer_elasticity.distribute_dofs();
        TKR::Elasticity::ElasticSystem stiffer_system(stiffer_elasticity);
        stiffer_system.setup(constraints);
        stiffer_system.assemble(mapping, constraints, loads);
        Elasticity::DirectSolver refactorised = std::move(solver);
        refactorised.factorize(stiffer_system.matrix());
        Epetra_MultiVector b(refactorised.row_map(), 3),
          x(refactorised.row_map(), 3);
        b.Random();
        refactorised.solve(x, b);
        deallog << "the tibia twice as stiff: " << refactorised.n_kept_blocks()
                << " of " << refactorised.n_blocks()
                << " blocks kept, residual below 1e-12: "
                << yes_no(max_relative_residual(stiffer_system.matrix(), x, b) <
                          1e-12)
                << std::endl;
        solver = std::move(refactorised);
        solver.factorize(K);
      }

      // A moved solver keeps its factorisation.
      Elasticity::DirectSolver      moved = std::move(solver);
      TrilinosWrappers::MPI::Vector u(system.rhs());
      moved.solve(u.trilinos_vector(), system.rhs().trilinos_vector());
      deallog << "load vector, residual below 1e-12: "
              << yes_no(max_relative_residual(K,
                                              u.trilinos_vector(),
                                              system.rhs().trilinos_vector()) <
                        1e-12)
              << std::endl;
    }
}
