// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_wear_wear_problem_h
#define tkr_wear_wear_problem_h

#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/timer.h>

#include <deal.II/distributed/shared_tria.h>

#include <deal.II/fe/mapping_q1.h>

#include <deal.II/lac/affine_constraints.h>

#include <tkr/contact/active_set_solver.h>
#include <tkr/contact/condensed_solver.h>
#include <tkr/elasticity/linear_elasticity.h>
#include <tkr/gait/gait_loads.h>
#include <tkr/gait/waveform.h>
#include <tkr/mortar/mortar_coupling.h>
#include <tkr/output/summary.h>
#include <tkr/output/vtu_output.h>
#include <tkr/parameters/parameters.h>
#include <tkr/wear/archard.h>

#include <map>
#include <memory>

namespace TKR::Wear
{
  /** What one gait step of the cycle did (for the report and steps.csv). */
  struct StepReport
  {
    double       percent = 0, flexion = 0, axial_force = 0;
    double       ap_force = 0, ie_torque = 0;
    unsigned int active_nodes = 0, newton_iterations = 0, pose_updates = 0;
    /** The tibia's rigid translation (pose) in this step, mm. */
    dealii::Tensor<1, 3> tibia_pose;
    /** The tibia's rotation about +z (IE, deg). */
    double ie_rotation  = 0;
    double max_pressure = 0, contact_force = 0, contact_area = 0;
    bool   converged = false;
    /** The pose iteration reached its tolerance. */
    bool   pose_converged = false;
    double wall_time      = 0;
  };

  /** The rigid part of the tibia's displacement on its inferior surface. */
  struct InferiorMotion
  {
    /** Mean displacement (mm). */
    dealii::Tensor<1, 3> mean;
    /** Best-fitting rotation about +z (deg). */
    double rotation_z = 0;
  };

  /**
   * The split of the MPI ranks into groups that share the steps of a cycle
   * (rank r is in group r * n_groups / n_ranks; group g solves the steps
   * g, g + n_groups, ...). Owns the group communicator.
   */
  struct StepGroups
  {
    StepGroups(const MPI_Comm world, const unsigned int requested_groups);
    ~StepGroups();
    StepGroups(const StepGroups &) = delete;
    StepGroups &
    operator=(const StepGroups &) = delete;

    MPI_Comm     communicator;
    unsigned int n_groups;
    unsigned int index;
    /** Rank 0 of the group. */
    bool is_group_root;
  };

  /**
   * `Problem = wear`: one ISO 14243-1 gait cycle (DESIGN.md sections 2 and
   * 4, steps 2, 6, 8). Every step is a static contact problem: the femur,
   * clamped on its fixation surface, is rotated rigidly by the flexion
   * angle (its displacements live in its co-rotated frame, so its
   * stiffness never changes); the tibia has no displacement condition, is
   * loaded on its inferior surface by the axial force, the AP force and the
   * IE torque, and held by the AP and IE restraint springs. The steps are
   * independent: the MPI ranks are split into groups that each solve a
   * share of them on their own parallel::shared triangulation, each step
   * from the same cold start (so the grouping does not change the result).
   * The stiffness is the same in every step, so the default contact solver
   * factorises it once (CondensedActiveSetSolver). Then the records are
   * collected on every rank and Archard's law gives the wear of the cycle.
   */
  class WearProblem
  {
  public:
    WearProblem(const Parameters::AllParameters &parameters,
                const MPI_Comm                   mpi_communicator);

    /** Run; returns true if every contact solve converged. */
    bool
    run();

    /** Wear depth per slave node after the cycle (mm). */
    const std::vector<double> &
    get_wear_depth() const
    {
      return wear_depth;
    }

  private:
    void
    make_grid();
    void
    setup_system();
    void
    solve_step(const unsigned int step);
    void
    collect_steps();
    void
    compute_wear();
    void
    output_step(const unsigned int step);
    void
    output_results();
    void
    print_step(const unsigned int step) const;
    void
    check_initial_overlap() const;
    void
    add_tray_constraints();
    /**
     * Loads of a step on the tibia translated by @p pose (mm), with the
     * two-rate restraints' excess force (N, along y) and torque (N mm,
     * about z).
     */
    Elasticity::BoundaryLoads
    step_loads(const Gait::GaitState      &gait,
               const dealii::Tensor<1, 3> &pose,
               const double                restraint_force  = 0,
               const double                restraint_torque = 0) const;
    /** The rigid part of the tibia's displacement. */
    InferiorMotion
    inferior_motion() const;

    const Parameters::AllParameters &parameters;
    const MPI_Comm                   world;
    const StepGroups                 groups;
    dealii::ConditionalOStream       pcout;
    dealii::TimerOutput              timer;

    dealii::parallel::shared::Triangulation<3> triangulation;
    const dealii::MappingQ1<3>                 mapping;
    Elasticity::LinearElasticity               elasticity;
    std::unique_ptr<Mortar::ContactSurface>    slave, master;
    std::unique_ptr<Mortar::MortarCoupling>    coupling;
    /** One of the two: the contact solver chosen in the parameter file. */
    std::unique_ptr<Contact::ActiveSetSolver>          solver;
    std::unique_ptr<Contact::CondensedActiveSetSolver> condensed;
    std::unique_ptr<Gait::Waveform>                    waveform;
    std::unique_ptr<Gait::GaitLoads>                   gait_loads;
    dealii::AffineConstraints<double>                  dirichlet;
    std::vector<bool>                                  is_femur_vertex;

    unsigned int n_steps;
    /** The tibia's rigid translation, carried from step to step (mm). */
    dealii::Tensor<1, 3>               tibia_pose;
    const unsigned int                 max_pose_iterations = 40;
    Contact::ContactState              state;
    std::vector<StepRecord>            records;
    std::vector<StepReport>            reports;
    std::vector<double>                wear_depth, slip;
    std::unique_ptr<Output::VtuSeries> step_series;
    /** What the VTU of a step needs (its solution, state and motion). */
    struct SavedStep
    {
      dealii::TrilinosWrappers::MPI::Vector solution;
      Contact::ContactState                 state;
      RigidMotion                           motion;
    };
    /** The steps of this group to be written as VTU after the cycle. */
    std::map<unsigned int, SavedStep> saved_steps;
    Output::Summary                   summary;
  };
} // namespace TKR::Wear

#endif
