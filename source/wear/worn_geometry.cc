// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <deal.II/fe/fe_q.h>

#include <tkr/wear/worn_geometry.h>

namespace TKR::Wear
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
    displacement.reinit(owned_dofs,
                        complete_index_set(dof_handler.n_dofs()),
                        mpi_communicator);
    mapping =
      std::make_unique<MappingQEulerian<3, TrilinosWrappers::MPI::Vector>>(
        1,
        dof_handler,
        displacement);
    update_positions();
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
    positions = triangulation.get_vertices();
    for (const auto &cell : dof_handler.active_cell_iterators())
      for (const auto v : cell->vertex_indices())
        for (unsigned int c = 0; c < 3; ++c)
          positions[cell->vertex_index(v)][c] =
            cell->vertex(v)[c] + displacement[cell->vertex_dof_index(v, c)];
  }
} // namespace TKR::Wear
