// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_problems_gait_cycle_h
#define tkr_problems_gait_cycle_h

#include <deal.II/lac/affine_constraints.h>

#include <tkr/base/mpi.h>
#include <tkr/contact/contact_solver.h>
#include <tkr/gait/protocol.h>
#include <tkr/gait/step_report.h>
#include <tkr/mortar/mortar_coupling.h>
#include <tkr/output/vtu_output.h>
#include <tkr/problems/two_body_model.h>
#include <tkr/wear/step_record.h>
#include <tkr/wear/wear_law.h>

#include <map>
#include <memory>
#include <string>
#include <vector>

namespace TKR::Problems
{
  /**
   * One gait cycle on the current geometry of a TwoBodyModel (DESIGN.md
   * sections 2 and 4): every step is a static contact problem in the
   * tibia's frame, the femur placed by the relative rigid motion of the
   * gait protocol (Gait::Protocol, `Gait/Control`) and both bodies'
   * displacements in their co-rotated frames, so that the stiffness never
   * changes within the cycle. The femur is clamped on its fixation
   * surface; the tibia's support, loads and pose solve are the
   * protocol's. The steps are independent: the MPI ranks are split into
   * step groups that each solve a share of them on their own model, each
   * step from the same start (its end state of the previous cycle, or
   * rest), so the grouping does not change the result; then every rank
   * gets every step's record (for the wear) and report.
   */
  class GaitCycle
  {
  public:
    /**
     * The cycle of the gait @p gait (the model's `Gait` subsection, or an
     * activity's of a mix, Parameters::Activity); @p name names the
     * activity in the screen report and its step VTU files ("": none).
     */
    GaitCycle(TwoBodyModel           &model,
              const StepGroups       &groups,
              const Parameters::Gait &gait,
              const std::string      &name = "");

    /**
     * The protocol (with its waveform), the Dirichlet and support
     * constraints, the contact surfaces and the contact solver (set up by
     * setup_solver()). Call after TwoBodyModel::distribute_dofs(). With
     * @p report_model, the degrees of freedom and ranks are printed (the
     * first activity's cycle of a mix).
     */
    void
    setup(const bool report_model = true);

    /**
     * Set the contact solver up for the stiffness geometry of the model
     * (the condensed solver assembles and factorises the stiffness there)
     * and register the protocol's observations. Again after every
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
     * output_steps(). With @p initial_geometry (the unworn insert of a
     * fresh run), step 0 starts with the tray lowered by the bodies'
     * overlap and refuses one larger than `Gait/Largest initial overlap`
     * (take_up_initial_overlap(); a warm-started worn state carries the
     * elastic indentation of the block before). A step whose pose does not
     * converge is cut back (cut_back()). An input error in one step group
     * is raised on every rank. A stop signal (stop_requested()) ends the
     * cycle before its next step and raises ExcStopped (its message the
     * signal's name) on every rank; the step starts of the steps done are
     * then the new ones. Returns true if every step converged.
     */
    bool
    solve(const bool print_steps,
          const bool keep_for_output,
          const bool initial_geometry);

    /** Each step's end state (after solve()), e.g. for a checkpoint. */
    const std::vector<Gait::StepStart> &
    get_step_starts() const
    {
      return starts;
    }

    /** Start the next solve() from these end states (restart). */
    void
    set_step_starts(const std::vector<Gait::StepStart> &step_starts)
    {
      starts = step_starts;
    }

    /**
     * Write the VTU files of the steps kept for output (`VTU interval`),
     * with the slip and wear of each node to the next step from @p wear
     * (the wear law's result for this cycle).
     */
    void
    output_steps(const Wear::CycleWear &wear);

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
    const std::vector<Gait::StepReport> &
    get_reports() const
    {
      return reports;
    }

    /** The gait protocol (after setup()). */
    const Gait::Protocol &
    get_protocol() const
    {
      return *protocol;
    }

    /**
     * The step with the largest axial force (the protocol's input channel
     * `axial_force_N`), or with the largest contact force if the protocol
     * has no such channel.
     */
    unsigned int
    peak_load_step() const;

