// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_problems_gait_cycle_h
#define tkr_problems_gait_cycle_h

#include <deal.II/lac/affine_constraints.h>

#include <tkr/base/mpi.h>
#include <tkr/contact/contact_solver.h>
#include <tkr/gait/gait_loads.h>
#include <tkr/gait/tibia_pose.h>
#include <tkr/gait/waveform.h>
#include <tkr/mortar/mortar_coupling.h>
#include <tkr/output/vtu_output.h>
#include <tkr/problems/two_body_model.h>
#include <tkr/wear/step_record.h>

#include <map>
#include <memory>
#include <vector>

namespace TKR::Problems
{
  /**
   * One ISO 14243-1 gait cycle on the current geometry of a TwoBodyModel
   * (DESIGN.md sections 2 and 4): every step is a static contact problem.
   * The femur, clamped on its fixation surface, is rotated rigidly by the
   * flexion angle (its displacements live in its co-rotated frame, so its
   * stiffness never changes); the tibia has no displacement condition, is
   * loaded on its inferior surface by the gait's forces and held by the
   * restraint springs, and its pose is iterated (Gait::TibiaPose). The
   * steps are independent: the MPI ranks are split into step groups that
   * each solve a share of them on their own model, each step from the same
   * cold start (so the grouping does not change the result); then every
   * rank gets every step's record (for the wear) and report.
   */
  class GaitCycle
  {
  public:
    GaitCycle(TwoBodyModel &model, const StepGroups &groups);

    /**
     * The waveform, the loads on the measured inferior surface, the
     * Dirichlet and tray constraints, the contact surfaces and the contact
     * solver (set up by setup_solver()). Call after
     * TwoBodyModel::distribute_dofs().
     */
    void
    setup();

    /**
     * Set the contact solver up for the stiffness geometry of the model
     * (the condensed solver assembles and factorises the stiffness there)
     * and register the tibia's motion functionals. Again after every
     * WornGeometry::update_stiffness_geometry().
     */
    void
    setup_solver();

    /**
     * Solve this group's steps on the current geometry and gather every
     * step's record, report and end state on every rank. Each step starts
     * from its end state of the previous call if `Wear/Warm start` is set
     * (and there is one), else from rest. With @p print_steps, each step's
     * line is printed (as it is done if there is one group, all at the end
     * otherwise); steps that did not converge are always printed. With
     * @p keep_for_output, the steps of the `VTU interval` are kept for
     * output_steps(). Returns true if every step converged.
     */
    bool
    solve(const bool print_steps, const bool keep_for_output);

    /** Each step's end state (after solve()), e.g. for a checkpoint. */
    const std::vector<Wear::StepStart> &
    get_step_starts() const
    {
      return starts;
    }

    /** Start the next solve() from these end states (restart). */
    void
    set_step_starts(const std::vector<Wear::StepStart> &step_starts)
    {
      starts = step_starts;
    }

    /** Write the VTU files of the steps kept for output (`VTU interval`). */
    void
    output_steps();

    unsigned int
    n_steps() const
    {
      return reports.size();
    }

    /** Every step's record (after solve()). */
    const std::vector<Wear::StepRecord> &
    get_records() const
    {
      return records;
    }

    /** Every step's report (after solve()). */
    const std::vector<Wear::StepReport> &
    get_reports() const
    {
      return reports;
    }

    /** Contact solves of this rank repeated because they left the
     *  coupling window (`Contact solver/Coupling window`). */
    unsigned int
    n_window_misses() const
    {
      return window_misses;
    }

    /** The mortar coupling (D_jj of the tibia_contact nodes). */
    const Mortar::MortarCoupling &
    get_coupling() const
    {
      return model.coupling();
    }

  private:
    /**
     * Solve step @p step: pose iteration of contact solves, record; keep
     * its solution for output if @p keep_for_output.
     */
    void
    solve_step(const unsigned int step,
               const bool         print,
               const bool         keep_for_output);

    /**
     * The vertex positions of a step in the tibia's frame: the femur's
     * moved by @p femur_motion and back by the tibia's pose @p tibia_pose,
     * the tibia's where they are. The gaps are those of the moved bodies,
     * and the slave side of the mortar coupling stays the same within a
     * block (MortarCoupling keeps it).
     */
    std::vector<dealii::Point<3>>
    step_positions(const Gait::RigidMotion    &femur_motion,
                   const dealii::Tensor<1, 3> &tibia_pose) const;

    /**
     * How far the tibia must rise (along +z, rigidly) for its contact
     * surface to touch the femur's at @p positions (step_positions() at
     * no pose): the smallest height of a femur_contact node above the
     * tibia_contact node nearest to it in the xy plane, if that is within
     * the search distance. A cold step whose femur is higher than half the
     * search distance starts from this pose, not from rest: in swing the
     * femur may rise from the insert by more than the search distance
     * (large flexion, an axis off the distal arc's centre), and the
     * axial force lifts the tibia after it anyway.
     */
    double
    touching_lift(const std::vector<dealii::Point<3>> &positions) const;

    /** The bodies must not overlap more than the tolerance at 0 %. */
    void
    check_initial_overlap() const;

    TwoBodyModel                           &model;
    const StepGroups                       &groups;
    std::unique_ptr<Gait::Waveform>         waveform;
    std::unique_ptr<Gait::GaitLoads>        gait_loads;
    std::unique_ptr<Gait::TibiaPose>        tibia_pose;
    dealii::AffineConstraints<double>       dirichlet;
    std::vector<bool>                       is_femur_vertex;
    std::unique_ptr<Contact::ContactSolver> solver;
    std::vector<Wear::StepRecord>           records;
    std::vector<Wear::StepReport>           reports;
    std::vector<Wear::StepStart>            starts;
    unsigned int                            window_misses = 0;

    /** What the VTU of a step needs (its solution, state and motion). */
    struct SavedStep
    {
      dealii::TrilinosWrappers::MPI::Vector solution;
      Contact::ContactState                 state;
      Gait::RigidMotion                     motion;
    };
    /** The steps of this group to be written as VTU after the cycle. */
    std::map<unsigned int, SavedStep>  saved_steps;
    std::unique_ptr<Output::VtuSeries> step_series;
  };
} // namespace TKR::Problems

#endif
