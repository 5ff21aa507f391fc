// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <deal.II/base/mpi.h>
#include <deal.II/base/utilities.h>

#include <tkr/base/atomic_file.h>
#include <tkr/base/exceptions.h>
#include <tkr/base/result_schema.h>
#include <tkr/output/summary.h>
#include <tkr/output/wear_output.h>
#include <tkr/problems/optimisation_problem.h>
#include <tkr/problems/study_cases.h>

#include <nlopt.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <regex>
#include <sstream>

namespace TKR::Problems
{
  using namespace dealii;

  namespace
  {
    double
    parse_number(const std::string &text, const std::string &what)
    {
      try
        {
          std::size_t  end   = 0;
          const double value = std::stod(text, &end);
          if (end == text.size() && std::isfinite(value))
            return value;
        }
      catch (const std::exception &)
        {}
      AssertThrow(false,
                  ExcInputError(what + ": <" + text + "> is not a number."));
      return 0;
    }

    /** What the quadratic test function gives (see its entry). */
    const std::vector<std::string> test_keys = {"mass_loss_mg",
                                                "max_pressure_MPa"};

  } // namespace

  double
  OptimisationProblem::Variable::value(const double u) const
  {
    const double t = std::clamp(u, 0., 1.);
    return log ? std::exp(std::log(lower) +
                          t * (std::log(upper) - std::log(lower))) :
                 lower + t * (upper - lower);
  }

  double
  OptimisationProblem::Variable::unit(const double x) const
  {
    return log ? (std::log(x) - std::log(lower)) /
                   (std::log(upper) - std::log(lower)) :
                 (x - lower) / (upper - lower);
  }

  double
  OptimisationProblem::Constraint::violation(const double result) const
  {
    const double scale = value != 0 ? std::abs(value) : 1.;
    return (at_most ? result - value : value - result) / scale;
  }

  bool
  OptimisationProblem::Evaluation::feasible(
    const std::vector<Constraint> &list) const
  {
    if (status != "done")
      return false;
    for (unsigned int c = 0; c < list.size(); ++c)
      if (list[c].violation(constraints[c]) > 1e-9)
        return false;
    return true;
  }

  OptimisationProblem::OptimisationProblem(
    const Parameters::AllParameters &parameters,
    const MPI_Comm                   mpi_communicator,
    const bool                       resume)
    : parameters(parameters)
    , mpi_communicator(mpi_communicator)
    , resume(resume)
    , is_root(Utilities::MPI::this_mpi_process(mpi_communicator) == 0)
    , runner("Optimisation",
             parameters.optimisation.base_file,
             parameters.optimisation.mesh_generator,
             parameters.optimisation.mesh_generator_arguments,
             resume,
             mpi_communicator)
  {
    parse_variables();
    parse_results();
    parse_scenarios();
    parse_verification();
  }

  std::string
  OptimisationProblem::place(const std::string &entry) const
  {
    const auto it = parameters.places.find("Optimisation/" + entry);
    return "Optimisation/" + entry + " (" +
           (it == parameters.places.end() ? parameters.parameter_file :
                                            it->second) +
           ")";
  }

