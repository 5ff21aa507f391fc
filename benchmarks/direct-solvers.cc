// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.
//
// Direct solvers for the stiffness matrix of a mesh: factorisation time and
// the time of many right-hand sides at once, as the condensed active set
// uses them (doc/performance.md).
//   cmake --build build/release --target direct-solvers
//   build/release/direct-solvers FILE.prm SOLVER [N_RHS]
// from the project root (where the parameter file's mesh path starts), with
// SOLVER one of
//   cholmod       Elasticity::DirectSolver (CHOLMOD, the solver tkr-wear uses)
//   Amesos_Klu    Trilinos Amesos KLU (tkr-wear's solver until 2026-12-01)
//   Amesos_Mumps  Trilinos Amesos MUMPS
//   orderings     CHOLMOD analysis and factorisation with AMD, METIS, both
//   forward       the columns K^{-1} e at the contact surfaces: N_RHS batched
//                 solves against sparse forward solves Y = L^{-1} P e and
//                 K^{-1}_SC = Y_S^T Y_C
// The matrix is the two-body stiffness of the parameter file's mesh, the
// femur clamped on femur_fixation and the tibia held by springs on
// tibia_inferior. One MPI rank unless run with mpirun (cholmod only).

#include <deal.II/base/mpi.h>
#include <deal.II/base/timer.h>

#include <deal.II/distributed/shared_tria.h>

#include <deal.II/fe/mapping_q1.h>

#include <deal.II/numerics/vector_tools.h>

#include <tkr/elasticity/direct_solver.h>
#include <tkr/elasticity/elastic_system.h>
#include <tkr/elasticity/linear_elasticity.h>
#include <tkr/mesh/mesh.h>
#include <tkr/mortar/contact_surface.h>
#include <tkr/parameters/parameters.h>

#include <Amesos.h>
#include <Amesos_BaseSolver.h>
#include <Epetra_CrsMatrix.h>
#include <Epetra_LinearProblem.h>
#include <Epetra_MultiVector.h>
#include <suitesparse/cholmod.h>

#include <iomanip>
#include <iostream>
#include <set>

using namespace dealii;
using namespace TKR;

namespace
{
  using Index = SuiteSparse_long;

  /** max over the columns of |A x - b| / |b|. */
  double
  relative_residual(const Epetra_CrsMatrix   &A,
                    const Epetra_MultiVector &X,
                    const Epetra_MultiVector &B)
  {
    Epetra_MultiVector R(B.Map(), B.NumVectors());
    A.Multiply(false, X, R);
    R.Update(-1., B, 1.);
    std::vector<double> r(B.NumVectors()), b(B.NumVectors());
    R.Norm2(r.data());
    B.Norm2(b.data());
    double worst = 0;
    for (int c = 0; c < B.NumVectors(); ++c)
      worst = std::max(worst, r[c] / b[c]);
    return worst;
  }

