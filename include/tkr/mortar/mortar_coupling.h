// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_mortar_mortar_coupling_h
#define tkr_mortar_mortar_coupling_h

#include <deal.II/base/point.h>
#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/base/tensor.h>

#include <tkr/mortar/contact_surface.h>

#include <utility>
#include <vector>

namespace TKR::Mortar
{
  /**
   * What the mortar coupling knows about one slave node j.
   *
   * With the dual basis psi_j (biorthogonal to the slave shape functions
   * phi_j), D_jj = int psi_j phi_j = int phi_j (the nodal area, mm^2) and
   * M_jk = int psi_j phi_k^master (mm^2). The weighted gap is
   * g_j = n_j . (sum_k M_jk x_k - D_jj x_j) (mm^3), so that the linearised
   * non-penetration condition reads
   * g_j + n_j . (sum_k M_jk u_k - D_jj u_j) >= 0.
   */
  struct SlaveNode
  {
    /** D_jj in mm^2 (over the whole support, so sum_j D_jj = area). */
    double D = 0;
    /** Nodal unit normal, pointing out of the slave body. */
    dealii::Tensor<1, 3> normal;
    /**
     * The nodal normal expressed in the frame of the master displacement
     * DoFs: R^T n_j if the master body is rotated by R but its
     * displacements are kept in its own (co-rotated) frame, else n_j.
     */
    dealii::Tensor<1, 3> master_normal;
    /** Weighted gap g_j in mm^3; g_j / D_jj is a distance (mm). */
    double weighted_gap = 0;
    /**
     * The master point that node j touches, sum_k M_jk x_k / sum_k M_jk
     * (current positions): the mortar projection of the node.
     */
    dealii::Point<3> master_point;
    /** (master node, M_jk) pairs. */
    std::vector<std::pair<unsigned int, double>> M;
    /**
     * True if every point of the node's support projects onto the master
     * surface. Only such nodes may become active: on the others D, M and
     * the gap would not be integrated over the same area.
     */
    bool covered = false;
  };

  /**
   * Statistics of the last computation of the coupling.
   */
  struct CouplingStatistics
  {
    unsigned int n_slave_faces = 0, n_master_faces = 0;
    /** Slave-master face pairs that were tested (after the tree search). */
    unsigned int n_candidate_pairs = 0;
    /** Pairs whose projections overlap, integration cells. */
    unsigned int n_overlapping_pairs = 0;
    unsigned int n_covered_nodes     = 0;
    /** Slave area (mm^2) and the part of it that projects onto the master. */
    double slave_area = 0, covered_area = 0;
  };

  /**
   * Dual-basis mortar coupling between a slave and a master surface
   * (DESIGN.md section 4.3), with segment-based integration:
   *
   * For every slave face, the master faces near it are found with an R-tree
   * of bounding boxes (O(N log N)). Each candidate master face is projected
   * along the slave face's centre normal into the slave face's parameter
   * square, clipped against it (Sutherland-Hodgman), and the overlap polygon
   * is split into triangles on which a Gauss rule is used. At every
   * quadrature point the slave point is projected back onto the master
   * face along the same direction, and psi_j(xi_s) phi_k(xi_m) is
   * integrated with the true slave surface element. D is integrated over
   * the whole slave face with the (biorthogonal, hence diagonal) dual
   * basis; nodes whose support is not fully covered by master projections
   * are flagged as not covered.
   */
  class MortarCoupling
  {
  public:
    MortarCoupling(const ContactSurface &slave, const ContactSurface &master);

    /**
     * Compute D, M, normals and weighted gaps for the vertex positions
     * @p positions (indexed by triangulation vertex). Master faces farther
     * than @p search_distance (mm) from a slave face, or facing the same
     * way as it, are not coupled to it. @p master_rotation is the rotation
     * R of the master body whose displacement DoFs live in its co-rotated
     * frame (identity: displacements in the global frame).
     */
    void
    reinit(const std::vector<dealii::Point<3>> &positions,
           const double                         search_distance,
           const dealii::Tensor<2, 3>          &master_rotation =
             dealii::unit_symmetric_tensor<3>());

    const std::vector<SlaveNode> &
    slave_nodes() const
    {
      return nodes;
    }
    const ContactSurface &
    slave_surface() const
    {
      return slave;
    }
    const ContactSurface &
    master_surface() const
    {
      return master;
    }
    const CouplingStatistics &
    statistics() const
    {
      return stats;
    }

  private:
    const ContactSurface  &slave;
    const ContactSurface  &master;
    std::vector<SlaveNode> nodes;
    CouplingStatistics     stats;
  };
} // namespace TKR::Mortar

#endif