  // PATH = LOWER .. UPPER [log], each path an entry of the base file whose
  // value (the start) lies within the bounds.
  void
  OptimisationProblem::parse_variables()
  {
    const Parameters::Optimisation &o = parameters.optimisation;
    static const std::regex         variable(
      R"(^\s*(\S.*?)\s*=\s*(\S+)\s*\.\.\s*(\S+?)\s*(log)?\s*$)");
    static const std::regex component(R"(^(.*)\[([0-9]+)\]$)");
    for (const std::string &item :
         Utilities::split_string_list(o.variables, ';'))
      {
        std::smatch match;
        AssertThrow(std::regex_match(item, match, variable),
                    ExcInputError(place("Variables") + ": <" + item +
                                  "> is not PATH = LOWER .. UPPER (or PATH "
                                  "= LOWER .. UPPER log)."));
        Variable          v;
        const std::string what = place("Variables") + ": " + match[1].str();
        v.input                = match[1].str();
        v.lower                = parse_number(match[2].str(), what);
        v.upper                = parse_number(match[3].str(), what);
        v.log                  = match[4].matched;
        AssertThrow(v.lower < v.upper,
                    ExcInputError(what + ": the bounds " + match[2].str() +
                                  " .. " + match[3].str() +
                                  " are empty (LOWER must be below UPPER)."));
        AssertThrow(!v.log || v.lower > 0,
                    ExcInputError(what + ": log needs positive bounds."));
        // The entry must be one of the base file (the same check and
        // message as a study's), and its base value is the start.
        StudyCase check;
        check.name = "the start";
        set_case_input(v.input,
                       match[2].str(),
                       runner.base(),
                       "Optimisation",
                       place("Variables"),
                       check);
        std::smatch indexed;
        const bool  has_index = std::regex_match(v.input, indexed, component);
        // (a moved entry's new path is the one the check set)
        std::string path = has_index ? indexed[1].str() : v.input;
        if (runner.base().entries.count(path) == 0)
          path = check.entries.begin()->first;
        const std::string base_value =
          Utilities::split_string_list(runner.base().entries.at(path), ',')
            .at(has_index ? std::stoul(indexed[2].str()) : 0);
        v.start = parse_number(base_value,
                               what + " (its value in the base "
                                      "file)");
        AssertThrow(v.lower <= v.start && v.start <= v.upper,
                    ExcInputError(what + ": the start, the base file's value " +
                                  base_value + ", lies outside " +
                                  match[2].str() + " .. " + match[3].str() +
                                  " (an infeasible start)."));
        variables.push_back(v);
      }
    AssertThrow(!variables.empty(),
                ExcInputError(place("Variables") +
                              ": Problem = optimisation needs at least one "
                              "variable (PATH = LOWER .. UPPER)."));
  }

  // A key of the results: a number of summary.json (or of the test
  // function).
  void
  OptimisationProblem::check_result_key(const std::string &key,
                                        const std::string &where) const
  {
    if (testing())
      AssertThrow(std::find(test_keys.begin(), test_keys.end(), key) !=
                    test_keys.end(),
                  ExcInputError(where + ": <" + key +
                                "> is not a result of the test function "
                                "(mass_loss_mg, max_pressure_MPa)."));
    const ResultField *field = ResultSchema::find("summary.json", key);
    AssertThrow(field != nullptr &&
                  (field->type == "number" || field->type == "integer"),
                ExcInputError(where + ": <" + key +
                              "> is not a number of summary.json (its "
                              "keys: doc/output.md, tkr-wear "
                              "--print-schema)."));
  }

  // The objective and the constraints: keys of the results.
  void
  OptimisationProblem::parse_results()
  {
    const Parameters::Optimisation &o = parameters.optimisation;

    // The objective: minimise KEY or maximise KEY.
    static const std::regex objective(
      R"(^\s*(minimise|minimize|maximise|maximize)\s+(\S+)\s*$)");
    std::smatch match;
    AssertThrow(std::regex_match(o.objective, match, objective),
                ExcInputError(place("Objective") + ": <" + o.objective +
                              "> is not minimise KEY or maximise KEY."));
    maximise      = match[1].str().substr(0, 3) == "max";
    objective_key = match[2].str();
    check_result_key(objective_key, place("Objective"));

    // The constraints: KEY <= VALUE or KEY >= VALUE.
    static const std::regex constraint(R"(^\s*(\S+)\s*(<=|>=)\s*(\S+)\s*$)");
    for (const std::string &item :
         Utilities::split_string_list(o.constraints, ';'))
      {
        AssertThrow(std::regex_match(item, match, constraint),
                    ExcInputError(place("Constraints") + ": <" + item +
                                  "> is not KEY <= VALUE or KEY >= VALUE."));
        Constraint c;
        c.key     = match[1].str();
        c.at_most = match[2].str() == "<=";
        c.value =
          parse_number(match[3].str(), place("Constraints") + ": " + c.key);
        check_result_key(c.key, place("Constraints"));
        constraints.push_back(c);
      }
    AssertThrow(constraints.empty() || o.method == "cobyla",
                ExcInputError(place("Method") + ": " + o.method +
                              " takes bounds only; with Constraints use "
                              "cobyla."));
  }