  void
  print(const std::string &what, const double value)
  {
    if (Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) == 0)
      std::cout << std::left << std::setw(40) << what << ' ' << value
                << std::endl;
  }

  // Time KLU or MUMPS through Amesos, or DirectSolver.
  void
  time_solver(const std::string                    &solver_type,
              Epetra_CrsMatrix                     &A,
              const TrilinosWrappers::SparseMatrix &matrix,
              const unsigned int                    n_rhs)
  {
    Epetra_MultiVector X(A.OperatorDomainMap(), n_rhs),
      B(A.OperatorRangeMap(), n_rhs);
    B.Random();
    Epetra_MultiVector X1(A.OperatorDomainMap(), 1),
      B1(A.OperatorRangeMap(), 1);
    B1.Random();
    Timer t;
    if (solver_type == "cholmod")
      {
        Elasticity::DirectSolver solver;
        solver.factorize(matrix);
        print("factorisation (s)", t.wall_time());
        print("nonzeros of L", solver.n_factor_nonzeros());
        print("reciprocal condition estimate",
              solver.reciprocal_condition_estimate());
        t.restart();
        solver.solve(X, B);
        print(std::to_string(n_rhs) + " right-hand sides (s)", t.wall_time());
        t.restart();
        for (int i = 0; i < 10; ++i)
          solver.solve(X1, B1);
        print("1 right-hand side, mean of 10 (s)", t.wall_time() / 10);
      }
    else
      {
        Epetra_LinearProblem               problem(&A, &X, &B);
        Amesos                             factory;
        std::unique_ptr<Amesos_BaseSolver> solver(
          factory.Create(solver_type, problem));
        AssertThrow(solver != nullptr, ExcMessage("No such Amesos solver."));
        Teuchos::ParameterList list;
        solver->SetParameters(list);
        solver->SymbolicFactorization();
        solver->NumericFactorization();
        print("factorisation (s)", t.wall_time());
        t.restart();
        solver->Solve();
        print(std::to_string(n_rhs) + " right-hand sides (s)", t.wall_time());
        problem.SetLHS(&X1);
        problem.SetRHS(&B1);
        t.restart();
        for (int i = 0; i < 10; ++i)
          solver->Solve();
        print("1 right-hand side, mean of 10 (s)", t.wall_time() / 10);
      }
    print("relative residual, " + std::to_string(n_rhs) + " right-hand sides",
          relative_residual(A, X, B));
    print("relative residual, 1 right-hand side", relative_residual(A, X1, B1));
  }

  /** The lower triangle of a one-rank matrix as a CHOLMOD matrix. */
  cholmod_sparse *
  lower_triangle(const Epetra_CrsMatrix &A, cholmod_common &common)
  {
    const Index     n = A.NumGlobalRows64();
    cholmod_sparse *S = cholmod_l_allocate_sparse(n,
                                                  n,
                                                  A.NumGlobalNonzeros64(),
                                                  true,
                                                  true,
                                                  -1,
                                                  CHOLMOD_REAL,
                                                  &common);
    auto           *p = static_cast<Index *>(S->p);
    auto           *i = static_cast<Index *>(S->i);
    auto           *x = static_cast<double *>(S->x);
    p[0]              = 0;
    for (Index row = 0; row < n; ++row)
      {
        int     length;
        double *values;
        int    *indices;
        A.ExtractMyRowView(row, length, values, indices);
        std::vector<std::pair<Index, double>> entries;
        for (int k = 0; k < length; ++k)
          {
            const Index j = A.ColMap().GID64(indices[k]);
            if (j == row || (j > row && values[k] != 0.))
              entries.emplace_back(j, values[k]);
          }
        std::sort(entries.begin(), entries.end());
        Index q = p[row];
        for (const auto &[j, a] : entries)
          {
            i[q] = j;
            x[q] = a;
            ++q;
          }
        p[row + 1] = q;
      }
    return S;
  }

  // CHOLMOD (supernodal) with each ordering: analysis and factorisation
  // times, nonzeros of L.
  void
  time_orderings(const Epetra_CrsMatrix &A)
  {
    for (const std::string ordering : {"AMD", "METIS", "AMD+METIS", "default"})
      {
        cholmod_common c;
        cholmod_l_start(&c);
        c.supernodal = CHOLMOD_SUPERNODAL;
        if (ordering == "AMD" || ordering == "METIS")
          {
            c.nmethods = 1;
            c.method[0].ordering =
              ordering == "AMD" ? CHOLMOD_AMD : CHOLMOD_METIS;
          }
        else if (ordering == "AMD+METIS")
          {
            c.nmethods           = 2;
            c.method[0].ordering = CHOLMOD_AMD;
            c.method[1].ordering = CHOLMOD_METIS;
          }
        cholmod_sparse *S = lower_triangle(A, c);
        Timer           t;
        cholmod_factor *L        = cholmod_l_analyze(S, &c);
        const double    analysis = t.wall_time();
        t.restart();
        cholmod_l_factorize(S, L, &c);
        const double factorisation = t.wall_time();
        std::cout << std::left << std::setw(10) << ordering << " analysis "
                  << analysis << " s, factorisation " << factorisation
                  << " s, nnz(L) " << c.lnz << ", flops " << c.fl
                  << ", chosen ordering " << L->ordering << std::endl;
        cholmod_l_free_factor(&L, &c);
        cholmod_l_free_sparse(&S, &c);
        cholmod_l_finish(&c);
      }
  }

  // The condensed solver needs K^{-1} at the contact surfaces' DoFs S for
  // unit loads at (some of) the same DoFs C. Batched: K^{-1} E_C, then the
  // rows S. Forward: with K = P^T L L^T P, K^{-1}_SC = Y_S^T Y_C for
  // Y = L^{-1} P E, each column a sparse forward solve (cholmod_solve2 with
  // Bset; it needs a simplicial factor), then Y_S^T Y_C row by row.
  void
  time_forward(const Epetra_CrsMatrix                     &A,
               const std::vector<types::global_dof_index> &surface,
               const unsigned int                          n_columns)
  {
    cholmod_common c;
    cholmod_l_start(&c);
    c.supernodal         = CHOLMOD_SUPERNODAL;
    c.nmethods           = 2;
    c.method[0].ordering = CHOLMOD_AMD;
    c.method[1].ordering = CHOLMOD_METIS;
    cholmod_sparse *S    = lower_triangle(A, c);
    cholmod_factor *L    = cholmod_l_analyze(S, &c);
    cholmod_l_factorize(S, L, &c);
    const Index        n   = S->nrow;
    const unsigned int n_S = surface.size();
    const unsigned int n_C = std::min<unsigned int>(n_columns, n_S);
    std::cout << "surface DoFs |S| " << n_S << ", columns |C| " << n_C
              << std::endl;

    // Batched full solves of the first n_C surface DoFs, 128 at a time.
    Timer               t;
    std::vector<double> batched(static_cast<std::size_t>(n_S) * n_C);
    {
      cholmod_dense *B = cholmod_l_zeros(n, 128, CHOLMOD_REAL, &c);
      cholmod_dense *X = nullptr, *Y = nullptr, *E = nullptr;
      for (unsigned int start = 0; start < n_C; start += 128)
        {
          const unsigned int m = std::min(128u, n_C - start);
          B->ncol              = m;
          auto *b              = static_cast<double *>(B->x);
          std::fill(b, b + n * 128, 0.);
          for (unsigned int k = 0; k < m; ++k)
            b[k * n + surface[start + k]] = 1.;
          cholmod_l_solve2(CHOLMOD_A, L, B, nullptr, &X, nullptr, &Y, &E, &c);
          const auto *x = static_cast<const double *>(X->x);
          for (unsigned int k = 0; k < m; ++k)
            for (unsigned int s = 0; s < n_S; ++s)
              batched[(start + k) * static_cast<std::size_t>(n_S) + s] =
                x[k * n + surface[s]];
        }
      cholmod_l_free_dense(&X, &c);
      cholmod_l_free_dense(&Y, &c);
      cholmod_l_free_dense(&E, &c);
      cholmod_l_free_dense(&B, &c);
    }
    const double batched_time = t.wall_time();
    std::cout << "batched (128) full solves: " << batched_time << " s, "
              << 1e3 * batched_time / n_C << " ms per column" << std::endl;

    // Sparse forward solves of all surface DoFs (L becomes simplicial).
    t.restart();
    std::vector<Index> inverse(n);
    {
      const auto *perm = static_cast<const Index *>(L->Perm);
      for (Index k = 0; k < n; ++k)
        inverse[perm[k]] = k;
    }
    std::vector<std::vector<std::pair<Index, double>>> Y_columns(n_S);
    {
      cholmod_dense  *B = cholmod_l_zeros(n, 1, CHOLMOD_REAL, &c);
      cholmod_sparse *Bset =
        cholmod_l_allocate_sparse(n, 1, 1, true, true, 0, CHOLMOD_PATTERN, &c);
      cholmod_dense  *X = nullptr, *Y = nullptr, *E = nullptr;
      cholmod_sparse *Xset = nullptr;
      auto           *b    = static_cast<double *>(B->x);
      for (unsigned int s = 0; s < n_S; ++s)
        {
          const Index k                    = inverse[surface[s]];
          b[k]                             = 1.;
          static_cast<Index *>(Bset->p)[0] = 0;
          static_cast<Index *>(Bset->p)[1] = 1;
          static_cast<Index *>(Bset->i)[0] = k;
          cholmod_l_solve2(CHOLMOD_L, L, B, Bset, &X, &Xset, &Y, &E, &c);
          b[k]                  = 0.;
          const auto *x         = static_cast<const double *>(X->x);
          const auto *pattern   = static_cast<const Index *>(Xset->i);
          const Index n_pattern = static_cast<const Index *>(Xset->p)[1];
          auto       &column    = Y_columns[s];
          for (Index q = 0; q < n_pattern; ++q)
            if (x[pattern[q]] != 0.)
              column.emplace_back(pattern[q], x[pattern[q]]);
          std::sort(column.begin(), column.end());
        }
      cholmod_l_free_dense(&X, &c);
      cholmod_l_free_dense(&Y, &c);
      cholmod_l_free_dense(&E, &c);
      cholmod_l_free_sparse(&Xset, &c);
      cholmod_l_free_sparse(&Bset, &c);
      cholmod_l_free_dense(&B, &c);
    }
    const double    forward_time = t.wall_time();
    double          nnz_Y        = 0;
    std::set<Index> rows;
    for (const auto &column : Y_columns)
      {
        nnz_Y += column.size();
        for (const auto &entry : column)
          rows.insert(entry.first);
      }
    std::cout << "sparse forward solves (|S| columns, incl. conversion to "
                 "simplicial): "
              << forward_time << " s, " << 1e3 * forward_time / n_S
              << " ms per column; mean nnz per column " << nnz_Y / n_S
              << ", rows touched " << rows.size() << " of " << n << std::endl;

    // K^{-1}_SC = Y_S^T Y_C: Y_S stored by rows (row k: the surface DoFs s
    // with Y(k, s) != 0 and the values), then column c of the product is
    // the sum over the pattern of y_c of y_c(k) times row k of Y_S.
    t.restart();
    std::vector<std::vector<std::pair<unsigned int, double>>> Y_rows(n);
    for (unsigned int s = 0; s < n_S; ++s)
      for (const auto &[i, y] : Y_columns[s])
        Y_rows[i].emplace_back(s, y);
    const double transpose_time = t.wall_time();
    t.restart();
    std::vector<double> product(n_S);
    double              max_difference = 0, max_value = 0;
    for (unsigned int k = 0; k < n_C; ++k)
      {
        std::fill(product.begin(), product.end(), 0.);
        for (const auto &[i, y] : Y_columns[k])
          for (const auto &[s, v] : Y_rows[i])
            product[s] += y * v;
        for (unsigned int s = 0; s < n_S; ++s)
          {
            const double reference =
              batched[k * static_cast<std::size_t>(n_S) + s];
            max_difference =
              std::max(max_difference, std::abs(product[s] - reference));
            max_value = std::max(max_value, std::abs(reference));
          }
      }
    const double product_time = t.wall_time();
    std::cout << "Y_S by rows: " << transpose_time
              << " s; Y_S^T Y_C row by row: " << product_time << " s, "
              << 1e3 * product_time / n_C
              << " ms per column; max |difference| / max |K^-1_SC| "
              << max_difference / max_value << std::endl;
    std::cout << "per column: batched " << 1e3 * batched_time / n_C
              << " ms, forward route "
              << 1e3 * (forward_time / n_S + product_time / n_C)
              << " ms (forward solves of all of S amortised over |S| "
                 "columns)"
              << std::endl;

    cholmod_l_free_factor(&L, &c);
    cholmod_l_free_sparse(&S, &c);
    cholmod_l_finish(&c);
  }
} // namespace

