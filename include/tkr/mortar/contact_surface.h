// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_mortar_contact_surface_h
#define tkr_mortar_contact_surface_h

#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>
#include <deal.II/base/types.h>

#include <deal.II/dofs/dof_handler.h>

#include <array>
#include <vector>

namespace TKR::Mortar
{
  /**
   * The quadrilateral faces of one boundary part (e.g. `tibia_contact`) of
   * a Q1 displacement field: its nodes (triangulation vertices with their
   * three displacement DoFs) and faces (four node numbers in deal.II's
   * lexicographic face order, and the eight vertices of the cell behind
   * the face, which tell the outward direction). Built once per mesh; the
   * geometry comes separately as the current position of every
   * triangulation vertex, so that the same surface serves the reference,
   * the rotated (femur) and the worn (tibia) geometry.
   */
  class ContactSurface
  {
  public:
    struct Node
    {
      unsigned int                                   vertex;
      std::array<dealii::types::global_dof_index, 3> dofs;
    };

    struct Face
    {
      std::array<unsigned int, 4> nodes;
      std::array<unsigned int, 8> cell_vertices;
    };

    /**
     * Collect the faces with boundary id @p boundary_id. The element of
     * @p dof_handler must be FESystem(FE_Q(1), 3).
     */
    ContactSurface(const dealii::DoFHandler<3>     &dof_handler,
                   const dealii::types::boundary_id boundary_id);

    /**
     * This surface (the same nodes in the same order, the same faces) with
     * the DoFs of @p dof_handler, another FESystem(FE_Q(1), 3) on the same
     * triangulation: the geometry's worn surface becomes the mortar
     * coupling's slave surface, so that both number the tibia_contact
     * nodes alike by construction.
     */
    ContactSurface
    with_dofs_of(const dealii::DoFHandler<3> &dof_handler) const;

    const std::vector<Node> &
    nodes() const
    {
      return node_list;
    }
    const std::vector<Face> &
    faces() const
    {
      return face_list;
    }
    /** The faces around each node. */
    const std::vector<std::vector<unsigned int>> &
    node_faces() const
    {
      return faces_of_node;
    }

    /**
     * The four vertices of face @p f and its outward unit normal sign:
     * returns +1 if the face's parametric normal (dx/dxi_0 x dx/dxi_1)
     * points out of its cell, -1 otherwise.
     */
    std::array<dealii::Point<3>, 4>
    face_vertices(const unsigned int                   f,
                  const std::vector<dealii::Point<3>> &positions) const;
    double
    orientation(const unsigned int                   f,
                const std::vector<dealii::Point<3>> &positions) const;

    /** Nodal areas and normals of the surface at some vertex positions. */
    struct NodalMeasures
    {
      /** int phi_j over the surface (mm^2): the node's share of the area
       *  (the mortar D_jj of the dual basis). */
      std::vector<double> area;
      /** The unit normal int phi_j n / |int phi_j n|, pointing out of the
       *  body. */
      std::vector<dealii::Tensor<1, 3>> normal;
      /** The whole area (mm^2), the sum of @p area. */
      double total_area = 0;
    };

    /**
     * The nodal areas and normals of the surface with its vertices at
     * @p positions (indexed by triangulation vertex), integrated with 2x2
     * Gauss points per bilinear face (exact for flat faces).
     */
    NodalMeasures
    nodal_measures(const std::vector<dealii::Point<3>> &positions) const;

  private:
    std::vector<Node>                      node_list;
    std::vector<Face>                      face_list;
    std::vector<std::vector<unsigned int>> faces_of_node;
  };
} // namespace TKR::Mortar

#endif
