// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.
//
// The contact patch test of patch_01 (structured meshes), patch_02
// (unstructured ones) and ipopt_mumps_01 (the Ipopt solver): two flat
// blocks with non-matching interface meshes, both on roller supports
// (u_x = 0 on x = 0, u_y = 0 on y = 0; the tibia also u_z = 0 on its
// inferior face), the femur pressed down by a uniform traction p on its
// fixation face and held only by contact. The exact solution is uniaxial
// stress in both bodies (different lateral expansion, free to slide), so
// the mortar contact must transmit exactly the uniform pressure p at every
// slave node.

#ifndef tkr_tests_contact_patch_test_h
#define tkr_tests_contact_patch_test_h

#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/timer.h>

#include <deal.II/distributed/shared_tria.h>

#include <deal.II/fe/mapping_q1.h>

#include <deal.II/numerics/vector_tools.h>

#include <tkr/contact/active_set_solver.h>
#include <tkr/mesh/mesh.h>
#include <tkr/mortar/mortar_coupling.h>

#include <memory>
#include <string>

#include "../tests.h"

/**
 * The patch test's problem on meshes/verification/@p mesh_file: bodies,
 * supports, load and the mortar coupling of the reference position.
 */
struct PatchProblem
{
  static constexpr double                     pressure = 3.; // MPa
  static constexpr dealii::types::boundary_id x_roller = 10, y_roller = 11;

  explicit PatchProblem(const std::string &mesh_file)
    : comm(MPI_COMM_WORLD)
    , triangulation(comm,
                    dealii::Triangulation<3>::none,
                    false,
                    dealii::parallel::shared::Triangulation<3>::partition_metis)
    , materials(make_materials())
    , timer(comm,
            std::cout,
            dealii::TimerOutput::never,
            dealii::TimerOutput::wall_times)
    , elasticity(read(mesh_file),
                 materials,
                 TKR::Parameters::LinearSolver{1e-10, 1000, true, 0.02, 2},
                 1,
                 comm,
                 timer)
  {
    using namespace TKR;
    elasticity.distribute_dofs();
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
    slave = std::make_unique<Mortar::ContactSurface>(
      elasticity.get_dof_handler(),
      Mesh::BoundaryIds::tibia_contact);
    master = std::make_unique<Mortar::ContactSurface>(
      elasticity.get_dof_handler(),
      Mesh::BoundaryIds::femur_contact);
    coupling = std::make_unique<Mortar::MortarCoupling>(*slave, *master);
    coupling->reinit(triangulation.get_vertices(), 1.);
    loads.tractions[Mesh::BoundaryIds::femur_fixation] =
      Tensor<1, 3>({0., 0., -pressure});
  }

  /** The largest relative error of the slave nodes' pressures. */
  static double
  max_pressure_error(const TKR::Contact::ContactState &state)
  {
    double max_error = 0;
    for (const double p : state.pressure)
      max_error = std::max(max_error, std::abs(p - pressure) / pressure);
    return max_error;
  }

  const MPI_Comm                               comm;
  dealii::parallel::shared::Triangulation<3>   triangulation;
  const TKR::Parameters::Materials             materials;
  dealii::TimerOutput                          timer;
  dealii::MappingQ1<3>                         mapping;
  TKR::Elasticity::LinearElasticity            elasticity;
  dealii::AffineConstraints<double>            dirichlet;
  std::unique_ptr<TKR::Mortar::ContactSurface> slave, master;
  std::unique_ptr<TKR::Mortar::MortarCoupling> coupling;
  TKR::Elasticity::BoundaryLoads               loads;

private:
  static TKR::Parameters::Materials
  make_materials()
  {
    TKR::Parameters::Materials materials;
    materials.femur = {220000., 0.31, 8.3};
    materials.tibia = {1100., 0.42, 0.935};
    return materials;
  }

  // Read the mesh; both blocks on rollers: x = 0 and y = 0 of the free
  // faces.
  dealii::parallel::shared::Triangulation<3> &
  read(const std::string &mesh_file)
  {
    using namespace TKR;
    Parameters::Mesh mesh = Parameters::Mesh::with_default_groups(
      std::string(SOURCE_DIR) + "/../../meshes/verification/" + mesh_file);
    Mesh::read_mesh(mesh, triangulation);
    for (const auto &cell : triangulation.active_cell_iterators())
      for (const auto &face : cell->face_iterators())
        if (face->at_boundary() &&
            face->boundary_id() == Mesh::BoundaryIds::free)
          {
            if (std::abs(face->center()[0]) < 1e-10)
              face->set_boundary_id(x_roller);
            else if (std::abs(face->center()[1]) < 1e-10)
              face->set_boundary_id(y_roller);
          }
    return triangulation;
  }
};

/**
 * Run the patch test on meshes/verification/@p mesh_file with the active
 * set solver, write the solve's numbers to deallog and return the largest
 * relative error of the slave nodes' pressures.
 */
inline double
run_patch_test(const std::string &mesh_file)
{
  using namespace TKR;
  PatchProblem problem(mesh_file);
  const Parameters::ContactSolver
    contact{Parameters::ContactAlgorithm::active_set, 1e-8, 20, 1., 1e-8, 0.01};
  ConditionalOStream       silent(std::cout, false);
  Contact::ActiveSetSolver solver(problem.elasticity,
                                  *problem.coupling,
                                  contact,
                                  problem.materials.tibia.youngs_modulus,
                                  problem.comm,
                                  silent,
                                  problem.timer,
                                  true);
  solver.setup(problem.mapping, problem.dirichlet, problem.loads);
  Contact::ContactState state;
  const auto            statistics =
    solver.solve(problem.mapping, problem.loads, 1e-8, state);

  deallog << "DoFs: " << problem.elasticity.get_dof_handler().n_dofs()
          << std::endl;
  deallog << "slave nodes: " << state.pressure.size()
          << ", active: " << statistics.n_active << std::endl;
  deallog << "converged: " << yes_no(statistics.converged) << " in "
          << statistics.newton_iterations << " active-set iteration(s)"
          << std::endl;
  deallog << "contact area (mm^2): " << statistics.contact_area << std::endl;
  deallog << "contact force (N): " << statistics.contact_force << std::endl;
  return PatchProblem::max_pressure_error(state);
}

#endif