    /** Contact solves of this rank repeated because they left the
     *  coupling window (`Contact solver/Coupling window`). */
    unsigned int
    n_window_misses() const
    {
      return window_misses;
    }

  private:
    /** What the contact solves of one step have done so far. */
    struct StepProgress
    {
      Contact::ContactState      state;
      Contact::ContactStatistics statistics;
      Gait::Observations         observations;
      Mortar::CouplingWindow     window;
      bool                       use_window        = false;
      unsigned int               newton_iterations = 0;
      unsigned int               n_solves          = 0;
      /**
       * The best estimate of the step's pose for the next block's
       * prediction (Contact::PoseStatistics::refined; empty: the accepted
       * pose).
       */
      Gait::Pose refined;
    };

    /**
     * The pose solve of step @p step at @p input from @p pose (updated):
     * Contact::PoseNewton on the protocol's pose equations
     * (Gait::PoseEquations), each residual a contact solve at a pose (in
     * the coupling window if there is one, again on the whole search
     * distance if the solution leaves it), the Newton steps from the
     * solver's analytic derivatives (the condensed active set) where
     * `Gait/Pose derivatives = analytic`, else by finite differences
     * (Contact::FiniteDifferencePose).
     */
    Gait::PoseSolve
    solve_pose(const unsigned int     step,
               const Gait::StepInput &input,
               Gait::Pose            &pose,
               StepProgress          &progress);

    /**
     * The cut-back of a step whose pose did not converge (as Abaqus cuts
     * an increment back): the instant of the step before is solved from
     * its own start, then the cycle is followed from there to the step's
     * instant in sub-steps (the inputs of the protocol at the instants in
     * between: load and flexion interpolated as the waveform is), each
     * from the end of the one before; a sub-step that does not converge is
     * halved, down to smallest_sub_step of the step. The elastic,
     * frictionless contact does not depend on the path, so the end is the
     * step's solution. On success @p pose and @p progress are the step's
     * end and the returned solve counts every solve of the cut-back
     * (PoseSolve::n_sub_steps the sub-steps); else they are left as they
     * were and the failed solve is returned.
     */
    Gait::PoseSolve
    cut_back(const unsigned int     step,
             const Gait::StepInput &input,
             const Gait::PoseSolve &failed,
             Gait::Pose            &pose,
             StepProgress          &progress);

    /**
     * The smallest sub-step of a cut-back, as a fraction of a step (five
     * halvings of the first sub-step of half a step).
     */
    static constexpr double smallest_sub_step = 1. / 64;

    /**
     * Solve step @p step: the protocol's pose solve of contact solves,
     * the record and report; keep its solution for output if
     * @p keep_for_output.
     */
    void
    solve_step(const unsigned int step,
               const bool         print,
               const bool         keep_for_output);

    /**
     * Where step @p step starts: its pose and active set of the previous
     * cycle (warm start, with the coupling window of its last solve), or
     * rest, with the tibia lifted to touch the femur if that is far from
     * it (touching_lift()).
     */
    Gait::Pose
    start_step(const unsigned int     step,
               const Gait::StepInput &input,
               StepProgress          &progress);

    /**
     * Warn if `Gait/Flexion axis point` is more than flexion_axis_limit
     * from a condyle's distal-arc centre (Gait::flexion_axis_warning()).
     */
    void
    check_flexion_axis() const;

    /**
     * How far (mm) the flexion axis may lie from a condyle's distal-arc
     * centre without a warning: the estimate itself is up to 1.6 mm off on
     * a short distal arc (TKR B, doc/geometry.md), and an axis 2 mm off
     * moved the coarse TKR A's mass loss by up to 4.8 %
     * (doc/robustness.md).
     */
    static constexpr double flexion_axis_limit = 2.;

    /** Refuse a coupling of step @p step without a covered node. */
    void
    check_coupling(const unsigned int step) const;

    /**
     * After a step's contact solve: the face clearances for the coupling
     * window and the observations, into @p progress.
     */
    void
    finish_solve(StepProgress &progress) const;

