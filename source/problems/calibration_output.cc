// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

// CalibrationProblem: the rounds of runs and fits, the interval, the
// output files (doc/calibration.md).

#include <deal.II/base/mpi.h>
#include <deal.II/base/utilities.h>

#include <tkr/base/atomic_file.h>
#include <tkr/base/exceptions.h>
#include <tkr/base/result_schema.h>
#include <tkr/output/summary.h>
#include <tkr/output/wear_output.h>
#include <tkr/problems/calibration_problem.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <set>
#include <sstream>

namespace TKR::Problems
{
  using namespace dealii;
  using Calibration::MassCurve;
  using Calibration::Point;

  namespace
  {
    /** The key of a fitted entry in calibration.json. */
    std::string
    key(const std::string &name)
    {
      return name == "Run-in factor"                       ? "run_in_factor" :
             name == "Run-in length"                       ? "run_in_length" :
             name.find("Table scale") != std::string::npos ? "table_scale" :
                                                             "wear_coefficient";
    }

    std::string
    joined(const std::vector<std::string> &names)
    {
      std::string list;
      for (const std::string &name : names)
        list += (list.empty() ? "" : ", ") + name;
      return list;
    }

    // The keys of calibration.json.
    // clang-format off
    [[maybe_unused]] const bool declared = ResultSchema::declare(
      "calibration.json",
      10,
      {
      {"problem", "string", "-", {}, "`calibration`"},
      {"fit", "string", "-", {}, "the fitted entries (`Calibration/Fit`), comma-separated"},
      {"fitted", "object", "-", {}, "the fitted values by key: `wear_coefficient` or `table_scale`, `run_in_factor`, `run_in_length`, as fitted"},
      {"confidence_level", "number", "-", {}, "`Calibration/Confidence level` of the interval"},
      {"lower", "object", "-", {}, "the interval's lower ends, keys as `fitted`"},
      {"upper", "object", "-", {}, "the interval's upper ends, keys as `fitted`"},
      {"interval_from", "string", "-", {}, "how the interval was computed: Student's t over the specimens' own fits, or on the residuals of one specimen (doc/calibration.md)"},
      {"specimen_fits", "list", "-", {}, "each specimen's own fit (keys as `fitted`) where the interval comes from them, else empty"},
      {"designs", "integer", "-", {}, "designs calibrated on"},
      {"specimens", "integer", "-", {}, "specimens over all designs' measured files"},
      {"points", "integer", "-", {}, "measured points (every row of the measured files)"},
      {"rms_residual_mg", "number", "mg", {}, "root mean square over the points of measured minus computed mass loss (the last run, at the fitted values)"},
      {"runs_per_design", "integer", "-", {}, "wear runs of each design (the first one, then one per fit)"},
      {"verification_mismatch_percent", "number", "%", {}, "the largest difference at the points between the last run's mass loss at the fitted values and the fit's prediction, in % of the largest measured mass"},
      {"verified", "boolean", "-", {}, "`verification_mismatch_percent` is within `Calibration/Tolerance`"},
      {"illustrative_data", "boolean", "-", {}, "a comment line of a measured file says \"illustrative\""},
      {"fit_iterations", "integer", "-", {}, "iterations of the fit (a trace)", {}, true}});
    // clang-format on
  } // namespace

  bool
  CalibrationProblem::run()
  {
    const Parameters::Calibration &calibration = parameters.calibration;
    Output::create_directory(parameters.output.directory, mpi_communicator);
    std::vector<double> x;
    for (const std::string &name : calibration.fit)
      x.push_back(name == "Run-in factor" ? calibration.run_in_factor :
                  name == "Run-in length" ? calibration.run_in_length :
                                            designs[0].coefficient);
    std::vector<MassCurve> curves = run_round(0, x);
    Calibration::FitResult result = fit_on(curves, points, x);
    std::vector<MassCurve> check;
    double                 mismatch = 0;
    unsigned int           runs     = 1;
    while (true)
      {
        check = run_round(runs++, result.x);
        // The run at the fitted values against the fit's prediction.
        mismatch = 0;
        for (const Point &point : points)
          mismatch = std::max(mismatch,
                              std::abs(predict(check, result.x, point) -
                                       predict(curves, result.x, point)) /
                                largest_mass);
        if (is_root)
          std::cout << "  the masses of this run differ from the fit's "
                    << "prediction by at most "
                    << format_number(100 * mismatch, 3)
                    << " % of the largest measured mass (Tolerance "
                    << format_number(100 * calibration.tolerance, 3) << " %)"
                    << std::endl;
        if (mismatch <= calibration.tolerance ||
            runs >= calibration.maximum_runs)
          break;
        curves = check;
        result = fit_on(curves, points, result.x);
      }
    output_results(check, result, interval(curves, result), runs, mismatch);
    return mismatch <= calibration.tolerance;
  }

