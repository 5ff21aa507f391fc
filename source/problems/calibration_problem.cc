// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <deal.II/base/mpi.h>
#include <deal.II/base/utilities.h>

#include <tkr/base/atomic_file.h>
#include <tkr/base/exceptions.h>
#include <tkr/output/summary.h>
#include <tkr/output/wear_output.h>
#include <tkr/problems/calibration_problem.h>
#include <tkr/problems/study_cases.h>
#include <tkr/problems/wear_problem.h>
#include <tkr/wear/wear_law.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <set>
#include <sstream>

namespace TKR::Problems
{
  using namespace dealii;
  using Calibration::Point;

  namespace
  {
    /** Per wear law, the entry that scales its rate: the "k" of
     *  tau = k F(c) (each law names its own, ModelEntries::rate). */
    std::map<std::string, std::string>
    rate_entries()
    {
      return Wear::WearLaws::kind().rate_entries();
    }


    /** The measured points of one file (data/measured/README.md). */
    struct Measured
    {
      std::vector<std::string> specimens;
      /** (specimen, cycles, mass) */
      std::vector<std::tuple<unsigned int, double, double>> rows;
      bool illustrative = false;
    };

    double
    measured_number(const std::string &field,
                    const std::string &where,
                    const std::string &column)
    {
      std::size_t end   = 0;
      double      value = 0;
      try
        {
          value = std::stod(field, &end);
        }
      catch (const std::exception &)
        {
          end = 0;
        }
      AssertThrow(end > 0 && end == field.size() && std::isfinite(value),
                  ExcInputError(where + "<" + field + "> in column <" + column +
                                "> is not a finite number."));
      return value;
    }

    Measured
    read_measured(const std::string &file)
    {
      std::ifstream in(file);
      AssertThrow(in,
                  ExcInputError("Calibration/Designs: cannot open the "
                                "measured data file <" +
                                file + ">."));
      Measured                 measured;
      std::vector<std::string> header;
      int         cycles = -1, mass = -1, specimen = -1, other = -1;
      std::string line;
      for (unsigned int line_number = 1; std::getline(in, line); ++line_number)
        {
          line = Utilities::trim(line);
          if (line.empty() || line[0] == '#')
            {
              std::transform(line.begin(), line.end(), line.begin(), ::tolower);
              measured.illustrative |=
                line.find("illustrative") != std::string::npos;
              continue;
            }
          const std::vector<std::string> fields =
            Utilities::split_string_list(line, ',');
          const std::string where =
            "Line <" + std::to_string(line_number) + "> of <" + file + ">: ";
          if (header.empty())
            {
              header = fields;
              for (unsigned int i = 0; i < header.size(); ++i)
                (header[i] == "cycles"   ? cycles :
                 header[i] == "mass_mg"  ? mass :
                 header[i] == "specimen" ? specimen :
                                           other) = i;
              AssertThrow(cycles >= 0 && mass >= 0,
                          ExcInputError(where + "the header needs the "
                                                "columns cycles and mass_mg "
                                                "(and optionally specimen; "
                                                "data/measured/README.md)."));
              continue;
            }
          AssertThrow(fields.size() == header.size(),
                      ExcInputError(where + "has " +
                                    std::to_string(fields.size()) +
                                    " fields, the header " +
                                    std::to_string(header.size()) + "."));
          const std::string name  = specimen >= 0 ? fields[specimen] : "";
          const auto        found = std::find(measured.specimens.begin(),
                                       measured.specimens.end(),
                                       name);
          if (found == measured.specimens.end())
            measured.specimens.push_back(name);
          const double c = measured_number(fields[cycles], where, "cycles");
          AssertThrow(c >= 0, ExcInputError(where + "cycles < 0."));
          measured.rows.emplace_back(std::find(measured.specimens.begin(),
                                               measured.specimens.end(),
                                               name) -
                                       measured.specimens.begin(),
                                     c,
                                     measured_number(fields[mass],
                                                     where,
                                                     "mass_mg"));
        }
      AssertThrow(!measured.rows.empty(),
                  ExcInputError("The measured data file <" + file +
                                "> has no points."));
      return measured;
    }
  } // namespace

  CalibrationProblem::CalibrationProblem(
    const Parameters::AllParameters &parameters,
    const MPI_Comm                   mpi_communicator)
    : parameters(parameters)
    , mpi_communicator(mpi_communicator)
    , is_root(Utilities::MPI::this_mpi_process(mpi_communicator) == 0)
  {
    const Parameters::Calibration &calibration = parameters.calibration;
    AssertThrow(!calibration.designs.empty(),
                ExcInputError("Problem = calibration needs Calibration/"
                              "Designs (BASE.prm: MEASURED.csv; ...)."));
    AssertThrow(!calibration.fit.empty(),
                ExcInputError("Calibration/Fit is empty: say what to fit."));
    for (const std::string &name : calibration.fit)
      if (name != "Run-in factor" && name != "Run-in length")
        {
          AssertThrow(rate_entry.empty(),
                      ExcInputError(
                        "Calibration/Fit names <" + rate_entry + "> and <" +
                        name +
                        ">: both scale the wear rate, the data cannot "
                        "tell them apart; fit the one of the designs' "
                        "wear law."));
          rate_entry = name;
        }
    for (const auto &files : calibration.designs)
      read_design(files);
    check_identifiable();
  }

