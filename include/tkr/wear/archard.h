// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_wear_archard_h
#define tkr_wear_archard_h

#include <tkr/wear/wear_law.h>

namespace TKR::Wear
{
  /** The entries of `Wear/Archard`. */
  struct ArchardParameters
  {
    /** Archard wear coefficient k in mm^3/(N m), as in the literature. */
    double wear_coefficient = 2e-7;
  };

  /**
   * Archard's law with a constant wear coefficient (`Wear law = archard`,
   * the reference paper's model, DESIGN.md section 2): dh/dt = k p |v_t|.
   * Over an interval from step a to step b the femur point that node j
   * touches at a slides by s_a, the one it touches at b by s_b
   * (IntervalSliding), and the trapezoidal rule gives the depth
   * k (p_a |s_a| + p_b |s_b|) / 2.
   */
  class ArchardWear : public WearLaw
  {
  public:
    /** @p k_per_metre: the `Wear coefficient` in mm^3/(N m). */
    explicit ArchardWear(const double k_per_metre);

    double
    interval_depth(const CycleSliding &sliding,
                   const unsigned int  i,
                   const unsigned int  j) const override;

  protected:
    std::string
    law_description() const override;

  private:
    /** The coefficient in mm^3/(N m), as given. */
    const double k_per_metre;
    /** The coefficient in mm^3/(N mm) = mm^2/N: k_per_metre x 1e-3. */
    const double k;
  };
} // namespace TKR::Wear

#endif
