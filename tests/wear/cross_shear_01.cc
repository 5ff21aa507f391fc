// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.
//
// Cross-shear (doc/wear.md, "Cross-shear") against the values the
// quadratic-work definition gives in closed form, for one node under a
// femur that translates through a closed path (one record per corner, the
// cycle closing from the last corner to the first): sliding back and forth
// along a line 0; a square path 1/2; a 2 x 1 rectangle 1/3 with the
// orientation along its long side; a regular 72-gon (a circle) 1/2; the
// rectangle turned by a rotation (path and surface normal) the same ratio
// and the turned orientation; the ratio independent of a uniform pressure;
// and legs of different pressures weighted by their work (square, the y
// legs at twice the pressure: 1/3).

#include <deal.II/base/tensor.h>

#include <tkr/wear/cross_shear.h>

#include <cmath>

#include "../tests.h"

namespace
{
  using namespace dealii;
  using namespace TKR;

  /** One record per corner of @p path (femur translations), the node's
   *  normal @p normal and pressure @p pressure at every corner. */
  Wear::CycleSliding
  cycle(const std::vector<Tensor<1, 3>> &path,
        const Tensor<1, 3>              &normal,
        const double                     pressure = 1.)
  {
    std::vector<Wear::StepRecord> records(path.size());
    for (unsigned int k = 0; k < path.size(); ++k)
      {
        records[k].motion.femur.translation = path[k];
        records[k].pressure                 = {pressure};
        records[k].femur_point              = {Point<3>()};
        records[k].displacement             = {Tensor<1, 3>()};
        records[k].normal                   = {normal};
      }
    return Wear::CycleSliding(records);
  }

  Tensor<1, 3>
  xy(const double x, const double y)
  {
    Tensor<1, 3> t;
    t[0] = x;
    t[1] = y;
    return t;
  }

  /** The ratio and work, and the orientation unless @p isotropic (then any
   *  direction in the plane has the most work). */
  void
  report(const std::string      &name,
         const Wear::CrossShear &cs,
         const bool              isotropic = false)
  {
    deallog << name << ": ratio " << cs.ratio;
    if (!isotropic)
      deallog << ", orientation " << cs.orientation;
    deallog << ", work " << cs.work << std::endl;
  }
} // namespace

int
main()
{
  initlog();
  deallog << std::fixed << std::setprecision(6);
  const Tensor<1, 3> e3({0., 0., 1.});
  report("line",
         Wear::cycle_cross_shear(
           cycle({xy(0, 0), xy(1, 0), xy(2, 0), xy(1, 0)}, e3))[0]);
  report("square",
         Wear::cycle_cross_shear(
           cycle({xy(0, 0), xy(1, 0), xy(1, 1), xy(0, 1)}, e3))[0],
         true);
  const std::vector<Tensor<1, 3>> rectangle = {xy(0, 0),
                                               xy(2, 0),
                                               xy(2, 1),
                                               xy(0, 1)};
  report("rectangle 2 x 1", Wear::cycle_cross_shear(cycle(rectangle, e3))[0]);
  std::vector<Tensor<1, 3>> circle;
  for (unsigned int k = 0; k < 72; ++k)
    circle.push_back(
      xy(std::cos(2 * M_PI * k / 72), std::sin(2 * M_PI * k / 72)));
  report("72-gon", Wear::cycle_cross_shear(cycle(circle, e3))[0], true);

  // the rectangle turned by 40 degrees about (1, 2, 3)
  const Tensor<1, 3> axis = Tensor<1, 3>({1., 2., 3.}) / std::sqrt(14.);
  const double c = std::cos(40 * M_PI / 180), s = std::sin(40 * M_PI / 180);
  const Tensor<2, 3> cross({{0., -axis[2], axis[1]},
                            {axis[2], 0., -axis[0]},
                            {-axis[1], axis[0], 0.}}); // cross * v = axis x v
  const Tensor<2, 3> R = c * unit_symmetric_tensor<3>() +
                         (1 - c) * outer_product(axis, axis) + s * cross;
  std::vector<Tensor<1, 3>> turned;
  for (const auto &t : rectangle)
    turned.push_back(R * t);
  const auto cs        = Wear::cycle_cross_shear(cycle(turned, R * e3))[0];
  const auto long_side = R * xy(1, 0);
  deallog << "turned rectangle: ratio " << cs.ratio
          << ", |orientation . R e_x| " << std::abs(cs.orientation * long_side)
          << ", work " << cs.work << std::endl;
  deallog << "turned rectangle: ratio equal to 1e-12: "
          << (std::abs(cs.ratio - 1. / 3.) < 1e-12 ? "yes" : "no") << std::endl;

  report("rectangle 2 x 1 at 7 MPa",
         Wear::cycle_cross_shear(cycle(rectangle, e3, 7.))[0]);
  report("square, y legs at twice the pressure",
         Wear::cross_shear({xy(1, 0), xy(0, 1), xy(-1, 0), xy(0, -1)},
                           {1., 2., 1., 2.}));
  report("no sliding", Wear::cross_shear({xy(0, 0)}, {1.}));
}
