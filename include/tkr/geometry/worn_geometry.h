// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_geometry_worn_geometry_h
#define tkr_geometry_worn_geometry_h

#include <deal.II/base/index_set.h>
#include <deal.II/base/point.h>

#include <deal.II/dofs/dof_handler.h>

#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/mapping_q_eulerian.h>

#include <deal.II/grid/tria.h>

#include <deal.II/lac/trilinos_vector.h>

#include <tkr/mortar/contact_surface.h>

#include <memory>
#include <vector>

namespace TKR::Geometry
{
  /**
   * The one owner of the bodies' reference geometry (DESIGN.md sections
   * 4.2, 4.7): the mesh as read, moved by the displacement that the
   * accumulated wear causes (zero on the femur, the wear depth along the
   * inward normal on `tibia_contact`, extended elastically into the tibia
   * by MeshMotion), and the accumulated wear depth itself.
   *
   * The displacement is a Q1 vector field on its own DoFHandler (whatever
   * the degree of the elasticity), held in a ghosted vector that every rank
   * has completely (a parallel::shared triangulation knows all cells; the
   * mortar coupling needs every surface vertex), and is the Euler vector of
   * a MappingQEulerian. Assembly, mortar coupling and output all use this
   * mapping and these vertex positions, so they always see the same
   * geometry; with zero wear it is the mesh itself.
   *
   * A second Euler vector keeps the geometry on which the stiffness was
   * last assembled (stiffness_mapping()): the stiffness may lag behind the
   * worn geometry by some blocks (`Wear/Stiffness update interval`), the
   * contact geometry never does.
   *
   * The gait's rigid motions (the femur's flexion, the tibia's pose) are
   * not part of it: they change from step to step and are applied to
   * vertex_positions() for the coupling only (the femur is co-rotated).
   *
   * It also knows the worn surface itself: the `tibia_contact` nodes
   * (worn_surface(), numbered as the slave nodes of the mortar coupling)
   * with their nodal areas and outward normals in the current geometry
   * (worn_surface_measures()), along which the wear moves them.
   */
  class WornGeometry
  {
  public:
    WornGeometry(const dealii::Triangulation<3> &triangulation,
                 const MPI_Comm                  mpi_communicator);

    /** Set up the field on the (read) mesh: zero displacement and depth. */
    void
    initialize();

    /** The mapping of the worn geometry (MappingQEulerian of degree 1). */
    const dealii::Mapping<3> &
    get_mapping() const
    {
      return *mapping;
    }

    /** The mapping of the geometry the stiffness was last assembled on. */
    const dealii::Mapping<3> &
    stiffness_mapping() const
    {
      return *stiffness_euler_mapping;
    }

    /** From now on the stiffness is assembled on the current geometry. */
    void
    update_stiffness_geometry();

    /**
     * The `tibia_contact` surface (its nodes in the order of the mortar
     * coupling's slave nodes, on the displacement field's DoFs).
     */
    const Mortar::ContactSurface &
    worn_surface() const
    {
      return *surface;
    }

    /**
     * Nodal areas (mm^2) and outward unit normals of worn_surface() in the
     * current geometry.
     */
    const Mortar::ContactSurface::NodalMeasures &
    worn_surface_measures() const
    {
      return surface_measures;
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

    /**
     * The displacement of every triangulation vertex (mm): what a
     * checkpoint stores (vertex numbers do not depend on the number of
     * ranks, DoF numbers do).
     */
    std::vector<dealii::Tensor<1, 3>>
    vertex_displacements(const bool of_stiffness_geometry = false) const;

    /**
     * Set the displacement field from vertex displacements (the stiffness
     * geometry stays).
     */
    void
    set_vertex_displacements(const std::vector<dealii::Tensor<1, 3>> &current);

    /** Set both displacement fields from vertex displacements. */
    void
    set_vertex_displacements(
      const std::vector<dealii::Tensor<1, 3>> &current,
      const std::vector<dealii::Tensor<1, 3>> &of_stiffness_geometry);

    /** The accumulated wear depth of every triangulation vertex (mm). */
    const std::vector<double> &
    wear_depth() const
    {
      return depth;
    }

    /** Add @p increment (mm, per vertex) to the accumulated depth. */
    void
    add_wear_depth(const std::vector<double> &increment);

    /** Replace the accumulated depth (per vertex, mm), e.g. on restart. */
    void
    set_wear_depth(const std::vector<double> &new_depth);

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

    /** The owned entries of a field from per-vertex displacements. */
    dealii::TrilinosWrappers::MPI::Vector
    field_from_vertices(
      const std::vector<dealii::Tensor<1, 3>> &vertex_displacement) const;

    /**
     * The per-vertex values (on every rank) of a field given by its owned
     * entries.
     */
    std::vector<dealii::Tensor<1, 3>>
    vertices_from_field(
      const dealii::TrilinosWrappers::MPI::Vector &owned_field) const;

  private:
    using EulerMapping =
      dealii::MappingQEulerian<3, dealii::TrilinosWrappers::MPI::Vector>;

    /** Vertex positions from the mesh and the displacement field. */
    void
    update_positions();

    /** The values of a (ghosted) field at every vertex. */
    std::vector<dealii::Tensor<1, 3>>
    values_at_vertices(
      const dealii::TrilinosWrappers::MPI::Vector &field) const;


    const dealii::Triangulation<3> &triangulation;
    const MPI_Comm                  mpi_communicator;
    const dealii::FESystem<3>       fe;
    dealii::DoFHandler<3>           dof_handler;
    dealii::IndexSet                owned_dofs;
    /**
     * The Euler vectors of the worn and of the stiffness geometry; their
     * addresses must not change (the mappings keep them).
     */
    dealii::TrilinosWrappers::MPI::Vector displacement, stiffness_displacement;
    std::unique_ptr<EulerMapping>         mapping, stiffness_euler_mapping;
    std::vector<dealii::Point<3>>         positions;
    std::unique_ptr<Mortar::ContactSurface> surface;
    Mortar::ContactSurface::NodalMeasures   surface_measures;
    std::vector<double>                     depth;
  };
} // namespace TKR::Geometry

#endif