  // The initial design's size; the scenarios: NAME: WEIGHT: FILE.
  void
  OptimisationProblem::parse_scenarios()
  {
    const Parameters::Optimisation &o = parameters.optimisation;
    AssertThrow(o.initial_design + 1 < o.maximum_evaluations,
                ExcInputError(place("Initial design") + " = " +
                              std::to_string(o.initial_design) +
                              ": the start and the initial design leave no "
                              "evaluation of Maximum evaluations = " +
                              std::to_string(o.maximum_evaluations) +
                              " to the method."));

    // The scenarios: NAME: WEIGHT: FILE.
    for (const std::string &item :
         Utilities::split_string_list(o.scenarios, ';'))
      {
        const std::vector<std::string> parts =
          Utilities::split_string_list(item, ':');
        AssertThrow(parts.size() == 3,
                    ExcInputError(place("Scenarios") + ": <" + item +
                                  "> is not NAME: WEIGHT: FILE."));
        Scenario s{parts[0],
                   std::filesystem::absolute(parts[2]).string(),
                   parse_number(parts[1],
                                place("Scenarios") + ": " + parts[0])};
        AssertThrow(std::regex_match(s.name, std::regex("[A-Za-z0-9_.-]+")) &&
                      s.name.rfind("eval-", 0) != 0,
                    ExcInputError(place("Scenarios") + ": <" + s.name +
                                  "> is not a name for a directory (letters, "
                                  "digits, _ . -; not eval-...)."));
        AssertThrow(s.weight >= 0,
                    ExcInputError(place("Scenarios") + ": " + s.name +
                                  ": a negative weight."));
        AssertThrow(std::filesystem::exists(s.file),
                    ExcInputError(place("Scenarios") + ": " + s.name +
                                  ": the file <" + s.file +
                                  "> does not exist."));
        for (const Scenario &other : scenarios)
          AssertThrow(other.name != s.name,
                      ExcInputError(place("Scenarios") + ": the name <" +
                                    s.name + "> is used twice."));
        scenarios.push_back(s);
      }
    AssertThrow(!testing() || scenarios.empty(),
                ExcInputError(place("Scenarios") +
                              ": the test function replaces the runs; it "
                              "takes no scenarios."));
  }

  // The verification: its generator arguments and entries (checked
  // against the base file).
  void
  OptimisationProblem::parse_verification()
  {
    const Parameters::Optimisation &o = parameters.optimisation;
    static const std::regex         setting(R"(^\s*(\S.*?)\s*=\s*(\S.*?)\s*$)");
    std::smatch                     match;
    for (const std::string &item :
         Utilities::split_string_list(o.verification_entries, ';'))
      {
        AssertThrow(std::regex_match(item, match, setting),
                    ExcInputError(place("Verification entries") + ": <" + item +
                                  "> is not PATH = VALUE."));
        StudyCase check;
        check.name = "the verification";
        set_case_input(match[1].str(),
                       match[2].str(),
                       runner.base(),
                       "Optimisation",
                       place("Verification entries"),
                       check);
        verification_entries[match[1].str()] = match[2].str();
      }
    AssertThrow(o.verification_generator_arguments.empty() ||
                  !o.mesh_generator.empty(),
                ExcInputError(place("Verification mesh generator arguments") +
                              ": there is no Mesh generator (without one, "
                              "set the verification's Mesh/File in "
                              "Verification entries)."));
    if (!testing() && (!o.verification_generator_arguments.empty() ||
                       !verification_entries.empty()))
      verification_runner = std::make_unique<CaseRunner>(
        "Optimisation",
        o.base_file,
        o.mesh_generator,
        o.verification_generator_arguments.empty() ?
          o.mesh_generator_arguments :
          o.verification_generator_arguments,
        resume,
        mpi_communicator);
  }

