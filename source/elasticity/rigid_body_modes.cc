// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <deal.II/base/quadrature.h>

#include <deal.II/fe/fe_values.h>

#include <deal.II/grid/grid_tools.h>

#include <tkr/elasticity/rigid_body_modes.h>

namespace TKR::Elasticity
{
  using namespace dealii;

  // A rigid motion is u(x) = a + w x (x - c). Its six basis vectors are the
  // unit translations a = e_d and the unit rotations w = e_d; c is the centre
  // of the bounding box, which keeps the rotation modes of the order of the
  // mesh size rather than of the distance to the origin.
  std::unique_ptr<Epetra_MultiVector>
  rigid_body_modes(const Mapping<3>    &mapping,
                   const DoFHandler<3> &dof_handler,
                   const IndexSet      &owned_dofs,
                   const Epetra_Map    &owned_map)
  {
    const auto &fe = dof_handler.get_fe();
    AssertThrow(fe.has_support_points(),
                ExcMessage("The element needs support points."));
    const Point<3> centre =
      GridTools::compute_bounding_box(dof_handler.get_triangulation()).center();

    auto modes = std::make_unique<Epetra_MultiVector>(owned_map, 6);
    const Quadrature<3> support_points(fe.get_unit_support_points());
    FEValues<3>         fe_values(mapping,
                          fe,
                          support_points,
                          update_quadrature_points);
    std::vector<types::global_dof_index> dof_indices(fe.n_dofs_per_cell());

    for (const auto &cell : dof_handler.active_cell_iterators())
      {
        if (cell->is_artificial())
          continue;
        cell->get_dof_indices(dof_indices);
        bool has_owned = false;
        for (const auto i : dof_indices)
          has_owned = has_owned || owned_dofs.is_element(i);
        if (!has_owned)
          continue;
        fe_values.reinit(cell);
        for (unsigned int i = 0; i < dof_indices.size(); ++i)
          {
            if (!owned_dofs.is_element(dof_indices[i]))
              continue;
            const unsigned int component =
              fe.system_to_component_index(i).first;
            const int local      = owned_dofs.index_within_set(dof_indices[i]);
            const Tensor<1, 3> x = fe_values.quadrature_point(i) - centre;
            (*modes)[component][local] = 1.;
            // Rotation about axis r: u = e_r x x, component c of it.
            for (unsigned int r = 0; r < 3; ++r)
              {
                Tensor<1, 3> axis;
                axis[r]                = 1.;
                (*modes)[3 + r][local] = cross_product_3d(axis, x)[component];
              }
          }
      }
    return modes;
  }
} // namespace TKR::Elasticity
