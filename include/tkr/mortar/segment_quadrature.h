// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_mortar_segment_quadrature_h
#define tkr_mortar_segment_quadrature_h

#include <deal.II/base/quadrature_lib.h>

#include <tkr/mortar/surface_geometry.h>

#include <array>
#include <vector>

namespace TKR::Mortar
{
  /** One quadrature point of an integration cell. */
  struct CellPoint
  {
    /** Parameters of the point on the slave and on the master face. */
    Point2 slave_xi, master_xi;
    /** Weight in the measure of the auxiliary plane (mm^2). */
    double weight;
  };

  /**
   * Quadrature on the integration cells of the segment-based mortar method.
   *
   * An integration cell is the (convex) intersection, in the auxiliary
   * plane of a slave face, of the projections of that slave face and of one
   * master face. Its points come from a fan of triangles with a Gauss rule
   * of degree 5; each point is mapped back to both faces by the inverse of
   * their projected bilinear maps.
   *
   * On unstructured (non-parallelogram) faces the integrands are not
   * polynomials in the plane (the inverse of a bilinear map is not one), so
   * no Gauss rule integrates even the shape functions exactly. Their exact
   * integrals over a whole face are known, though: fit_weights() changes
   * the weights by the least amount that makes them integrate the shape
   * functions of chosen faces exactly ("moment fitting").
   */
  class CellQuadrature
  {
  public:
    CellQuadrature();

    /**
     * Append the quadrature points of the counter-clockwise convex polygon
     * @p cell (plane coordinates), which lies in both @p slave and
     * @p master, to @p points, with Gauss weights. False (and nothing
     * appended) if a point cannot be mapped back to a face.
     */
    bool
    append_points(const Polygon          &cell,
                  const PlaneQuadInverse &slave,
                  const PlaneQuadInverse &master,
                  std::vector<CellPoint> &points) const;

  private:
    const dealii::QGaussSimplex<2> triangle_rule;
  };
  /**
   * A face whose shape functions fit_weights() is to integrate exactly: the
   * cells that make it up (indices into the cell list), whether the points'
   * master (else slave) parameters are the face's, and the exact integrals
   * of its shape functions phi_1, phi_2, phi_3 over the union of the cells
   * (phi_0 = 1 - the others follows from the cells' areas).
   */
  struct FittingFace
  {
    std::vector<unsigned int> cells;
    bool                      master;
    std::array<double, 3>     integrals;
  };

  /**
   * Change the weights of @p points, which form cells (cell c has the
   * points [cell_ranges[c].first, cell_ranges[c].second) and the area
   * cell_areas[c]), by the least amount (in the norm weighted by the
   * present weights) such that every cell that belongs to one of @p faces
   * keeps its area and every face's shape functions are integrated to the
   * given values: with the conditions C w = b, the correction is
   * w_q -> w_q (1 + sum_r lambda_r C_rq) with (C W C^T) lambda = b - C w.
   * The system decouples into one small dense system per face if all faces
   * are slave faces (their cells are disjoint); otherwise it is one sparse
   * system. Returns the largest remaining relative error of a condition;
   * the weights are left unchanged (and 1 returned) if a weight would
   * change by more than half.
   */
  double
  fit_weights(
    std::vector<CellPoint>                                   &points,
    const std::vector<std::pair<unsigned int, unsigned int>> &cell_ranges,
    const std::vector<double>                                &cell_areas,
    const std::vector<FittingFace>                           &faces);
} // namespace TKR::Mortar

#endif
