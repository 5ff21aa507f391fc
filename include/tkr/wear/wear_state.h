// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_wear_wear_state_h
#define tkr_wear_wear_state_h

#include <deal.II/base/tensor.h>

#include <tkr/gait/step_report.h>

#include <vector>

namespace TKR::Wear
{
  /**
   * One side of the insert (medial or lateral, of `Gait/Medial side`):
   * what labs report for each condyle.
   */
  struct SideResult
  {
    /** Worn volume so far (mm^3). */
    double volume = 0;
    /** Largest accumulated depth (mm). */
    double max_depth = 0;
    /** The side's worn area in percent of the whole tibia_contact area (the
     *  two sides add up to the insert's). */
    double wear_area_percent = 0;
    /** The block's cycle's mean cross-shear (frictional work x area
     *  weighted). */
    double mean_cross_shear = 0;
  };

  /**
   * What one activity of a mix (`Gait/Activities`) has worn so far: the
   * wear of its cycles times its share, summed over the blocks (the
   * activities' results add up to the run's).
   */
  struct ActivityResult
  {
    /** Worn volume (mm^3) and mass (mg). */
    double volume = 0, mass = 0;
    /** Largest depth of the activity's accumulated wear (mm). */
    double max_depth = 0;
    /** Worn volume of the medial and of the lateral side (mm^3). */
    double medial_volume = 0, lateral_volume = 0;
  };

  /**
   * The state of the wear run after an extrapolation block: one row of
   * `wear_history.csv`.
   */
  struct BlockResult
  {
    unsigned int block  = 0;
    double       cycles = 0;
    /** Worn volume (mm^3) and mass (mg) so far. */
    double volume = 0, mass = 0;
    /** Largest accumulated wear depth (mm). */
    double max_depth = 0;
    /** Worn part of tibia_contact (%, accumulated depth > threshold). */
    double wear_area_percent = 0;
    /** Peak pressure (MPa) and largest contact area (mm^2) of the cycle. */
    double peak_pressure = 0, max_contact_area = 0;
    /** Wall time of the run so far (s). */
    double wall_time = 0;
    /** The medial and the lateral side. */
    SideResult medial, lateral;
    /** Per activity of a mix (empty without one). */
    std::vector<ActivityResult> activities;
  };

  /** A gait step that did not converge (or failed its load balance). */
  struct FailedStep
  {
    /** The block (1, 2, ...) and the step of its cycle. */
    unsigned int block = 0, step = 0;
    /** The pose solve's last residual (mm). */
    double pose_residual = 0;
    /** Whether the contact solves converged. */
    bool contact_converged = false;
    /** The protocol's load balance (at most 1 when balanced). */
    double load_balance = 0;
  };

  /**
   * Everything the loop over extrapolation blocks (DESIGN.md section 4.7)
   * needs to go on: what a checkpoint holds. Geometry data is stored per
   * triangulation vertex and per tibia_contact node, both independent of
   * the number of ranks.
   */
  struct WearRunState
  {
    /** Blocks done and cycles done. */
    unsigned int block  = 0;
    double       cycles = 0;
    /** n_Delta now (halved on distortion if configured). */
    double cycles_per_block = 0;
    /** The block after which the stiffness was last assembled. */
    unsigned int stiffness_block = 0;
    /** Displacement of every vertex: worn and stiffness geometry (mm). */
    std::vector<dealii::Tensor<1, 3>> displacement, stiffness_displacement;
    /** Accumulated wear depth of every vertex (mm). */
    std::vector<double> depth;
    /** Each gait step's end state of the last block (warm starts). */
    std::vector<Gait::StepStart> step_starts;
    /** One row per block done (and block 0). */
    std::vector<BlockResult> history;
    /** Worn volume (mm^3), sums over all blocks, every step converged. */
    double volume = 0;
    /** Worn volume of the medial and of the lateral side (mm^3). */
    double volume_medial = 0, volume_lateral = 0;
    /**
     * Per activity of a mix (empty without one): its accumulated depth of
     * every vertex (mm) and its volumes (ActivityResult's mass and largest
     * depth unused).
     */
    std::vector<std::vector<double>> activity_depth;
    std::vector<ActivityResult>      activity_volume;
    unsigned long long               contact_solves    = 0;
    unsigned long long               newton_iterations = 0;
    unsigned long long               steps             = 0;
    /** Pose Newton steps off the Newton direction (StepReport). */
    unsigned long long pose_fallbacks = 0;
    /** Steps solved by a cut-back, and their sub-steps (StepReport). */
    unsigned long long cut_back_steps = 0, sub_steps = 0;
    bool               converged = true;
    /** Peak pressure over the run (MPa). */
    double max_pressure = 0;
    /** Every step that did not converge, over all blocks. */
    std::vector<FailedStep> failed_steps;
    /** Mass loss of the first cycle (mg), on the unworn insert. */
    double first_cycle_mass = 0;
    /** Wall time of the run before this start (s). */
    double wall_time = 0;
  };
} // namespace TKR::Wear

#endif
