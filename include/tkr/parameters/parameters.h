// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_parameters_parameters_h
#define tkr_parameters_parameters_h

#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>

#include <tkr/base/registry.h>

#include <map>
#include <string>
#include <utility>
#include <vector>

/**
 * The run-time parameters of tkr-wear, one struct per subsection of the
 * parameter file (step-44 style). Every struct has a static
 * `declare_parameters()` that declares its entries (with pattern and a
 * documentation string that states the unit) and a `parse_parameters()` that
 * reads them back. AllParameters joins them. Units everywhere: mm, N, MPa,
 * s, mg.
 */
namespace TKR::Parameters
{
  /**
   * `subsection Mesh`: the gmsh file with both bodies, the names of its
   * physical groups and the finite element degree.
   */
  struct Mesh
  {
    /** The gmsh `.msh` file (relative to the working directory). */
    std::string file;
    /** Polynomial degree of the FE_Q displacement elements. */
    unsigned int fe_degree;
    /** Physical-group names (DESIGN.md section 3). */
    std::string femur_name, tibia_name;
    std::string femur_contact_name, femur_fixation_name;
    std::string tibia_contact_name, tibia_inferior_name;
    /**
     * Warn when a cell with a face on tibia_contact or femur_contact has a
     * smaller scaled Jacobian than this.
     */
    double contact_cell_quality;

    static void
    declare_parameters(dealii::ParameterHandler &prm);
    void
    parse_parameters(dealii::ParameterHandler &prm);

    /** Q1 on @p file with the group names of DESIGN.md section 3. */
    static Mesh
    with_default_groups(const std::string &file);
  };

  /** One linear-elastic, isotropic material. */
  struct Material
  {
    /** Young's modulus in MPa. */
    double youngs_modulus;
    /** Poisson's ratio (dimensionless, in (-1, 0.5)). */
    double poissons_ratio;
    /** Density in mg/mm^3. */
    double density;

    /** Declare the entries with the given defaults. */
    static void
    declare_parameters(dealii::ParameterHandler &prm,
                       const double              youngs_modulus,
                       const double              poissons_ratio,
                       const double              density);
    void
    parse_parameters(dealii::ParameterHandler &prm);

    /** First Lame constant lambda in MPa. */
    double
    lambda() const;
    /** Shear modulus mu in MPa. */
    double
    mu() const;
  };

  /** `subsection Materials`: `subsection Femur` and `subsection Tibia`. */
  struct Materials
  {
    Material femur, tibia;

    static void
    declare_parameters(dealii::ParameterHandler &prm);
    void
    parse_parameters(dealii::ParameterHandler &prm);
  };

  /**
   * `subsection Elasticity`: the two-body demonstration problem
   * (`Problem = elasticity`) in which the bodies do not interact. Each body
   * is clamped on its fixation (femur) or inferior (tibia) face and loaded
   * by a uniform traction on its contact face.
   */
  struct Elasticity
  {
    /** Traction on `femur_contact`, in MPa (force per area, x,y,z). */
    dealii::Tensor<1, 3> femur_contact_traction;
    /** Traction on `tibia_contact`, in MPa. */
    dealii::Tensor<1, 3> tibia_contact_traction;

    static void
    declare_parameters(dealii::ParameterHandler &prm);
    void
    parse_parameters(dealii::ParameterHandler &prm);
  };

  /** How the tibia's inferior face is supported in a static contact solve. */
  enum class TibiaSupport
  {
    clamped,
    loaded
  };

  /** `subsection Static contact` (`Problem = contact`). */
  struct StaticContact
  {
    /** Displacement of `femur_fixation` in mm. */
    dealii::Tensor<1, 3> femur_displacement;
    TibiaSupport         tibia_inferior;
    /** Axial force on `tibia_inferior` (N, along +z) if loaded. */
    double axial_force;
    /**
     * Total stiffness (N/mm) of the tangential (x and y) springs spread
     * over `tibia_inferior` when loaded; they hold the tibia's in-plane
     * rigid motions, which frictionless contact cannot.
     */
    double tangential_spring;
    /**
     * Free faces whose normal is parallel to this axis (0, 1, 2) get the
     * roller condition u.n = 0 (e.g. x for a plane-strain slab); -1: none.
     */
    int roller_axis;

