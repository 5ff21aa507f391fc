// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_contact_hertz_h
#define tkr_contact_hertz_h

#include <deal.II/base/point.h>

#include <tkr/parameters/parameters.h>

#include <vector>

/**
 * Hertz's solutions for the verification of the contact solver (Johnson,
 * Contact Mechanics, 1985, sections 4.2 and 4.3).
 */
namespace TKR::Contact::Hertz
{
  /** Contact radius (or half-width) a in mm and peak pressure p0 in MPa. */
  struct Solution
  {
    double a  = 0;
    double p0 = 0;
  };

  /** E* with 1/E* = (1 - nu_1^2)/E_1 + (1 - nu_2^2)/E_2, in MPa. */
  double
  effective_modulus(const Parameters::Material &body_1,
                    const Parameters::Material &body_2);

  /**
   * Sphere of radius @p R on a half-space, total force @p F (N):
   * a = (3 F R / (4 E*))^(1/3), p0 = 3 F / (2 pi a^2).
   */
  Solution
  sphere(const double F, const double R, const double E_star);

  /**
   * Cylinder of radius @p R and length @p L on a half-space in plane strain,
   * force @p F (N): with P = F / L, b = sqrt(4 P R / (pi E*)),
   * p0 = 2 P / (pi b).
   */
  Solution
  cylinder(const double F, const double L, const double R, const double E_star);

  /**
   * Fit Hertz's elliptic profile p(r) = p0 sqrt(1 - r^2/a^2) to nodal
   * pressures: p^2 is linear in r^2, so a least-squares line through
   * (r_j^2, p_j^2) gives p0^2 and p0^2/a^2. Uses all nodes with p_j > 0.
   * This measures the contact radius from the whole pressure field instead
   * of from the area of the active nodes, whose lumped weights make that
   * estimate O(h) inaccurate.
   */
  Solution
  fit(const std::vector<double> &r, const std::vector<double> &p);
} // namespace TKR::Contact::Hertz

#endif
