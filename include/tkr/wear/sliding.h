// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_wear_sliding_h
#define tkr_wear_sliding_h

#include <deal.II/base/tensor.h>

#include <tkr/wear/step_record.h>

#include <vector>

namespace TKR::Wear
{
  /**
   * The sliding of the femur over every `tibia_contact` node in one
   * interval of the gait cycle, from step a to step b (DESIGN.md section
   * 4.6): for each end of the interval where the node is in contact, the
   * pressure there and the slip vector of the femur material point the
   * node touches at that end, in the tibia's frame. A femur point X moves
   * by M_b(X) - M_a(X) (M the relative motion of each step) while the
   * node moves by u_b - u_a (its elastic displacement); the slip is the
   * part of the difference tangential to the node's surface at that end.
   * Where the node is not in contact at an end, its pressure and slip
   * vector there are zero.
   */
  struct IntervalSliding
  {
    /** Contact pressure (MPa) at the start and at the end of the interval. */
    std::vector<double> pressure_start, pressure_end;
    /** Slip vectors (mm) from the femur points touched at the start and at
     *  the end. */
    std::vector<dealii::Tensor<1, 3>> slip_start, slip_end;

    /**
     * The slip distance of node @p j over the interval (mm): the mean of
     * the two slips where the node touches at both ends, the one where it
     * touches at one end only, zero where it touches at neither.
     */
    double
    slip_distance(const unsigned int j) const;
  };

  /**
   * The sliding of a periodic gait cycle: one IntervalSliding per
   * interval from step i to step i + 1 (the last step followed by the
   * first), from the steps' records. Everything a wear law needs from the
   * contact solves: the laws (WearLaw) never see the records themselves.
   */
  class CycleSliding
  {
  public:
    /** The intervals of the cycle of @p records (one per step). */
    explicit CycleSliding(const std::vector<StepRecord> &records);

    unsigned int
    n_intervals() const
    {
      return intervals.size();
    }

    /** Number of tibia_contact nodes. */
    unsigned int
    n_nodes() const
    {
      return intervals.empty() ? 0 : intervals[0].pressure_start.size();
    }

    /** Interval @p i (from step i to step i + 1). */
    const IntervalSliding &
    interval(const unsigned int i) const
    {
      return intervals[i];
    }

  private:
    std::vector<IntervalSliding> intervals;
  };
} // namespace TKR::Wear

#endif