    static void
    declare_parameters(dealii::ParameterHandler &prm);
    void
    parse_parameters(dealii::ParameterHandler &prm);
  };

  /** `subsection Gait`: the knee simulator's gait cycle. */
  struct Gait
  {
    /**
     * The protocol that drives the knee: the name of a registered one
     * (Gait::Protocols; each protocol registers itself,
     * Gait::ProtocolPlugin).
     */
    std::string control;
    /** CSV file of the protocol's channels over the cycle, by column name. */
    std::string  waveform_file;
    unsigned int steps_per_cycle;
    /** A point on the flexion axis (mm); the axis is parallel to x. */
    dealii::Point<3> flexion_axis_point;
    /** +1 if medial is +x, -1 if medial is -x (left and right knees). */
    int medial_direction;
    /** Medial offset of the axial load line as a fraction of the width. */
    double axial_load_offset;
    /** The ML spring in N/mm (not ISO 14243-1's; 0: none). */
    double ml_spring_stiffness;
    /**
     * The femur's AP position on the insert (mm, + anterior) when the AP
     * restraint is relaxed: the restraint's neutral tibia position is at
     * minus this (force control), the prescribed AP displacement shifted by
     * minus this (displacement control).
     */
    double femur_ap_offset = 0.;
    /** Factors on waveform channels by column name (empty: none). */
    std::map<std::string, double> channel_scales;
    /**
     * `Activities`: the activity mix as written (paths resolved; empty:
     * one activity, this subsection's), read into AllParameters::mix.
     */
    std::string activities;
    /**
     * Axial spring (N/mm) on the tibia's displacement relative to its pose:
     * numerical stabilisation that vanishes as the pose iteration converges.
     */
    double axial_stabilisation_spring;
    /** Pose updates stop when the mean inferior displacement is below this
     * (mm). */
    double pose_tolerance;
    /** The largest overlap of the bodies at 0 % that the first step takes
     * up by lowering the tray (mm); more is refused. */
    double largest_initial_overlap;
    /**
     * The pose Newton's derivatives of the contact solution: analytic
     * (true, `Pose derivatives = analytic`: pose and contact solved
     * together; needs the condensed active set) or by finite differences.
     */
    bool analytic_pose_derivatives;
    /** The insert sits in a rigid tray that cannot tilt sagittally. */
    bool rigid_tray;
    /**
     * Largest distance of a tibia_inferior node from the surface's
     * least-squares plane, as a fraction of the insert's width.
     */
    double tray_flatness_tolerance;
    /** MPI groups that share the steps of a cycle (0: one per rank). */
    unsigned int step_groups;
    /**
     * Each protocol's own entries (`Gait/<its subsection>`, e.g. the
     * restraints of `Gait/Force control`), parsed by the protocol
     * (Gait::ProtocolPlugin::entries), by the protocol's name.
     */
    ModelParameters protocols;

    static void
    declare_parameters(dealii::ParameterHandler &prm);
    void
    parse_parameters(dealii::ParameterHandler &prm);
  };

  /**
   * One activity of a mix (`Gait/Activities`, doc/gait.md): a gait with
   * its share of the cycles.
   */
  struct Activity
  {
    /** The name as written ("stair ascent") and as a column prefix
     *  ("stair_ascent"). */
    std::string name, slug;
    /** The share of the cycles (the shares of a mix add up to 1). */
    double share = 1;
    /** The parameter file of its `Gait` subsection ("": the main file's). */
    std::string file;
    /** The main file's `Gait` subsection with the activity file's on top. */
    Gait gait;

    /**
     * The `NAME: SHARE[: FILE.prm]` list @p activities with each FILE
     * taken from @p directory (internal::resolve_path()).
     */
    static std::string
    resolve_files(const std::string &activities, const std::string &directory);
  };

