// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <deal.II/base/quadrature_lib.h>

#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/mapping_q1.h>

#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/full_matrix.h>

#include <tkr/elasticity/linear_elasticity.h>
#include <tkr/geometry/mesh_motion.h>
#include <tkr/mesh/mesh.h>

#include <array>
#include <limits>
#include <map>
#include <utility>

namespace TKR::Geometry
{
  using namespace dealii;

  namespace
  {
    /**
     * The constraints of the extension: every femur DoF and every DoF on
     * tibia_inferior zero, every DoF on tibia_contact the given vertex
     * displacement (or zero without one); then the tibia's other (free)
     * boundary vertices slide on their surface: u . n = 0 with n the
     * vertex's normal, averaged over its free faces, one line on its
     * dominant component. The sides of the insert stay where they are; an
     * elastic extension with free sides would let them bulge (by a third
     * of the depth on the TKR insert: test geometry/mesh_motion_01).
     */
    AffineConstraints<double>
    extension_constraints(const DoFHandler<3>             &dof_handler,
                          const std::vector<Tensor<1, 3>> *displacement)
    {
      AffineConstraints<double> constraints;
      std::map<unsigned int,
               std::pair<Tensor<1, 3>, std::array<types::global_dof_index, 3>>>
        sliding;
      for (const auto &cell : dof_handler.active_cell_iterators())
        {
          if (cell->material_id() == Mesh::MaterialIds::femur)
            {
              for (const auto v : cell->vertex_indices())
                for (unsigned int c = 0; c < 3; ++c)
                  constraints.add_line(cell->vertex_dof_index(v, c));
              continue;
            }
          for (const auto f : cell->face_indices())
            {
              if (!cell->face(f)->at_boundary())
                continue;
              const auto id = cell->face(f)->boundary_id();
              if (id != Mesh::BoundaryIds::tibia_inferior &&
                  id != Mesh::BoundaryIds::tibia_contact)
                {
                  // Area-weighted: the cross product of the diagonals.
                  const auto         face = cell->face(f);
                  const Tensor<1, 3> normal =
                    cross_product_3d(face->vertex(3) - face->vertex(0),
                                     face->vertex(2) - face->vertex(1));
                  const double sign =
                    normal * (face->center() - cell->center()) > 0 ? 1. : -1.;
                  for (const auto v : face->vertex_indices())
                    {
                      auto &[n, dofs] = sliding[face->vertex_index(v)];
                      n += sign * normal;
                      for (unsigned int c = 0; c < 3; ++c)
                        dofs[c] = face->vertex_dof_index(v, c);
                    }
                  continue;
                }
              const bool moves =
                id == Mesh::BoundaryIds::tibia_contact && displacement;
              for (const auto v : cell->face(f)->vertex_indices())
                for (unsigned int c = 0; c < 3; ++c)
                  {
                    const auto dof = cell->face(f)->vertex_dof_index(v, c);
                    if (constraints.is_constrained(dof))
                      continue;
                    constraints.add_line(dof);
                    if (moves)
                      constraints.set_inhomogeneity(
                        dof,
                        (*displacement)[cell->face(f)->vertex_index(v)][c]);
                  }
            }
        }
      for (const auto &[vertex, normal_and_dofs] : sliding)
        {
          const auto &[n, dofs] = normal_and_dofs;
          if (constraints.is_constrained(dofs[0]) || n.norm() == 0.)
            continue;
          unsigned int d = 0;
          for (unsigned int e = 1; e < 3; ++e)
            if (std::abs(n[e]) > std::abs(n[d]))
              d = e;
          constraints.add_line(dofs[d]);
          for (unsigned int e = 0; e < 3; ++e)
            if (e != d && n[e] != 0.)
              constraints.add_entry(dofs[d], dofs[e], -n[e] / n[d]);
        }
      constraints.close();
      return constraints;
    }
  } // namespace

  MeshMotion::MeshMotion(const WornGeometry &geometry,
                         const MPI_Comm      mpi_communicator,
                         TimerOutput        &timer)
    : geometry(geometry)
    , mpi_communicator(mpi_communicator)
    , timer(timer)
  {}

  // The bilinear form int eps(v) : C : eps(u) of an isotropic material
  // with E = 1 and nu = 0.3 on the mesh as read.
  FEValues<3>
  MeshMotion::make_fe_values() const
  {
    return FEValues<3>(reference_mapping,
                       geometry.get_dof_handler().get_fe(),
                       QGauss<3>(2),
                       update_gradients | update_JxW_values);
  }