int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  AssertThrow(argc >= 3,
              ExcMessage("Usage: direct-solvers FILE.prm SOLVER [N_RHS]"));
  auto               prm         = Parameters::read_parameters(argv[1]);
  const std::string  solver_type = argv[2];
  const unsigned int n_rhs       = argc > 3 ? std::stoi(argv[3]) : 128;
  TimerOutput timer(std::cout, TimerOutput::never, TimerOutput::wall_times);
  parallel::shared::Triangulation<3> tria(
    MPI_COMM_WORLD,
    Triangulation<3>::none,
    false,
    parallel::shared::Triangulation<3>::partition_metis);
  Mesh::read_mesh(prm.mesh, tria);
  Elasticity::LinearElasticity el(tria,
                                  prm.materials,
                                  prm.linear_solver,
                                  1,
                                  MPI_COMM_WORLD,
                                  timer);
  el.distribute_dofs();
  MappingQ1<3>              mapping;
  AffineConstraints<double> c;
  VectorTools::interpolate_boundary_values(mapping,
                                           el.get_dof_handler(),
                                           Mesh::BoundaryIds::femur_fixation,
                                           Functions::ZeroFunction<3>(3),
                                           c);
  c.close();
  TKR::Elasticity::ElasticSystem system(el);
  system.setup(c);
  Elasticity::BoundaryLoads loads;
  Tensor<2, 3>              S;
  S[0][0] = S[1][1] = S[2][2]                      = 0.1;
  loads.springs[Mesh::BoundaryIds::tibia_inferior] = S;
  system.assemble(mapping, c, loads);
  print("DoFs", el.get_dof_handler().n_dofs());
  print("nonzeros of K", system.matrix().n_nonzero_elements());
  print("MPI ranks", Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD));
  print("BLAS threads (0: not set)", Elasticity::DirectSolver::blas_threads());
  if (Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) == 0)
    std::cout << "BLAS (dgemm_) from "
              << Elasticity::DirectSolver::blas_library() << std::endl;

  Epetra_CrsMatrix &A =
    const_cast<Epetra_CrsMatrix &>(system.matrix().trilinos_matrix());
  if (solver_type == "orderings")
    time_orderings(A);
  else if (solver_type == "forward")
    {
      std::vector<types::global_dof_index> surface;
      for (const auto id :
           {Mesh::BoundaryIds::tibia_contact, Mesh::BoundaryIds::femur_contact})
        {
          const Mortar::ContactSurface contact_surface(el.get_dof_handler(),
                                                       id);
          for (const auto &node : contact_surface.nodes())
            for (const auto dof : node.dofs)
              if (!c.is_constrained(dof))
                surface.push_back(dof);
        }
      time_forward(A, surface, n_rhs);
    }
  else
    time_solver(solver_type, A, system.matrix(), n_rhs);
}
