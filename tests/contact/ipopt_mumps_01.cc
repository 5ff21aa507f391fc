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

#include <deal.II/base/timer.h>

#include <deal.II/distributed/shared_tria.h>

#include <deal.II/fe/mapping_q1.h>

#include <deal.II/numerics/vector_tools.h>

#include <tkr/contact/ipopt_solver.h>
#include <tkr/mesh/mesh.h>
#include <tkr/mortar/mortar_coupling.h>

#include <dmumps_c.h>

#include "../tests.h"

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

  // The patch test (as in patch_01, coarse mesh) with Ipopt.
  const double                       pressure = 3.; // MPa
  constexpr types::boundary_id       x_roller = 10, y_roller = 11;
  parallel::shared::Triangulation<3> triangulation(
    comm,
    Triangulation<3>::none,
    false,
    parallel::shared::Triangulation<3>::partition_metis);
  Parameters::Mesh mesh = Parameters::Mesh::with_default_groups(
    std::string(SOURCE_DIR) + "/../../meshes/verification/patch-coarse.msh");
  Mesh::read_mesh(mesh, triangulation);
  for (const auto &cell : triangulation.active_cell_iterators())
    for (const auto &face : cell->face_iterators())
      if (face->at_boundary() && face->boundary_id() == Mesh::BoundaryIds::free)
        {
          if (std::abs(face->center()[0]) < 1e-10)
            face->set_boundary_id(x_roller);
          else if (std::abs(face->center()[1]) < 1e-10)
            face->set_boundary_id(y_roller);
        }

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

  AffineConstraints<double> dirichlet;
  for (const auto &[id, component] :
       std::vector<std::pair<types::boundary_id, unsigned int>>{
         {x_roller, 0},
         {y_roller, 1},
         {Mesh::BoundaryIds::tibia_inferior, 2}})
    {
      ComponentMask mask(3, false);
      mask.set(component, true);
      VectorTools::interpolate_boundary_values(mapping,
                                               elasticity.get_dof_handler(),
                                               id,
                                               Functions::ZeroFunction<3>(3),
                                               dirichlet,
                                               mask);
    }
  dirichlet.close();

  const Mortar::ContactSurface slave(elasticity.get_dof_handler(),
                                     Mesh::BoundaryIds::tibia_contact);
  const Mortar::ContactSurface master(elasticity.get_dof_handler(),
                                      Mesh::BoundaryIds::femur_contact);
  Mortar::MortarCoupling       coupling(slave, master);
  coupling.reinit(triangulation.get_vertices(), 1.);

  // Ipopt to 1e-10 (1e-2 x the contact solver's tolerance).
  Parameters::ContactSolver parameters;
  parameters.tolerance = 1e-8;
  ConditionalOStream        silent(std::cout, false);
  Contact::IpoptSolver      solver(elasticity,
                              coupling,
                              parameters,
                              materials.tibia.youngs_modulus,
                              comm,
                              silent,
                              timer);
  Elasticity::BoundaryLoads loads;
  loads.tractions[Mesh::BoundaryIds::femur_fixation] =
    Tensor<1, 3>({0., 0., -pressure});
  solver.setup(mapping, dirichlet, loads);
  Contact::ContactState state;
  const auto            statistics = solver.solve(mapping, loads, 0., state);

  double max_error = 0;
  for (unsigned int j = 0; j < state.pressure.size(); ++j)
    max_error =
      std::max(max_error, std::abs(state.pressure[j] - pressure) / pressure);
  deallog << "DoFs: " << elasticity.get_dof_handler().n_dofs() << std::endl;
  deallog << "Ipopt converged: " << yes_no(statistics.converged) << std::endl;
  deallog << "slave nodes: " << state.pressure.size()
          << ", active: " << statistics.n_active << std::endl;
  deallog << "contact force (N): " << statistics.contact_force << std::endl;
  deallog << "pressure uniform (= p) to 1e-6: " << yes_no(max_error < 1e-6)
          << std::endl;
}