  void
  CalibrationProblem::read_design(const Parameters::Calibration::Design &files)
  {
    Design design;
    design.base_file     = files.base_file;
    design.measured_file = files.measured_file;
    design.name          = std::filesystem::path(files.base_file).stem();
    for (unsigned int n = 2; std::any_of(designs.begin(),
                                         designs.end(),
                                         [&](const Design &other) {
                                           return other.name == design.name;
                                         });
         ++n)
      design.name = std::filesystem::path(files.base_file).stem().string() +
                    "-" + std::to_string(n);
    design.base = Parameters::read_parameters(files.base_file);
    AssertThrow(design.base.problem == Parameters::ProblemType::wear,
                ExcInputError("Calibration/Designs: <" + files.base_file +
                              "> is not a wear run (Problem = wear)."));
    const auto laws      = rate_entries();
    const auto law_entry = laws.find(design.base.wear.law);
    AssertThrow(rate_entry.empty() ||
                  (law_entry != laws.end() && law_entry->second == rate_entry),
                ExcInputError("Calibration/Fit names <" + rate_entry +
                              ">, but <" + files.base_file +
                              "> runs the wear law <" + design.base.wear.law +
                              ">, which does not use it."));
    if (law_entry != laws.end())
      design.coefficient = std::stod(design.base.entries.at(law_entry->second));
    if (!design.base.wear.run_in_file.empty())
      design.run_in = Wear::read_run_in(design.base.wear.run_in_file);

    const Measured measured     = read_measured(files.measured_file);
    design.illustrative         = measured.illustrative;
    design.specimens            = measured.specimens;
    unsigned int first_specimen = 0;
    for (const Design &other : designs)
      first_specimen += other.specimens.size();
    for (const auto &[specimen, cycles, mass] : measured.rows)
      {
        points.push_back({static_cast<unsigned int>(designs.size()),
                          first_specimen + specimen,
                          cycles,
                          mass});
        design.end_cycles = std::max(design.end_cycles, cycles);
        largest_mass      = std::max(largest_mass, mass);
      }
    designs.push_back(design);
  }

  void
  CalibrationProblem::check_identifiable() const
  {
    const Parameters::Calibration &calibration = parameters.calibration;
    const auto                     fits        = [&](const std::string &name) {
      return std::count(calibration.fit.begin(), calibration.fit.end(), name) >
             0;
    };
    std::vector<std::string> missing;
    for (unsigned int d = 0; d < designs.size(); ++d)
      if (designs[d].end_cycles <= 0)
        missing.push_back("<" + designs[d].measured_file +
                          "> has no point after 0 cycles");
    std::set<double> cycles, in_run_in, after_run_in;
    for (const Point &point : points)
      if (point.cycles > 0)
        {
          cycles.insert(point.cycles);
          (point.cycles < calibration.run_in_length ? in_run_in : after_run_in)
            .insert(point.cycles);
        }
    if (cycles.size() < calibration.fit.size())
      missing.push_back(std::to_string(calibration.fit.size()) +
                        " fitted entries need weighings at as many cycle "
                        "counts; there are " +
                        std::to_string(cycles.size()));
    const bool factor = fits("Run-in factor"), length = fits("Run-in length");
    if ((factor || length) && in_run_in.empty())
      missing.push_back(
        "fitting the run-in's " +
        std::string(factor && length ? "factor and length" :
                    factor           ? "factor" :
                                       "length") +
        " needs weighings during the run-in (after 0 and before "
        "Calibration/Run-in length = " +
        format_number(calibration.run_in_length, 10) +
        " cycles); there are none");
    if (length && after_run_in.empty())
      missing.push_back("fitting the run-in's length needs weighings after "
                        "it (from " +
                        format_number(calibration.run_in_length, 10) +
                        " cycles on)");
    std::string list, fit;
    for (const std::string &item : missing)
      list += (list.empty() ? "" : "; ") + item;
    for (const std::string &name : calibration.fit)
      fit += (fit.empty() ? "" : ", ") + name;
    AssertThrow(missing.empty(),
                ExcInputError("Calibration: the measured data cannot "
                              "determine Calibration/Fit = " +
                              fit + ": " + list +
                              ". Add the missing points or fit fewer "
                              "entries."));
  }

  CalibrationProblem::Values
  CalibrationProblem::values(const std::vector<double> &x) const
  {
    Values       values;
    unsigned int i       = 0;
    values.coefficient   = 0;
    values.run_in_factor = parameters.calibration.run_in_factor;
    values.run_in_length = parameters.calibration.run_in_length;
    for (const std::string &name : parameters.calibration.fit)
      {
        (name == rate_entry      ? values.coefficient :
         name == "Run-in factor" ? values.run_in_factor :
                                   values.run_in_length) = x[i++];
        values.fitted_run_in |= name != rate_entry;
      }
    return values;
  }

