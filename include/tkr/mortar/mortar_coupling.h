// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_mortar_mortar_coupling_h
#define tkr_mortar_mortar_coupling_h

#include <deal.II/base/point.h>
#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/base/tensor.h>

#include <tkr/mortar/contact_surface.h>
#include <tkr/mortar/segment_quadrature.h>

#include <memory>
#include <optional>
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
   *
   * Where the master surface covers only part of the node's support (at
   * the edge of the master surface, or of the search distance), M_jk and
   * g_j are integrated over the covered part only, consistently with its
   * area (MortarCoupling explains the rule): then sum_k M_jk = D_jj and
   * g_j / D_jj is the mean gap over the covered part, never a gap to
   * a master surface that is not there, plus the edge offset of a node
   * with less than half its support covered (gap_offset).
   */
  struct SlaveNode
  {
    /** D_jj in mm^2: the nodal area, over the whole support (so
     *  sum_j D_jj = slave area). */
    double D = 0;
    /** Nodal unit normal, pointing out of the slave body. */
    dealii::Tensor<1, 3> normal;
    /**
     * The nodal normal expressed in the frame of the master displacement
     * DoFs: R^T n_j if the master body is rotated by R but its
     * displacements are kept in its own (co-rotated) frame, else n_j.
     */
    dealii::Tensor<1, 3> master_normal;
    /** Weighted gap g_j in mm^3; g_j / D_jj is a distance (mm): the mean
     *  gap over the covered part of the support plus gap_offset. */
    double weighted_gap = 0;
    /**
     * The edge offset (mm) included in weighted_gap / D_jj:
     * MortarCoupling::edge_offset() of the covered fraction; 0 where at
     * least half the support is covered.
     */
    double gap_offset = 0;
    /**
     * The master point that node j touches, sum_k M_jk x_k / sum_k M_jk
     * (current positions): the mortar projection of the node.
     */
    dealii::Point<3> master_point;
    /**
     * The derivative of the weighted gap g_j with respect to a rigid
     * translation v of the master surface (mm^2): g_j changes by
     * gap_gradient . v. Each point of the support sees the master along the
     * face's projection direction n_0, so it moves by n_m (n_m . v) /
     * (n_m . n_0) with n_m the master's normal there: gap_gradient =
     * int psi_j (n_j . n_0) n_m / (n_m . n_0), scaled like M. Equal to D_jj
     * n_j where the surfaces are parallel; it differs by the angle between
     * them, which is what makes the contact hold the bodies tangentially.
     */
    dealii::Tensor<1, 3> gap_gradient;
    /** (master node, M_jk) pairs, sorted by master node; their sum is
     *  D_jj if any part of the support is covered. */
    std::vector<std::pair<unsigned int, double>> M;
    /**
     * True if the node may become active: at least
     * MortarCoupling::min_covered_fraction of its support is covered by
     * projections of master faces.
     */
    bool covered = false;
    /** The covered part of the support: int_covered phi_j / D_jj (0..1). */
    double covered_fraction = 0;
  };

  /**
   * Statistics of the last computation of the coupling.
   */
  struct CouplingStatistics
  {
    unsigned int n_slave_faces = 0, n_master_faces = 0;
    /** Slave-master face pairs that were tested (after the tree search). */
    unsigned int n_candidate_pairs = 0;
    /** Pairs whose projections overlap: integration cells. */
    unsigned int n_overlapping_pairs = 0;
    /** Slave faces with at least one integration cell. */
    unsigned int n_integrated_faces = 0;
    /** Slave faces covered entirely, partly, and more than once (a master
     *  surface folded over itself as seen from the face: left out). */
    unsigned int n_fully_covered_faces = 0, n_partly_covered_faces = 0,
                 n_overcovered_faces = 0;
    /** Slave faces whose projection onto their own plane is not convex
     *  (left out), and candidate pairs left out because the master face's
     *  projection is not convex or a point could not be mapped back. */
    unsigned int n_invalid_faces = 0, n_rejected_pairs = 0;
    /** Faces (slave, and master ones on a flat interface) whose shape
     *  functions the quadrature weights were fitted to integrate exactly,
     *  and the largest remaining relative error of such an integral (1 if
     *  the fitting was refused). */
    unsigned int n_fitted_faces = 0;
    double       fitting_error  = 0;
    /** Quadrature points of all integration cells. */
    unsigned int n_quadrature_points = 0;
    /** Nodes that may become active; of them, those whose support is only
     *  partly covered; nodes with some coverage that may not. */
    unsigned int n_covered_nodes = 0, n_partly_covered_nodes = 0,
                 n_uncovered_touched_nodes = 0;
    /** Slave area (mm^2) and the part of it that the projections of the
     *  master faces cover (integrated on the slave surface). */
    double slave_area = 0, covered_area = 0;
    /** With a CouplingWindow: slave faces within the search distance,
     *  those near the master surface, and those integrated; slave nodes
     *  left out (their support reaches beyond the integrated faces). */
    unsigned int n_faces_in_reach = 0, n_near_faces = 0, n_window_faces = 0,
                 n_left_out_nodes = 0;
  };

  /**
   * A narrower choice of the slave faces that MortarCoupling::reinit()
   * integrates than the search distance (the contact zone and a margin
   * around it), with what the caller expects the solve to do: the
   * displacements of a previous solve. See MortarCoupling::reinit().
   */
  struct CouplingWindow
  {
    /** Width w of the window (mm). */
    double width = 0;
    /** A previous solve's lower bound of the distance of each slave face
     *  from the master surface after the displacement
     *  (MortarCoupling::face_clearances(), mm); empty: no window. */
    std::vector<double> face_clearance;
  };

  /**
   * Dual-basis mortar coupling between a slave and a master surface
   * (DESIGN.md section 4.3) by segment-based integration in auxiliary
   * planes (Puso & Laursen 2004; Popp, Gee & Wall 2009, 2010):
   *
   * For every slave face an auxiliary plane is laid through its centre,
   * normal to the average of its nodal normals. The master faces near it
   * are found with an R-tree of bounding boxes (O(N log N)); each one that
   * faces the slave face and lies within the search distance is projected
   * onto the plane along that normal, together with the slave face, and
   * the two convex quadrilaterals are clipped (Sutherland-Hodgman). The
   * clip polygon is an integration cell, with the quadrature of
   * CellQuadrature: its points are mapped back onto the slave and the
   * master face by the inverse of their projected bilinear maps, the
   * weights integrate the shape functions of fully covered slave faces (and
   * on a flat interface of the master faces) exactly, and they are
   * multiplied by the ratio of the slave surface element to the plane's,
   * so that the integrals are over the true slave surface. Coverage is
   * measured in the plane, the same way for D, M and the gap.
   *
   * On a fully covered slave face the test functions are the dual basis
   * psi_i = sum_k A_ik phi_k with A = D_e M_e^{-1} from that same
   * quadrature (so that biorthogonality, sum_k M_jk = D_jj and the exact
   * reproduction of linear fields hold to round-off). On a face less than
   * dual_coverage (80 %) covered (the edge of the master surface) they are
   * the standard shape functions phi_i, which are positive: g_j / D_jj is
   * then a true (positively weighted) mean of the gap over the covered
   * part, never an extrapolation. In between they are the blend
   * t psi^dual + (1 - t) phi (dual_weight()), psi^dual from the covered
   * part's quadrature, so that M and the gaps do not jump where a face's
   * coverage reaches 1 (a jump of 1.5 % of the contact force on TKR A
   * coarse when they switched there). Each node's row is integrated over the
   * covered part of its support (area D^c_j = int_covered phi_j) and then
   * scaled by D_jj / D^c_j, a positive scaling of the node's constraint that
   * does not change the discrete contact problem but keeps D_jj the nodal area.
   *
   * Edge rule: a node whose covered fraction f_j = D^c_j / D_jj is at
   * least full_constraint_fraction (1/2) has the full constraint; below it
   * its gap is raised by the edge offset
   * h(f) = l_j ((1/2 - f) / f)^2 (l_j = sqrt(D_jj), edge_offset()), which
   * vanishes with its derivative at f = 1/2 and grows without bound as the
   * coverage goes to zero. So a node that slides off the edge of the master
   * surface carries a force that goes continuously to zero (the contact
   * force is continuous in the pose; issue 33), instead of dropping the
   * moment it stops projecting onto the master surface (4C/BACI's rule,
   * "HasProj", which this replaced: a jump of 1 to 2 % of the contact
   * force on TKR A coarse, tests/mortar/coupling_continuity). Nodes with
   * less than min_covered_fraction covered are not covered (the offset is
   * then above 10^5 l_j).
   */
  class MortarCoupling
  {
  public:
    /**
     * Nodes with less than this part of their support covered are not
     * covered (a guard against round-off slivers; see the edge rule above).
     */
    static constexpr double min_covered_fraction = 1e-3;

    /** Nodes with at least this part of their support covered have the
     *  full constraint, no edge offset (see the edge rule above). */
    static constexpr double full_constraint_fraction = 0.5;

    /**
     * The edge offset h(f) in mm of a node with the covered fraction
     * @p fraction (> 0) and the length @p length (sqrt(D_jj), mm):
     * length ((1/2 - f) / f)^2 below full_constraint_fraction, else 0.
     */
    static double
    edge_offset(const double fraction, const double length);

    /** Slave faces with at most this part of their projection covered use
     *  the standard basis (see the class documentation). */
    static constexpr double dual_coverage = 0.8;

    /**
     * The weight t of the dual basis in the test functions
     * psi = t psi^dual + (1 - t) phi of a face with the covered part
     * @p coverage of its projection: 0 up to dual_coverage, 1 at full
     * coverage, the cubic smoothstep in between (continuous with its
     * derivative).
     */
    static double
    dual_weight(const double coverage);

    MortarCoupling(const ContactSurface &slave, const ContactSurface &master);

    /**
     * Compute D, M, normals and weighted gaps for the vertex positions
     * @p positions (indexed by triangulation vertex). Master faces farther
     * than @p search_distance (mm) from a slave face, or facing the same
     * way as it, are not coupled to it. @p master_rotation is the rotation
     * R of the master body whose displacement DoFs live in its co-rotated
     * frame (identity: displacements in the global frame).
     *
     * With a @p window (width w, the face clearances of a previous solve):
     * a slave face is near if its clearance is below w. (The clearance is
     * that of the deformed bodies, which a pose update barely changes: it
     * moves the tibia, and its displacement back.) The faces around the
     * nodes of near faces are integrated as without the window, so these
     * nodes get the same rows; nodes with a face that is not integrated
     * are left out (not covered, no row). The cost then follows the
     * contact zone instead of the part of the surface within the search
     * distance. Check the solve with window_holds(). (On a flat interface
     * a master face covered in part by left-out faces loses its fitted
     * weights; curved surfaces have none.)
     */
    void
    reinit(const std::vector<dealii::Point<3>> &positions,
           const double                         search_distance,
           const dealii::Tensor<2, 3>          &master_rotation =
             dealii::unit_symmetric_tensor<3>(),
           const CouplingWindow *window = nullptr);

    /**
     * After a reinit() with a CouplingWindow: true if the displacement of
     * a solve on this coupling (@p slave_displacement of every slave node,
     * @p master_displacement a bound of the master nodes') leaves every
     * slave face outside the window at least half its width from the
     * master surface. Then every left-out node has a gap of at least w/2
     * on its whole support and would be inactive with zero pressure in the
     * coupling over the whole search distance too: the solve is the one
     * without the window. False means: solve again without it. Always
     * true after a reinit() without a window.
     */
    bool
    window_holds(const std::vector<dealii::Tensor<1, 3>> &slave_displacement,
                 const double master_displacement) const;

    /**
     * A lower bound of the distance of each slave face from the master
     * surface (along its plane normal, mm) after a displacement
     * (@p slave_displacement of every slave node, @p master_displacement a
     * bound of the master nodes'): the bound of the last reinit() minus
     * the largest u_v . n0 of its nodes (its points move by convex
     * combinations of them) minus the master's bound; infinity for faces
     * that no master face within the search distance faces. For the
     * CouplingWindow of the next solves.
     */
    std::vector<double>
    face_clearances(const std::vector<dealii::Tensor<1, 3>> &slave_displacement,
                    const double master_displacement) const;

    const std::vector<SlaveNode> &
    slave_nodes() const
    {
      return nodes;
    }
    /** How many times reinit() ran: what is computed from the nodes may
     *  be kept while this stays the same. */
    std::uint64_t
    generation() const
    {
      return n_reinits;
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
    struct MasterGeometry;
    struct Accumulator;
    struct SlaveProjection;
    struct SlaveCache;
    struct FacePair;

    /**
     * What depends on the slave surface alone (nodal areas and normals, the
     * faces' auxiliary planes and projections): computed again only when
     * the slave vertices moved since the last call. In the gait the tibia
     * stays put within a block (the femur moves relative to it), so this
     * is computed once per block.
     */
    void
    update_slave_cache(const std::vector<dealii::Point<3>> &positions);

    /** Slave face @p e projected onto its auxiliary plane; false if the
     *  projection is not convex. */
    bool
    project_slave_face(const unsigned int                   e,
                       const std::vector<dealii::Point<3>> &positions,
                       std::optional<SlaveProjection>      &projection);

    /**
     * The master faces that may couple to slave face @p e (facing it,
     * within the search distance, overlapping it in its plane) into
     * @p pairs, with their projections onto its plane, and a lower bound of its
     * distance to them along its plane normal into face_distance (infinity if
     * there are none).
     */
    void
    find_pairs(const unsigned int                   e,
               const std::vector<dealii::Point<3>> &positions,
               const MasterGeometry                &master_faces,
               const double                         search_distance,
               Accumulator                         &accumulator,
               std::vector<FacePair>               &pairs);

    /**
     * With a window: which slave faces are integrated (those with a node
     * on a face nearer than the window's width after its expected
     * displacement) and which nodes are left out.
     */
    void
    choose_window_faces(const CouplingWindow &window,
                        std::vector<bool>    &integrated,
                        std::vector<bool>    &left_out);

    /** By how much a displacement may close the gap of slave face @p e
     *  (see face_clearances()). */
    double
    closure(const unsigned int                       e,
            const std::vector<dealii::Tensor<1, 3>> &slave_displacement,
            const double                             master_displacement) const;

    /** The integration cells of slave face @p e and the master faces
     *  @p pairs, with Gauss points. */
    void
    make_cells(const unsigned int           e,
               const std::vector<FacePair> &pairs,
               Accumulator                 &accumulator);

    /** The integration cell of slave face @p e and the master face of
     *  @p pair; @p slave_inverse inverts the slave face's projection. */
    void
    make_cell(const unsigned int      e,
              const FacePair         &pair,
              const SlaveProjection  &slave_face,
              const PlaneQuadInverse &slave_inverse,
              Accumulator            &accumulator);

    /** Fit the weights of the points to exact face integrals. */
    void
    fit_weights(Accumulator &accumulator);

    /** The contributions of slave face @p e to D and M. */
    void
    assemble_face(const unsigned int                   e,
                  const std::vector<dealii::Point<3>> &positions,
                  Accumulator                         &accumulator);

    /** Rows of M, the edge rule, weighted gaps, master points; nodes
     *  @p left_out (if not empty) get none. */
    void
    finish_nodes(const std::vector<dealii::Point<3>> &positions,
                 const dealii::Tensor<2, 3>          &master_rotation,
                 const std::vector<bool>             &left_out,
                 Accumulator                         &accumulator);

    const ContactSurface  &slave;
    const ContactSurface  &master;
    const CellQuadrature   cell_quadrature;
    std::vector<SlaveNode> nodes;
    CouplingStatistics     stats;
    /** The slave-side data of update_slave_cache(). */
    std::shared_ptr<SlaveCache> slave_cache;
    /** reinit()'s working space, kept between calls for its memory. */
    std::shared_ptr<Accumulator> scratch;
    /** Per slave face, of the last reinit(): the lower bound of its
     *  distance to the master faces that may couple to it (mm, infinity
     *  if none may), and whether it was within the window (all true
     *  without one). */
    std::vector<double> face_distance;
    std::vector<bool>   near_face;
    /** Width of the last reinit()'s window (0: none). */
    double window_width = 0;
    /** See generation(). */
    std::uint64_t n_reinits = 0;
  };
} // namespace TKR::Mortar

#endif