  /** `subsection Wear`: the wear law and its extrapolation. */
  struct Wear
  {
    /**
     * The wear law: the name of a registered one (Wear::WearLaws; each
     * law registers itself, Wear::WearLawPlugin).
     */
    std::string law;
    /**
     * Each law's own entries (`Wear/<its subsection>`, e.g. the wear
     * coefficient of `Wear/Archard`), parsed by the law
     * (Wear::WearLawPlugin::entries), by the law's name.
     */
    ModelParameters laws;
    /** The CSV table of the run-in factor over cycles (empty: none). */
    std::string run_in_file;
    /** `work tensor` or `abs sin` (Wear::CrossShearDefinition). */
    std::string cross_shear_definition;
    /** Total number of gait cycles. */
    double cycles;
    /** Cycles per extrapolation step (n_Delta). */
    double cycles_per_extrapolation_step;
    /** Wear depth in mm above which a surface point counts as worn. */
    double wear_area_threshold;
    /** Re-assemble the stiffness every this many blocks (0: never). */
    unsigned int stiffness_update_interval;
    /** Start each step from the same step of the previous block. */
    bool warm_start;
    /** Smallest allowed ratio of a tibia cell's Jacobian (worn/unworn). */
    double distortion_limit;
    /** Halve n_Delta and retry a block that distorts a cell too much. */
    bool halve_step_on_distortion;

    static void
    declare_parameters(dealii::ParameterHandler &prm);
    void
    parse_parameters(dealii::ParameterHandler &prm);
  };

  /** The algorithm for the contact problem. */
  enum class ContactAlgorithm
  {
    /** condensed_active_set for Problem = wear, active_set otherwise. */
    automatic,
    active_set,
    condensed_active_set,
    ipopt
  };

  /** `subsection Contact solver`. */
  struct ContactSolver
  {
    ContactAlgorithm algorithm;
    /** Relative residual tolerance of the Newton iteration. */
    double       tolerance;
    unsigned int max_iterations;
    /** Master faces farther than this (mm) from a slave face are ignored. */
    double search_distance;
    /** Width of the coupling window of the gait's solves (mm, 0: none). */
    double coupling_window;
    /** Nodes with an initial gap up to this (mm) start active. */
    double initial_contact_distance;
    /** A gap below minus this (mm) means the bodies overlap: refused. */
    double overlap_tolerance;

    static void
    declare_parameters(dealii::ParameterHandler &prm);
    void
    parse_parameters(dealii::ParameterHandler &prm);
  };

  /** `subsection Linear solver`: CG preconditioned by Trilinos ML AMG. */
  struct LinearSolver
  {
    /** Relative residual reduction of CG. */
    double       tolerance;
    unsigned int max_iterations;
    /** Use the six rigid-body modes as AMG near-null space. */
    bool rigid_body_modes;
    /** ML aggregation threshold and smoother sweeps (Chebyshev degree). */
    double       aggregation_threshold;
    unsigned int smoother_sweeps;
    /**
     * Relative residual of CG in the Newton steps of the AMG-CG active set
     * that only decide the next active set (inexact Newton); the step that
     * confirms the set is solved to `tolerance`. (Last, with the default
     * of the parameter file, so that brace initialisers of the other
     * members stay valid.)
     */
    double newton_step_tolerance = 1e-6;

    static void
    declare_parameters(dealii::ParameterHandler &prm);
    void
    parse_parameters(dealii::ParameterHandler &prm);
  };

  /** `subsection Output`. */
  struct Output
  {
    std::string directory;
    /** Write VTU every this many steps (0: never). */
    unsigned int vtu_interval;
    /** A wear run: write the worn tibia every this many blocks and after
     *  the last (0: never). */
    unsigned int worn_vtu_interval;
    /** Write a checkpoint every this many extrapolation steps (0: never). */
    unsigned int checkpoint_interval;
    /** Measured mass loss (CSV) drawn into mass_loss.png ("" if none). */
    std::string measured_mass_loss_file;
    /** Draw mass_loss.png and wear_map.png at the end of a wear run. */
    bool plots;
    /** Leave out timings and wall-clock numbers (for regression tests). */
    bool testing;

    static void
    declare_parameters(dealii::ParameterHandler &prm);
    void
    parse_parameters(dealii::ParameterHandler &prm);
  };

  /** Analytic solutions a contact run can be compared with. */
  enum class AnalyticSolution
  {
    none,
    hertz_sphere,
    hertz_cylinder
  };

