// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <tkr/parameters/parameters.h>

namespace TKR::Parameters
{
  using namespace dealii;

  void
  Optimisation::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Optimisation");
    {
      prm.declare_entry("Base parameter file",
                        "",
                        Patterns::Anything(),
                        "Problem = optimisation: the parameter file of the "
                        "wear run (Problem = wear) whose entries the "
                        "variables set. Evaluation i runs it with their "
                        "values in <Output/Directory>/eval-NNNN.");
      prm.declare_entry(
        "Variables",
        "",
        Patterns::Anything(),
        "The variables, separated by ';': PATH = LOWER .. UPPER, or PATH = "
        "LOWER .. UPPER log (searched in the logarithm: positive bounds), "
        "PATH an entry of the base file as a study names it (Subsection/"
        "Entry, PATH[i] for a component, Generator/NAME for a parameter of "
        "the Mesh generator). The start is the base file's value, which must "
        "lie within the bounds.");
      prm.declare_entry("Objective",
                        "minimise volume_loss_mm3",
                        Patterns::Anything(),
                        "minimise KEY or maximise KEY: KEY a number of the "
                        "wear run's summary.json (doc/output.md).");
      prm.declare_entry("Constraints",
                        "",
                        Patterns::Anything(),
                        "KEY <= VALUE or KEY >= VALUE, separated by ';', KEY "
                        "a number of summary.json (e.g. max_pressure_MPa <= "
                        "25). A failed evaluation violates every one. Empty: "
                        "none.");
      prm.declare_entry("Method",
                        "cobyla",
                        Patterns::Selection("cobyla|bobyqa"),
                        "NLopt's derivative-free method: cobyla (Powell's "
                        "linear approximations; bounds and constraints) or "
                        "bobyqa (Powell's quadratic models; bounds only).");
      prm.declare_entry("Maximum evaluations",
                        "30",
                        Patterns::Integer(1),
                        "Wear runs at most.");
      prm.declare_entry("Tolerance",
                        "1e-3",
                        Patterns::Double(0),
                        "Stop when a step changes every variable by less "
                        "than this fraction of its range (NLopt's relative x "
                        "tolerance on the variables scaled to 0 .. 1).");
      prm.declare_entry("Initial step",
                        "0.25",
                        Patterns::Double(0, 1),
                        "The method's first step, a fraction of each "
                        "variable's range.");
      prm.declare_entry("Mesh generator",
                        "",
                        Patterns::Anything(),
                        "As Study/Mesh generator: a program that writes each "
                        "evaluation's mesh from its Generator/NAME "
                        "variables (e.g. meshes/gen/tkr_variant.py). Empty: "
                        "none.");
      prm.declare_entry("Mesh generator arguments",
                        "",
                        Patterns::Anything(),
                        "The generator's fixed arguments, e.g. --variant a "
                        "--resolution coarse.");
      prm.declare_entry(
        "Test function",
        "none",
        Patterns::Selection("none|quadratic"),
        "none: each evaluation is a wear run. quadratic: no wear run; the "
        "results are known functions of the variables' unit coordinates u "
        "(0 at the lower bound, 1 at the upper): mass_loss_mg = 1 + sum "
        "(u_i - 0.3)^2, max_pressure_MPa = 10 + 20 u_0 (a check of the "
        "method and the bookkeeping, doc/optimisation.md).");
    }
    prm.leave_subsection();
  }

  void
  Optimisation::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Optimisation");
    {
      base_file                = prm.get("Base parameter file");
      variables                = prm.get("Variables");
      objective                = prm.get("Objective");
      constraints              = prm.get("Constraints");
      method                   = prm.get("Method");
      maximum_evaluations      = prm.get_integer("Maximum evaluations");
      tolerance                = prm.get_double("Tolerance");
      initial_step             = prm.get_double("Initial step");
      mesh_generator           = prm.get("Mesh generator");
      mesh_generator_arguments = prm.get("Mesh generator arguments");
      test_function            = prm.get("Test function");
    }
    prm.leave_subsection();
  }
} // namespace TKR::Parameters
