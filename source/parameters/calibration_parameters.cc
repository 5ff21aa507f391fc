// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

// `subsection Calibration` (Problem = calibration, doc/calibration.md).

#include <deal.II/base/utilities.h>

#include <tkr/base/exceptions.h>
#include <tkr/parameters/parameters.h>

#include "model_kinds.h"
#include "parameter_file.h"

namespace TKR::Parameters
{
  using namespace dealii;

  namespace
  {
    /** The `BASE: MEASURED` pairs of @p designs, trimmed. */
    std::vector<std::pair<std::string, std::string>>
    design_pairs(const std::string &designs)
    {
      std::vector<std::pair<std::string, std::string>> pairs;
      for (const std::string &design :
           Utilities::split_string_list(designs, ';'))
        {
          if (design.empty())
            continue;
          const std::vector<std::string> parts =
            Utilities::split_string_list(design, ':');
          AssertThrow(parts.size() == 2 && !parts[0].empty() &&
                        !parts[1].empty(),
                      ExcInputError(
                        "Calibration/Designs: <" + design +
                        "> is not BASE.prm: MEASURED.csv (a wear run's "
                        "parameter file and its measured mass loss, "
                        "data/measured/README.md; designs separated by ';')."));
          pairs.emplace_back(parts[0], parts[1]);
        }
      return pairs;
    }
  } // namespace

  std::string
  Calibration::resolve_designs(const std::string &designs,
                               const std::string &directory)
  {
    std::string resolved;
    for (const auto &[base, measured] : design_pairs(designs))
      resolved += (resolved.empty() ? "" : "; ") +
                  internal::resolve_path(base, directory) + ": " +
                  internal::resolve_path(measured, directory);
    return resolved;
  }

  void
  Calibration::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Calibration");
    {
      prm.declare_entry(
        "Designs",
        "",
        Patterns::Anything(),
        "Problem = calibration: the designs whose measured mass loss the "
        "model is fitted to, BASE.prm: MEASURED.csv separated by ';'. BASE "
        "is a wear run (Problem = wear) of the design, MEASURED its "
        "gravimetric data (data/measured/README.md: cycles, mass_mg, "
        "specimen). The fitted entries are shared by all designs. Relative "
        "paths are taken from this file's directory.");
      // the rate entry of every wear law that has one (ModelEntries::rate)
      std::string rate_entries, rate_laws;
      for (const auto &[law, entry] : internal::wear_laws().rate_entries())
        {
          rate_entries += entry + "|";
          rate_laws += (rate_laws.empty() ? "" : ", ") + law + ": " + entry;
        }
      prm.declare_entry(
        "Fit",
        "Wear/Archard/Wear coefficient",
        Patterns::MultipleSelection(rate_entries +
                                    "Run-in factor|Run-in length"),
        "What is fitted (least squares on the mass loss): the entry that "
        "scales the designs' wear law's rate (" +
          rate_laws +
          "; at most one, the designs' law's), the "
          "run-in's initial factor "
          "and its length (the run-in falls linearly from the factor at 0 "
          "cycles to 1 at the length; written as the run-in file of "
          "calibrated.prm). Entries not fitted keep the base files' values.");
      prm.declare_entry("Run-in factor",
                        "2",
                        Patterns::Double(0),
                        "The run-in's initial factor: the start of the fit, "
                        "or its value if only the Run-in length is fitted.");
      prm.declare_entry("Run-in length",
                        "1e6",
                        Patterns::Double(1),
                        "The run-in's length (cycles): the start of the "
                        "fit, or its value if only the Run-in factor is "
                        "fitted. Fitting the run-in needs measured points "
                        "within this many cycles.");
      prm.declare_entry("Confidence level",
                        "0.95",
                        Patterns::Double(0.5, 0.9999),
                        "The level of the fitted values' confidence "
                        "intervals (Student's t over the specimens' own "
                        "fits; doc/calibration.md).");
      prm.declare_entry(
        "Tolerance",
        "0.01",
        Patterns::Double(0),
        "The fit is accepted when a wear run at the fitted values gives "
        "the masses the fit predicted, at every measured point within "
        "this fraction of the largest measured mass; otherwise it is "
        "fitted again on that run.");
      prm.declare_entry("Maximum runs",
                        "4",
                        Patterns::Integer(2),
                        "Wear runs per design at most (the first at the base "
                        "values, each further one at the values fitted so "
                        "far).");
    }
    prm.leave_subsection();
  }

  void
  Calibration::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Calibration");
    {
      designs.clear();
      for (const auto &[base, measured] : design_pairs(prm.get("Designs")))
        designs.push_back({base, measured});
      fit              = Utilities::split_string_list(prm.get("Fit"), ',');
      run_in_factor    = prm.get_double("Run-in factor");
      run_in_length    = prm.get_double("Run-in length");
      confidence_level = prm.get_double("Confidence level");
      tolerance        = prm.get_double("Tolerance");
      maximum_runs     = prm.get_integer("Maximum runs");
      AssertThrow(run_in_factor > 0,
                  ExcInputError("Calibration/Run-in factor must be positive "
                                "(a factor on the wear rate)."));
    }
    prm.leave_subsection();
  }
} // namespace TKR::Parameters
