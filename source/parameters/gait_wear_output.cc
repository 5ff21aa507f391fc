// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.
//
// The parameters of the wear run: subsections Gait, Wear and Output.

#include <tkr/base/exceptions.h>
#include <tkr/parameters/parameters.h>

#include "model_kinds.h"
#include "vector_entry.h"

namespace TKR::Parameters
{
  using namespace dealii;
  using internal::get_vector;
  using internal::vector_pattern;

  namespace
  {
    /** The protocol, its waveform and the knee's frame. */
    void
    declare_gait_cycle(ParameterHandler &prm)
    {
      internal::gait_protocols().check_registered();
      prm.declare_entry(
        "Control",
        "force",
        Patterns::Selection(internal::gait_protocols().names()),
        internal::gait_protocols().documentation(
          "The gait protocol, how the simulator drives the knee (its own "
          "entries in its subsection below): ") +
          " The waveform file must have the protocol's columns "
          "(doc/gait.md).");
      prm.declare_entry(
        "Waveform file",
        "data/iso14243-1.csv",
        Patterns::FileName(),
        "CSV table of the gait cycle, read by the column names of its "
        "header line: percent_cycle and the protocol's channels (force: "
        "flexion_deg, axial_force_N, ap_force_N, ie_torque_Nm; "
        "displacement: flexion_deg, axial_force_N, ap_displacement_mm, "
        "ie_rotation_deg, e.g. data/iso14243-3.csv); other "
        "columns are ignored. The rows must cover the whole cycle. A "
        "relative path is taken from the directory of the parameter file "
        "that sets it, then from the working directory.");
      prm.declare_entry("Steps per cycle",
                        "100",
                        Patterns::Integer(1),
                        "Number of quasi-static contact solves per cycle.");
      prm.declare_entry("Flexion axis point",
                        "0, -2, 53.001",
                        vector_pattern(),
                        "A point (mm) on the flexion axis, which is parallel "
                        "to x: the centre of the distal arc of the femoral "
                        "component's J-curve in the sagittal plane. The "
                        "default is that of the default mesh (TKR A, "
                        "meshes/tkr/tkr-a-report.txt); your own CAD needs "
                        "its own.");
      prm.declare_entry("Medial side",
                        "+x",
                        Patterns::Selection("+x|-x"),
                        "Which direction of x is medial (left and right "
                        "knees differ).");
    }

    /** The axial load's line of action. */
    void
    declare_gait_loads(ParameterHandler &prm)
    {
      prm.declare_entry("Axial load offset",
                        "0.07",
                        Patterns::Double(-0.5, 0.5),
                        "Medial offset of the axial load line, as a fraction "
                        "of the medial-lateral width of the insert.");
    }

    /** The tibia's pose solve, its tray and the parallel steps. */
    void
    declare_gait_pose(ParameterHandler &prm)
    {
      prm.declare_entry("Axial stabilisation spring",
                        "100",
                        Patterns::Double(0),
                        "Total stiffness in N/mm of an axial spring spread "
                        "over the tibial inferior surface that acts on the "
                        "tibia's displacement relative to its current pose "
                        "(rigid translation) only. It keeps every linear "
                        "system regular while the active set is wrong and "
                        "vanishes as the pose iteration converges (its force "
                        "is then below this times the Pose tolerance).");
      prm.declare_entry(
        "Largest initial overlap",
        "0.5",
        Patterns::Double(0),
        "Where the meshed bodies overlap at 0 % of the cycle (the facets of "
        "a CAD export or of split cells), the first step starts with the "
        "tray lowered by the overlap (reported): its axial position is an "
        "unknown of both protocols. An overlap above this (mm) is refused: "
        "it is more than facets explain (a CAD export's chords stray up to "
        "0.44 mm from the surface at a 0.25 mm chordal tolerance, "
        "doc/geometry.md), so a body is misplaced, in other units, or the "
        "flexion axis is wrong.");
      prm.declare_entry("Pose tolerance",
                        "0.001",
                        Patterns::Double(0),
                        "The tibia's pose (rigid translation) is updated "
                        "until the mean displacement of its inferior "
                        "surface is below this (mm).");
      prm.declare_entry(
        "Pose derivatives",
        "analytic",
        Patterns::Selection("analytic|finite differences"),
        "How the pose Newton of a step (doc/gait.md) differentiates the "
        "contact solution by the tibia's pose (force control: its "
        "translation and IE rotation; displacement control: its ML position "
        "and height). analytic: from the condensed active set's compliance "
        "columns, the pose and the contact pressures solved together (Contact "
        "solver/Solver = condensed active set or auto); finite differences: "
        "one more contact solve per pose unknown, Newton on the pose alone "
        "(what the AMG-CG active set and Ipopt use whatever this says; with "
        "the condensed active set a check of the analytic derivatives).");
      prm.declare_entry("Tibial tray",
                        "rigid",
                        Patterns::Selection("rigid|free"),
                        "rigid: the inferior surface moves like the "
                        "simulator's tray: it translates, rotates about z "
                        "(IE) and ab/adducts, but does not tilt in the "
                        "sagittal plane (needs a nearly flat inferior "
                        "surface, see Tray flatness tolerance). free: no "
                        "constraint (the insert may tilt under the AP "
                        "force).");
      prm.declare_entry(
        "Tray flatness tolerance",
        "1e-3",
        Patterns::Double(0),
        "With Tibial tray = rigid: how far the tibia_inferior nodes may lie "
        "from their least-squares plane, as a fraction of the insert's "
        "medial-lateral width (1e-3: 0.07 mm on a 70 mm insert; real "
        "inserts' backs are not exactly planar). Each node is tied to the "
        "tray at its own position; a surface farther from flat is refused.");
      prm.declare_entry("Step groups",
                        "0",
                        Patterns::Integer(0),
                        "The steps of a cycle are independent: the MPI ranks "
                        "are split into this many groups, each solving every "
                        "n-th step on its own copy of the mesh (0: one group "
                        "per rank). The result does not depend on it.");
    }

