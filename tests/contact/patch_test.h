// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.
//
// The contact patch test of patch_01 (structured meshes) and patch_02
// (unstructured ones): two flat blocks with non-matching interface meshes,
// both on roller supports (u_x = 0 on x = 0, u_y = 0 on y = 0; the tibia
// also u_z = 0 on its inferior face), the femur pressed down by a uniform
// traction p on its fixation face and held only by contact. The exact
// solution is uniaxial stress in both bodies (different lateral expansion,
// free to slide), so the mortar contact must transmit exactly the uniform
// pressure p at every slave node.

#ifndef tkr_tests_contact_patch_test_h
#define tkr_tests_contact_patch_test_h

#include <deal.II/base/conditional_ostream.h>

#include <deal.II/distributed/shared_tria.h>

#include <deal.II/fe/mapping_q1.h>

#include <deal.II/numerics/vector_tools.h>

#include <tkr/contact/active_set_solver.h>
#include <tkr/mesh/mesh.h>
#include <tkr/mortar/mortar_coupling.h>

#include "../tests.h"

/**
 * Run the patch test on meshes/verification/@p mesh_file, write the
 * solve's numbers to deallog and return the largest relative error of the
 * slave nodes' pressures.
 */
inline double
run_patch_test(const std::string &mesh_file)
{
  using namespace TKR;
  const MPI_Comm               comm     = MPI_COMM_WORLD;
  const double                 pressure = 3.; // MPa
  constexpr types::boundary_id x_roller = 10, y_roller = 11;

  parallel::shared::Triangulation<3> triangulation(
    comm,
    Triangulation<3>::none,
    false,
    parallel::shared::Triangulation<3>::partition_metis);
  Parameters::Mesh mesh = Parameters::Mesh::with_default_groups(
    std::string(SOURCE_DIR) + "/../../meshes/verification/" + mesh_file);
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
  const Parameters::ContactSolver
    contact{Parameters::ContactAlgorithm::active_set, 1e-8, 20, 1., 1e-8, 0.01};

  TimerOutput                  timer(comm,
                    std::cout,
                    TimerOutput::never,
                    TimerOutput::wall_times);
  MappingQ1<3>                 mapping;
  Elasticity::LinearElasticity elasticity(triangulation,
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

  ConditionalOStream        silent(std::cout, false);
  Contact::ActiveSetSolver  solver(elasticity,
                                  coupling,
                                  contact,
                                  materials.tibia.youngs_modulus,
                                  comm,
                                  silent,
                                  timer,
                                  true);
  Elasticity::BoundaryLoads loads;
  loads.tractions[Mesh::BoundaryIds::femur_fixation] =
    Tensor<1, 3>({0., 0., -pressure});
  solver.setup(mapping, dirichlet, loads);
  Contact::ContactState state;
  const auto            statistics = solver.solve(mapping, loads, 1e-8, state);

  double max_error = 0;
  for (unsigned int j = 0; j < state.pressure.size(); ++j)
    max_error =
      std::max(max_error, std::abs(state.pressure[j] - pressure) / pressure);
  deallog << "DoFs: " << elasticity.get_dof_handler().n_dofs() << std::endl;
  deallog << "slave nodes: " << state.pressure.size()
          << ", active: " << statistics.n_active << std::endl;
  deallog << "converged: " << yes_no(statistics.converged) << " in "
          << statistics.newton_iterations << " active-set iteration(s)"
          << std::endl;
  deallog << "contact area (mm^2): " << statistics.contact_area << std::endl;
  deallog << "contact force (N): " << statistics.contact_force << std::endl;
  return max_error;
}

#endif