  /** `subsection Verification`: compare a contact run with theory. */
  struct Verification
  {
    AnalyticSolution analytic_solution;
    /** Radius of the sphere or cylinder (mm). */
    double radius;
    /** Length of the cylinder (mm), for the force per length. */
    double cylinder_length;
    /**
     * The band (relative) within which the fitted contact radius and peak
     * pressure must lie around Hertz's values for the comparison to pass.
     */
    double hertz_tolerance;
    /** Solve again with Ipopt and report the differences. */
    bool cross_check_with_ipopt;

    static void
    declare_parameters(dealii::ParameterHandler &prm);
    void
    parse_parameters(dealii::ParameterHandler &prm);
  };

  /**
   * `subsection Study` (`Problem = study`): many variants of one wear run
   * (doc/studies.md). The cases are the product of the grid's factors,
   * the rows of the cases file and the samples (each 1 if not given).
   */
  struct Study
  {
    /** The parameter file of the run that the cases vary (resolved). */
    std::string base_file;
    /**
     * Full-factorial factors, `PATH = v1, v2, ...` separated by `;` (PATH
     * a "Subsection/Entry" of the base file, with `[i]` for a component of
     * a vector entry; `+=` and `*=` add to or multiply the base value).
     */
    std::string grid;
    /** CSV file of cases, one column per entry path ("" if none). */
    std::string cases_file;
    /** `none`, `latin hypercube` or `monte carlo`. */
    std::string sampling;
    /** Number of samples (sampling only). */
    unsigned int samples;
    /** Seed of the random numbers (the same seed, the same samples). */
    unsigned int seed;
    /**
     * Per entry a distribution, `PATH = uniform(a, b)`, `normal(mean,
     * sd)` or `log-normal(mu, sigma)` (of ln X), separated by `;`; `+=`
     * and `*=` as in the grid.
     */
    std::string distributions;
    /** MPI ranks that run one case together. */
    unsigned int ranks_per_case;
    /**
     * A program that writes each case's mesh (resolved; "" for none), with
     * its fixed arguments; the case's `Generator/NAME` entries become
     * `--set NAME=VALUE` arguments (doc/studies.md).
     */
    std::string mesh_generator, mesh_generator_arguments;

    static void
    declare_parameters(dealii::ParameterHandler &prm);
    void
    parse_parameters(dealii::ParameterHandler &prm);
  };

  /**
   * `subsection Calibration` (`Problem = calibration`, doc/calibration.md):
   * fit entries of one or more wear runs to measured mass loss.
   */
  struct Calibration
  {
    /** One design: its wear run's parameter file and its measured data. */
    struct Design
    {
      std::string base_file, measured_file;
    };
    /** `BASE.prm: MEASURED.csv` separated by `;` (paths resolved). */
    std::vector<Design> designs;
    /** What is fitted: some of `Wear/Archard/Wear coefficient`, `Run-in
     *  factor`, `Run-in length` (in this order, as listed). */
    std::vector<std::string> fit;
    /** The run-in's start values (and fixed values if not fitted). */
    double run_in_factor, run_in_length;
    /** The confidence level of the intervals (0..1). */
    double confidence_level;
    /** Stop when the verification run's masses differ from the
     *  prediction by at most this fraction of the largest measured mass. */
    double tolerance;
    /** Wear runs per design at most. */
    unsigned int maximum_runs;

    /** @p designs (`BASE: MEASURED; ...`) with each path taken from
     *  @p directory as other file entries are (resolve_path()). */
    static std::string
    resolve_designs(const std::string &designs, const std::string &directory);

    static void
    declare_parameters(dealii::ParameterHandler &prm);
    void
    parse_parameters(dealii::ParameterHandler &prm);
  };

