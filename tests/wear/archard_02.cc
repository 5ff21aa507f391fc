// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.
//
// The Archard law on hand-made step records (no finite elements): a femur
// rotating by the flexion angle about an axis parallel to x, a tibia whose
// pose is a rotation about z plus a translation, unequal pressures at the
// two ends of an interval, different femur points touched at the two ends,
// elastic displacements and tilted normals. Checked against an
// independent computation of the same definitions:
// - node 0 (in contact at both ends): depth k (p_a |s_a| + p_b |s_b|) / 2;
// - node 1 (in contact at the start only): k p_a |s_a| / 2, slip |s_a|;
// - node 2 (never in contact): nothing;
// - a pure flexion (tibia at rest, u = 0, one femur point): the slip is the
//   chord 2 r sin(dtheta / 2) of the point's circle, and the depth
//   k (p_a + p_b) chord / 2;
// - the unit conversion: the law's k is the Wear coefficient x 1e-3.

#include <deal.II/base/numbers.h>

#include <tkr/parameters/parameters.h>
#include <tkr/wear/archard.h>
#include <tkr/wear/wear_law.h>

#include <cmath>

#include "../tests.h"

namespace
{
  using TKR::Gait::RelativeMotion;
  using TKR::Gait::RigidMotion;

  /** Rotation by @p degrees about the axis @p d (0, 1, 2). */
  Tensor<2, 3>
  rotation(const unsigned int d, const double degrees)
  {
    const double       c = std::cos(degrees * numbers::PI / 180.);
    const double       s = std::sin(degrees * numbers::PI / 180.);
    const unsigned int i = (d + 1) % 3, j = (d + 2) % 3;
    Tensor<2, 3>       R;
    R[d][d] = 1;
    R[i][i] = R[j][j] = c;
    R[i][j]           = -s;
    R[j][i]           = s;
    return R;
  }

  /** A step: flexion @p theta about the axis through P, tibia pose. */
  RelativeMotion
  step_motion(const double theta, const double phi, const Tensor<1, 3> &t)
  {
    const Point<3> P(0., -2., 53.);
    RelativeMotion motion;
    motion.femur.rotation    = rotation(0, theta);
    motion.femur.translation = P - motion.femur.rotation * P;
    motion.tibia.rotation    = rotation(2, phi);
    motion.tibia.translation = t;
    return motion;
  }

  /** The femur point X in the tibia's frame, computed independently. */
  Point<3>
  in_tibia_frame(const double        theta,
                 const double        phi,
                 const Tensor<1, 3> &t,
                 const Point<3>     &X)
  {
    const Point<3>     P(0., -2., 53.);
    const Tensor<1, 3> flexed = rotation(0, theta) * (X - P) + P;
    return Point<3>(rotation(2, -phi) * (flexed - t));
  }

  Tensor<1, 3>
  tangential(const Tensor<1, 3> &v, const Tensor<1, 3> &n)
  {
    return v - (v * n) * n;
  }
} // namespace

