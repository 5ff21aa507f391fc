// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_gait_protocol_h
#define tkr_gait_protocol_h

#include <deal.II/base/conditional_ostream.h>

#include <deal.II/dofs/dof_handler.h>

#include <deal.II/lac/affine_constraints.h>

#include <tkr/base/registry.h>
#include <tkr/base/result_schema.h>
#include <tkr/elasticity/linear_elasticity.h>
#include <tkr/gait/rigid_motion.h>
#include <tkr/gait/step_report.h>
#include <tkr/gait/waveform.h>
#include <tkr/parameters/parameters.h>

#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace TKR::Gait
{
  /**
   * Values of the linear functionals of the displacement that a protocol
   * asked for (Protocol::observations()), after a contact solve, looked
   * up by name.
   */
  class Observations
  {
  public:
    Observations() = default;

    /** The observations @p names with the values @p values. */
    Observations(std::vector<std::string> names, std::vector<double> values);

    /** The value of the observation @p name; an internal error if unknown. */
    double
    operator[](const std::string &name) const;

  private:
    std::vector<std::string> names;
    std::vector<double>      values;
  };

  /** What the pose solve of a step did. */
  struct PoseSolve
  {
    /** Updates of the pose (Newton steps; with a cut-back's, each of its
     *  solves counted as one more). */
    unsigned int n_updates = 0;
    /** The pose met its tolerance (and every contact solve converged). */
    bool converged = false;
    /** The residual of the last solve in the protocol's measure (mm). */
    double residual = 0;
    /**
     * Steps of the pose Newton that left the Newton direction (a direction
     * replaced by S^-1 r, a step at the line search's bracket end;
     * Contact::PoseStatistics): counted in summary.json (pose_fallbacks).
     */
    unsigned int n_fallbacks = 0;
    /**
     * Sub-steps of a cut-back (Problems::GaitCycle::cut_back(); 0: the step
     * was solved at once): counted in summary.json (sub_steps).
     */
    unsigned int n_sub_steps = 0;
  };

  /**
   * The pose unknowns of a protocol that the contact solver can solve
   * together with the contact (Contact::PoseSystem): which values of the
   * Pose are unknowns, the equation each is paired with (an observation
   * that vanishes at the step's equilibrium, with its scale in mm per unit
   * of the observation; unknown p is paired with equation p: moving it by
   * one unit moves the observation by about minus one unit when nothing
   * holds the tibia), and how the other values follow from the unknowns.
   */
  struct PoseEquations
  {
    std::vector<unsigned int>                   unknowns;
    std::vector<std::pair<std::string, double>> residuals;
    /**
     * Per unknown, the index in load_basis() of the unit generalized force
     * it works against (a force along a translation, a torque about a
     * rotation in N mm): the pose solve's line search weighs the pose
     * equations by the compliance of these loads (doc/gait.md).
     */
    std::vector<unsigned int>   forces;
    std::function<void(Pose &)> complete = [](Pose &) {};
  };

  /**
   * A gait protocol (DESIGN.md section 10): how a knee simulator drives
   * the two bodies through a cycle, e.g. ISO 14243-1 force control. It
   * owns everything that differs between protocols, so that the gait
   * driver (Problems::GaitCycle) never asks which protocol it runs:
   * - the tibia's support: constraints (a rigid tray), springs and the
   *   tractions every step's loads are combinations of (load_basis());
   * - per step, from its waveform: the inputs (input()), the relative
   *   rigid motion of the femur in the tibia's frame (motion()) and the
   *   coefficients of the load basis (load_coefficients()), both for a
   *   pose;
   * - the linear functionals of the displacement its pose solve reads,
   *   registered by name (observations());
   * - the pose of a step: its unknowns and the equations that hold at the
   *   step's equilibrium (pose_equations()), which the driver solves by
   *   Newton's method (Problems::GaitCycle::solve_pose()); the pose is
   *   otherwise opaque to the driver (warm starts and checkpoints keep it
   *   as it is);
   * - its part of the step report (report(), input_text(), pose_text(),
   *   the columns of steps.csv).
   * A new protocol is one class behind this interface that registers
   * itself (a ProtocolPlugin, Protocols::add() in its .cc file): nothing
   * else names the protocols.
   */
  class Protocol
  {
  public:
    virtual ~Protocol() = default;

    /** The `Gait/Control` name of the protocol ("force"). */
    virtual std::string
    name() const = 0;

    /** What the protocol is, for the screen ("ISO 14243-1 force control"). */
    virtual std::string
    description() const = 0;

    /**
     * What the protocol measured and chose when it was made (e.g. the
     * tibia's inferior surface), one line for the screen.
     */
    virtual std::string
    setup_text() const = 0;

    /**
     * Add the constraints of the tibia's support to @p constraints (e.g.
     * the rigid tray) and say what was done on @p pcout.
     */
    virtual void
    add_constraints(const dealii::DoFHandler<3>       &dof_handler,
                    dealii::AffineConstraints<double> &constraints,
                    const dealii::ConditionalOStream  &pcout) const = 0;

    /** The waveform the protocol's inputs come from. */
    virtual const Waveform &
    waveform() const = 0;

    /** The springs of every step (they go into the stiffness matrix). */
    virtual Elasticity::BoundaryLoads
    springs() const = 0;

    /** The tractions of which every step's loads are combinations. */
    virtual std::vector<Elasticity::BoundaryLoads>
    load_basis() const = 0;

    /**
     * The linear functionals of the displacement that the pose solve
     * needs, by name: tractions whose work is the functional.
     */
    virtual std::vector<std::pair<std::string, Elasticity::BoundaryLoads>>
    observations() const = 0;

    /** The inputs of the step at @p percent of the cycle. */
    virtual StepInput
    input(const double percent) const = 0;

    /**
     * The pose a step starts from without a warm start: at rest, with the
     * tibia lifted by @p lift (mm, along +z) towards the femur.
     */
    virtual Pose
    rest_pose(const StepInput &input, const double lift) const = 0;

    /** The femur's rigid motion in the tibia's frame in @p pose. */
    virtual RelativeMotion
    motion(const StepInput &input, const Pose &pose) const = 0;

    /** The coefficients of load_basis() in @p pose. */
    virtual std::vector<double>
    load_coefficients(const StepInput &input, const Pose &pose) const = 0;

    /**
     * The pose unknowns and their equations (PoseEquations): what the
     * gait driver's pose Newton solves in each step (doc/gait.md).
     */
    virtual PoseEquations
    pose_equations() const = 0;

    /**
     * The protocol's numbers of a solved step for @p report: report.pose
     * and report.pose_values (pose_columns()), from the pose and the
     * observations of its last contact solve.
     */
    virtual void
    report(const Pose         &pose,
           const Observations &last,
           StepReport         &report) const = 0;

    /**
     * The step's equilibrium as the protocol can check it from @p report,
     * in units of what its tolerances allow: at most 1 for a step that is
     * in equilibrium (e.g. under force control, the axial force carried by
     * the contact).
     */
    virtual double
    load_balance(const StepReport &report) const = 0;

    /**
     * The protocol's own results of a computed cycle from its steps'
     * @p reports, named as in summary.json (doc/output.md; e.g. the range of
     * the tibia's AP position under force control): the run's result
     * (Wear::RunResult) carries them.
     */
    virtual std::vector<std::pair<std::string, double>>
    cycle_results(const std::vector<StepReport> &reports) const = 0;

    /** What load_balance() checks, for the screen ("axial force"). */
    virtual std::string
    load_balance_text() const = 0;

    /** Names (with units) of StepInput::values, e.g. for steps.csv. */
    virtual std::vector<std::string>
    input_columns() const = 0;

    /** Names (with units) of StepReport::pose_values, for steps.csv. */
    virtual std::vector<std::string>
    pose_columns() const = 0;

    /** The inputs in a step's screen line ("flexion 12.0 deg, ..."). */
    virtual std::string
    input_text(const StepReport &report) const = 0;

    /** The pose in a step's screen line ("tibia y 0.30 z 0.06 mm"). */
    virtual std::string
    pose_text(const StepReport &report) const = 0;
  };

  /**
   * A protocol's own results, declared by the protocol in its own file
   * (ResultSchema): its inputs (its waveform's channels, steps.csv's
   * columns after `percent`), its pose (StepReport::pose_values, the
   * columns after `converged`) and its cycle results (cycle_results(),
   * summary.json; also per activity of a mix, `activity_NAME_...`). The
   * names of input_columns(), pose_columns() and cycle_results() are
   * these.
   */
  struct ProtocolResults
  {
    std::vector<ResultField> inputs, pose, cycle;
  };

  /** Declare @p results of the protocol @p name; true (for a static
   *  initialiser). */
  bool
  declare_results(const std::string &name, const ProtocolResults &results);

  /** The names of @p fields. */
  std::vector<std::string>
  names(const std::vector<ResultField> &fields);

  /**
   * The inputs of the step at @p percent of the cycle (any real, taken
   * modulo 100) from @p waveform: what Protocol::input() returns for a
   * protocol whose inputs are its waveform's channels.
   */
  StepInput
  waveform_input(const Waveform &waveform, const double percent);

  struct InferiorSurface;

  /**
   * A gait protocol as a plugin (Registry): the name that selects it in
   * `Gait/Control`, the phrase that documents it there, its own entries
   * (`Gait/<subsection>`, e.g. `Gait/Force control`; ModelEntries), and
   * how it is made from the gait parameters, its own entries as parsed (a
   * std::any of its entries' type) and the tibia's inferior surface (where
   * its loads act). Each protocol's .cc file registers its own
   * (Protocols::add()) and writes its name once.
   */
  struct ProtocolPlugin
  {
    static constexpr const char *kind = "gait protocol", *section = "Gait",
                                *selector = "Control";
    std::string  name;
    std::string  documentation;
    ModelEntries entries;
    std::function<std::unique_ptr<Protocol>(const Parameters::Gait &,
                                            const std::any &,
                                            const InferiorSurface &)>
      create;
  };

  /** The registered gait protocols. */
  using Protocols = Registry<ProtocolPlugin>;

  /**
   * The protocol of `Gait/Control` with the waveform of `Gait/Waveform
   * file`, for the bodies of @p triangulation (e.g. the tibia's inferior
   * surface, where its loads act).
   */
  std::unique_ptr<Protocol>
  create_protocol(const Parameters::Gait         &parameters,
                  const dealii::Triangulation<3> &triangulation);
} // namespace TKR::Gait

#endif
