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
  AllParameters::declare_parameters(ParameterHandler &prm)
  {
    prm.declare_entry("Problem",
                      "wear",
                      Patterns::Selection(
                        "wear|contact|elasticity|study|calibration|"
                        "optimisation"),
                      "wear: the ISO 14243-1 wear run; contact: one static "
                      "contact solve; elasticity: both bodies loaded "
                      "separately, without contact (demonstration); study: "
                      "many variants of a wear run (subsection Study, "
                      "doc/studies.md); calibration: fit the wear model to "
                      "measured mass loss (subsection Calibration, "
                      "doc/calibration.md); optimisation: the entries of a "
                      "wear run that minimise one of its results "
                      "(subsection Optimisation, doc/optimisation.md).");
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
    Calibration::declare_parameters(prm);
    Optimisation::declare_parameters(prm);
  }

  void
  AllParameters::parse_parameters(ParameterHandler &prm)
  {
    const std::string name = prm.get("Problem");
    problem                = (name == "wear"        ? ProblemType::wear :
                              name == "contact"     ? ProblemType::contact :
                              name == "study"       ? ProblemType::study :
                              name == "calibration" ? ProblemType::calibration :
                              name == "optimisation" ? ProblemType::optimisation :
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
    calibration.parse_parameters(prm);
    optimisation.parse_parameters(prm);
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
        "Wear/Archard/Wear coefficient, Materials/Tibia/Young's modulus), "
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
        "multiply the base value (e.g. Wear/Archard/Wear coefficient *= "
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

  namespace internal
  {
    void
    parse_text(ParameterHandler    &prm,
               const ParameterText &text,
               const std::string   &filename)
    {
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
      std::vector<std::string> files = {"Mesh/File",
                                        "Gait/Waveform file",
                                        "Wear/Run-in file",
                                        "Output/Measured mass loss file",
                                        "Study/Base parameter file",
                                        "Study/Cases file",
                                        "Study/Mesh generator",
                                        "Optimisation/Base parameter file",
                                        "Optimisation/Mesh generator"};
      for (const std::string &entry : model_file_entries())
        files.push_back(entry);
      for (const std::string &entry : files)
        set_entry(prm,
                  entry,
                  resolve_path(get_entry(prm, entry),
                               text.directory_of(entry)));
      set_entry(
        prm,
        "Calibration/Designs",
        Calibration::resolve_designs(get_entry(prm, "Calibration/Designs"),
                                     text.directory_of("Calibration/Designs")));
      for (const std::string entry :
           {"Gait/Activities", "Optimisation/Scenarios"})
        set_entry(prm,
                  entry,
                  Activity::resolve_files(get_entry(prm, entry),
                                          text.directory_of(entry)));
    }
  } // namespace internal

  // ParameterHandler reads the text with the includes expanded
  // (internal::ParameterText) and reports a bad line with an exception
  // whose message names the line ("Line <7> of file <x.prm>: ..."). We
  // keep that message with the file and line the text came from, drop
  // deal.II's stack-trace header, and add the hint where to find the valid
  // entries. Relative paths are taken from the directory of the file that
  // sets them (then the working directory, then the sources' bundled
  // data). An activity mix reads each activity's file on top of this one.
  AllParameters
  read_parameters(const std::string &filename)
  {
    const internal::ParameterText text(filename, moved_entries());
    ParameterHandler              prm;
    AllParameters::declare_parameters(prm);
    internal::parse_text(prm, text, filename);
    AllParameters parameters;
    try
      {
        parameters.parse_parameters(prm);
        parameters.mix = internal::read_mix(filename, parameters.gait);
      }
    catch (const ExcInputError &exc)
      {
        AssertThrow(false,
                    ExcInputError("Error in the parameter file <" + filename +
                                  ">: " + exception_message(exc)));
      }
    parameters.parameter_file = filename;
    parameters.entries        = internal::list_entries(prm);
    parameters.notes          = text.moved_notes();
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
        case ProblemType::calibration:
          return "calibration";
        case ProblemType::optimisation:
          return "optimisation";
      }
    return "";
  }
} // namespace TKR::Parameters