  /**
   * `subsection Optimisation` (`Problem = optimisation`,
   * doc/optimisation.md): the entries of a wear run that minimise (or
   * maximise) one of its results within bounds and constraints on others.
   */
  struct Optimisation
  {
    /** The parameter file of the wear run (resolved). */
    std::string base_file;
    /** `PATH = LOWER .. UPPER [log]` separated by `;`. */
    std::string variables;
    /** `minimise KEY` or `maximise KEY`. */
    std::string objective;
    /** `KEY <= VALUE` or `KEY >= VALUE` separated by `;`. */
    std::string constraints;
    /** `cobyla` or `bobyqa` (NLopt). */
    std::string method;
    /** Evaluations at most. */
    unsigned int maximum_evaluations;
    /** NLopt's xtol_rel on the variables in unit coordinates. */
    double tolerance;
    /** The first step, as a fraction of each variable's range. */
    double initial_step;
    /** As Study's (resolved; "" for none). */
    std::string mesh_generator, mesh_generator_arguments;
    /** `none` (wear runs) or `quadratic` (a known function, for tests). */
    std::string test_function;
    /** Latin hypercube points before the method, and their seed. */
    unsigned int initial_design, seed;
    /** The size of the rank groups of runs that go at once (0: all). */
    unsigned int ranks_per_evaluation;
    /** `NAME: WEIGHT: FILE` separated by `;` (files resolved). */
    std::string scenarios;
    /** `weighted sum` or `worst case`. */
    std::string combine_scenarios;
    /** The verification's generator arguments and entries. */
    std::string verification_generator_arguments, verification_entries;

    static void
    declare_parameters(dealii::ParameterHandler &prm);
    void
    parse_parameters(dealii::ParameterHandler &prm);
  };

  /** The problems the program solves (`set Problem = ...`). */
  enum class ProblemType
  {
    elasticity,
    contact,
    wear,
    study,
    calibration,
    optimisation
  };

  /** All parameters of a run. */
  struct AllParameters
  {
    ProblemType   problem;
    Mesh          mesh;
    Materials     materials;
    Elasticity    elasticity;
    StaticContact static_contact;
    Gait          gait;
    Wear          wear;
    ContactSolver contact_solver;
    LinearSolver  linear_solver;
    Output        output;
    Verification  verification;
    Study         study;
    Calibration   calibration;
    Optimisation  optimisation;
    /**
     * The activity mix of `Gait/Activities` (empty: none, the run's gait
     * is `gait`); read by read_parameters().
     */
    std::vector<Activity> mix;

    /**
     * The activities of a wear run: the mix, or without one the single
     * activity `gait` (name "", share 1).
     */
    std::vector<Activity>
    activities() const;

    /** The parameter file these values came from ("" for the defaults). */
    std::string parameter_file;

    /**
     * Every entry as read, "Subsection/Entry" -> value (paths resolved),
     * e.g. for a checkpoint's record of the run's parameters.
     */
    std::map<std::string, std::string> entries;

    /** "FILE:LINE" of each entry the parameter file sets, by path. */
    std::map<std::string, std::string> places;

    /**
     * What the reader has to say about the file: an entry set where it
     * was before it moved into a model's subsection (moved_entries()).
     */
    std::vector<std::string> notes;

    static void
    declare_parameters(dealii::ParameterHandler &prm);
    void
    parse_parameters(dealii::ParameterHandler &prm);
  };

  /**
   * Read a parameter file. Every error a user can make (missing file,
   * unknown subsection or entry, a value that does not match its pattern,
   * unbalanced `subsection`/`end`) is turned into an ExcInputError whose
   * message names the file, the line and the entry.
   */
  AllParameters
  read_parameters(const std::string &filename);

  /** Write the complete, documented default parameter file. */
  void
  print_default_parameters(std::ostream &out);

  /**
   * The entries that moved into a model's own subsection, as (old path,
   * new path), e.g. ("Wear/Wear coefficient", "Wear/Archard/Wear
   * coefficient"): a parameter file, a study's setting or a checkpoint
   * that names the old path means the new one(s).
   */
  std::vector<std::pair<std::string, std::string>>
  moved_entries();

  /** The paths of the models' entries that are input files. */
  std::vector<std::string>
  model_file_entries();

  /**
   * The subsections ("Wear/Area/") of the models that @p parameters do
   * not select (another wear law's, another protocol's): their entries
   * do not act on the run.
   */
  std::vector<std::string>
  unselected_model_subsections(const AllParameters &parameters);

  /** Name of a problem type as written in the parameter file. */
  std::string
  to_string(const ProblemType problem);
} // namespace TKR::Parameters

#endif