  std::string
  OptimisationProblem::name(const unsigned int index) const
  {
    char text[32];
    std::snprintf(text, sizeof(text), "eval-%04u", index);
    return text;
  }

  std::string
  OptimisationProblem::directory(const unsigned int index) const
  {
    return parameters.output.directory + "/" + name(index);
  }

  std::map<std::string, double>
  OptimisationProblem::test_results(const std::vector<double> &u) const
  {
    double sum = 0;
    for (const double t : u)
      sum += (t - 0.3) * (t - 0.3);
    return {{"mass_loss_mg", 1 + sum}, {"max_pressure_MPa", 10 + 20 * u[0]}};
  }

  // The method minimises: a done evaluation's objective (negated to
  // maximise); a failed one is worse than every done one.
  double
  OptimisationProblem::merit(const unsigned int index) const
  {
    const auto value = [&](const Evaluation &e) {
      return maximise ? -e.objective : e.objective;
    };
    if (evaluations[index].status == "done")
      return value(evaluations[index]);
    double worst = -std::numeric_limits<double>::max(),
           least = std::numeric_limits<double>::max();
    for (const Evaluation &e : evaluations)
      if (e.status == "done")
        {
          worst = std::max(worst, value(e));
          least = std::min(least, value(e));
        }
    return worst + std::max({worst - least, 1e-3 * std::abs(worst), 1e-12});
  }

  unsigned int
  OptimisationProblem::best() const
  {
    unsigned int best_index = 0;
    const auto   violation  = [&](const Evaluation &e) {
      double v = e.status == "done" ? 0. : 1e300;
      for (unsigned int c = 0; c < constraints.size() && e.status == "done";
           ++c)
        v = std::max(v, constraints[c].violation(e.constraints[c]));
      return v;
    };
    for (unsigned int i = 1; i < evaluations.size(); ++i)
      {
        const Evaluation &e = evaluations[i], &b = evaluations[best_index];
        const bool f = e.feasible(constraints), g = b.feasible(constraints);
        if ((f && !g) || (f && g && merit(i) < merit(best_index)) ||
            (!f && !g && violation(e) < violation(b)))
          best_index = i;
      }
    return best_index;
  }

  double
  OptimisationProblem::objective_callback(unsigned,
                                          const double *u,
                                          double *,
                                          void *data)
  {
    auto *problem = static_cast<OptimisationProblem *>(data);
    try
      {
        const std::vector<double> point(u, u + problem->variables.size());
        return problem->merit(problem->evaluate(point));
      }
    catch (...)
      {
        problem->pending = std::current_exception();
        throw nlopt::forced_stop();
      }
  }

  // Constraint c: its violation (<= 0 where it holds); a failed
  // evaluation violates it by its whole value.
  double
  OptimisationProblem::constraint_callback(unsigned,
                                           const double *u,
                                           double *,
                                           void *data)
  {
    const auto &[problem, c] =
      *static_cast<std::pair<OptimisationProblem *, unsigned int> *>(data);
    try
      {
        const std::vector<double> point(u, u + problem->variables.size());
        const Evaluation &e = problem->evaluations[problem->evaluate(point)];
        return e.status == "done" ?
                 problem->constraints[c].violation(e.constraints[c]) :
                 1.;
      }
    catch (...)
      {
        problem->pending = std::current_exception();
        throw nlopt::forced_stop();
      }
  }

  void
  OptimisationProblem::announce() const
  {
    const Parameters::Optimisation &o = parameters.optimisation;
    if (!is_root)
      return;
    // Without --resume, the evaluations of an earlier run go.
    std::filesystem::create_directories(parameters.output.directory);
    if (!resume)
      for (const auto &entry :
           std::filesystem::directory_iterator(parameters.output.directory))
        if (entry.path().filename().string().rfind("eval-", 0) == 0 ||
            entry.path().filename().string().rfind("verify-", 0) == 0)
          std::filesystem::remove_all(entry.path());
    std::cout << "Optimisation <" << parameters.parameter_file
              << ">: " << o.objective << " of <"
              << std::filesystem::path(o.base_file).filename().string() << ">, "
              << variables.size() << " variable(s), " << constraints.size()
              << " constraint(s), " << o.method << " (NLopt), at most "
              << o.maximum_evaluations << " evaluations"
              << (o.test_function != "none" ?
                    ", test function " + o.test_function :
                    std::string())
              << (resume ? ", resumed" : "") << std::endl;
  }

