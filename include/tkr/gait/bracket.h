// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_gait_bracket_h
#define tkr_gait_bracket_h

#include <vector>

namespace TKR::Gait
{
  /**
   * The safeguard of one pose component in both protocols' pose iterations
   * (PoseUpdate for force control, DisplacementControl::solve_pose()): the
   * latest value at which a contact solve asked for more (the correction
   * d > 0: the low end) and the latest at which it asked for less (d < 0:
   * the high end), and the signs of the last three corrections. Where d
   * decreases along the component, a low end below the high end encloses
   * a root of d (or a jump of d across zero, e.g. where a contact node
   * enters the active set).
   */
  class Bracket
  {
  public:
    /** Record a solve at @p value that asked for the correction @p d. */
    void
    add(const double value, const double d);

    /** Both ends seen and the low one below the high one. */
    bool
    encloses() const;

    /** high - low if encloses(), else infinity. */
    double
    width() const;

    /** The middle of the ends. */
    double
    middle() const;

    /** The false-position point of the ends, held within the bracket's
     *  middle half (so that it shrinks to at most 3/4 per solve). */
    double
    false_position() const;

    /** The correction's sign alternated over the last three solves. */
    bool
    oscillates() const;

    /** Forget the signs (the ends stay). */
    void
    forget_signs();

  private:
    bool   has_low = false, has_high = false;
    double q_low = 0, d_low = 0, q_high = 0, d_high = 0;
    /** Signs of d at the last three values (without zeros). */
    std::vector<int> signs;
  };
} // namespace TKR::Gait

#endif
