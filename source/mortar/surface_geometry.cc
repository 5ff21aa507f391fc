// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <deal.II/base/tensor.h>

#include <tkr/mortar/surface_geometry.h>

#include <algorithm>
#include <cmath>

namespace TKR::Mortar
{
  using namespace dealii;

  namespace
  {
    /** The z component of the cross product of two plane vectors. */
    double
    cross(const Tensor<1, 2> &a, const Tensor<1, 2> &b)
    {
      return a[0] * b[1] - a[1] * b[0];
    }
  } // namespace

  std::array<double, 4>
  BilinearQuad::shape_values(const Point2 &xi)
  {
    return {{(1 - xi[0]) * (1 - xi[1]),
             xi[0] * (1 - xi[1]),
             (1 - xi[0]) * xi[1],
             xi[0] * xi[1]}};
  }

  Point<3>
  BilinearQuad::point(const Point2 &xi) const
  {
    const auto N = shape_values(xi);
    Point<3>   x;
    for (unsigned int i = 0; i < 4; ++i)
      x += N[i] * vertices[i];
    return x;
  }

  std::array<Tensor<1, 3>, 2>
  BilinearQuad::tangents(const Point2 &xi) const
  {
    const auto &X = vertices;
    return {{(1 - xi[1]) * (X[1] - X[0]) + xi[1] * (X[3] - X[2]),
             (1 - xi[0]) * (X[2] - X[0]) + xi[0] * (X[3] - X[1])}};
  }

  Tensor<1, 3>
  BilinearQuad::area_normal(const Point2 &xi) const
  {
    const auto t = tangents(xi);
    return cross_product_3d(t[0], t[1]);
  }

  // An orthonormal tangent pair: t_1 from the coordinate axis least aligned
  // with n (so that it is never nearly parallel to n), t_2 = n x t_1.
  AuxiliaryPlane::AuxiliaryPlane(const Point<3>     &centre,
                                 const Tensor<1, 3> &unit_normal)
    : centre(centre)
    , n(unit_normal)
  {
    unsigned int axis = 0;
    for (unsigned int d = 1; d < 3; ++d)
      if (std::abs(n[d]) < std::abs(n[axis]))
        axis = d;
    Tensor<1, 3> e;
    e[axis] = 1.;
    t1      = e - (e * n) * n;
    t1 /= t1.norm();
    t2 = cross_product_3d(n, t1);
  }

  Point2
  AuxiliaryPlane::coordinates(const Point<3> &x) const
  {
    const Tensor<1, 3> d = x - centre;
    return Point2(d * t1, d * t2);
  }

  double
  AuxiliaryPlane::height(const Point<3> &x) const
  {
    return (x - centre) * n;
  }

  Point2
  PlaneQuad::point(const Point2 &xi) const
  {
    const auto N = BilinearQuad::shape_values(xi);
    Point2     p;
    for (unsigned int i = 0; i < 4; ++i)
      p += N[i] * vertices[i];
    return p;
  }

  // With a = p_1 - p_0, b = p_2 - p_0, c = p_0 - p_1 - p_2 + p_3 the columns
  // of the Jacobian are a + c xi_1 and b + c xi_0, so its determinant is
  // a x b + (a x c) xi_0 + (c x b) xi_1: the xi_0 xi_1 term c x c vanishes.
  std::array<double, 3>
  PlaneQuad::determinant_coefficients() const
  {
    const auto        &p = vertices;
    const Tensor<1, 2> a = p[1] - p[0], b = p[2] - p[0];
    const Tensor<1, 2> c = (p[0] - p[1]) + (p[3] - p[2]);
    return {{cross(a, b), cross(a, c), cross(c, b)}};
  }

  PlaneQuadInverse::PlaneQuadInverse(const PlaneQuad &quad)
  {
    const auto &v = quad.vertices;
    p0            = v[0];
    ax            = v[1][0] - v[0][0];
    ay            = v[1][1] - v[0][1];
    bx            = v[2][0] - v[0][0];
    by            = v[2][1] - v[0][1];
    cx            = v[0][0] - v[1][0] - v[2][0] + v[3][0];
    cy            = v[0][1] - v[1][1] - v[2][1] + v[3][1];
    scale = std::max((v[3] - v[0]).norm_square(), (v[2] - v[1]).norm_square());
  }

