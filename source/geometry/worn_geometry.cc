// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <deal.II/fe/fe_q.h>

#include <tkr/geometry/worn_geometry.h>
#include <tkr/mesh/mesh.h>

namespace TKR::Geometry
{
  using namespace dealii;

  WornGeometry::WornGeometry(const Triangulation<3> &triangulation,
                             const MPI_Comm          mpi_communicator)
    : triangulation(triangulation)
    , mpi_communicator(mpi_communicator)
    , fe(FE_Q<3>(1), 3)
    , dof_handler(triangulation)
  {}

  void
  WornGeometry::initialize()
  {
    dof_handler.distribute_dofs(fe);
    owned_dofs = dof_handler.locally_owned_dofs();
    // Every rank reads every entry: all DoFs are ghosts.
    for (auto *field : {&displacement, &stiffness_displacement})
      field->reinit(owned_dofs,
                    complete_index_set(dof_handler.n_dofs()),
                    mpi_communicator);
    mapping = std::make_unique<EulerMapping>(1, dof_handler, displacement);
    stiffness_euler_mapping =
      std::make_unique<EulerMapping>(1, dof_handler, stiffness_displacement);
    depth.assign(triangulation.n_vertices(), 0.);
    surface = std::make_unique<Mortar::ContactSurface>(
      dof_handler,
      Mesh::BoundaryIds::tibia_contact);
    update_positions();
  }

  void
  WornGeometry::update_stiffness_geometry()
  {
    stiffness_displacement = displacement;
  }

  void
  WornGeometry::set_displacement(
    const TrilinosWrappers::MPI::Vector &owned_displacement)
  {
    displacement = owned_displacement;
    update_positions();
  }

  void
  WornGeometry::update_positions()
  {
    positions    = triangulation.get_vertices();
    const auto u = vertex_displacements();
    for (unsigned int v = 0; v < positions.size(); ++v)
      positions[v] += u[v];
    surface_measures = surface->nodal_measures(positions);
  }

  std::vector<Tensor<1, 3>>
  WornGeometry::vertex_displacements(const bool of_stiffness_geometry) const
  {
    return values_at_vertices(of_stiffness_geometry ? stiffness_displacement :
                                                      displacement);
  }

  std::vector<Tensor<1, 3>>
  WornGeometry::vertices_from_field(
    const TrilinosWrappers::MPI::Vector &owned_field) const
  {
    TrilinosWrappers::MPI::Vector field(displacement);
    field = owned_field;
    return values_at_vertices(field);
  }

  std::vector<Tensor<1, 3>>
  WornGeometry::values_at_vertices(
    const TrilinosWrappers::MPI::Vector &field) const
  {
    std::vector<Tensor<1, 3>> u(triangulation.n_vertices());
    for (const auto &cell : dof_handler.active_cell_iterators())
      for (const auto v : cell->vertex_indices())
        for (unsigned int c = 0; c < 3; ++c)
          u[cell->vertex_index(v)][c] = field[cell->vertex_dof_index(v, c)];
    return u;
  }

  TrilinosWrappers::MPI::Vector
  WornGeometry::field_from_vertices(
    const std::vector<Tensor<1, 3>> &vertex_displacement) const
  {
    TrilinosWrappers::MPI::Vector field(owned_dofs, mpi_communicator);
    for (const auto &cell : dof_handler.active_cell_iterators())
      for (const auto v : cell->vertex_indices())
        for (unsigned int c = 0; c < 3; ++c)
          {
            const auto dof = cell->vertex_dof_index(v, c);
            if (owned_dofs.is_element(dof))
              field[dof] = vertex_displacement[cell->vertex_index(v)][c];
          }
    field.compress(VectorOperation::insert);
    return field;
  }

  void
  WornGeometry::set_vertex_displacements(
    const std::vector<Tensor<1, 3>> &current)
  {
    set_displacement(field_from_vertices(current));
  }

  void
  WornGeometry::set_vertex_displacements(
    const std::vector<Tensor<1, 3>> &current,
    const std::vector<Tensor<1, 3>> &of_stiffness_geometry)
  {
    stiffness_displacement = field_from_vertices(of_stiffness_geometry);
    set_displacement(field_from_vertices(current));
  }

  void
  WornGeometry::add_wear_depth(const std::vector<double> &increment)
  {
    AssertDimension(increment.size(), depth.size());
    for (unsigned int v = 0; v < depth.size(); ++v)
      depth[v] += increment[v];
  }

  void
  WornGeometry::set_wear_depth(const std::vector<double> &new_depth)
  {
    AssertDimension(new_depth.size(), depth.size());
    depth = new_depth;
  }
} // namespace TKR::Geometry
