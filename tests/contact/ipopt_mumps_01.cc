// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.
//
// Ipopt's sequential MUMPS (libdmumps_seq) and the parallel MUMPS that
// Trilinos Amesos pulls in (libdmumps) define the same symbols (dmumps_c,
// the MPI stubs, ...). This program calls the parallel MUMPS itself, so
// that libdmumps is a direct dependency of the executable and comes first
// in the loader's global search order, ahead of anything libtkr brings in.
// Then it solves the contact patch test (patch-coarse.msh, see patch_01)
// with the Ipopt reference solver: if Ipopt's calls to dmumps_c were bound
// to the parallel MUMPS, they would fail ("ERROR in MPI_ALLREDUCE"). The
// exact contact pressure is uniform, lambda_j = p.

#include <tkr/contact/ipopt_solver.h>

#include <dmumps_c.h>

#include "patch_test.h"

namespace
{
  // 2 x1 + x2 = 4, x1 + 3 x2 = 7 (x = (1, 2)) with the parallel MUMPS on
  // MPI_COMM_WORLD; the matrix and right-hand side live on rank 0.
  std::vector<double>
  solve_with_parallel_mumps()
  {
    DMUMPS_STRUC_C id;
    id.comm_fortran = static_cast<MUMPS_INT>(MPI_Comm_c2f(MPI_COMM_WORLD));
    id.par          = 1;
    id.sym          = 0;
    id.job          = -1;
    dmumps_c(&id);
    id.icntl[0] = id.icntl[1] = id.icntl[2] = -1; // no output
    id.icntl[3]                             = 0;

    MUMPS_INT           row[]    = {1, 1, 2, 2};
    MUMPS_INT           column[] = {1, 2, 1, 2};
    double              value[]  = {2., 1., 1., 3.};
    std::vector<double> rhs      = {4., 7.};
    id.n                         = 2;
    id.nnz                       = 4;
    id.irn                       = row;
    id.jcn                       = column;
    id.a                         = value;
    id.rhs                       = rhs.data();
    id.job                       = 6;
    dmumps_c(&id);
    const int error = id.infog[0];
    id.job          = -2;
    dmumps_c(&id);
    AssertThrow(error == 0, ExcMessage("Parallel MUMPS failed."));
    return rhs;
  }
} // namespace

int
main(int argc, char **argv)
{
  using namespace TKR;
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  initlog();
  const MPI_Comm comm = MPI_COMM_WORLD;

  const std::vector<double> x = solve_with_parallel_mumps();
  deallog << "parallel MUMPS: x = " << x[0] << ' ' << x[1] << std::endl;

  // The patch test (as in patch_01, coarse mesh) with Ipopt to 1e-10
  // (1e-2 x the contact solver's tolerance).
  PatchProblem              problem("patch-coarse.msh");
  Parameters::ContactSolver parameters;
  parameters.tolerance = 1e-8;
  ConditionalOStream   silent(std::cout, false);
  Contact::IpoptSolver solver(problem.elasticity,
                              *problem.coupling,
                              parameters,
                              problem.materials.tibia.youngs_modulus,
                              comm,
                              silent,
                              problem.timer);
  solver.setup(problem.mapping, problem.dirichlet, problem.loads);
  Contact::ContactState state;
  const auto            statistics =
    solver.solve(problem.mapping, problem.loads, 0., state);
  const double max_error = PatchProblem::max_pressure_error(state);

  deallog << "DoFs: " << problem.elasticity.get_dof_handler().n_dofs()
          << std::endl;
  deallog << "Ipopt converged: " << yes_no(statistics.converged) << std::endl;
  deallog << "slave nodes: " << state.pressure.size()
          << ", active: " << statistics.n_active << std::endl;
  deallog << "contact force (N): " << statistics.contact_force << std::endl;
  deallog << "pressure uniform (= p) to 1e-6: " << yes_no(max_error < 1e-6)
          << std::endl;
}