  // Newton's method for p(xi) = p, written out for the 2x2 system
  // (p(xi) = p_0 + a xi_0 + b xi_1 + c xi_0 xi_1, see above). Without a
  // guess the first iterate solves the affine approximation at the centre of
  // the square. The iteration stops when the correction falls below 1e-8:
  // convergence is quadratic, so the error is then of the order of its
  // square (round-off).
  bool
  PlaneQuadInverse::operator()(const Point2 &p,
                               Point2       &xi,
                               const bool    use_guess) const
  {
    double x = use_guess ? xi[0] : 0.5, y = use_guess ? xi[1] : 0.5;
    for (unsigned int iteration = 0; iteration < 30; ++iteration)
      {
        const double j00 = ax + cx * y, j10 = ay + cy * y;
        const double j01 = bx + cx * x, j11 = by + cy * x;
        const double det = j00 * j11 - j01 * j10;
        if (!(std::abs(det) > 1e-14 * scale))
          return false;
        const double fx = p0[0] + ax * x + bx * y + cx * x * y - p[0];
        const double fy = p0[1] + ay * x + by * y + cy * x * y - p[1];
        const double dx = (j11 * fx - j01 * fy) / det;
        const double dy = (j00 * fy - j10 * fx) / det;
        x -= dx;
        y -= dy;
        if (std::max(std::abs(dx), std::abs(dy)) < 1e-8)
          {
            xi = Point2(x, y);
            return true;
          }
        if (std::abs(x) > 1e3 || std::abs(y) > 1e3)
          return false;
      }
    return false;
  }

  Polygon
  PlaneQuad::outline() const
  {
    return {vertices[0], vertices[1], vertices[3], vertices[2]};
  }

  int
  PlaneQuad::convex_orientation() const
  {
    const Polygon q     = outline();
    const double  scale = std::max((vertices[3] - vertices[0]).norm_square(),
                                  (vertices[2] - vertices[1]).norm_square());
    int           sign  = 0;
    for (unsigned int i = 0; i < 4; ++i)
      {
        const double turn =
          cross(q[(i + 1) % 4] - q[i], q[(i + 2) % 4] - q[(i + 1) % 4]);
        const int s = (turn > 1e-10 * scale)  ? 1 :
                      (turn < -1e-10 * scale) ? -1 :
                                                0;
        if (s == 0 || (sign != 0 && s != sign))
          return 0;
        sign = s;
      }
    return sign;
  }

  double
  signed_area(const Polygon &polygon)
  {
    double area = 0;
    for (unsigned int i = 0; i < polygon.size(); ++i)
      {
        const Point2 &a = polygon[i];
        const Point2 &b = polygon[(i + 1) % polygon.size()];
        area += a[0] * b[1] - a[1] * b[0];
      }
    return 0.5 * area;
  }

  // Sutherland-Hodgman: the subject is clipped successively against the
  // half planes to the left of the edges of the counter-clockwise clip
  // polygon. Both polygons are convex, so the result is the exact
  // intersection (a convex polygon). A vertex that lies on a clip edge is
  // kept once; repeated vertices are removed at the end.
  Polygon
  clip_polygon(const Polygon &subject, const Polygon &clip)
  {
    // Each clip edge at most doubles the vertices (in exact arithmetic
    // it adds at most one to a convex polygon).
    AssertThrow(subject.size() << clip.size() <= Polygon::static_capacity,
                ExcInternalError());
    Polygon polygon = subject;
    if (signed_area(polygon) < 0)
      std::reverse(polygon.begin(), polygon.end());
    double scale = 0;
    for (const auto &p : clip)
      scale = std::max(scale, (p - clip[0]).norm());

    Polygon clipped;
    for (unsigned int edge = 0; edge < clip.size() && polygon.size() > 2;
         ++edge)
      {
        const Point2      &a = clip[edge];
        const Tensor<1, 2> e = clip[(edge + 1) % clip.size()] - a;
        // Signed distance (times |e|) to the left of the edge.
        const auto inside = [&](const Point2 &p) { return cross(e, p - a); };
        clipped.clear();
        for (unsigned int i = 0; i < polygon.size(); ++i)
          {
            const Point2 &p  = polygon[i];
            const Point2 &q  = polygon[(i + 1) % polygon.size()];
            const double  dp = inside(p), dq = inside(q);
            if (dp >= 0)
              clipped.push_back(p);
            if ((dp > 0 && dq < 0) || (dp < 0 && dq > 0))
              clipped.push_back(p + (dp / (dp - dq)) * (q - p));
          }
        // (copies the clipped vertices only; a swap would exchange both
        // whole arrays)
        polygon.assign(clipped.begin(), clipped.end());
      }

    // Remove repeated vertices (a vertex on a clip edge, or a clip corner
    // met by several subject edges).
    clipped.clear();
    for (unsigned int i = 0; i < polygon.size(); ++i)
      if (clipped.empty() ||
          (polygon[i] - clipped.back()).norm() > 1e-13 * scale)
        clipped.push_back(polygon[i]);
    while (clipped.size() > 1 &&
           (clipped.back() - clipped.front()).norm() <= 1e-13 * scale)
      clipped.pop_back();
    if (clipped.size() < 3 || signed_area(clipped) <= 0)
      return {};
    return clipped;
  }
} // namespace TKR::Mortar