  double
  CalibrationProblem::effective_cycles(const Values      &values,
                                       const unsigned int d,
                                       const double       c) const
  {
    if (values.fitted_run_in)
      return Calibration::run_in_integral(values.run_in_factor,
                                          values.run_in_length,
                                          c);
    return designs[d].run_in.empty() ? c : designs[d].run_in.integral(0, c);
  }

  std::vector<Calibration::MassCurve>
  CalibrationProblem::run_round(const unsigned int         round,
                                const std::vector<double> &x)
  {
    const Values                        at = values(x);
    std::vector<Calibration::MassCurve> curves;
    for (unsigned int d = 0; d < designs.size(); ++d)
      {
        const Design     &design    = designs[d];
        const std::string directory = parameters.output.directory + "/run-" +
                                      std::to_string(round + 1) + "/" +
                                      design.name;
        Output::create_directory(directory, mpi_communicator);
        std::map<std::string, std::string> entries = {
          {"Wear/Cycles", format_number(design.end_cycles, 10)},
          {"Output/Directory", directory},
          {"Output/Plots", "false"},
          {"Output/VTU interval", "0"}};
        std::string described;
        if (at.coefficient > 0)
          {
            entries[rate_entry] = format_number(at.coefficient, 12);
            described += rate_entry + " = " + format_number(at.coefficient, 6);
          }
        if (at.fitted_run_in)
          {
            entries["Wear/Run-in file"] = directory + "/run-in.csv";
            described += std::string(described.empty() ? "" : ", ") +
                         "run-in " + format_number(at.run_in_factor, 6) +
                         " to 1 at " + format_number(at.run_in_length, 6) +
                         " cycles";
            if (is_root)
              write_atomically(directory + "/run-in.csv",
                               "cycles,factor\n0," +
                                 format_number(at.run_in_factor, 12) + "\n" +
                                 format_number(at.run_in_length, 12) + ",1\n");
          }
        if (is_root)
          {
            write_atomically(directory + "/case.prm",
                             case_parameter_text(design.base_file,
                                                 {},
                                                 entries,
                                                 "Calibration run " +
                                                   std::to_string(round + 1) +
                                                   " of " + design.name));
            std::cout << "Calibration run " << round + 1 << " of "
                      << design.name << " (" << directory << "/log.txt)"
                      << (described.empty() ? "" : ": " + described)
                      << std::endl;
          }
        MPI_Barrier(mpi_communicator);
        const double          start  = MPI_Wtime();
        const Wear::RunResult result = run_wear(directory, round, design.name);
        std::vector<double>   tau, mass;
        const double          k =
          at.coefficient > 0 ? at.coefficient : design.coefficient;
        for (const Wear::BlockResult &block : result.history)
          {
            tau.push_back(k * effective_cycles(at, d, block.cycles));
            mass.push_back(block.mass);
          }
        curves.emplace_back(tau, mass);
        if (is_root)
          std::cout << "  " << format_number(result.history.back().mass, 6)
                    << " mg after " << format_number(result.cycles, 6)
                    << " cycles, " << result.blocks << " blocks, "
                    << std::setprecision(3) << std::fixed << MPI_Wtime() - start
                    << " s" << std::defaultfloat << std::endl;
      }
    return curves;
  }

  Wear::RunResult
  CalibrationProblem::run_wear(const std::string &directory,
                               const unsigned int round,
                               const std::string &name) const
  {
    Wear::RunResult result;
    bool            converged = false;
    {
      CaseOutput output(directory + "/log.txt", is_root);
      // The problem keeps references into its parameters.
      const Parameters::AllParameters run_parameters =
        Parameters::read_parameters(directory + "/case.prm");
      WearProblem problem(run_parameters, mpi_communicator);
      converged = problem.run();
      result    = problem.result();
    }
    AssertThrow(converged,
                ExcInputError("Calibration run " + std::to_string(round + 1) +
                              " of " + name + " did not converge (" +
                              directory +
                              "/log.txt, summary.json): the fit cannot "
                              "use it."));
    return result;
  }

  double
  CalibrationProblem::predict(const std::vector<Calibration::MassCurve> &curves,
                              const std::vector<double>                 &x,
                              const Point &point) const
  {
    const Values at = values(x);
    const double k =
      at.coefficient > 0 ? at.coefficient : designs[point.design].coefficient;
    return curves[point.design](
      k * effective_cycles(at, point.design, point.cycles));
  }

  Calibration::FitResult
  CalibrationProblem::fit_on(const std::vector<Calibration::MassCurve> &curves,
                             const std::vector<Point>  &fit_points,
                             const std::vector<double> &start) const
  {
    Calibration::FitResult result = Calibration::fit(
      fit_points,
      [&](const std::vector<double> &x, const Point &point) {
        return predict(curves, x, point);
      },
      start,
      parameters.calibration.fit);
    // The same values on every rank (the runs' histories agree to the
    // last digit, but the fit should not depend on it).
    result.x = Utilities::MPI::broadcast(mpi_communicator, result.x, 0);
    return result;
  }
} // namespace TKR::Problems
