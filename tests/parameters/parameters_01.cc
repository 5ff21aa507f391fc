// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.
//
// Every entry of the parameter file reaches its field of AllParameters:
// - a table names, for each of the entries, the field it sets and a valid
//   value other than the default; the table must list exactly the entries
//   that --print-parameters writes (a new entry without a row fails);
// - the default file written by print_default_parameters() reads back
//   with every field at its documented default;
// - a file that sets every entry to its other value reads back with every
//   field changed to it;
// - relative paths in an included file are taken from that file's
//   directory, and an error in an included file names that file and line;
// - an entry set where it was before it moved into a model's subsection
//   (Wear coefficient, the force control's restraints, the cross-shear
//   table of both laws that have one) is read at its new place, with a
//   note naming the line and the new path; a checkpoint that recorded it
//   at its old place resumes, and is refused naming the new place when
//   the value differs;
// - Lame constants follow from E and nu.

#include <tkr/base/exceptions.h>
#include <tkr/gait/displacement_control.h>
#include <tkr/gait/gait_loads.h>
#include <tkr/output/checkpoint.h>
#include <tkr/parameters/parameters.h>
#include <tkr/wear/archard.h>
#include <tkr/wear/cross_shear_laws.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iomanip>
#include <map>
#include <sstream>

#include "../tests.h"

namespace
{
  using P = TKR::Parameters::AllParameters;

  /** A value as the tests compare it: numbers normalised, else the text. */
  std::string
  norm(const std::string &value)
  {
    std::istringstream  in(value);
    std::ostringstream  out;
    std::string         item;
    bool                numbers = true;
    std::vector<double> values;
    while (std::getline(in, item, ','))
      {
        try
          {
            std::size_t end;
            values.push_back(std::stod(item, &end));
            numbers =
              numbers && dealii::Utilities::trim(item.substr(end)).empty();
          }
        catch (...)
          {
            numbers = false;
          }
      }
    if (!numbers || values.empty())
      return value;
    for (unsigned int i = 0; i < values.size(); ++i)
      out << (i ? ", " : "") << std::setprecision(12) << values[i];
    return out.str();
  }

  std::string
  num(const double x)
  {
    std::ostringstream out;
    out << std::setprecision(17) << x;
    return norm(out.str());
  }

  std::string
  vec(const dealii::Tensor<1, 3> &t)
  {
    return num(t[0]) + ", " + num(t[1]) + ", " + num(t[2]);
  }

  std::string
  yes(const bool b)
  {
    return b ? "true" : "false";
  }

  std::string
  file_name(const std::string &path)
  {
    return std::filesystem::path(path).filename().string();
  }

  const TKR::Gait::Restraints &
  restraints(const P &p)
  {
    return p.gait.protocols.get<TKR::Gait::Restraints>("force");
  }

  const TKR::Gait::DisplacementSigns &
  signs(const P &p)
  {
    return p.gait.protocols.get<TKR::Gait::DisplacementSigns>("displacement");
  }

  const std::string &
  table(const P &p, const std::string &law)
  {
    return p.wear.laws.get<TKR::Wear::CrossShearLawParameters>(law)
      .cross_shear_table;
  }

  struct Row
  {
    std::string                           entry;
    std::string                           other;
    std::function<std::string(const P &)> field;
    bool                                  is_path = false;
  };