  void
  MeshMotion::cell_matrix(const DoFHandler<3>::active_cell_iterator &cell,
                          FEValues<3>                               &fe_values,
                          FullMatrix<double>                        &matrix)
  {
    const auto                      &fe = fe_values.get_fe();
    const Parameters::Material       material{1., 0.3, 1.};
    const FEValuesExtractors::Vector u(0);
    fe_values.reinit(cell);
    matrix = 0;
    for (const unsigned int q : fe_values.quadrature_point_indices())
      for (unsigned int i = 0; i < fe.n_dofs_per_cell(); ++i)
        {
          const auto sigma_i =
            Elasticity::stress(material, fe_values[u].symmetric_gradient(i, q));
          for (unsigned int j = 0; j < fe.n_dofs_per_cell(); ++j)
            matrix(i, j) += sigma_i * fe_values[u].symmetric_gradient(j, q) *
                            fe_values.JxW(q);
        }
  }

  void
  MeshMotion::setup()
  {
    TimerOutput::Scope scope(timer, "mesh motion set-up");
    const auto        &dof_handler = geometry.get_dof_handler();
    const IndexSet    &owned       = geometry.locally_owned_dofs();
    constraints = extension_constraints(dof_handler, nullptr);

    // Every rank knows every cell: it builds the rows it owns.
    DynamicSparsityPattern               dsp(dof_handler.n_dofs(),
                               dof_handler.n_dofs(),
                               owned);
    std::vector<types::global_dof_index> dofs(
      dof_handler.get_fe().n_dofs_per_cell());
    for (const auto &cell : dof_handler.active_cell_iterators())
      {
        cell->get_dof_indices(dofs);
        for (const auto row : dofs)
          if (owned.is_element(row))
            dsp.add_entries(row, dofs.begin(), dofs.end());
      }
    matrix.reinit(owned, owned, dsp, mpi_communicator);

    // The femur's DoFs are all constrained; an identity element matrix on
    // its cells gives their rows a diagonal.
    FullMatrix<double> local(dofs.size(), dofs.size());
    FEValues<3>        fe_values = make_fe_values();
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          if (cell->material_id() == Mesh::MaterialIds::femur)
            {
              local = IdentityMatrix(dofs.size());
            }
          else
            cell_matrix(cell, fe_values, local);
          cell->get_dof_indices(dofs);
          constraints.distribute_local_to_global(local, dofs, matrix);
        }
    matrix.compress(VectorOperation::add);
    direct_solver.factorize(matrix);
  }

  // The inhomogeneous constraints carry the surface displacement; their
  // effect on the other rows, -K_{free,contact} g, comes from the element
  // matrices of the cells that touch tibia_contact.
  std::vector<Tensor<1, 3>>
  MeshMotion::extend(const std::vector<Tensor<1, 3>> &vertex_displacement) const
  {
    TimerOutput::Scope              scope(timer, "mesh motion");
    const auto                     &dof_handler = geometry.get_dof_handler();
    const AffineConstraints<double> moved =
      extension_constraints(dof_handler, &vertex_displacement);

    TrilinosWrappers::MPI::Vector rhs(geometry.locally_owned_dofs(),
                                      mpi_communicator);
    const unsigned int            n = dof_handler.get_fe().n_dofs_per_cell();
    FullMatrix<double>            local(n, n);
    Vector<double>                zero(n);
    std::vector<types::global_dof_index> dofs(n);
    FEValues<3>                          fe_values = make_fe_values();
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned() &&
          cell->material_id() == Mesh::MaterialIds::tibia)
        {
          cell->get_dof_indices(dofs);
          bool moves = false;
          for (const auto dof : dofs)
            moves = moves || moved.get_inhomogeneity(dof) != 0.;
          if (!moves)
            continue;
          cell_matrix(cell, fe_values, local);
          moved.distribute_local_to_global(zero, dofs, rhs, local);
        }
    rhs.compress(VectorOperation::add);

    TrilinosWrappers::MPI::Vector u(rhs);
    direct_solver.solve(u.trilinos_vector(), rhs.trilinos_vector());
    moved.distribute(u);
    return geometry.vertices_from_field(u);
  }

  Distortion
  MeshMotion::distortion(
    const std::vector<Tensor<1, 3>> &vertex_displacement) const
  {
    Distortion result;
    for (const auto &cell :
         geometry.get_dof_handler().get_triangulation().active_cell_iterators())
      if (cell->material_id() == Mesh::MaterialIds::tibia)
        {
          std::array<Point<3>, 8> x, x_moved;
          for (const unsigned int v : cell->vertex_indices())
            {
              x[v]       = cell->vertex(v);
              x_moved[v] = x[v] + vertex_displacement[cell->vertex_index(v)];
            }
          const double ratio =
            Mesh::min_vertex_jacobian(x_moved) / Mesh::min_vertex_jacobian(x);
          if (ratio < result.min_ratio)
            {
              result.min_ratio = ratio;
              result.cell      = cell->active_cell_index();
              result.centre    = cell->center();
              for (const unsigned int v : cell->vertex_indices())
                result.vertices[v] = cell->vertex_index(v);
            }
        }
    return result;
  }
} // namespace TKR::Geometry