int
main()
{
  initlog();
  TKR::Parameters::Wear parameters;
  parameters.law = "archard";
  parameters.laws.set("archard", TKR::Wear::ArchardParameters{2e-7});
  const double k = 2e-7 * 1e-3; // mm^3/(N mm)

  // Two steps a, b; three nodes.
  const double          theta_a = 5, theta_b = 12, phi_a = 0.5, phi_b = 2.5;
  const Tensor<1, 3>    t_a({0., 0.1, 0.02}), t_b({0.05, -0.3, 0.04});
  TKR::Wear::StepRecord a, b;
  a.motion      = step_motion(theta_a, phi_a, t_a);
  b.motion      = step_motion(theta_b, phi_b, t_b);
  a.pressure    = {10., 12., 0.};
  b.pressure    = {20., 0., 0.};
  a.femur_point = {Point<3>(10., 3., 30.), Point<3>(-8., -4., 31.), Point<3>()};
  b.femur_point = {Point<3>(10.2, 2.7, 30.1), Point<3>(), Point<3>()};
  a.displacement = {Tensor<1, 3>({0.001, -0.002, -0.01}),
                    Tensor<1, 3>({0., 0.003, -0.02}),
                    Tensor<1, 3>()};
  b.displacement = {Tensor<1, 3>({-0.002, 0.001, -0.03}),
                    Tensor<1, 3>({0.001, 0., -0.001}),
                    Tensor<1, 3>()};
  Tensor<1, 3> n0({0.1, -0.2, 1.}), n1({-0.3, 0.1, 1.}), n2({0., 0., 1.});
  n0 /= n0.norm();
  n1 /= n1.norm();
  a.normal = {n0, n1, n2};
  b.normal = {n0, n1, n2};

  const auto law = TKR::Wear::create_wear_law(parameters);
  // The cycle a -> b -> a: interval 0 is a -> b.
  const auto wear = law->cycle_wear(TKR::Wear::CycleSliding({a, b}));

  const auto slip = [&](const Point<3> &X, const unsigned int j) {
    const Tensor<1, 3> relative = (in_tibia_frame(theta_b, phi_b, t_b, X) -
                                   in_tibia_frame(theta_a, phi_a, t_a, X)) -
                                  (b.displacement[j] - a.displacement[j]);
    return tangential(relative, a.normal[j]).norm();
  };
  const double s0a = slip(a.femur_point[0], 0), s0b = slip(b.femur_point[0], 0);
  const double s1a    = slip(a.femur_point[1], 1);
  const double depth0 = 0.5 * k * (10. * s0a + 20. * s0b);
  const double depth1 = 0.5 * k * 12. * s1a;
  const auto  &d      = wear.interval_depth[0];
  deallog << "law: " << law->description() << std::endl;
  deallog << "node 0 (both ends, p 10 and 20 MPa): depth / k (p_a s_a + p_b "
             "s_b) / 2 = "
          << d[0] / depth0
          << ", to 1e-12: " << yes_no(std::abs(d[0] / depth0 - 1.) < 1e-12)
          << std::endl;
  deallog << "node 0 slip (mean of the two) / expected: "
          << wear.interval_slip[0][0] / (0.5 * (s0a + s0b)) << std::endl;
  deallog << "node 1 (start only): depth / (k p_a s_a / 2) = " << d[1] / depth1
          << ", slip / s_a = " << wear.interval_slip[0][1] / s1a << std::endl;
  deallog << "node 2 (never in contact): depth " << d[2] << ", slip "
          << wear.interval_slip[0][2] << std::endl;
  deallog << "slips (mm, x 1e3): " << 1e3 * s0a << ' ' << 1e3 * s0b << ' '
          << 1e3 * s1a << std::endl;

  // A pure flexion: the point slides along its circle about the axis.
  TKR::Wear::StepRecord c = a, e = b;
  c.motion = step_motion(theta_a, 0., Tensor<1, 3>());
  e.motion = step_motion(theta_b, 0., Tensor<1, 3>());
  const Point<3> X(0., 18., 33.);
  c.femur_point = e.femur_point = {X, X, X};
  c.displacement =
    e.displacement = {Tensor<1, 3>(), Tensor<1, 3>(), Tensor<1, 3>()};
  // The normal at the point, in the plane of the motion's chord: radial.
  const Point<3>     P(0., -2., 53.);
  const Tensor<1, 3> mid = rotation(0, 0.5 * (theta_a + theta_b)) * (X - P);
  c.normal = e.normal = {mid / mid.norm(), mid / mid.norm(), mid / mid.norm()};
  const auto   circle = law->cycle_wear(TKR::Wear::CycleSliding({c, e}));
  const double chord  = 2. * (X - P).norm() *
                       std::sin(0.5 * (theta_b - theta_a) * numbers::PI / 180.);
  deallog << "pure flexion: slip / chord 2 r sin(dtheta/2) = "
          << circle.interval_slip[0][0] / chord << std::endl;
  deallog << "pure flexion: depth / (k (p_a + p_b) chord / 2) = "
          << circle.interval_depth[0][0] / (0.5 * k * 30. * chord) << std::endl;
  deallog << "cycle depth = sum of the intervals (a->b, b->a): "
          << yes_no(std::abs(circle.depth[0] - circle.interval_depth[0][0] -
                             circle.interval_depth[1][0]) <
                    1e-15 * circle.depth[0])
          << std::endl;
}
