// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.
//
// Two blocks of different materials (femur: CoCrMo, tibia: UHMWPE), each on
// roller supports (u_x = 0 on x = 0, u_y = 0 on y = 0, u_z = 0 on the far
// z face) and compressed by a uniform pressure p on its contact face. The
// exact solution is a state of uniaxial stress, sigma_zz = -p, with the
// linear displacement u = (nu p x / E, nu p y / E, -p (z - z_0) / E), which
// Q1 elements reproduce exactly. Checks displacement and stress to 1e-10
// relative, on one or two MPI ranks (same output).

#include <deal.II/base/quadrature_lib.h>

#include <deal.II/distributed/shared_tria.h>

#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/mapping_q1.h>

#include <deal.II/grid/grid_generator.h>

#include <deal.II/numerics/vector_tools.h>

#include <tkr/elasticity/elastic_system.h>
#include <tkr/elasticity/linear_elasticity.h>
#include <tkr/mesh/mesh.h>

#include "../tests.h"

namespace
{
  constexpr double pressure  = 2.0; // MPa
  constexpr double tibia_top = 8., femur_bottom = 9., femur_top = 15.;
  constexpr types::boundary_id x_roller = 10, y_roller = 11, z_roller = 12;

  Tensor<1, 3>
  exact_displacement(const TKR::Parameters::Material &material,
                     const Point<3>                  &x,
                     const double                     z_fixed)
  {
    const double strain = pressure / material.youngs_modulus;
    return Tensor<1, 3>({material.poissons_ratio * strain * x[0],
                         material.poissons_ratio * strain * x[1],
                         -strain * (x[2] - z_fixed)});
  }
} // namespace

