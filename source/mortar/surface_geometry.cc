// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <deal.II/base/tensor.h>

#include <tkr/mortar/surface_geometry.h>

#include <algorithm>
#include <cmath>

namespace TKR::Mortar
{
  using namespace dealii;

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

  // Newton's method for F(xi, beta) = x(xi) + beta d - p = 0. The Jacobian
  // has the columns dx/dxi_0, dx/dxi_1, d. For a flat face one step is
  // exact; curved bilinear faces need a few.
  bool
  BilinearQuad::project(const Point<3>     &p,
                        const Tensor<1, 3> &direction,
                        Point2             &xi,
                        double             &beta) const
  {
    xi                 = Point2(0.5, 0.5);
    beta               = 0;
    const double scale = std::max((vertices[3] - vertices[0]).norm(),
                                  (vertices[2] - vertices[1]).norm());
    for (unsigned int iteration = 0; iteration < 20; ++iteration)
      {
        const Tensor<1, 3> F = point(xi) + beta * direction - p;
        const auto         t = tangents(xi);
        Tensor<2, 3>       J;
        for (unsigned int d = 0; d < 3; ++d)
          {
            J[d][0] = t[0][d];
            J[d][1] = t[1][d];
            J[d][2] = direction[d];
          }
        const double det = determinant(J);
        if (std::abs(det) < 1e-12 * scale * scale * direction.norm() + 1e-300)
          return false;
        const Tensor<1, 3> step = invert(J) * F;
        xi[0] -= step[0];
        xi[1] -= step[1];
        beta -= step[2];
        if (std::abs(step[0]) + std::abs(step[1]) < 1e-14 &&
            F.norm() < 1e-12 * scale)
          return true;
        if (std::abs(xi[0]) > 1e3 || std::abs(xi[1]) > 1e3)
          return false;
      }
    // Accept if the residual is small even if the step criterion was missed.
    return (point(xi) + beta * direction - p).norm() < 1e-10 * scale;
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

  // Sutherland-Hodgman: clip successively against the four half planes
  // xi_0 >= 0, xi_0 <= 1, xi_1 >= 0, xi_1 <= 1.
  Polygon
  clip_to_unit_square(const Polygon &input)
  {
    Polygon polygon = input;
    if (signed_area(polygon) < 0)
      std::reverse(polygon.begin(), polygon.end());

    for (unsigned int edge = 0; edge < 4 && !polygon.empty(); ++edge)
      {
        const unsigned int coordinate = edge / 2;
        const bool         upper      = edge % 2;
        // Signed distance inside the half plane (>= 0 means inside).
        const auto inside = [&](const Point2 &p) {
          return upper ? 1. - p[coordinate] : p[coordinate];
        };
        Polygon clipped;
        for (unsigned int i = 0; i < polygon.size(); ++i)
          {
            const Point2 &a  = polygon[i];
            const Point2 &b  = polygon[(i + 1) % polygon.size()];
            const double  da = inside(a), db = inside(b);
            if (da >= 0)
              clipped.push_back(a);
            if ((da >= 0) != (db >= 0))
              {
                const double s = da / (da - db);
                clipped.push_back(Point2(a + s * (b - a)));
              }
          }
        polygon = clipped;
      }
    if (polygon.size() < 3 || std::abs(signed_area(polygon)) < 1e-14)
      return {};
    return polygon;
  }
} // namespace TKR::Mortar