  std::vector<Row>
  table(const std::string &source)
  {
    using namespace TKR::Parameters;
    const auto algorithm = [](const P &p) {
      switch (p.contact_solver.algorithm)
        {
          case ContactAlgorithm::automatic:
            return std::string("auto");
          case ContactAlgorithm::active_set:
            return std::string("active set");
          case ContactAlgorithm::condensed_active_set:
            return std::string("condensed active set");
          case ContactAlgorithm::ipopt:
            return std::string("ipopt");
        }
      return std::string();
    };
    const auto analytic = [](const P &p) {
      return p.verification.analytic_solution == AnalyticSolution::none ?
               std::string("none") :
             p.verification.analytic_solution ==
                 AnalyticSolution::hertz_sphere ?
               std::string("hertz sphere") :
               std::string("hertz cylinder");
    };
    const auto material = [](const P &p, const bool femur) -> const Material & {
      return femur ? p.materials.femur : p.materials.tibia;
    };
    std::vector<Row> rows = {{"Problem",
                              "contact",
                              [](const P &p) { return to_string(p.problem); }},
                             {"Contact solver/Coupling window",
                              "0.1",
                              [](const P &p) {
                                return num(p.contact_solver.coupling_window);
                              }},
                             {"Contact solver/Initial contact distance",
                              "0.02",
                              [](const P &p) {
                                return num(
                                  p.contact_solver.initial_contact_distance);
                              }},
                             {"Contact solver/Max iterations",
                              "60",
                              [](const P &p) {
                                return num(p.contact_solver.max_iterations);
                              }},
                             {"Contact solver/Overlap tolerance",
                              "0.04",
                              [](const P &p) {
                                return num(p.contact_solver.overlap_tolerance);
                              }},
                             {"Contact solver/Search distance",
                              "3",
                              [](const P &p) {
                                return num(p.contact_solver.search_distance);
                              }},
                             {"Contact solver/Solver", "ipopt", algorithm},
                             {"Contact solver/Tolerance",
                              "1e-9",
                              [](const P &p) {
                                return num(p.contact_solver.tolerance);
                              }},
                             {"Elasticity/Femur contact traction",
                              "1, 2, 3",
                              [](const P &p) {
                                return vec(p.elasticity.femur_contact_traction);
                              }},
                             {"Elasticity/Tibia contact traction",
                              "-1, -2, -3",
                              [](const P &p) {
                                return vec(p.elasticity.tibia_contact_traction);
                              }},
                             {"Gait/Force control/AP force sign",
                              "-1",
                              [](const P &p) {
                                return num(restraints(p).ap_force_sign);
                              }},
                             {"Gait/Force control/AP spring range",
                              "3",
                              [](const P &p) {
                                return num(restraints(p).ap_spring_range);
                              }},
                             {"Gait/Force control/AP spring stiffness",
                              "10",
                              [](const P &p) {
                                return num(restraints(p).ap_spring_stiffness);
                              }},
                             {"Gait/Force control/AP spring stiffness beyond range",
                              "50",
                              [](const P &p) {
                                return num(restraints(p).ap_spring_stiffness_beyond);
                              }},
                             {"Gait/Axial load offset",
                              "0.05",
                              [](const P &p) {
                                return num(p.gait.axial_load_offset);
                              }},
                             {"Gait/Axial stabilisation spring",
                              "120",
                              [](const P &p) {
                                return num(p.gait.axial_stabilisation_spring);
                              }},
                             {"Gait/Control",
                              "displacement",
                              [](const P &p) { return p.gait.control; }},
                             {"Gait/Displacement control/AP displacement sign",
                              "-1",
                              [](const P &p) {
                                return num(signs(p).ap_displacement_sign);
                              }},
                             {"Gait/Displacement control/IE rotation sign",
                              "-1",
                              [](const P &p) {
                                return num(signs(p).ie_rotation_sign);
                              }},
                             {"Gait/Femur AP offset",
                              "1.5",
                              [](const P &p) {
                                return num(p.gait.femur_ap_offset);
                              }},
                             {"Gait/Channel scales",
                              "axial_force_N: 1.25",
                              [](const P &p) {
                                std::string text;
                                for (const auto &[name, factor] :
                                     p.gait.channel_scales)
                                  text += name + ": " + num(factor);
                                return text;
                              }},
                             {"Gait/Activities",
                              "walking: 1",
                              [](const P &p) {
                                return p.gait.activities;
                              }},
                             {"Study/Base parameter file",
                              source + "/prm/iso14243-1-coarse.prm",
                              [](const P &p) {
                                return file_name(p.study.base_file);
                              },
                              true},
                             {"Study/Cases file",
                              source + "/data/iso14243-1.csv",
                              [](const P &p) {
                                return file_name(p.study.cases_file);
                              },
                              true},
                             {"Study/Grid",
                              "Wear/Wear coefficient = 1e-7, 2e-7",
                              [](const P &p) { return p.study.grid; }},
                             {"Study/Sampling",
                              "monte carlo",
                              [](const P &p) { return p.study.sampling; }},
                             {"Study/Samples",
                              "8",
                              [](const P &p) { return num(p.study.samples); }},
                             {"Study/Seed",
                              "7",
                              [](const P &p) { return num(p.study.seed); }},
                             {"Study/Distributions",
                              "Wear/Wear coefficient = uniform(1e-7, 3e-7)",
                              [](const P &p) { return p.study.distributions; }},
                             {"Study/Mesh generator",
                              source + "/meshes/gen/tkr_variant.py",
                              [](const P &p) {
                                return file_name(p.study.mesh_generator);
                              },
                              true},
                             {"Study/Mesh generator arguments",
                              "--variant b",
                              [](const P &p) {
                                return p.study.mesh_generator_arguments;
                              }},
                             {"Study/Ranks per case",
                              "2",
                              [](const P &p) {
                                return num(p.study.ranks_per_case);
                              }},
                             {"Optimisation/Base parameter file",
                              source + "/prm/iso14243-1-coarse.prm",
                              [](const P &p) {
                                return file_name(p.optimisation.base_file);
                              },
                              true},
                             {"Optimisation/Variables",
                              "Gait/ML spring stiffness = 5 .. 25",
                              [](const P &p) {
                                return p.optimisation.variables;
                              }},
                             {"Optimisation/Objective",
                              "maximise mass_loss_mg",
                              [](const P &p) {
                                return p.optimisation.objective;
                              }},
                             {"Optimisation/Constraints",
                              "max_pressure_MPa <= 25",
                              [](const P &p) {
                                return p.optimisation.constraints;
                              }},
                             {"Optimisation/Method",
                              "bobyqa",
                              [](const P &p) { return p.optimisation.method; }},
                             {"Optimisation/Maximum evaluations",
                              "12",
                              [](const P &p) {
                                return num(p.optimisation.maximum_evaluations);
                              }},
                             {"Optimisation/Tolerance",
                              "0.01",
                              [](const P &p) {
                                return num(p.optimisation.tolerance);
                              }},
                             {"Optimisation/Initial step",
                              "0.125",
                              [](const P &p) {
                                return num(p.optimisation.initial_step);
                              }},
                             {"Optimisation/Mesh generator",
                              source + "/meshes/gen/tkr_variant.py",
                              [](const P &p) {
                                return file_name(p.optimisation.mesh_generator);
                              },
                              true},
                             {"Optimisation/Mesh generator arguments",
                              "--variant b",
                              [](const P &p) {
                                return p.optimisation.mesh_generator_arguments;
                              }},
                             {"Optimisation/Test function",
                              "quadratic",
                              [](const P &p) {
                                return p.optimisation.test_function;
                              }},
                             {"Optimisation/Initial design",
                              "6",
                              [](const P &p) {
                                return num(p.optimisation.initial_design);
                              }},
                             {"Optimisation/Seed",
                              "7",
                              [](const P &p) {
                                return num(p.optimisation.seed);
                              }},
                             {"Optimisation/Ranks per evaluation",
                              "2",
                              [](const P &p) {
                                return num(
                                  p.optimisation.ranks_per_evaluation);
                              }},
                             {"Optimisation/Scenarios",
                              "walk: 0.5: " + source + "/prm/one-cycle.prm",
                              [](const P &p) {
                                return p.optimisation.scenarios;
                              }},
                             {"Optimisation/Combine scenarios",
                              "worst case",
                              [](const P &p) {
                                return p.optimisation.combine_scenarios;
                              }},
                             {"Optimisation/Verification mesh generator "
                              "arguments",
                              "--variant b --resolution medium",
                              [](const P &p) {
                                return p.optimisation
                                  .verification_generator_arguments;
                              }},
                             {"Optimisation/Verification entries",
                              "Gait/Steps per cycle = 50",
                              [](const P &p) {
                                return p.optimisation.verification_entries;
                              }},
                             {"Gait/Flexion axis point",
                              "1, -3, 50",
                              [](const P &p) {
                                return vec(p.gait.flexion_axis_point);
                              }},
                             {"Gait/Force control/IE spring range",
                              "5",
                              [](const P &p) {
                                return num(restraints(p).ie_spring_range);
                              }},
                             {"Gait/Force control/IE spring stiffness",
                              "140",
                              [](const P &p) {
                                return num(restraints(p).ie_spring_stiffness);
                              }},
                             {"Gait/Force control/IE spring stiffness beyond range",
                              "400",
                              [](const P &p) {
                                return num(restraints(p).ie_spring_stiffness_beyond);
                              }},
                             {"Gait/Force control/IE torque sign",
                              "-1",
                              [](const P &p) {
                                return num(restraints(p).ie_torque_sign);
                              }},
                             {"Gait/ML spring stiffness",
                              "5",
                              [](const P &p) {
                                return num(p.gait.ml_spring_stiffness);
                              }},
                             {"Gait/Medial side",
                              "-x",
                              [](const P &p) {
                                return p.gait.medial_direction > 0 ?
                                         std::string("+x") :
                                         std::string("-x");
                              }},
                             {"Gait/Pose derivatives",
                              "finite differences",
                              [](const P &p) {
                                return p.gait.analytic_pose_derivatives ?
                                         std::string("analytic") :
                                         std::string("finite differences");
                              }},
                             {"Gait/Pose tolerance",
                              "0.002",
                              [](const P &p) {
                                return num(p.gait.pose_tolerance);
                              }},
                             {"Gait/Largest initial overlap",
                              "0.25",
                              [](const P &p) {
                                return num(p.gait.largest_initial_overlap);
                              }},
                             {"Gait/Step groups",
                              "2",
                              [](const P &p) {
                                return num(p.gait.step_groups);
                              }},
                             {"Gait/Steps per cycle",
                              "50",
                              [](const P &p) {
                                return num(p.gait.steps_per_cycle);
                              }},
                             {"Gait/Tibial tray",
                              "free",
                              [](const P &p) {
                                return p.gait.rigid_tray ?
                                         std::string("rigid") :
                                         std::string("free");
                              }},
                             {"Gait/Tray flatness tolerance",
                              "2e-3",
                              [](const P &p) {
                                return num(p.gait.tray_flatness_tolerance);
                              }},
                             {"Gait/Waveform file",
                              source + "/data/measured/../iso14243-1.csv",
                              [](const P &p) {
                                return file_name(p.gait.waveform_file);
                              },
                              true},
                             {"Linear solver/AMG aggregation threshold",
                              "0.03",
                              [](const P &p) {
                                return num(
                                  p.linear_solver.aggregation_threshold);
                              }},
                             {"Linear solver/AMG smoother sweeps",
                              "3",
                              [](const P &p) {
                                return num(p.linear_solver.smoother_sweeps);
                              }},
                             {"Linear solver/Max iterations",
                              "1000",
                              [](const P &p) {
                                return num(p.linear_solver.max_iterations);
                              }},
                             {"Linear solver/Newton step tolerance",
                              "1e-7",
                              [](const P &p) {
                                return num(
                                  p.linear_solver.newton_step_tolerance);
                              }},
                             {"Linear solver/Rigid body modes",
                              "false",
                              [](const P &p) {
                                return yes(p.linear_solver.rigid_body_modes);
                              }},
                             {"Linear solver/Tolerance",
                              "1e-11",
                              [](const P &p) {
                                return num(p.linear_solver.tolerance);
                              }},
                             {"Mesh/Contact cell quality",
                              "0.2",
                              [](const P &p) {
                                return num(p.mesh.contact_cell_quality);
                              }},
                             {"Mesh/Femur contact group",
                              "fc",
                              [](const P &p) {
                                return p.mesh.femur_contact_name;
                              }},
                             {"Mesh/Femur fixation group",
                              "ff",
                              [](const P &p) {
                                return p.mesh.femur_fixation_name;
                              }},
                             {"Mesh/Femur group",
                              "f",
                              [](const P &p) { return p.mesh.femur_name; }},
                             {"Mesh/File",
                              source + "/meshes/tkr/tkr-b-coarse.msh",
                              [](const P &p) { return file_name(p.mesh.file); },
                              true},
                             {"Mesh/Finite element degree",
                              "2",
                              [](const P &p) { return num(p.mesh.fe_degree); }},
                             {"Mesh/Tibia contact group",
                              "tc",
                              [](const P
                                   &p) { return p.mesh.tibia_contact_name; }},
                             {"Mesh/Tibia group",
                              "t",
                              [](const P &p) { return p.mesh.tibia_name; }},
                             {"Mesh/Tibia inferior group",
                              "ti",
                              [](const P &p) {
                                return p.mesh.tibia_inferior_name;
                              }},
                             {"Output/Checkpoint interval",
                              "5",
                              [](const P &p) {
                                return num(p.output.checkpoint_interval);
                              }},
                             {"Output/Directory",
                              "results2",
                              [](const P &p) { return p.output.directory; }},
                             {"Output/Measured mass loss file",
                              source + "/data/measured/example-gravimetric.csv",
                              [](const P &p) {
                                return file_name(
                                  p.output.measured_mass_loss_file);
                              },
                              true},
                             {"Output/Plots",
                              "false",
                              [](const P &p) { return yes(p.output.plots); }},
                             {"Output/Testing",
                              "true",
                              [](const P &p) { return yes(p.output.testing); }},
                             {"Output/VTU interval",
                              "3",
                              [](const P
                                   &p) { return num(p.output.vtu_interval); }},
                             {"Output/Worn VTU interval",
                              "4",
                              [](const P &p) {
                                return num(p.output.worn_vtu_interval);
                              }},
                             {"Static contact/Axial force",
                              "900",
                              [](const P &p) {
                                return num(p.static_contact.axial_force);
                              }},
                             {"Static contact/Femur displacement",
                              "0.1, 0.2, -0.3",
                              [](const P &p) {
                                return vec(p.static_contact.femur_displacement);
                              }},
                             {"Static contact/Roller faces",
                              "y",
                              [](const P &p) {
                                const int a = p.static_contact.roller_axis;
                                return a < 0 ? std::string("none") :
                                               std::string(1, char('x' + a));
                              }},
                             {"Static contact/Tibia inferior",
                              "loaded",
                              [](const P &p) {
                                return p.static_contact.tibia_inferior ==
                                           TibiaSupport::loaded ?
                                         std::string("loaded") :
                                         std::string("clamped");
                              }},
                             {"Static contact/Tibia tangential spring",
                              "50",
                              [](const P &p) {
                                return num(p.static_contact.tangential_spring);
                              }},
                             {"Verification/Analytic solution",
                              "hertz cylinder",
                              analytic},
                             {"Verification/Cross-check with Ipopt",
                              "true",
                              [](const P &p) {
                                return yes(
                                  p.verification.cross_check_with_ipopt);
                              }},
                             {"Verification/Cylinder length",
                              "12",
                              [](const P &p) {
                                return num(p.verification.cylinder_length);
                              }},
                             {"Verification/Hertz tolerance",
                              "0.02",
                              [](const P &p) {
                                return num(p.verification.hertz_tolerance);
                              }},
                             {"Verification/Radius",
                              "25",
                              [](const P
                                   &p) { return num(p.verification.radius); }},
                             {"Wear/Cycles",
                              "1e6",
                              [](const P &p) { return num(p.wear.cycles); }},
                             {"Wear/Cycles per extrapolation step",
                              "1e4",
                              [](const P &p) {
                                return num(
                                  p.wear.cycles_per_extrapolation_step);
                              }},
                             {"Wear/Distortion limit",
                              "0.3",
                              [](const P &
                                   p) { return num(p.wear.distortion_limit); }},
                             {"Wear/Halve step on distortion",
                              "true",
                              [](const P &p) {
                                return yes(p.wear.halve_step_on_distortion);
                              }},
                             {"Wear/Stiffness update interval",
                              "5",
                              [](const P &p) {
                                return num(p.wear.stiffness_update_interval);
                              }},
                             {"Wear/Warm start",
                              "false",
                              [](
                                const P &p) { return yes(p.wear.warm_start); }},
                             {"Wear/Wear area threshold",
                              "2e-4",
                              [](const P &p) {
                                return num(p.wear.wear_area_threshold);
                              }},
                             {"Wear/Archard/Wear coefficient",
                              "3e-7",
                              [](const P &p) {
                                return num(
                                  p.wear.laws
                                    .get<TKR::Wear::ArchardParameters>(
                                      "archard")
                                    .wear_coefficient);
                              }},
                             {"Wear/Wear law",
                              "area",
                              [](const P &p) { return p.wear.law; }},
                             {"Wear/Archard cs/Cross-shear table",
                              source + "/data/wear/example-archard-cs.csv",
                              [](const P &p) {
                                return file_name(table(p, "archard_cs"));
                              },
                              true},
                             {"Wear/Archard cs/Table scale",
                              "1.5",
                              [](const P &p) {
                                return num(
                                  p.wear.laws
                                    .get<TKR::Wear::CrossShearLawParameters>(
                                      "archard_cs")
                                    .table_scale);
                              }},
                             {"Wear/Area/Table scale",
                              "0.5",
                              [](const P &p) {
                                return num(
                                  p.wear.laws
                                    .get<TKR::Wear::CrossShearLawParameters>(
                                      "area")
                                    .table_scale);
                              }},
                             {"Wear/Area/Cross-shear table",
                              source + "/data/wear/example-area-law.csv",
                              [](const P &p) {
                                return file_name(table(p, "area"));
                              },
                              true},
                             {"Calibration/Designs",
                              "a.prm: b.csv",
                              [](const P &p) {
                                std::string designs;
                                for (const auto &d : p.calibration.designs)
                                  designs += d.base_file + ": " +
                                             d.measured_file;
                                return designs;
                              }},
                             {"Calibration/Fit",
                              "Run-in factor, Run-in length",
                              [](const P &p) {
                                std::string fit;
                                for (const std::string &name :
                                     p.calibration.fit)
                                  fit += (fit.empty() ? "" : ", ") + name;
                                return fit;
                              }},
                             {"Calibration/Run-in factor",
                              "3",
                              [](const P &p) {
                                return num(p.calibration.run_in_factor);
                              }},
                             {"Calibration/Run-in length",
                              "5e5",
                              [](const P &p) {
                                return num(p.calibration.run_in_length);
                              }},
                             {"Calibration/Confidence level",
                              "0.9",
                              [](const P &p) {
                                return num(p.calibration.confidence_level);
                              }},
                             {"Calibration/Tolerance",
                              "0.02",
                              [](const P &p) {
                                return num(p.calibration.tolerance);
                              }},
                             {"Calibration/Maximum runs",
                              "6",
                              [](const P &p) {
                                return num(p.calibration.maximum_runs);
                              }},
                             {"Wear/Cross-shear definition",
                              "abs sin",
                              [](const P &p) {
                                return p.wear.cross_shear_definition;
                              }},
                             {"Wear/Run-in file",
                              source + "/data/wear/example-run-in.csv",
                              [](const P &p) {
                                return file_name(p.wear.run_in_file);
                              },
                              true}};
    for (const bool femur : {true, false})
      {
        const std::string m = femur ? "Materials/Femur/" : "Materials/Tibia/";
        rows.push_back({m + "Density", femur ? "8" : "0.94", [=](const P &p) {
                          return num(material(p, femur).density);
                        }});
        rows.push_back(
          {m + "Poisson's ratio", femur ? "0.3" : "0.4", [=](const P &p) {
             return num(material(p, femur).poissons_ratio);
           }});
        rows.push_back(
          {m + "Young's modulus", femur ? "210000" : "1000", [=](const P &p) {
             return num(material(p, femur).youngs_modulus);
           }});
      }
    return rows;
  }