int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  initlog();
  const MPI_Comm comm = MPI_COMM_WORLD;

  parallel::shared::Triangulation<3> triangulation(
    comm,
    Triangulation<3>::none,
    false,
    parallel::shared::Triangulation<3>::partition_metis);
  {
    Triangulation<3> tibia, femur;
    GridGenerator::subdivided_hyper_rectangle(tibia,
                                              {3, 4, 2},
                                              Point<3>(0, 0, 0),
                                              Point<3>(10, 12, tibia_top));
    GridGenerator::subdivided_hyper_rectangle(femur,
                                              {2, 3, 3},
                                              Point<3>(0, 0, femur_bottom),
                                              Point<3>(10, 12, femur_top));
    GridGenerator::merge_triangulations(tibia, femur, triangulation);
  }
  for (const auto &cell : triangulation.active_cell_iterators())
    {
      const bool is_tibia = cell->center()[2] < tibia_top;
      cell->set_material_id(is_tibia ? TKR::Mesh::MaterialIds::tibia :
                                       TKR::Mesh::MaterialIds::femur);
      for (const auto &face : cell->face_iterators())
        if (face->at_boundary())
          {
            const Point<3> c = face->center();
            if (std::abs(c[0]) < 1e-12)
              face->set_boundary_id(x_roller);
            else if (std::abs(c[1]) < 1e-12)
              face->set_boundary_id(y_roller);
            else if (std::abs(c[2]) < 1e-12 ||
                     std::abs(c[2] - femur_top) < 1e-12)
              face->set_boundary_id(z_roller);
            else if (std::abs(c[2] - tibia_top) < 1e-12)
              face->set_boundary_id(TKR::Mesh::BoundaryIds::tibia_contact);
            else if (std::abs(c[2] - femur_bottom) < 1e-12)
              face->set_boundary_id(TKR::Mesh::BoundaryIds::femur_contact);
          }
    }

  TKR::Parameters::Materials materials;
  materials.femur = {220000., 0.31, 8.3};
  materials.tibia = {1100., 0.42, 0.935};
  TKR::Parameters::LinearSolver solver{1e-12, 500, true, 0.02, 2};

  TimerOutput                       timer(comm,
                    std::cout,
                    TimerOutput::never,
                    TimerOutput::wall_times);
  MappingQ1<3>                      mapping;
  TKR::Elasticity::LinearElasticity elasticity(triangulation,
                                               materials,
                                               solver,
                                               1,
                                               comm,
                                               timer);
  elasticity.distribute_dofs();
  const auto &dof_handler = elasticity.get_dof_handler();

  AffineConstraints<double> constraints;
  for (unsigned int d = 0; d < 3; ++d)
    {
      ComponentMask mask(3, false);
      mask.set(d, true);
      VectorTools::interpolate_boundary_values(mapping,
                                               dof_handler,
                                               x_roller + d,
                                               Functions::ZeroFunction<3>(3),
                                               constraints,
                                               mask);
    }
  constraints.close();
  TKR::Elasticity::ElasticSystem system(elasticity);
  system.setup(constraints);
  TKR::Elasticity::BoundaryLoads loads;
  loads.tractions = {
    {TKR::Mesh::BoundaryIds::tibia_contact, Tensor<1, 3>({0, 0, -pressure})},
    {TKR::Mesh::BoundaryIds::femur_contact, Tensor<1, 3>({0, 0, pressure})}};
  system.assemble(mapping, constraints, loads);
  system.setup_preconditioner(mapping);
  const auto statistics = system.solve(constraints);
  deallog << "DoFs: " << dof_handler.n_dofs() << std::endl;
  deallog << "CG converged: " << yes_no(statistics.converged) << std::endl;

  // Compare nodal values and quadrature-point stresses with the exact
  // solution, relative to the largest exact displacement and to p.
  double      max_u = 0, u_error = 0, sigma_error = 0;
  const auto &fe = elasticity.get_fe();
  FEValues<3> fe_values(mapping,
                        fe,
                        Quadrature<3>(
                          fe.base_element(0).get_unit_support_points()),
                        update_quadrature_points | update_values);
  FEValues<3> fe_values_q(mapping, fe, QGauss<3>(2), update_gradients);
  const FEValuesExtractors::Vector   u(0);
  std::vector<Tensor<1, 3>>          values(fe_values.n_quadrature_points);
  std::vector<SymmetricTensor<2, 3>> strains(fe_values_q.n_quadrature_points);
  for (const auto &cell : dof_handler.active_cell_iterators())
    if (cell->is_locally_owned())
      {
        const bool is_tibia =
          cell->material_id() == TKR::Mesh::MaterialIds::tibia;
        const auto &material = is_tibia ? materials.tibia : materials.femur;
        fe_values.reinit(cell);
        fe_values[u].get_function_values(system.solution(), values);
        for (unsigned int q = 0; q < values.size(); ++q)
          {
            const Tensor<1, 3> exact =
              exact_displacement(material,
                                 fe_values.quadrature_point(q),
                                 is_tibia ? 0. : femur_top);
            max_u   = std::max(max_u, exact.norm());
            u_error = std::max(u_error, (values[q] - exact).norm());
          }
        fe_values_q.reinit(cell);
        fe_values_q[u].get_function_symmetric_gradients(system.solution(),
                                                        strains);
        SymmetricTensor<2, 3> exact_stress;
        exact_stress[2][2] = -pressure;
        for (const auto &strain : strains)
          sigma_error = std::max(
            sigma_error,
            (TKR::Elasticity::stress(material, strain) - exact_stress).norm());
      }
  max_u       = Utilities::MPI::max(max_u, comm);
  u_error     = Utilities::MPI::max(u_error, comm) / max_u;
  sigma_error = Utilities::MPI::max(sigma_error, comm) / pressure;

  deallog << "Largest exact displacement (um): " << 1e3 * max_u << std::endl;
  deallog << "Max displacement femur (um): "
          << 1e3 * elasticity.max_displacement(system.solution(),
                                               TKR::Mesh::MaterialIds::femur)
          << std::endl;
  deallog << "Max displacement tibia (um): "
          << 1e3 * elasticity.max_displacement(system.solution(),
                                               TKR::Mesh::MaterialIds::tibia)
          << std::endl;
  deallog << "Displacement error below 1e-10 relative: "
          << yes_no(u_error < 1e-10) << std::endl;
  deallog << "Stress error below 1e-10 relative: "
          << yes_no(sigma_error < 1e-10) << std::endl;
  if (u_error >= 1e-10 || sigma_error >= 1e-10)
    deallog << "errors: " << u_error << ' ' << sigma_error << std::endl;
}
