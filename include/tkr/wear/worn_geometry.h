// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_wear_worn_geometry_h
#define tkr_wear_worn_geometry_h

#include <deal.II/base/index_set.h>
#include <deal.II/base/point.h>

#include <deal.II/dofs/dof_handler.h>

#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/mapping_q_eulerian.h>

#include <deal.II/grid/tria.h>

#include <deal.II/lac/trilinos_vector.h>

#include <memory>
#include <vector>

namespace TKR::Wear
{
  /**
   * The one owner of the bodies' reference geometry (DESIGN.md section
   * 4.2, 4.7): the mesh as read, moved by the displacement that the
   * accumulated wear causes (zero on the femur, the wear depth along the
   * inward normal on `tibia_contact`, extended elastically into the
   * tibia). The displacement is a Q1 vector field on its own DoFHandler
   * (whatever the degree of the elasticity), held in a ghosted vector
   * that every rank has completely (a parallel::shared triangulation
   * knows all cells; the mortar coupling needs every surface vertex), and
   * is the Euler vector of a MappingQEulerian. Assembly, mortar coupling
   * and output all use this mapping and these vertex positions, so they
   * always see the same geometry; with zero wear it is the mesh itself.
   *
   * The gait's rigid motions (the femur's flexion, the tibia's pose) are
   * not part of it: they change from step to step and are applied to
   * vertex_positions() for the coupling only (the femur is co-rotated).
   */
  class WornGeometry
  {
  public:
    WornGeometry(const dealii::Triangulation<3> &triangulation,
                 const MPI_Comm                  mpi_communicator);

    /** Set up the field on the (read) mesh, with zero displacement. */
    void
    initialize();

    /** The mapping of the worn geometry (MappingQEulerian of degree 1). */
    const dealii::Mapping<3> &
    get_mapping() const
    {
      return *mapping;
    }

    /** Position of every triangulation vertex in the worn geometry (mm). */
    const std::vector<dealii::Point<3>> &
    vertex_positions() const
    {
      return positions;
    }

    /**
     * Replace the displacement field by @p displacement (locally owned
     * entries, on get_dof_handler()) and update the vertex positions.
     */
    void
    set_displacement(const dealii::TrilinosWrappers::MPI::Vector &displacement);

    /** The Q1 vector DoFHandler of the displacement field. */
    const dealii::DoFHandler<3> &
    get_dof_handler() const
    {
      return dof_handler;
    }

    /** The displacement field (ghosted: every entry readable everywhere). */
    const dealii::TrilinosWrappers::MPI::Vector &
    get_displacement() const
    {
      return displacement;
    }

    /** The locally owned DoFs of the displacement field. */
    const dealii::IndexSet &
    locally_owned_dofs() const
    {
      return owned_dofs;
    }

  private:
    /** Vertex positions from the mesh and the displacement field. */
    void
    update_positions();

    const dealii::Triangulation<3> &triangulation;
    const MPI_Comm                  mpi_communicator;
    const dealii::FESystem<3>       fe;
    dealii::DoFHandler<3>           dof_handler;
    dealii::IndexSet                owned_dofs;
    /** The Euler vector; its address must not change (the mapping keeps
     * it). */
    dealii::TrilinosWrappers::MPI::Vector displacement;
    std::unique_ptr<
      dealii::MappingQEulerian<3, dealii::TrilinosWrappers::MPI::Vector>>
                                  mapping;
    std::vector<dealii::Point<3>> positions;
  };
} // namespace TKR::Wear

#endif
