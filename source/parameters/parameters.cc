// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <deal.II/base/utilities.h>

#include <tkr/base/exceptions.h>
#include <tkr/parameters/parameters.h>

#include "parameter_file.h"
#include "vector_entry.h"

#include <fstream>
#include <sstream>

namespace TKR::Parameters
{
  using namespace dealii;
  using internal::get_vector;
  using internal::vector_pattern;


  void
  Mesh::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Mesh");
    {
      prm.declare_entry("File",
                        "meshes/tkr/tkr-a-coarse.msh",
                        Patterns::FileName(),
                        "The gmsh mesh (.msh, format 4.1) that holds both "
                        "bodies as separate hexahedral volumes. A relative "
                        "path is taken from the directory of the parameter "
                        "file that sets it, then from the working "
                        "directory, then from the tkr-wear sources (the "
                        "bundled meshes).");
      prm.declare_entry(
        "Contact cell quality",
        "0.3",
        Patterns::Double(-1, 1),
        "Warn when a cell with a face on tibia_contact has a smaller scaled "
        "Jacobian (the smallest over its corners of the "
        "determinant of the three edges leaving the corner over the "
        "product of their lengths: 1 for a cube), and note it for "
        "femur_contact. Nodal contact pressures and wear depths scatter on "
        "distorted contact cells (doc/geometry.md).");
      prm.declare_entry("Finite element degree",
                        "1",
                        Patterns::Integer(1, 3),
                        "Polynomial degree of the FE_Q displacement element.");
      prm.declare_entry("Femur group",
                        "femur",
                        Patterns::Anything(),
                        "Name of the physical volume of the femoral "
                        "component.");
      prm.declare_entry("Tibia group",
                        "tibia",
                        Patterns::Anything(),
                        "Name of the physical volume of the tibial insert.");
      prm.declare_entry("Femur contact group",
                        "femur_contact",
                        Patterns::Anything(),
                        "Name of the physical surface of the femoral "
                        "articular surface (mortar master side).");
      prm.declare_entry("Femur fixation group",
                        "femur_fixation",
                        Patterns::Anything(),
                        "Name of the physical surface of the femoral back "
                        "side (clamped).");
      prm.declare_entry("Tibia contact group",
                        "tibia_contact",
                        Patterns::Anything(),
                        "Name of the physical surface of the tibial articular "
                        "surface (mortar slave side, where wear lives).");
      prm.declare_entry("Tibia inferior group",
                        "tibia_inferior",
                        Patterns::Anything(),
                        "Name of the physical surface of the tibial back "
                        "side (loads and springs act here).");
    }
    prm.leave_subsection();
  }

  void
  Mesh::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Mesh");
    {
      file                 = prm.get("File");
      fe_degree            = prm.get_integer("Finite element degree");
      contact_cell_quality = prm.get_double("Contact cell quality");
      femur_name           = prm.get("Femur group");
      tibia_name           = prm.get("Tibia group");
      femur_contact_name   = prm.get("Femur contact group");
      femur_fixation_name  = prm.get("Femur fixation group");
      tibia_contact_name   = prm.get("Tibia contact group");
      tibia_inferior_name  = prm.get("Tibia inferior group");
    }
    prm.leave_subsection();
  }

  Mesh
  Mesh::with_default_groups(const std::string &file)
  {
    return Mesh{file,
                1,
                "femur",
                "tibia",
                "femur_contact",
                "femur_fixation",
                "tibia_contact",
                "tibia_inferior",
                0.3};
  }

  void
  Material::declare_parameters(ParameterHandler &prm,
                               const double      youngs_modulus,
                               const double      poissons_ratio,
                               const double      density)
  {
    prm.declare_entry("Young's modulus",
                      Utilities::to_string(youngs_modulus),
                      Patterns::Double(0, Patterns::Double::max_double_value),
                      "Young's modulus E in MPa.");
    prm.declare_entry("Poisson's ratio",
                      Utilities::to_string(poissons_ratio),
                      Patterns::Double(-0.999, 0.499),
                      "Poisson's ratio nu (dimensionless).");
    prm.declare_entry("Density",
                      Utilities::to_string(density),
                      Patterns::Double(0, Patterns::Double::max_double_value),
                      "Density in mg/mm^3 (converts worn volume to mass).");
  }

  void
  Material::parse_parameters(ParameterHandler &prm)
  {
    youngs_modulus = prm.get_double("Young's modulus");
    poissons_ratio = prm.get_double("Poisson's ratio");
    density        = prm.get_double("Density");
    AssertThrow(youngs_modulus > 0,
                ExcInputError("Young's modulus must be positive (got " +
                              prm.get("Young's modulus") + ")."));
  }

  double
  Material::lambda() const
  {
    return youngs_modulus * poissons_ratio /
           ((1. + poissons_ratio) * (1. - 2. * poissons_ratio));
  }

  double
  Material::mu() const
  {
    return youngs_modulus / (2. * (1. + poissons_ratio));
  }

  void
  Materials::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Materials");
    {
      prm.enter_subsection("Femur");
      Material::declare_parameters(prm, 220000., 0.31, 8.3);
      prm.leave_subsection();
      prm.enter_subsection("Tibia");
      Material::declare_parameters(prm, 1100., 0.42, 0.935);
      prm.leave_subsection();
    }
    prm.leave_subsection();
  }

  void
  Materials::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Materials");
    {
      prm.enter_subsection("Femur");
      femur.parse_parameters(prm);
      prm.leave_subsection();
      prm.enter_subsection("Tibia");
      tibia.parse_parameters(prm);
      prm.leave_subsection();
    }
    prm.leave_subsection();
  }

  void
  Elasticity::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Elasticity");
    {
      prm.declare_entry("Femur contact traction",
                        "0, 0, 1",
                        vector_pattern(),
                        "(Problem = elasticity) Uniform traction on the "
                        "femoral contact surface, x,y,z in MPa. The femur is "
                        "clamped on its fixation surface.");
      prm.declare_entry("Tibia contact traction",
                        "0, 0, -1",
                        vector_pattern(),
                        "(Problem = elasticity) Uniform traction on the "
                        "tibial contact surface, x,y,z in MPa. The tibia is "
                        "clamped on its inferior surface.");
    }
    prm.leave_subsection();
  }

  void
  Elasticity::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Elasticity");
    {
      femur_contact_traction = get_vector(prm, "Femur contact traction");
      tibia_contact_traction = get_vector(prm, "Tibia contact traction");
    }
    prm.leave_subsection();
  }

  void
  StaticContact::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Static contact");
    {
      prm.declare_entry("Femur displacement",
                        "0, 0, -0.01",
                        vector_pattern(),
                        "(Problem = contact) Displacement of the femoral "
                        "fixation surface, x,y,z in mm.");
      prm.declare_entry("Tibia inferior",
                        "clamped",
                        Patterns::Selection("clamped|loaded"),
                        "(Problem = contact) clamped: zero displacement on "
                        "the tibial inferior surface; loaded: the axial force "
                        "acts there and the tibia is held only by contact.");
      prm.declare_entry("Axial force",
                        "1000",
                        Patterns::Double(0, Patterns::Double::max_double_value),
                        "(Problem = contact, Tibia inferior = loaded) Force "
                        "on the tibial inferior surface along +z, in N.");
      prm.declare_entry("Tibia tangential spring",
                        "100",
                        Patterns::Double(0),
                        "(Tibia inferior = loaded) Total stiffness in N/mm of "
                        "the x and y springs spread uniformly over the "
                        "tibial inferior surface; they hold the in-plane "
                        "rigid motions that frictionless contact cannot.");
      prm.declare_entry("Roller faces",
                        "none",
                        Patterns::Selection("none|x|y|z"),
                        "Untagged (free) faces whose normal is parallel to "
                        "this axis get the roller condition u.n = 0, e.g. x "
                        "for plane strain in a slab normal to x.");
    }
    prm.leave_subsection();
  }

  void
  StaticContact::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Static contact");
    {
      femur_displacement = get_vector(prm, "Femur displacement");
      tibia_inferior =
        (prm.get("Tibia inferior") == "loaded" ? TibiaSupport::loaded :
                                                 TibiaSupport::clamped);
      axial_force            = prm.get_double("Axial force");
      tangential_spring      = prm.get_double("Tibia tangential spring");
      const std::string axis = prm.get("Roller faces");
      roller_axis            = (axis == "none" ? -1 :
                                axis == "x"    ? 0 :
                                axis == "y"    ? 1 :
                                                 2);
    }
    prm.leave_subsection();
  }

  void
  ContactSolver::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Contact solver");
    {
      prm.declare_entry(
        "Solver",
        "auto",
        Patterns::Selection("auto|active set|condensed active set|ipopt"),
        "active set: primal-dual active set (semismooth Newton) with "
        "AMG-preconditioned CG on the whole body; condensed active set: the "
        "same iteration on the contact surface (Delassus matrix from one "
        "sparse Cholesky factorisation (CHOLMOD) of the stiffness, kept for "
        "all solves; "
        "needs a stiffness without rigid-body motion); ipopt: the same "
        "discrete problem as a convex QP solved by Ipopt (reference, slow, "
        "Problem = contact only); auto: condensed active set for Problem = "
        "wear, active set for Problem = contact.");
      prm.declare_entry("Tolerance",
                        "1e-8",
                        Patterns::Double(0),
                        "Relative residual at which a contact solve with an "
                        "unchanged active set counts as converged.");
      prm.declare_entry("Max iterations",
                        "50",
                        Patterns::Integer(1),
                        "Maximum number of active-set (Newton) iterations.");
      prm.declare_entry("Search distance",
                        "2",
                        Patterns::Double(0),
                        "Master faces farther than this (mm) from a slave "
                        "face are not coupled to it. Larger than any gap "
                        "that can close in one solve.");
      prm.declare_entry(
        "Coupling window",
        "0.05",
        Patterns::Double(0),
        "Problem = wear: each contact solve of a warm-started step (blocks "
        "after the first) integrates the mortar coupling only around the "
        "slave faces that come within this distance (mm) of the femur after "
        "the displacement of the step's previous solve (and the nodes of "
        "their faces). After the solve it checks that "
        "every face left out stayed at least half of it away; if not, the "
        "solve is repeated with the whole search distance. The results do "
        "not change, only the cost. 0: always the whole search distance.");
      prm.declare_entry("Initial contact distance",
                        "0.01",
                        Patterns::Double(0),
                        "Slave nodes whose initial gap exceeds the smallest "
                        "by at most this (mm) start in the active set (when "
                        "there is no warm start). Problem = contact raises it "
                        "to half the approach of the Femur displacement "
                        "beyond the smallest gap (the edge of Hertz's "
                        "contact zone), which saves Newton steps.");
      prm.declare_entry("Overlap tolerance",
                        "0.05",
                        Patterns::Double(0),
                        "The bodies may overlap by at most this (mm) in the "
                        "initial geometry; more is refused as a mesh error.");
    }
    prm.leave_subsection();
  }

  void
  ContactSolver::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Contact solver");
    {
      const std::string name = prm.get("Solver");
      algorithm =
        (name == "ipopt"      ? ContactAlgorithm::ipopt :
         name == "active set" ? ContactAlgorithm::active_set :
         name == "condensed active set" ?
                                ContactAlgorithm::condensed_active_set :
                                ContactAlgorithm::automatic);
      tolerance                = prm.get_double("Tolerance");
      max_iterations           = prm.get_integer("Max iterations");
      search_distance          = prm.get_double("Search distance");
      coupling_window          = prm.get_double("Coupling window");
      initial_contact_distance = prm.get_double("Initial contact distance");
      overlap_tolerance        = prm.get_double("Overlap tolerance");
    }
    prm.leave_subsection();
  }

  void
  Verification::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Verification");
    {
      prm.declare_entry("Analytic solution",
                        "none",
                        Patterns::Selection("none|hertz sphere|hertz cylinder"),
                        "(Problem = contact) Compare the contact pressure "
                        "with Hertz's solution for the computed contact "
                        "force: a sphere on a half-space, or a cylinder (axis "
                        "along x) on a half-space in plane strain.");
      prm.declare_entry("Radius",
                        "20",
                        Patterns::Double(0),
                        "Radius of the sphere or cylinder, mm.");
      prm.declare_entry("Cylinder length",
                        "10",
                        Patterns::Double(0),
                        "Length of the cylinder along x, mm (the force per "
                        "length is the contact force over it).");
      prm.declare_entry(
        "Hertz tolerance",
        "0.05",
        Patterns::Double(0),
        "(Analytic solution = hertz ...) The comparison passes when the "
        "fitted contact radius (half-width) and the fitted peak pressure "
        "lie within this fraction of Hertz's values; the screen and "
        "summary.json (hertz_within_tolerance) say whether they do "
        "(doc/verification.md lists what each mesh reaches).");
      prm.declare_entry(
        "Cross-check with Ipopt",
        "false",
        Patterns::Bool(),
        "(Problem = contact, Solver = (condensed) active set, one MPI "
        "rank) Solve the same discrete problem again with "
        "Ipopt and report the largest differences of "
        "displacement and pressure.");
    }
    prm.leave_subsection();
  }

  void
  Verification::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Verification");
    {
      const std::string name = prm.get("Analytic solution");
      analytic_solution =
        (name == "hertz sphere"   ? AnalyticSolution::hertz_sphere :
         name == "hertz cylinder" ? AnalyticSolution::hertz_cylinder :
                                    AnalyticSolution::none);
      radius                 = prm.get_double("Radius");
      cylinder_length        = prm.get_double("Cylinder length");
      hertz_tolerance        = prm.get_double("Hertz tolerance");
      cross_check_with_ipopt = prm.get_bool("Cross-check with Ipopt");
    }
    prm.leave_subsection();
  }

  void
  LinearSolver::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Linear solver");
    {
      prm.declare_entry("Tolerance",
                        "1e-10",
                        Patterns::Double(0),
                        "Relative residual reduction of the CG solver.");
      prm.declare_entry(
        "Newton step tolerance",
        "1e-6",
        Patterns::Double(0),
        "Relative CG residual of the Newton steps of the AMG-CG active set "
        "(Contact solver/Solver = active set) that only decide the next "
        "active set (inexact Newton). A step is solved on to Tolerance when "
        "the active set does not change (its solution is the result) or "
        "when the sign of a node's complementarity function is not yet "
        "certain at this accuracy. Values at or below Tolerance solve every "
        "step to Tolerance.");
      prm.declare_entry("Max iterations",
                        "2000",
                        Patterns::Integer(1),
                        "Maximum number of CG iterations.");
      prm.declare_entry("Rigid body modes",
                        "true",
                        Patterns::Bool(),
                        "Give Trilinos ML the six rigid-body modes as "
                        "near-null space (false: the three translations).");
      prm.declare_entry("AMG aggregation threshold",
                        "0.02",
                        Patterns::Double(0),
                        "Trilinos ML aggregation threshold: matrix entries "
                        "weaker than this (relative) are dropped when "
                        "building aggregates.");
      prm.declare_entry("AMG smoother sweeps",
                        "2",
                        Patterns::Integer(1),
                        "Degree of the Chebyshev smoother of Trilinos ML.");
    }
    prm.leave_subsection();
  }

  void
  LinearSolver::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Linear solver");
    {
      tolerance             = prm.get_double("Tolerance");
      newton_step_tolerance = prm.get_double("Newton step tolerance");
      max_iterations        = prm.get_integer("Max iterations");
      rigid_body_modes      = prm.get_bool("Rigid body modes");
      aggregation_threshold = prm.get_double("AMG aggregation threshold");
      smoother_sweeps       = prm.get_integer("AMG smoother sweeps");
    }
    prm.leave_subsection();
  }

  void
  AllParameters::declare_parameters(ParameterHandler &prm)
  {
    prm.declare_entry("Problem",
                      "wear",
                      Patterns::Selection("wear|contact|elasticity|study"),
                      "wear: the ISO 14243-1 wear run; contact: one static "
                      "contact solve; elasticity: both bodies loaded "
                      "separately, without contact (demonstration); study: "
                      "many variants of a wear run (subsection Study, "
                      "doc/studies.md).");
    Mesh::declare_parameters(prm);
    Materials::declare_parameters(prm);
    Elasticity::declare_parameters(prm);
    StaticContact::declare_parameters(prm);
    Gait::declare_parameters(prm);
    Wear::declare_parameters(prm);
    ContactSolver::declare_parameters(prm);
    LinearSolver::declare_parameters(prm);
    Output::declare_parameters(prm);
    Verification::declare_parameters(prm);
    Study::declare_parameters(prm);
  }

  void
  AllParameters::parse_parameters(ParameterHandler &prm)
  {
    const std::string name = prm.get("Problem");
    problem                = (name == "wear"    ? ProblemType::wear :
                              name == "contact" ? ProblemType::contact :
                              name == "study"   ? ProblemType::study :
                                                  ProblemType::elasticity);
    mesh.parse_parameters(prm);
    materials.parse_parameters(prm);
    elasticity.parse_parameters(prm);
    static_contact.parse_parameters(prm);
    gait.parse_parameters(prm);
    wear.parse_parameters(prm);
    contact_solver.parse_parameters(prm);
    linear_solver.parse_parameters(prm);
    output.parse_parameters(prm);
    verification.parse_parameters(prm);
    study.parse_parameters(prm);
  }

  void
  Study::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Study");
    {
      prm.declare_entry("Base parameter file",
                        "",
                        Patterns::Anything(),
                        "Problem = study: the parameter file of the wear run "
                        "whose variants are the cases (Problem = wear). Each "
                        "case runs it with its entries overridden, in "
                        "<Output/Directory of the study>/case-NNNN.");
      prm.declare_entry(
        "Grid",
        "",
        Patterns::Anything(),
        "Full-factorial factors separated by ';', each PATH = v1, v2, ... "
        "with PATH an entry of the base file as Subsection/Entry (e.g. "
        "Wear/Wear coefficient, Materials/Tibia/Young's modulus), "
        "PATH[i] for component i of a vector entry (e.g. Gait/Flexion axis "
        "point[1]). PATH += v adds v to the base value, PATH *= v "
        "multiplies it. A factor with one value sets that entry in every "
        "case.");
      prm.declare_entry("Cases file",
                        "",
                        Patterns::Anything(),
                        "CSV file of cases: a header of entry paths (as in "
                        "Grid, plain values), one row per case. Empty: "
                        "none.");
      prm.declare_entry("Sampling",
                        "none",
                        Patterns::Selection("none|latin hypercube|monte carlo"),
                        "How the samples of Distributions are drawn: latin "
                        "hypercube (each entry's range cut into Samples "
                        "strata of equal probability, one sample in each, "
                        "strata paired at random) or monte carlo "
                        "(independent samples). Reproducible from Seed.");
      prm.declare_entry("Samples",
                        "0",
                        Patterns::Integer(0),
                        "Number of samples (Sampling other than none).");
      prm.declare_entry("Seed",
                        "1",
                        Patterns::Integer(0),
                        "Seed of the random numbers (mt19937_64): the same "
                        "seed gives the same samples on any machine.");
      prm.declare_entry(
        "Distributions",
        "",
        Patterns::Anything(),
        "Per sampled entry a distribution, separated by ';': PATH = "
        "uniform(a, b), normal(mean, sd) or log-normal(mu, sigma) (mu, "
        "sigma of ln X); PATH += ... and PATH *= ... add the sample to or "
        "multiply the base value (e.g. Wear/Wear coefficient *= "
        "uniform(0.8, 1.2)).");
      prm.declare_entry("Ranks per case",
                        "1",
                        Patterns::Integer(1),
                        "MPI ranks that run one case together; the job's "
                        "ranks form groups of this size that take cases "
                        "from a shared queue until none is left.");
      prm.declare_entry(
        "Mesh generator",
        "",
        Patterns::Anything(),
        "A program that writes each case's mesh, e.g. "
        "meshes/gen/tkr_variant.py (the parametric TKR). Called per case "
        "as GENERATOR ARGUMENTS --set NAME=VALUE ... -o case-NNNN/mesh.msh "
        "--prm case-NNNN/mesh.prm, with NAME=VALUE for every Generator/NAME "
        "entry of the case; mesh.prm (the mesh file and the flexion axis) is "
        "included after the base file. GENERATOR ARGUMENTS --print lists "
        "the base values as NAME=VALUE lines. Empty: none.");
      prm.declare_entry("Mesh generator arguments",
                        "",
                        Patterns::Anything(),
                        "The generator's fixed arguments, e.g. --variant a "
                        "--resolution coarse.");
    }
    prm.leave_subsection();
  }

  void
  Study::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Study");
    {
      base_file                = prm.get("Base parameter file");
      grid                     = prm.get("Grid");
      cases_file               = prm.get("Cases file");
      sampling                 = prm.get("Sampling");
      samples                  = prm.get_integer("Samples");
      seed                     = prm.get_integer("Seed");
      distributions            = prm.get("Distributions");
      ranks_per_case           = prm.get_integer("Ranks per case");
      mesh_generator           = prm.get("Mesh generator");
      mesh_generator_arguments = prm.get("Mesh generator arguments");
    }
    prm.leave_subsection();
  }

  // ParameterHandler reads the text with the includes expanded
  // (internal::ParameterText) and reports a bad line with an exception
  // whose message names the line ("Line <7> of file <x.prm>: ..."). We
  // keep that message with the file and line the text came from, drop
  // deal.II's stack-trace header, and add the hint where to find the valid
  // entries. Relative paths are taken from the directory of the file that
  // sets them (then the working directory, then the sources' bundled
  // data).
  AllParameters
  read_parameters(const std::string &filename)
  {
    const internal::ParameterText text(filename);
    ParameterHandler              prm;
    AllParameters::declare_parameters(prm);
    try
      {
        std::istringstream in(text.text());
        prm.parse_input(in, filename);
      }
    catch (const ExceptionBase &exc)
      {
        AssertThrow(false,
                    ExcInputError(
                      text.locate(exception_message(exc)) +
                      "\n(tkr-wear --print-parameters lists every valid "
                      "entry with its documentation.)"));
      }
    AllParameters parameters;
    try
      {
        parameters.parse_parameters(prm);
      }
    catch (const ExcInputError &exc)
      {
        AssertThrow(false,
                    ExcInputError("Error in the parameter file <" + filename +
                                  ">: " + exception_message(exc)));
      }
    parameters.parameter_file = filename;
    parameters.entries        = internal::list_entries(prm);
    const auto resolve = [&](std::string &path, const std::string &entry) {
      path = internal::resolve_path(path, text.directory_of(entry));
      parameters.entries[entry] = path;
    };
    resolve(parameters.mesh.file, "Mesh/File");
    resolve(parameters.gait.waveform_file, "Gait/Waveform file");
    resolve(parameters.wear.cross_shear_table, "Wear/Cross-shear table");
    resolve(parameters.wear.run_in_file, "Wear/Run-in file");
    resolve(parameters.output.measured_mass_loss_file,
            "Output/Measured mass loss file");
    resolve(parameters.study.base_file, "Study/Base parameter file");
    resolve(parameters.study.cases_file, "Study/Cases file");
    resolve(parameters.study.mesh_generator, "Study/Mesh generator");
    for (const auto &entry : parameters.entries)
      if (const std::string place = text.place_of(entry.first); !place.empty())
        parameters.places[entry.first] = place;
    return parameters;
  }

  void
  print_default_parameters(std::ostream &out)
  {
    ParameterHandler prm;
    AllParameters::declare_parameters(prm);
    prm.print_parameters(out, ParameterHandler::PRM);
  }

  std::string
  to_string(const ProblemType problem)
  {
    switch (problem)
      {
        case ProblemType::wear:
          return "wear";
        case ProblemType::contact:
          return "contact";
        case ProblemType::elasticity:
          return "elasticity";
        case ProblemType::study:
          return "study";
      }
    return "";
  }
} // namespace TKR::Parameters