  // The start (the base file's values), or with an initial design the best
  // of the start and the Latin hypercube, evaluated at once.
  std::vector<double>
  OptimisationProblem::start_point()
  {
    const Parameters::Optimisation &o = parameters.optimisation;
    const unsigned int              n = variables.size();
    std::vector<double>             u(n);
    for (unsigned int i = 0; i < n; ++i)
      u[i] = std::clamp(variables[i].unit(variables[i].start), 0., 1.);
    if (o.initial_design == 0)
      return u;
    if (is_root)
      std::cout << "Initial design: the start and " << o.initial_design
                << " points of a Latin hypercube (seed " << o.seed << ")"
                << std::endl;
    std::vector<std::vector<double>> points = {u};
    for (const std::vector<double> &p :
         unit_samples(o.initial_design, n, o.seed, true))
      points.push_back(p);
    evaluate_batch(points);
    return evaluations[best()].u;
  }

  // NLopt from @p u; its first point, if evaluated already, is read from
  // the table (and counts against Maximum evaluations once).
  std::string
  OptimisationProblem::run_method(std::vector<double> u)
  {
    const Parameters::Optimisation &o = parameters.optimisation;
    const unsigned int              n = variables.size();
    nlopt::opt method(o.method == "cobyla" ? nlopt::LN_COBYLA :
                                             nlopt::LN_BOBYQA,
                      n);
    method.set_lower_bounds(std::vector<double>(n, 0.));
    method.set_upper_bounds(std::vector<double>(n, 1.));
    method.set_initial_step(std::vector<double>(n, o.initial_step));
    method.set_xtol_abs(o.tolerance);
    method.set_maxeval(o.maximum_evaluations + 1 -
                       std::max<std::size_t>(1, evaluations.size()));
    method.set_min_objective(objective_callback, this);
    constraint_data.clear();
    for (unsigned int c = 0; c < constraints.size(); ++c)
      constraint_data.emplace_back(this, c);
    for (auto &data : constraint_data)
      method.add_inequality_constraint(constraint_callback, &data, 0.);
    double minimum = 0;
    try
      {
        switch (method.optimize(u, minimum))
          {
            case nlopt::XTOL_REACHED:
              return "the variables changed by less than Tolerance";
            case nlopt::FTOL_REACHED:
              return "the objective changed by less than its tolerance";
            case nlopt::MAXEVAL_REACHED:
              return "Maximum evaluations reached";
            default:
              return "converged";
          }
      }
    catch (const nlopt::forced_stop &)
      {
        AssertThrow(pending, ExcInternalError());
        std::rethrow_exception(pending);
      }
    catch (const nlopt::roundoff_limited &)
      {
        return "rounding errors limit the progress";
      }
  }

  bool
  OptimisationProblem::run()
  {
    announce();
    std::string stop_reason;
    try
      {
        stop_reason = run_method(start_point());
      }
    catch (...)
      {
        // The evaluations so far are in the table; the error (or the stop)
        // goes on.
        if (is_root && !evaluations.empty())
          write_results("stopped by an error or a signal");
        throw;
      }
    verify();
    if (is_root)
      write_results(stop_reason);
    if (parameters.output.plots)
      {
        const std::string error =
          Output::run_script("plot-optimisation",
                             {parameters.output.directory},
                             parameters.output.directory +
                               "/plot-optimisation.log",
                             mpi_communicator);
        if (is_root && !error.empty())
          std::cout << "Warning: " << error << std::endl;
      }
    return evaluations[best()].feasible(constraints);
  }
} // namespace TKR::Problems