  unsigned int
  CalibrationProblem::n_specimens() const
  {
    unsigned int n = 0;
    for (const Design &design : designs)
      n += design.specimens.size();
    return n;
  }

  std::vector<std::vector<double>>
  CalibrationProblem::specimen_fits(const std::vector<MassCurve> &curves,
                                    const Calibration::FitResult &result) const
  {
    std::vector<std::vector<Point>> specimens(n_specimens());
    for (const Point &point : points)
      specimens[point.specimen].push_back(point);
    std::vector<std::vector<double>> fits;
    if (specimens.size() < 2)
      return fits;
    for (const std::vector<Point> &own : specimens)
      {
        std::set<double> cycles;
        for (const Point &point : own)
          if (point.cycles > 0)
            cycles.insert(point.cycles);
        if (cycles.size() < result.x.size())
          return {};
        try
          {
            fits.push_back(fit_on(curves, own, result.x).x);
          }
        catch (const ExcInputError &)
          {
            return {};
          }
      }
    return fits;
  }

  CalibrationProblem::Interval
  CalibrationProblem::interval(const std::vector<MassCurve> &curves,
                               const Calibration::FitResult &result) const
  {
    const unsigned int n          = result.x.size();
    const double       confidence = parameters.calibration.confidence_level;
    Interval           interval;
    interval.specimens           = specimen_fits(curves, result);
    const bool          own_fits = !interval.specimens.empty();
    std::vector<double> half(n);
    if (own_fits)
      {
        const double m = interval.specimens.size();
        const double t =
          Calibration::student_t_quantile((1 + confidence) / 2, m - 1);
        for (unsigned int i = 0; i < n; ++i)
          {
            double mean = 0, variance = 0;
            for (const auto &x : interval.specimens)
              mean += x[i] / m;
            for (const auto &x : interval.specimens)
              variance += (x[i] - mean) * (x[i] - mean) / (m - 1);
            half[i] = t * std::sqrt(variance / m);
          }
        interval.from = "Student's t over the " +
                        std::to_string(interval.specimens.size()) +
                        " specimens' own fits";
      }
    else
      {
        unsigned int used = 0;
        for (const Point &point : points)
          used += point.cycles > 0;
        AssertThrow(used > n,
                    ExcInputError("Calibration: " + std::to_string(used) +
                                  " measured points after 0 cycles cannot "
                                  "give a confidence interval of " +
                                  std::to_string(n) +
                                  " fitted entries; add points."));
        const double variance = result.sum_of_squares / (used - n);
        const double t =
          Calibration::student_t_quantile((1 + confidence) / 2, used - n);
        // Delta method: the fit runs in log x.
        for (unsigned int i = 0; i < n; ++i)
          half[i] = t * result.x[i] *
                    std::sqrt(variance * result.inverse_normal_matrix[i][i]);
        interval.from =
          "Student's t on the residuals (" +
          std::string(n_specimens() == 1 ?
                        "1 specimen: no scatter between specimens to use" :
                        "a specimen alone does not determine the fitted "
                        "entries") +
          ")";
      }
    for (unsigned int i = 0; i < n; ++i)
      {
        interval.lower.push_back(result.x[i] - half[i]);
        interval.upper.push_back(result.x[i] + half[i]);
      }
    return interval;
  }

