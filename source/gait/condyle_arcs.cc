// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <deal.II/base/tensor.h>

#include <tkr/base/exceptions.h>
#include <tkr/gait/condyle_arcs.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace TKR::Gait
{
  using namespace dealii;

  namespace
  {
    /**
     * The least-squares solution of sum_i (a_i . c - b_i)^2 for three
     * unknowns (normal equations; the systems here are small and well
     * scaled); zero if they are singular.
     */
    Tensor<1, 3>
    least_squares(const std::vector<std::array<double, 3>> &rows,
                  const std::vector<double>                &rhs)
    {
      Tensor<2, 3> normal;
      Tensor<1, 3> right;
      for (unsigned int i = 0; i < rows.size(); ++i)
        for (unsigned int a = 0; a < 3; ++a)
          {
            right[a] += rows[i][a] * rhs[i];
            for (unsigned int b = 0; b < 3; ++b)
              normal[a][b] += rows[i][a] * rows[i][b];
          }
      if (std::abs(determinant(normal)) <
          1e-14 * std::pow(trace(normal) + 1e-300, 3))
        return Tensor<1, 3>();
      return invert(normal) * right;
    }

    // The distal arc of the condyle of @p points (flexion_axis.py's
    // condyle_arc()).
    DistalArc
    condyle_arc(const std::vector<Point<3>> &points, const double depth)
    {
      const double band = 1.5;
      DistalArc    arc;
      if (points.empty())
        return arc;
      const Point<3>      apex = *std::min_element(points.begin(),
                                              points.end(),
                                              [](const auto &a, const auto &b) {
                                                return a[2] < b[2];
                                              });
      std::vector<double> x, y, z;
      double              mean_x = 0;
      for (const Point<3> &p : points)
        mean_x += p[0] / points.size();
      arc.x = mean_x;
      for (const Point<3> &p : points)
        if (std::abs(p[0] - apex[0]) <= band && p[2] <= apex[2] + depth)
          {
            x.push_back(p[0] - apex[0]);
            y.push_back(p[1]);
            z.push_back(p[2]);
          }
      if (x.size() < 5)
        return arc;
      // The condyle's frontal curvature lifts the nodes off its apex line:
      // a parabola in x through the nodes near the apex (in y) is taken
      // off the heights, if it curves upwards.
      std::vector<std::array<double, 3>> rows;
      std::vector<double>                rhs;
      double x_min = std::numeric_limits<double>::max(), x_max = -x_min;
      for (unsigned int i = 0; i < x.size(); ++i)
        if (std::abs(y[i] - apex[1]) <= 3.)
          {
            rows.push_back({{1., x[i], x[i] * x[i]}});
            rhs.push_back(z[i]);
            x_min = std::min(x_min, x[i]);
            x_max = std::max(x_max, x[i]);
          }
      if (rows.size() >= 4 && x_max - x_min > 0.2 * band)
        {
          const Tensor<1, 3> c = least_squares(rows, rhs);
          if (c[2] > 0)
            for (unsigned int i = 0; i < x.size(); ++i)
              z[i] -= c[1] * x[i] + c[2] * x[i] * x[i];
        }
      // Kasa's fit: y^2 + z^2 + d y + e z + f = 0.
      rows.clear();
      rhs.clear();
      for (unsigned int i = 0; i < x.size(); ++i)
        {
          rows.push_back({{y[i], z[i], 1.}});
          rhs.push_back(-(y[i] * y[i] + z[i] * z[i]));
        }
      const Tensor<1, 3> c = least_squares(rows, rhs);
      arc.centre_y         = -c[0] / 2;
      arc.centre_z         = -c[1] / 2;
      arc.radius           = std::sqrt(std::max(arc.centre_y * arc.centre_y +
                                        arc.centre_z * arc.centre_z - c[2],
                                      0.));
      double sum           = 0;
      for (unsigned int i = 0; i < x.size(); ++i)
        {
          const double r = std::hypot(y[i] - arc.centre_y, z[i] - arc.centre_z);
          sum += (r - arc.radius) * (r - arc.radius);
        }
      arc.rms      = std::sqrt(sum / x.size());
      arc.n_points = x.size();
      return arc;
    }
  } // namespace

  std::vector<DistalArc>
  distal_arcs(const std::vector<Point<3>> &points, const double depth)
  {
    if (points.empty())
      return {};
    double lo = std::numeric_limits<double>::max(), hi = -lo;
    for (const Point<3> &p : points)
      {
        lo = std::min(lo, p[0]);
        hi = std::max(hi, p[0]);
      }
    const double          middle = 0.5 * (lo + hi);
    std::vector<Point<3>> low_side, high_side;
    for (const Point<3> &p : points)
      (p[0] < middle ? low_side : high_side).push_back(p);
    std::vector<DistalArc> arcs;
    for (const auto *side : {&low_side, &high_side})
      {
        const DistalArc arc = condyle_arc(*side, depth);
        if (arc.n_points > 0)
          arcs.push_back(arc);
      }
    return arcs;
  }

  std::string
  flexion_axis_warning(const std::vector<DistalArc> &arcs,
                       const Point<3>               &axis_point,
                       const double                  limit)
  {
    const auto side = [](const DistalArc &a) {
      return std::string(a.x < 0 ? "-x" : "+x");
    };
    const auto describe = [&](const DistalArc &a) {
      return "the condyle at " + side(a) +
             ": distal arc centred at (y, z) = (" + format_number(a.centre_y) +
             ", " + format_number(a.centre_z) + "), radius " +
             format_number(a.radius) + " mm";
    };
    // A profile that is no circle within 0.1 mm (the fit window reaching
    // into the next arc, or across a box or cam) gives no centre to judge
    // the axis by (TKR C's coarse mesh: rms 0.154 mm on one condyle).
    std::vector<DistalArc> circles;
    for (const DistalArc &a : arcs)
      if (a.rms <= 0.1)
        circles.push_back(a);
    std::string far;
    for (const DistalArc &a : circles)
      {
        const double distance =
          std::hypot(a.centre_y - axis_point[1], a.centre_z - axis_point[2]);
        if (distance > limit)
          far += (far.empty() ? "" : "; ") + describe(a) + ", " +
                 format_number(distance) + " mm from the axis";
      }
    double apart = 0;
    if (circles.size() == 2)
      apart = std::hypot(circles[0].centre_y - circles[1].centre_y,
                         circles[0].centre_z - circles[1].centre_z);
    if (far.empty() && apart <= limit)
      return "";
    std::string text =
      "Warning: the flexion axis through (y, z) = (" +
      format_number(axis_point[1]) + ", " + format_number(axis_point[2]) +
      ") is more than " + format_number(limit) +
      " mm from a condyle's distal arc (estimated from femur_contact as "
      "scripts/mesh-implant does): " +
      (far.empty() ? describe(circles[0]) + "; " + describe(circles[1]) : far) +
      ".";
    if (apart > limit)
      text += " The two arcs' centres are " + format_number(apart) +
              " mm apart: no single axis is the centre of both, and about "
              "any axis one condyle rises against the other as the femur "
              "flexes (the tray ab/adducts after it, and the load moves "
              "between the condyles).";
    text += " Use the component's design axis if its maker states one, "
            "else check the estimate (doc/gait.md, \"The flexion axis\").";
    return text;
  }
} // namespace TKR::Gait