  /** The entries of a parameter file written by print_parameters. */
  std::map<std::string, std::string>
  entries_of(const std::string &text)
  {
    std::map<std::string, std::string> entries;
    std::istringstream                 in(text);
    std::vector<std::string>           path;
    std::string                        line;
    while (std::getline(in, line))
      {
        const std::string c = dealii::Utilities::trim(line);
        if (c.rfind("subsection ", 0) == 0)
          path.push_back(dealii::Utilities::trim(c.substr(11)));
        else if (c == "end")
          path.pop_back();
        else if (c.rfind("set ", 0) == 0)
          {
            std::string entry;
            for (const auto &p : path)
              entry += p + '/';
            const auto eq = c.find('=');
            entry += dealii::Utilities::trim(c.substr(4, eq - 4));
            entries[entry] = dealii::Utilities::trim(c.substr(eq + 1));
          }
      }
    return entries;
  }

  /** A file that sets @p values (entry -> value), one subsection each. */
  std::string
  file_setting(const std::map<std::string, std::string> &values)
  {
    std::string text;
    for (const auto &[entry, value] : values)
      {
        std::vector<std::string> parts;
        std::istringstream       in(entry);
        std::string              part;
        while (std::getline(in, part, '/'))
          parts.push_back(part);
        for (unsigned int i = 0; i + 1 < parts.size(); ++i)
          text += "subsection " + parts[i] + "\n";
        text += "set " + parts.back() + " = " + value + "\n";
        for (unsigned int i = 0; i + 1 < parts.size(); ++i)
          text += "end\n";
      }
    return text;
  }
} // namespace