  std::pair<std::vector<std::string>, std::string>
  CalibrationProblem::write_tables(const std::vector<MassCurve> &check,
                                   const Calibration::FitResult &result,
                                   const Interval               &interval) const
  {
    const std::string       &directory = parameters.output.directory;
    const unsigned int       n         = result.x.size();
    std::vector<std::string> specimen_names, design_of;
    for (const Design &design : designs)
      for (const std::string &specimen : design.specimens)
        {
          specimen_names.push_back(specimen.empty() ? "measured" : specimen);
          design_of.push_back(design.name);
        }

    // The residual of each point against the run at the fitted values.
    std::ostringstream table, screen;
    table << "design,specimen,cycles,measured_mg,computed_mg,residual_mg\n";
    for (const Point &point : points)
      {
        const double computed = predict(check, result.x, point);
        table << designs[point.design].name << ","
              << specimen_names[point.specimen] << ","
              << format_number(point.cycles, 10) << ","
              << format_number(point.mass, 10) << ","
              << format_number(computed, 10) << ","
              << format_number(point.mass - computed, 10) << "\n";
        screen << "  " << std::left << std::setw(22)
               << designs[point.design].name.substr(0, 21) << std::setw(18)
               << specimen_names[point.specimen].substr(0, 17) << std::right
               << std::setw(10) << format_number(point.cycles / 1e6, 4)
               << std::setw(11) << format_number(point.mass, 5) << std::setw(11)
               << format_number(computed, 5) << std::setw(10)
               << format_number(point.mass - computed, 3) << "\n";
      }
    write_atomically(directory + "/calibration.csv", table.str());

    // The fitted curve and the band of the interval's corners.
    std::ostringstream curve_table;
    curve_table << "design,cycles,fitted_mg,lower_mg,upper_mg\n";
    for (unsigned int d = 0; d < designs.size(); ++d)
      for (unsigned int j = 0; j <= 100; ++j)
        {
          const Point point{d, 0, designs[d].end_cycles * j / 100., 0};
          double      lower = predict(check, result.x, point), upper = lower;
          for (unsigned int corner = 0; corner < (1u << n); ++corner)
            {
              std::vector<double> x(n);
              for (unsigned int i = 0; i < n; ++i)
                x[i] = (corner >> i & 1) ?
                         interval.upper[i] :
                         std::max(interval.lower[i], 1e-3 * result.x[i]);
              lower = std::min(lower, predict(check, x, point));
              upper = std::max(upper, predict(check, x, point));
            }
          curve_table << designs[d].name << ","
                      << format_number(point.cycles, 10) << ","
                      << format_number(predict(check, result.x, point), 10)
                      << "," << format_number(lower, 10) << ","
                      << format_number(upper, 10) << "\n";
        }
    write_atomically(directory + "/calibration_curves.csv", curve_table.str());
    return {specimen_names, screen.str()};
  }

  void
  CalibrationProblem::output_results(const std::vector<MassCurve> &check,
                                     const Calibration::FitResult &result,
                                     const Interval               &interval,
                                     const unsigned int            runs,
                                     const double mismatch) const
  {
    if (!is_root)
      return;
    const Parameters::Calibration &calibration = parameters.calibration;
    const std::string             &directory   = parameters.output.directory;
    const unsigned int             n           = result.x.size();
    const auto [specimen_names, residuals] =
      write_tables(check, result, interval);
    double sum_of_squares = 0;
    for (const Point &point : points)
      sum_of_squares +=
        std::pow(point.mass - predict(check, result.x, point), 2);
    bool illustrative = false;
    for (const Design &design : designs)
      illustrative |= design.illustrative;
    const bool verified = mismatch <= calibration.tolerance;

    const double rms = std::sqrt(sum_of_squares / points.size());
    write_json(result, interval, runs, mismatch, rms, illustrative);
    write_calibrated_prm(result, illustrative);
    if (parameters.output.plots)
      if (const std::string failure =
            Output::run_script("plot-calibration",
                               {directory},
                               directory + "/plot-calibration.log",
                               MPI_COMM_SELF);
          !failure.empty())
        std::cout << "Warning: no calibration.png: " << failure << std::endl;

    std::cout << "\nCalibration of " << joined(calibration.fit) << " on "
              << points.size() << " measured points of "
              << specimen_names.size() << " specimen(s), " << designs.size()
              << " design(s), " << runs << " wear runs per design:\n";
    for (unsigned int i = 0; i < n; ++i)
      std::cout << "  " << std::left << std::setw(30) << calibration.fit[i]
                << std::right << " = " << format_number(result.x[i], 6) << "   "
                << format_number(100 * calibration.confidence_level, 3)
                << " % interval [" << format_number(interval.lower[i], 6)
                << ", " << format_number(interval.upper[i], 6) << "]\n";
    std::cout << "  (interval: " << interval.from << ")\n"
              << "  rms residual " << format_number(rms, 4)
              << " mg; the last run (at the fitted values) gives the masses "
              << "the fit predicted within " << format_number(100 * mismatch, 3)
              << " % of the largest measured mass"
              << (verified ? "" : ": NOT VERIFIED, more than Tolerance") << "\n"
              << "Residuals (measured - computed at the fitted values):\n"
              << "  design                specimen            Mcycles  "
              << "measured  computed  residual (mg)\n"
              << residuals << "Wrote " << directory
              << "/calibrated.prm (the fitted entries on "
              << designs[0].base_file << "), calibration.json, "
              << "calibration.csv, calibration_curves.csv" << std::endl;
    if (illustrative)
      std::cout << "Note: the measured data say they are ILLUSTRATIVE (a "
                << "comment line of the file): these values calibrate no "
                << "real implant." << std::endl;
  }

