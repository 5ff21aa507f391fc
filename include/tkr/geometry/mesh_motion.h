// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_geometry_mesh_motion_h
#define tkr_geometry_mesh_motion_h

#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>
#include <deal.II/base/timer.h>

#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/mapping_q1.h>

#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>
#include <deal.II/lac/trilinos_vector.h>

#include <tkr/elasticity/direct_solver.h>
#include <tkr/geometry/worn_geometry.h>

#include <vector>

namespace TKR::Geometry
{
  /** How much a displacement field distorts the tibia's cells. */
  struct Distortion
  {
    /**
     * The smallest ratio, over the tibia's cells, of a cell's smallest
     * vertex Jacobian determinant in the displaced mesh to that in the
     * mesh as read (1: unchanged, <= 0: inverted).
     */
    double min_ratio = 1;
    /** The cell (active cell index) where it is, and its centre (mm). */
    unsigned int     cell = 0;
    dealii::Point<3> centre;
    /** The cell's vertices (triangulation vertex numbers). */
    std::array<unsigned int, 8> vertices = {};
  };

  /**
   * The motion of the tibia's mesh that follows its worn surface
   * (DESIGN.md section 4.7): given the displacement of the `tibia_contact`
   * vertices, the displacement of every vertex of the tibia is the solution
   * of a linear-elastic problem on the tibia as read (E = 1, nu = 0.3;
   * only the shape of the extension matters) with that displacement on
   * `tibia_contact`, zero on `tibia_inferior` and the other faces free;
   * the femur does not move. The operator does not change from block to
   * block, so it is factorised once (setup()) and every block costs one
   * right-hand side and one back substitution (extend()).
   */
  class MeshMotion
  {
  public:
    MeshMotion(const WornGeometry  &geometry,
               const MPI_Comm       mpi_communicator,
               dealii::TimerOutput &timer);

    /** Assemble and factorise the extension operator. */
    void
    setup();

    /**
     * The displacement of every vertex (on every rank) whose values on the
     * `tibia_contact` vertices are those of @p vertex_displacement (indexed
     * by triangulation vertex; other entries are not read), extended into
     * the tibia.
     */
    std::vector<dealii::Tensor<1, 3>>
    extend(const std::vector<dealii::Tensor<1, 3>> &vertex_displacement) const;

    /**
     * The distortion of the tibia's cells by @p vertex_displacement
     * (indexed by triangulation vertex) against the mesh as read.
     */
    Distortion
    distortion(
      const std::vector<dealii::Tensor<1, 3>> &vertex_displacement) const;

  private:
    /**
     * The element matrix of the extension operator on a tibia cell, with
     * @p fe_values (on the mesh as read: reference_mapping).
     */
    static void
    cell_matrix(const dealii::DoFHandler<3>::active_cell_iterator &cell,
                dealii::FEValues<3>                               &fe_values,
                dealii::FullMatrix<double>                        &matrix);

    /** FEValues for cell_matrix(). */
    dealii::FEValues<3>
    make_fe_values() const;

    const WornGeometry                    &geometry;
    const dealii::MappingQ1<3>             reference_mapping;
    const MPI_Comm                         mpi_communicator;
    dealii::TimerOutput                   &timer;
    dealii::AffineConstraints<double>      constraints;
    dealii::TrilinosWrappers::SparseMatrix matrix;
    mutable Elasticity::DirectSolver       direct_solver;
  };
} // namespace TKR::Geometry

#endif