int
main()
{
  initlog();
  const std::string  source = std::string(SOURCE_DIR) + "/../..";
  std::ostringstream defaults_text;
  TKR::Parameters::print_default_parameters(defaults_text);
  const auto defaults = entries_of(defaults_text.str());
  const auto rows     = table(source);

  // The table lists exactly the declared entries.
  std::map<std::string, std::string> others;
  for (const auto &row : rows)
    others[row.entry] = row.other;
  unsigned int n_missing = 0, n_unknown = 0;
  for (const auto &[entry, value] : defaults)
    if (!others.count(entry))
      {
        deallog << "no table row for the entry " << entry << std::endl;
        ++n_missing;
      }
  for (const auto &[entry, value] : others)
    if (!defaults.count(entry))
      {
        deallog << "table row for an unknown entry " << entry << std::endl;
        ++n_unknown;
      }
  // Entries whose other value is their default (a selection of one).
  for (const auto &row : rows)
    if (norm(row.other) == norm(defaults.at(row.entry)))
      deallog << "only one value possible: " << row.entry << std::endl;
  deallog << "declared entries: " << defaults.size()
          << ", table rows: " << rows.size() << ", missing " << n_missing
          << ", unknown " << n_unknown << std::endl;

  // Defaults, then every entry changed.
  {
    std::ofstream out("defaults.prm");
    out << defaults_text.str();
  }
  {
    std::ofstream out("changed.prm");
    out << file_setting(others);
  }
  for (const std::string name : {"defaults", "changed"})
    {
      const P      p      = TKR::Parameters::read_parameters(name + ".prm");
      unsigned int n_read = 0, n_differ = 0;
      for (const auto &row : rows)
        {
          const std::string expected =
            name == "defaults" ? defaults.at(row.entry) : row.other;
          const std::string want =
            row.is_path ? file_name(expected) : norm(expected);
          const std::string got = row.field(p);
          if (got == want)
            ++n_read;
          else
            {
              ++n_differ;
              deallog << name << ": " << row.entry << " = " << expected
                      << " read as " << got << std::endl;
            }
        }
      deallog << name << ": " << n_read << " entries read back, " << n_differ
              << " differ" << std::endl;
      if (name == "changed")
        {
          const auto &m = p.materials.tibia;
          deallog << "tibia lambda " << m.lambda() << " mu " << m.mu()
                  << " (E nu / ((1 + nu)(1 - 2 nu)) = "
                  << 1000. * 0.4 / (1.4 * 0.2)
                  << ", E / (2 (1 + nu)) = " << 1000. / 2.8 << ")" << std::endl;
        }
    }

  // Includes and relative paths: sub/base.prm names a mesh relative to
  // its own directory (sub/mesh.msh, a copy), top.prm in another
  // directory includes it.
  std::filesystem::create_directories("sub");
  std::filesystem::copy_file(source + "/meshes/verification/patch-coarse.msh",
                             "sub/mesh.msh",
                             std::filesystem::copy_options::overwrite_existing);
  {
    std::ofstream out("sub/base.prm");
    out << "subsection Mesh\n  set File = mesh.msh\nend\n";
  }
  {
    std::ofstream out("top.prm");
    out << "set Problem = contact\ninclude sub/base.prm\n";
  }
  const P included = TKR::Parameters::read_parameters("top.prm");
  deallog << "included file's relative mesh path: " << included.mesh.file
          << " exists " << yes_no(std::filesystem::exists(included.mesh.file))
          << std::endl;
  {
    std::ofstream out("sub/bad.prm");
    out
      << "# a comment\nsubsection Mesh\n  set Finite element degree = 7\nend\n";
  }
  {
    std::ofstream out("top_bad.prm");
    out << "set Problem = contact\n\ninclude sub/bad.prm\n";
  }
  try
    {
      TKR::Parameters::read_parameters("top_bad.prm");
      deallog << "top_bad.prm: read (unexpected)" << std::endl;
    }
  catch (const TKR::ExcInputError &exc)
    {
      const std::string message = TKR::exception_message(exc);
      deallog << "error in an included file: "
              << message.substr(0, message.find(':')) << std::endl;
    }

  // Entries in their places before the models had subsections.
  {
    std::ofstream out("sub/old.prm");
    out << "set Problem = contact\nsubsection Gait\n  set AP spring "
           "stiffness = 12\n  set IE rotation sign = -1\nend\n"
           "subsection Wear\n  set Wear law = archard_cs\n  set Wear "
           "coefficient = 4e-7\n  set Cross-shear table = \\\n"
           "    data/wear/example-archard-cs.csv\nend\n";
  }
  const P old = TKR::Parameters::read_parameters("sub/old.prm");
  deallog << "old places: AP spring stiffness "
          << restraints(old).ap_spring_stiffness << ", IE rotation sign "
          << signs(old).ie_rotation_sign << ", wear coefficient "
          << old.wear.laws.get<TKR::Wear::ArchardParameters>("archard")
               .wear_coefficient
          << ", tables " << file_name(table(old, "archard_cs")) << " "
          << file_name(table(old, "area"))
          << " (found: " << yes_no(std::filesystem::exists(table(old, "area")))
          << ")" << std::endl;
  for (const std::string &note : old.notes)
    deallog << "note: " << note << std::endl;
  deallog << "the old places are not entries: "
          << yes_no(old.entries.count("Wear/Wear coefficient") == 0 &&
                    old.entries.count("Gait/AP spring stiffness") == 0)
          << std::endl;

  // A checkpoint's record of the state parameters written before the
  // entries moved: the same values under the old paths (an Archard run).
  {
    std::ofstream out("sub/archard.prm");
    out << "set Problem = contact\nsubsection Wear\n  set Wear coefficient = "
           "4e-7\nend\n";
  }
  const P    archard = TKR::Parameters::read_parameters("sub/archard.prm");
  const auto record  = [&](const std::string &coefficient) {
    std::string text;
    for (const auto &[entry, value] : TKR::Output::state_parameters(archard))
      {
        std::string path = entry;
        for (const auto &[from, to] : TKR::Parameters::moved_entries())
          if (path == to || path == to + " (checksum)")
            path = from + path.substr(to.size());
        text += path + " = " +
                (path == "Wear/Wear coefficient" ? coefficient : value) + "\n";
      }
    return text;
  };
  for (const std::string coefficient : {"4e-7", "5e-7"})
    try
      {
        TKR::Output::check_state_parameters("old.h5",
                                            record(coefficient),
                                            archard);
        deallog << "checkpoint with Wear/Wear coefficient = " << coefficient
                << ": accepted" << std::endl;
      }
    catch (const TKR::ExcInputError &exc)
      {
        const std::string message = TKR::exception_message(exc);
        deallog << "checkpoint with Wear/Wear coefficient = " << coefficient
                << ": refused: " << message.substr(0, message.find(". "))
                << std::endl;
      }
}
