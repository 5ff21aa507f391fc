// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_mortar_surface_geometry_h
#define tkr_mortar_surface_geometry_h

#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>

#include <array>
#include <vector>

/**
 * Geometry of bilinear surface quadrilaterals for the mortar method: the
 * map from the unit square, projections along a direction, and clipping of
 * polygons in the unit square.
 */
namespace TKR::Mortar
{
  /** A point of the unit square [0,1]^2 (face parameter space). */
  using Point2 = dealii::Point<2>;

  /**
   * The bilinear map $x(\xi) = \sum_i N_i(\xi) X_i$ of a quadrilateral face
   * with vertices X_0..X_3 in deal.II's lexicographic order
   * ((0,0), (1,0), (0,1), (1,1)).
   */
  struct BilinearQuad
  {
    std::array<dealii::Point<3>, 4> vertices;

    /** The four bilinear shape functions at @p xi. */
    static std::array<double, 4>
    shape_values(const Point2 &xi);

    dealii::Point<3>
    point(const Point2 &xi) const;

    /** The two tangent vectors dx/dxi_0 and dx/dxi_1 at @p xi. */
    std::array<dealii::Tensor<1, 3>, 2>
    tangents(const Point2 &xi) const;

    /** Not normalised normal dx/dxi_0 x dx/dxi_1; its length is dA/dxi. */
    dealii::Tensor<1, 3>
    area_normal(const Point2 &xi) const;

    /**
     * Find xi and beta with x(xi) + beta * direction = p (Newton's method
     * on the 3x3 system). Returns false if Newton fails to converge or
     * the direction is (nearly) tangent to the face. xi may lie outside the
     * unit square: the caller decides what to accept.
     */
    bool
    project(const dealii::Point<3>     &p,
            const dealii::Tensor<1, 3> &direction,
            Point2                     &xi,
            double                     &beta) const;
  };

  /** A polygon in the face parameter plane, counter-clockwise. */
  using Polygon = std::vector<Point2>;

  /** Signed area (positive if counter-clockwise). */
  double
  signed_area(const Polygon &polygon);

  /**
   * Intersection of a simple @p polygon with the unit square
   * (Sutherland-Hodgman; exact for convex polygons, which the projected
   * faces of a reasonable mesh are). The result is counter-clockwise; empty
   * if they do not overlap.
   */
  Polygon
  clip_to_unit_square(const Polygon &polygon);
} // namespace TKR::Mortar

#endif