    /** The springs and signs beyond ISO 14243-1's, the mounting offset and
     *  the channels' scales. */
    void
    declare_gait_adjustments(ParameterHandler &prm)
    {
      prm.declare_entry("ML spring stiffness",
                        "0",
                        Patterns::Double(0),
                        "Medial-lateral spring, N/mm. Not part of ISO "
                        "14243-1 (the tibia is free medial-laterally and "
                        "held by the conformity of the insert); a small "
                        "value stabilises very flat inserts.");
      prm.declare_entry(
        "Femur AP offset",
        "0",
        Patterns::Double(),
        "Where the femur sits on the insert when the AP restraint is "
        "relaxed (mm, positive = femur anterior of the insert's neutral "
        "position; a mounting offset). Control = force: the AP restraint's "
        "neutral position moves the tibia by minus this; Control = "
        "displacement: the prescribed AP displacement is shifted by minus "
        "this. 0: the positions of the mesh.");
      prm.declare_entry(
        "Channel scales",
        "",
        Patterns::Map(Patterns::Anything(),
                      Patterns::Double(),
                      0,
                      20,
                      ",",
                      ":"),
        "Factors on waveform channels, by column name, e.g. "
        "\"axial_force_N: 1.1, ap_force_N: 0.9\" (a column the protocol "
        "does not read is refused). Empty: the waveform as tabulated.");
      prm.declare_entry(
        "Activities",
        "",
        Patterns::Anything(),
        "An activity mix (Problem = wear, doc/gait.md): NAME: SHARE[: "
        "FILE.prm] per activity, separated by ';', e.g. \"walking: 0.85; "
        "stair ascent: 0.1: stair.prm; deep knee bend: 0.05: bend.prm\". "
        "Each block solves one cycle of every activity on the same worn "
        "geometry and wears the insert by their share-weighted sum. An "
        "activity's FILE sets only entries of subsection Gait (its waveform, "
        "protocol, steps, ...), read on top of this file's; without FILE the "
        "activity is this file's gait. The shares must add up to 1. Empty: "
        "no mix, one activity.");
    }
  } // namespace

