// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <deal.II/base/mpi.h>
#include <deal.II/base/utilities.h>

#include <tkr/base/atomic_file.h>
#include <tkr/base/exceptions.h>
#include <tkr/base/result_schema.h>
#include <tkr/output/summary.h>
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
    const Parameters::Optimisation &o     = parameters.optimisation;
    const auto                      place = [&](const std::string &entry) {
      const auto it = parameters.places.find("Optimisation/" + entry);
      return "Optimisation/" + entry + " (" +
             (it == parameters.places.end() ? parameters.parameter_file :
                                                                   it->second) +
             ")";
    };
    const bool testing = (o.test_function != "none");

    // The variables: PATH = LOWER .. UPPER [log].
    static const std::regex variable(
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

    // A key of the results: a number of summary.json (or of the test
    // function).
    const auto check_key = [&](const std::string &key,
                               const std::string &where) {
      if (testing)
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
    };

    // The objective: minimise KEY or maximise KEY.
    static const std::regex objective(
      R"(^\s*(minimise|minimize|maximise|maximize)\s+(\S+)\s*$)");
    std::smatch match;
    AssertThrow(std::regex_match(o.objective, match, objective),
                ExcInputError(place("Objective") + ": <" + o.objective +
                              "> is not minimise KEY or maximise KEY."));
    maximise      = match[1].str().substr(0, 3) == "max";
    objective_key = match[2].str();
    check_key(objective_key, place("Objective"));

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
        check_key(c.key, place("Constraints"));
        constraints.push_back(c);
      }
    AssertThrow(constraints.empty() || o.method == "cobyla",
                ExcInputError(place("Method") + ": " + o.method +
                              " takes bounds only; with Constraints use "
                              "cobyla."));
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

  // A wear run of the base file with the variables at u (or the test
  // function): its objective and constraint results, or its failure.
  OptimisationProblem::Evaluation
  OptimisationProblem::run_evaluation(const unsigned int         index,
                                      const std::vector<double> &u)
  {
    Evaluation e;
    e.u = u;
    StudyCase inputs;
    inputs.name =
      directory(index).substr(parameters.output.directory.size() + 1);
    for (unsigned int i = 0; i < variables.size(); ++i)
      {
        e.x.push_back(variables[i].value(u[i]));
        set_case_input(variables[i].input,
                       format_number(e.x[i], 12),
                       runner.base(),
                       "Optimisation",
                       "Variables",
                       inputs);
      }
    bool        found = false;
    std::string error;
    if (is_root && resume)
      try
        {
          found = read_evaluation(index, u, e);
        }
      catch (const ExcInputError &exc)
        {
          error = exception_message(exc);
        }
    error = Utilities::MPI::broadcast(mpi_communicator, error, 0);
    AssertThrow(error.empty(), ExcInputError(error));
    if (Utilities::MPI::broadcast(mpi_communicator, found, 0))
      {
        e = Utilities::MPI::broadcast(mpi_communicator, e, 0);
        return e;
      }

    const double start = MPI_Wtime();
    on_root(
      [&]() {
        runner.write_parameter_file(directory(index),
                                    inputs.entries,
                                    inputs.name + " of the optimisation <" +
                                      parameters.parameter_file +
                                      ">: tkr-wear case.prm repeats it alone.");
      },
      mpi_communicator);
    std::map<std::string, double> results;
    if (parameters.optimisation.test_function != "none")
      results = test_results(u);
    else
      {
        const StepGroups          group(mpi_communicator, 1);
        const CaseRunner::Outcome outcome =
          runner.run(directory(index), inputs.entries, group, inputs.name);
        AssertThrow(outcome.status != "stopped",
                    ExcStopped(outcome.reason + " (" + inputs.name +
                               "): tkr-wear --resume " +
                               parameters.parameter_file +
                               " continues the optimisation."));
        e.status = outcome.status;
        e.reason = outcome.reason;
        results.insert(outcome.results.begin(), outcome.results.end());
      }
    const auto result = [&](const std::string &key) {
      const auto it = results.find(key);
      if (it != results.end())
        return it->second;
      if (e.status == "done")
        {
          e.status = "failed";
          e.reason = "the run wrote no result " + key;
        }
      return 0.;
    };
    e.objective = result(objective_key);
    for (const Constraint &c : constraints)
      e.constraints.push_back(result(c.key));
    e.wall_time = MPI_Wtime() - start;
    // Rank 0's values on every rank: the method takes the same path.
    e = Utilities::MPI::broadcast(mpi_communicator, e, 0);
    if (is_root)
      write_evaluation(index, e);
    return e;
  }

  unsigned int
  OptimisationProblem::evaluate(const std::vector<double> &u)
  {
    for (unsigned int i = evaluations.size(); i-- > 0;)
      if (evaluations[i].u == u)
        return i;
    const int signal = stop_requested(mpi_communicator);
    AssertThrow(signal == 0,
                ExcStopped("Stopped by " + signal_name(signal) +
                           ": the evaluations done are kept; tkr-wear "
                           "--resume " +
                           parameters.parameter_file +
                           " continues the optimisation."));
    const unsigned int index = evaluations.size();
    evaluations.push_back(run_evaluation(index, u));
    const Evaluation &e = evaluations[index];
    if (is_root)
      {
        std::ostringstream line;
        line << name(index) << ":";
        for (unsigned int i = 0; i < variables.size(); ++i)
          line << (i ? "," : "") << " " << variables[i].input << " = "
               << format_number(e.x[i], 6);
        if (e.status == "done")
          {
            line << " -> " << objective_key << " = "
                 << format_number(e.objective, 6);
            for (unsigned int c = 0; c < constraints.size(); ++c)
              line << ", " << constraints[c].key << " = "
                   << format_number(e.constraints[c], 6);
            line << (e.feasible(constraints) ? "" : " (infeasible)");
          }
        else
          line << " -> FAILED: " << e.reason;
        if (e.resumed)
          line << " (read back)";
        std::cout << line.str() << std::endl;
      }
    AssertThrow(index > 0 || e.status == "done",
                ExcInputError("The start of the optimisation (the base "
                              "file's values, " +
                              directory(0) + ") failed: " + e.reason));
    return index;
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

  bool
  OptimisationProblem::run()
  {
    const Parameters::Optimisation &o = parameters.optimisation;
    if (is_root)
      {
        // Without --resume, the evaluations of an earlier run go.
        std::filesystem::create_directories(parameters.output.directory);
        if (!resume)
          for (const auto &entry :
               std::filesystem::directory_iterator(parameters.output.directory))
            if (entry.path().filename().string().rfind("eval-", 0) == 0)
              std::filesystem::remove_all(entry.path());
        std::cout << "Optimisation <" << parameters.parameter_file
                  << ">: " << o.objective << " of <"
                  << std::filesystem::path(o.base_file).filename().string()
                  << ">, " << variables.size() << " variable(s), "
                  << constraints.size() << " constraint(s), " << o.method
                  << " (NLopt), at most " << o.maximum_evaluations
                  << " evaluations"
                  << (o.test_function != "none" ?
                        ", test function " + o.test_function :
                        std::string())
                  << (resume ? ", resumed" : "") << std::endl;
      }
    const unsigned int n = variables.size();
    nlopt::opt         method(o.method == "cobyla" ? nlopt::LN_COBYLA :
                                             nlopt::LN_BOBYQA,
                      n);
    method.set_lower_bounds(std::vector<double>(n, 0.));
    method.set_upper_bounds(std::vector<double>(n, 1.));
    method.set_initial_step(std::vector<double>(n, o.initial_step));
    method.set_xtol_abs(o.tolerance);
    method.set_maxeval(o.maximum_evaluations);
    method.set_min_objective(objective_callback, this);
    constraint_data.clear();
    for (unsigned int c = 0; c < constraints.size(); ++c)
      constraint_data.emplace_back(this, c);
    for (auto &data : constraint_data)
      method.add_inequality_constraint(constraint_callback, &data, 0.);

    std::vector<double> u(n);
    for (unsigned int i = 0; i < n; ++i)
      u[i] = std::clamp(variables[i].unit(variables[i].start), 0., 1.);
    double      minimum = 0;
    std::string stop_reason;
    try
      {
        switch (method.optimize(u, minimum))
          {
            case nlopt::XTOL_REACHED:
              stop_reason = "the variables changed by less than Tolerance";
              break;
            case nlopt::FTOL_REACHED:
              stop_reason = "the objective changed by less than its tolerance";
              break;
            case nlopt::MAXEVAL_REACHED:
              stop_reason = "Maximum evaluations reached";
              break;
            default:
              stop_reason = "converged";
          }
      }
    catch (const nlopt::forced_stop &)
      {
        AssertThrow(pending, ExcInternalError());
      }
    catch (const nlopt::roundoff_limited &)
      {
        stop_reason = "rounding errors limit the progress";
      }
    if (pending)
      {
        // The evaluations so far are in the table; the error (or the stop)
        // goes on.
        if (is_root)
          write_results("stopped by an error or a signal");
        std::rethrow_exception(pending);
      }
    if (is_root)
      write_results(stop_reason);
    return evaluations[best()].feasible(constraints);
  }
} // namespace TKR::Problems