  void
  CalibrationProblem::write_json(const Calibration::FitResult &result,
                                 const Interval               &interval,
                                 const unsigned int            runs,
                                 const double                  mismatch,
                                 const double                  rms,
                                 const bool illustrative) const
  {
    const Parameters::Calibration       &calibration = parameters.calibration;
    const unsigned int                   n           = result.x.size();
    Output::Summary                      json("calibration.json");
    Output::Summary::Record              fitted, lower, upper;
    std::vector<Output::Summary::Record> specimens;
    for (unsigned int i = 0; i < n; ++i)
      {
        fitted.emplace_back(key(calibration.fit[i]), result.x[i]);
        lower.emplace_back(key(calibration.fit[i]), interval.lower[i]);
        upper.emplace_back(key(calibration.fit[i]), interval.upper[i]);
      }
    for (const auto &x : interval.specimens)
      {
        Output::Summary::Record record;
        for (unsigned int i = 0; i < n; ++i)
          record.emplace_back(key(calibration.fit[i]), x[i]);
        specimens.push_back(record);
      }
    json.set("problem", "calibration");
    json.set("fit", joined(calibration.fit));
    json.set("fitted", fitted);
    json.set("confidence_level", calibration.confidence_level);
    json.set("lower", lower);
    json.set("upper", upper);
    json.set("interval_from", interval.from);
    json.set("specimen_fits", specimens);
    json.set("designs", static_cast<unsigned int>(designs.size()));
    json.set("specimens", n_specimens());
    json.set("points", static_cast<unsigned int>(points.size()));
    json.set("rms_residual_mg", rms);
    json.set("runs_per_design", runs);
    json.set("verification_mismatch_percent", 100 * mismatch);
    json.set("verified", mismatch <= calibration.tolerance);
    json.set("illustrative_data", illustrative);
    json.set("fit_iterations", result.iterations);
    write_atomically(parameters.output.directory + "/calibration.json",
                     json.to_json());
  }

  void
  CalibrationProblem::write_calibrated_prm(const Calibration::FitResult &result,
                                           const bool illustrative) const
  {
    const std::string &directory = parameters.output.directory;
    const Values       at        = values(result.x);
    std::ostringstream entries;
    entries << "# Written by tkr-wear (Problem = calibration, "
            << parameters.parameter_file << "): the entries fitted to\n";
    for (const Design &design : designs)
      entries << "#   " << design.measured_file << "\n";
    if (illustrative)
      entries << "# ILLUSTRATIVE DATA (the measured file says so): these "
                 "values calibrate no real implant.\n";
    entries << "# Include this file after a design's own parameter file to "
               "run it with them.\nsubsection Wear\n";
    if (at.coefficient > 0)
      {
        // Wear/LAW/ENTRY: the law's subsection inside Wear.
        const std::string inner = rate_entry.substr(5);
        const std::size_t slash = inner.find('/');
        entries << "  subsection " << inner.substr(0, slash) << "\n    set "
                << inner.substr(slash + 1) << " = "
                << format_number(at.coefficient, 12) << "\n  end\n";
      }
    if (at.fitted_run_in)
      {
        entries << "  set Run-in file = calibrated-run-in.csv\n";
        write_atomically(directory + "/calibrated-run-in.csv",
                         "# The run-in fitted by tkr-wear (Problem = "
                         "calibration): factor " +
                           format_number(at.run_in_factor, 12) +
                           " at 0 cycles, falling linearly to 1 at " +
                           format_number(at.run_in_length, 12) +
                           " cycles.\ncycles,factor\n0," +
                           format_number(at.run_in_factor, 12) + "\n" +
                           format_number(at.run_in_length, 12) + ",1\n");
      }
    entries << "end\n";
    write_atomically(directory + "/calibrated-entries.prm", entries.str());
    write_atomically(
      directory + "/calibrated.prm",
      "# The first design of the calibration with the fitted entries: "
      "tkr-wear calibrated.prm runs it.\n# Another design: include its "
      "parameter file, then calibrated-entries.prm.\ninclude " +
        designs[0].base_file +
        "\ninclude calibrated-entries.prm\nsubsection Output\n  set "
        "Directory = " +
        directory + "/calibrated\nend\n");
  }
} // namespace TKR::Problems
