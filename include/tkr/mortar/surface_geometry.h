// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_mortar_surface_geometry_h
#define tkr_mortar_surface_geometry_h

#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>

#include <boost/container/static_vector.hpp>

#include <array>
#include <vector>

/**
 * Geometry of bilinear surface quadrilaterals for the mortar method: the
 * map from the unit square, the auxiliary plane of a slave face, the
 * projection of a face onto that plane (a plane bilinear map and its
 * inverse) and the clipping of plane polygons.
 */
namespace TKR::Mortar
{
  /** A point of the unit square [0,1]^2 (face parameter space) or of a plane.
   */
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
  };

  /** A polygon in a plane (counter-clockwise unless stated), its
   *  vertices kept in place, without the heap (a coupling clips thousands
   *  of pairs). A quadrilateral clipped by another has at most eight in
   *  exact arithmetic and at most 64 whatever the round-off
   *  (clip_polygon()). */
  using Polygon = boost::container::static_vector<Point2, 64>;

  /**
   * The auxiliary plane of a slave face (Puso & Laursen 2004; Popp et al.
   * 2010): through the face centre x_0, with unit normal n_0 (the averaged
   * nodal normal of the face). Points are projected onto it along n_0; a
   * point x has the in-plane coordinates ((x - x_0) . t_1, (x - x_0) . t_2)
   * with an orthonormal tangent pair t_1 x t_2 = n_0, and the height
   * (x - x_0) . n_0 above it (mm).
   */
  class AuxiliaryPlane
  {
  public:
    AuxiliaryPlane(const dealii::Point<3>     &centre,
                   const dealii::Tensor<1, 3> &unit_normal);

    Point2
    coordinates(const dealii::Point<3> &x) const;

    double
    height(const dealii::Point<3> &x) const;

    const dealii::Tensor<1, 3> &
    normal() const
    {
      return n;
    }

  private:
    dealii::Point<3>     centre;
    dealii::Tensor<1, 3> n, t1, t2;
  };

  /**
   * A bilinear quadrilateral in a plane: the projection of a face onto an
   * auxiliary plane, $p(\xi) = \sum_i N_i(\xi) p_i$. Its Jacobian
   * determinant is linear in xi, $j_0 + j_1 \xi_0 + j_2 \xi_1$ (positive
   * for a counter-clockwise outline 0, 1, 3, 2).
   */
  struct PlaneQuad
  {
    std::array<Point2, 4> vertices;

    Point2
    point(const Point2 &xi) const;

    /** (j_0, j_1, j_2) of the determinant above. */
    std::array<double, 3>
    determinant_coefficients() const;

    /** The outline p_0, p_1, p_3, p_2. */
    Polygon
    outline() const;

    /**
     * +1 (-1) if the quadrilateral is strictly convex and its outline is
     * counter-clockwise (clockwise), 0 if it is not convex or degenerate:
     * only then is the map one-to-one, so that every point of the outline
     * comes from exactly one point of the face.
     */
    int
    convex_orientation() const;
  };

  /**
   * The inverse of a PlaneQuad's map, for many points of one quadrilateral:
   * the map's coefficients (p(xi) = p_0 + a xi_0 + b xi_1 + c xi_0 xi_1)
   * and scale computed once (a coupling maps every quadrature point back to
   * both of its faces).
   */
  class PlaneQuadInverse
  {
  public:
    explicit PlaneQuadInverse(const PlaneQuad &quad);

    /**
     * The parameters xi with p(xi) = @p p by Newton's method, from @p xi as
     * given if @p use_guess, else from the affine approximation at the
     * centre (xi may lie slightly outside the unit square for points on its
     * edges). False if Newton's method does not converge.
     */
    bool
    operator()(const Point2 &p, Point2 &xi, const bool use_guess) const;

  private:
    Point2 p0;
    double ax, ay, bx, by, cx, cy, scale;
  };

  /** Signed area (positive if counter-clockwise). */
  double
  signed_area(const Polygon &polygon);

  /**
   * Intersection of a convex polygon @p subject with a convex,
   * counter-clockwise polygon @p clip (Sutherland-Hodgman, one half plane
   * of the clip polygon after the other). The result is counter-clockwise,
   * without repeated vertices; empty if the polygons do not overlap.
   */
  Polygon
  clip_polygon(const Polygon &subject, const Polygon &clip);
} // namespace TKR::Mortar

#endif
