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
        "Initial design",
        "0",
        Patterns::Integer(0),
        "Points of a Latin hypercube over the variables' bounds (in unit "
        "coordinates, the log ones in the logarithm) evaluated with the "
        "start before the method, in parallel over groups of Ranks per "
        "evaluation ranks; the method starts from the best of them. 0: the "
        "method starts from the start.");
      prm.declare_entry("Seed",
                        "2026",
                        Patterns::Integer(0),
                        "The seed of the initial design's random numbers "
                        "(std::mt19937_64, as a study's).");
      prm.declare_entry("Ranks per evaluation",
                        "1",
                        Patterns::Integer(0),
                        "Runs that can go at once (the initial design, the "
                        "scenarios of an evaluation, the verification) go "
                        "on groups of this many ranks (their step groups); "
                        "a run alone takes all ranks. 0: all ranks for "
                        "every run.");
      prm.declare_entry(
        "Scenarios",
        "",
        Patterns::Anything(),
        "Several designs or activities at once: NAME: WEIGHT: FILE, "
        "separated by ';', FILE a parameter file included after the base "
        "file (after the mesh generator's mesh.prm) in the scenario's run "
        "(e.g. another activity mix, load or size). Each evaluation runs "
        "every scenario, in eval-NNNN/NAME; the objective is combined by "
        "Combine scenarios, a constraint holds if it holds in every "
        "scenario. Empty: the base file alone.");
      prm.declare_entry("Combine scenarios",
                        "weighted sum",
                        Patterns::Selection("weighted sum|worst case"),
                        "The objective of an evaluation with Scenarios: the "
                        "sum of the scenarios' objectives times their "
                        "weights, or the worst of them (the largest to "
                        "minimise, the smallest to maximise; weights "
                        "unused).");
      prm.declare_entry(
        "Verification mesh generator arguments",
        "",
        Patterns::Anything(),
        "With a Mesh generator: its fixed arguments for the verification "
        "(e.g. --variant a --resolution medium, the next finer mesh). The "
        "start and the best design run again with them (and the "
        "Verification entries) in verify-start and verify-best, and both "
        "numbers are reported. Empty (and no Verification entries): no "
        "verification.");
      prm.declare_entry(
        "Verification entries",
        "",
        Patterns::Anything(),
        "Entries set in the verification runs, PATH = VALUE separated by "
        "';' (e.g. Mesh/File = tkr-a-medium.msh without a mesh generator). "
        "Empty (and no Verification mesh generator arguments): no "
        "verification.");
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
      initial_design           = prm.get_integer("Initial design");
      seed                     = prm.get_integer("Seed");
      ranks_per_evaluation     = prm.get_integer("Ranks per evaluation");
      scenarios                = prm.get("Scenarios");
      combine_scenarios        = prm.get("Combine scenarios");
      verification_generator_arguments =
        prm.get("Verification mesh generator arguments");
      verification_entries = prm.get("Verification entries");
    }
    prm.leave_subsection();
  }
} // namespace TKR::Parameters