  void
  Gait::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Gait");
    {
      declare_gait_cycle(prm);
      declare_gait_loads(prm);
      declare_gait_pose(prm);
      declare_gait_adjustments(prm);
      internal::gait_protocols().declare_parameters(prm);
    }
    prm.leave_subsection();
  }

  void
  Gait::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Gait");
    {
      control                 = prm.get("Control");
      waveform_file           = prm.get("Waveform file");
      steps_per_cycle         = prm.get_integer("Steps per cycle");
      flexion_axis_point      = Point<3>(get_vector(prm, "Flexion axis point"));
      medial_direction        = (prm.get("Medial side") == "+x" ? 1 : -1);
      axial_load_offset       = prm.get_double("Axial load offset");
      ml_spring_stiffness     = prm.get_double("ML spring stiffness");
      step_groups             = prm.get_integer("Step groups");
      rigid_tray              = (prm.get("Tibial tray") == "rigid");
      tray_flatness_tolerance = prm.get_double("Tray flatness tolerance");
      axial_stabilisation_spring = prm.get_double("Axial stabilisation spring");
      pose_tolerance             = prm.get_double("Pose tolerance");
      largest_initial_overlap    = prm.get_double("Largest initial overlap");
      analytic_pose_derivatives  = (prm.get("Pose derivatives") == "analytic");
      femur_ap_offset            = prm.get_double("Femur AP offset");
      protocols = internal::gait_protocols().parse_parameters(prm);
      channel_scales.clear();
      for (const std::string &pair :
           Utilities::split_string_list(prm.get("Channel scales"), ','))
        {
          const auto parts = Utilities::split_string_list(pair, ':');
          channel_scales[parts.at(0)] =
            Utilities::string_to_double(parts.at(1));
        }
      activities = prm.get("Activities");
    }
    prm.leave_subsection();
  }

  namespace
  {
    /** The wear law, its constants and the run-in. */
    void
    declare_wear_law(ParameterHandler &prm)
    {
      internal::wear_laws().check_registered();
      prm.declare_entry("Wear law",
                        "archard",
                        Patterns::Selection(internal::wear_laws().names()),
                        internal::wear_laws().documentation(
                          "How the sliding of a gait cycle wears the insert "
                          "(doc/wear.md); each law's constants are in its own "
                          "subsection below: "));
      prm.declare_entry(
        "Run-in file",
        "",
        Patterns::FileName(),
        "CSV file (columns cycles, factor) of a factor on the wear rate over "
        "the cycle count, piecewise linear and constant beyond the last row, "
        "integrated exactly over each extrapolation block (doc/wear.md, "
        "Run-in); empty: no run-in (factor 1). Any wear law. A relative path "
        "is taken from the directory of the parameter file that sets it, "
        "then from the working directory.");
    }
  } // namespace

  void
  Wear::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Wear");
    {
      declare_wear_law(prm);
      internal::wear_laws().declare_parameters(prm);
      prm.declare_entry("Cycles",
                        "5e6",
                        Patterns::Double(0),
                        "Number of gait cycles to simulate.");
      prm.declare_entry(
        "Cross-shear definition",
        "work tensor",
        Patterns::Selection("work tensor|abs sin"),
        "How each node's cross-shear ratio is computed (doc/wear.md, "
        "Cross-shear): work tensor, the work across the principal molecular "
        "orientation (PMO) by the sin^2 of each slip's angle to it, the PMO "
        "the work tensor's principal direction (ratio 0..0.5); abs sin, by "
        "the |sin|, the PMO the direction of most work by |cos|, found "
        "numerically (ratio 0..0.7071). A cross-shear table names its "
        "definition by its column (cross_shear, cross_shear_abs_sin) and is "
        "refused with the other.");
      prm.declare_entry("Cycles per extrapolation step",
                        "5e4",
                        Patterns::Double(1),
                        "n_Delta: the wear of one computed cycle is "
                        "multiplied by this number before the worn surface "
                        "is moved.");
      prm.declare_entry("Wear area threshold",
                        "1e-4",
                        Patterns::Double(0),
                        "Wear depth in mm above which a point of the tibial "
                        "contact surface counts towards the wear area.");
      prm.declare_entry(
        "Stiffness update interval",
        "10",
        Patterns::Integer(0),
        "Re-assemble and re-factorise the stiffness on the worn geometry "
        "every this many extrapolation blocks (1: every block; 0: never, the "
        "stiffness of the unworn insert throughout). The contact geometry "
        "(mortar coupling) is always the worn one. Larger values are faster; "
        "doc/wear.md lists what they cost in accuracy.");
      prm.declare_entry("Warm start",
                        "true",
                        Patterns::Bool(),
                        "Start every gait step from the same step of the "
                        "previous block (tibia pose, restraint forces, active "
                        "set) instead of from rest; from the third block on, "
                        "the pose extrapolated linearly from the step's "
                        "poses of the two blocks before (doc/wear.md).");
      prm.declare_entry(
        "Distortion limit",
        "0.2",
        Patterns::Double(0, 1),
        "A block is refused when the worn geometry would shrink the smallest "
        "Jacobian determinant of a tibia cell below this fraction of its "
        "value in the unworn mesh (0 < limit < 1; a cell at 0 is inverted).");
      prm.declare_entry("Halve step on distortion",
                        "false",
                        Patterns::Bool(),
                        "When a block would distort a cell beyond the "
                        "Distortion limit: halve the Cycles per extrapolation "
                        "step and retry the block (true), or stop with an "
                        "error (false).");
    }
    prm.leave_subsection();
  }

  void
  Wear::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Wear");
    {
      law                    = prm.get("Wear law");
      run_in_file            = prm.get("Run-in file");
      cross_shear_definition = prm.get("Cross-shear definition");
      laws                   = internal::wear_laws().parse_parameters(prm);
      internal::wear_laws().check(law, laws);
      cycles = prm.get_double("Cycles");
      cycles_per_extrapolation_step =
        prm.get_double("Cycles per extrapolation step");
      wear_area_threshold       = prm.get_double("Wear area threshold");
      stiffness_update_interval = prm.get_integer("Stiffness update interval");
      warm_start                = prm.get_bool("Warm start");
      distortion_limit          = prm.get_double("Distortion limit");
      halve_step_on_distortion  = prm.get_bool("Halve step on distortion");
      AssertThrow(distortion_limit > 0 && distortion_limit < 1,
                  ExcInputError("Wear/Distortion limit must lie strictly "
                                "between 0 and 1."));
    }
    prm.leave_subsection();
  }

  void
  Output::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Output");
    {
      prm.declare_entry("Directory",
                        "output",
                        Patterns::DirectoryName(),
                        "Where summary.json, VTU/PVD files and checkpoints "
                        "go. Created if missing.");
      prm.declare_entry("VTU interval",
                        "1",
                        Patterns::Integer(0),
                        "Write VTU output every this many steps (0: never): "
                        "a wear run's steps of the last computed cycle, the "
                        "solution of Problem = contact or elasticity.");
      prm.declare_entry("Worn VTU interval",
                        "1",
                        Patterns::Integer(0),
                        "A wear run: write the worn tibia (worn.pvd: depth, "
                        "wear rate, slip, pressure per vertex) after every "
                        "this many extrapolation blocks and after the last "
                        "(0: never). Independent of VTU interval.");
      prm.declare_entry("Checkpoint interval",
                        "10",
                        Patterns::Integer(0),
                        "Write a checkpoint (checkpoint.h5 in the output "
                        "directory) every this many extrapolation blocks "
                        "(0: never); tkr-wear --resume FILE.prm continues "
                        "from the newest one.");
      prm.declare_entry("Measured mass loss file",
                        "",
                        Patterns::Anything(),
                        "Optional CSV file (columns cycles,mass_mg[,specimen]; "
                        "see data/measured/README.md) whose points are drawn "
                        "over the computed mass loss in mass_loss.png. A "
                        "relative path is taken from the directory of the "
                        "parameter file that sets it, then from the "
                        "working directory.");
      prm.declare_entry("Plots",
                        "true",
                        Patterns::Bool(),
                        "At the end of a wear run, draw mass_loss.png and "
                        "wear_map.png with scripts/plot-wear (needs python3 "
                        "with matplotlib).");
      prm.declare_entry("Testing",
                        "false",
                        Patterns::Bool(),
                        "Leave timings and wall-clock numbers out of the "
                        "screen output, for regression tests.");
    }
    prm.leave_subsection();
  }

  void
  Output::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Output");
    {
      directory               = prm.get("Directory");
      vtu_interval            = prm.get_integer("VTU interval");
      worn_vtu_interval       = prm.get_integer("Worn VTU interval");
      checkpoint_interval     = prm.get_integer("Checkpoint interval");
      measured_mass_loss_file = prm.get("Measured mass loss file");
      plots                   = prm.get_bool("Plots");
      testing                 = prm.get_bool("Testing");
    }
    prm.leave_subsection();
  }

  namespace
  {
    /** @p list of the wear laws' kind, then of the protocols'. */
    template <typename List>
    auto
    of_every_model(const List &list)
    {
      auto all = list(internal::wear_laws());
      for (auto &item : list(internal::gait_protocols()))
        all.push_back(std::move(item));
      return all;
    }
  } // namespace

  std::vector<std::pair<std::string, std::string>>
  moved_entries()
  {
    return of_every_model(
      [](const ModelKind &kind) { return kind.moved_entries(); });
  }

  std::vector<std::string>
  model_file_entries()
  {
    return of_every_model(
      [](const ModelKind &kind) { return kind.file_entries(); });
  }

  std::vector<std::string>
  unselected_model_subsections(const AllParameters &parameters)
  {
    std::vector<std::string> unselected;
    for (const auto &[name, path] : internal::wear_laws().subsections())
      if (name != parameters.wear.law)
        unselected.push_back(path);
    for (const auto &[name, path] : internal::gait_protocols().subsections())
      if (name != parameters.gait.control)
        unselected.push_back(path);
    return unselected;
  }
} // namespace TKR::Parameters