    /**
     * Tell the solver which nodes the first cycle's solves will probably
     * need (ContactSolver::expect()): those within a clearance of the
     * femur where each step of this group starts.
     */
    void
    expect_contact();

    /** The mortar coupling at @p motion, in @p window if given. */
    void
    couple(const Gait::RelativeMotion   &motion,
           const Mortar::CouplingWindow *window);

    /**
     * The vertex positions of a step in the tibia's frame: the femur's
     * moved by @p motion, the tibia's where they are. The gaps are those
     * of the moved bodies, and the slave side of the mortar coupling stays
     * the same within a block (MortarCoupling keeps it).
     */
    std::vector<dealii::Point<3>>
    step_positions(const Gait::RelativeMotion &motion) const;

    /**
     * How far the tibia must rise (along +z, rigidly) for its contact
     * surface to touch the femur's at @p positions (step_positions() at
     * rest): the smallest height of a femur_contact node above the
     * tibia_contact node nearest to it in the xy plane, if that is within
     * the search distance. A cold step whose femur is higher than half the
     * search distance starts from this pose, not from rest: in swing the
     * femur may rise from the insert by more than the search distance
     * (large flexion, an axis off the distal arc's centre), and the
     * axial force lifts the tibia after it anyway.
     */
    double
    touching_lift(const std::vector<dealii::Point<3>> &positions) const;

    /** The lift of a cold step's start at @p input: touching_lift() at
     *  rest if that is more than half the search distance, else 0. */
    double
    cold_lift(const Gait::StepInput &input) const;

    /**
     * At the first step of the initial geometry from rest (@p pose), the
     * bodies' overlap: one is refused above `Gait/Largest initial overlap`
     * (a misplaced body or a wrong flexion axis, not a faceting artefact);
     * a smaller one is taken up by the tray, which starts lowered by it:
     * returns the overlap (mm; 0: none), and initial_overlap records it
     * for the report.
     */
    double
    take_up_initial_overlap(const Gait::StepInput &input,
                            const Gait::Pose      &pose);

    /** Exchange the records, reports and starts of @p own_steps. */
    void
    gather_steps(const std::vector<unsigned int> &own_steps);

    TwoBodyModel     &model;
    const StepGroups &groups;
    /** The gait of this cycle (the model's, or an activity's). */
    const Parameters::Gait gait;
    /** The activity's slug ("" without a mix). */
    const std::string                       name;
    std::unique_ptr<Gait::Protocol>         protocol;
    dealii::AffineConstraints<double>       dirichlet;
    std::vector<bool>                       is_femur_vertex;
    std::unique_ptr<Contact::ContactSolver> solver;
    std::vector<std::string>                observation_names;
    std::vector<Wear::StepRecord>           records;
    std::vector<Gait::StepReport>           reports;
    std::vector<Gait::StepStart>            starts;
    unsigned int                            window_misses = 0;
    /** The protocol's pose unknowns and equations (solve_pose() solves
     *  them). */
    Gait::PoseEquations pose_equations;
    /** At most this many Newton iterations or updates of a step's pose. */
    static constexpr unsigned int max_pose_iterations = 40;
    /** Check the overlap at step 0 in this solve() (initial geometry). */
    bool check_overlap = false;
    /**
     * The overlap (mm) by which step 0 of the initial geometry started
     * with the tray lowered (take_up_initial_overlap()); 0: none.
     */
    double initial_overlap = 0;
    /**
     * The step starts at the beginning of the current solve(): a cut-back
     * starts from the step before as it stood then, whichever steps this
     * group has solved since (the result does not depend on the groups).
     */
    std::vector<Gait::StepStart> cycle_starts;

    /** What the VTU of a step needs (its solution, state and motion). */
    struct SavedStep
    {
      dealii::TrilinosWrappers::MPI::Vector solution;
      Contact::ContactState                 state;
      Gait::RelativeMotion                  motion;
    };
    /** The steps of this group to be written as VTU after the cycle. */
    std::map<unsigned int, SavedStep>  saved_steps;
    std::unique_ptr<Output::VtuSeries> step_series;
  };
} // namespace TKR::Problems

#endif
