// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.
//
// The runs of Problem = optimisation: an evaluation's runs (one per
// scenario), runs that go at once over rank groups (the initial design,
// the scenarios, the verification), the scenarios' results combined.

#include <deal.II/base/mpi.h>
#include <deal.II/base/utilities.h>

#include <tkr/base/exceptions.h>
#include <tkr/output/summary.h>
#include <tkr/problems/optimisation_problem.h>
#include <tkr/problems/study_cases.h>

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <sstream>

namespace TKR::Problems
{
  using namespace dealii;

  std::vector<OptimisationProblem::Run>
  OptimisationProblem::evaluation_runs(
    const std::string                        &directory,
    const std::vector<double>                &u,
    const std::map<std::string, std::string> &extra,
    Evaluation                               &e) const
  {
    StudyCase inputs;
    inputs.name = std::filesystem::path(directory).filename().string();
    e.u         = u;
    e.x.clear();
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
    for (const auto &[input, value] : extra)
      set_case_input(input,
                     value,
                     runner.base(),
                     "Optimisation",
                     "Verification entries",
                     inputs);
    if (scenarios.empty())
      return {{directory, "", inputs.name, inputs.entries}};
    std::vector<Run> runs;
    for (const Scenario &s : scenarios)
      runs.push_back({directory + "/" + s.name,
                      s.file,
                      inputs.name + "/" + s.name,
                      inputs.entries});
    return runs;
  }

  // Group g does the runs g, g + n_groups, ... (StepGroups::own_items());
  // its rank 0 writes their parameter files and sends their outcomes.
  std::vector<CaseRunner::Outcome>
  OptimisationProblem::run_all(const CaseRunner       &case_runner,
                               const std::vector<Run> &runs) const
  {
    const unsigned int n_ranks =
      Utilities::MPI::n_mpi_processes(mpi_communicator);
    const unsigned int size = parameters.optimisation.ranks_per_evaluation;
    const unsigned int n_groups =
      size == 0 ?
        1 :
        std::max<unsigned int>(1,
                               std::min<unsigned int>(runs.size(),
                                                      n_ranks / size));
    const StepGroups                 group(mpi_communicator, n_groups);
    std::vector<CaseRunner::Outcome> outcomes(runs.size());
    bool                             stopped = false;
    for (const unsigned int r : group.own_items(runs.size()))
      {
        const Run &run = runs[r];
        stopped        = stopped || stop_requested(group.communicator) != 0;
        if (stopped)
          {
            outcomes[r].status = "stopped";
            outcomes[r].reason = "Stopped by a signal before " + run.label;
            continue;
          }
        on_root(
          [&]() {
            case_runner.write_parameter_file(
              run.directory,
              run.entries,
              run.label + " of the optimisation <" + parameters.parameter_file +
                ">: tkr-wear case.prm repeats it alone.",
              run.include);
          },
          group.communicator);
        outcomes[r] =
          case_runner.run(run.directory, run.entries, group, run.label);
        stopped = outcomes[r].status == "stopped";
      }
    const std::vector<int> roots =
      Utilities::MPI::all_gather(mpi_communicator,
                                 group.is_group_root ? int(group.index) : -1);
    for (unsigned int r = 0; r < runs.size(); ++r)
      {
        const int root =
          std::find(roots.begin(), roots.end(), int(r % n_groups)) -
          roots.begin();
        outcomes[r] =
          Utilities::MPI::broadcast(mpi_communicator, outcomes[r], root);
      }
    for (const CaseRunner::Outcome &o : outcomes)
      AssertThrow(o.status != "stopped",
                  ExcStopped(o.reason + ": tkr-wear --resume " +
                             parameters.parameter_file +
                             " continues the optimisation."));
    return outcomes;
  }

  void
  OptimisationProblem::combine(const std::vector<CaseRunner::Outcome> &outcomes,
                               Evaluation                             &e) const
  {
    e.status = "done";
    e.reason.clear();
    e.wall_time = 0;
    e.scenario_objectives.clear();
    std::vector<double>              objective;
    std::vector<std::vector<double>> constraint(constraints.size());
    for (unsigned int s = 0; s < outcomes.size(); ++s)
      {
        const CaseRunner::Outcome &o = outcomes[s];
        const std::string          scenario =
          scenarios.empty() ? "" : scenarios[s].name + ": ";
        e.wall_time += o.wall_time;
        const std::map<std::string, double> results(o.results.begin(),
                                                    o.results.end());
        const auto result = [&](const std::string &key) {
          const auto it = results.find(key);
          if (it != results.end())
            return it->second;
          if (e.status == "done")
            {
              e.status = "failed";
              e.reason = scenario + "the run wrote no result " + key;
            }
          return 0.;
        };
        if (o.status != "done" && e.status == "done")
          {
            e.status = "failed";
            e.reason = scenario + o.reason;
          }
        objective.push_back(result(objective_key));
        for (unsigned int c = 0; c < constraints.size(); ++c)
          constraint[c].push_back(result(constraints[c].key));
      }
    if (scenarios.empty())
      e.objective = objective[0];
    else if (parameters.optimisation.combine_scenarios == "worst case")
      e.objective = maximise ?
                      *std::min_element(objective.begin(), objective.end()) :
                      *std::max_element(objective.begin(), objective.end());
    else
      {
        e.objective = 0;
        for (unsigned int s = 0; s < scenarios.size(); ++s)
          e.objective += scenarios[s].weight * objective[s];
      }
    if (!scenarios.empty())
      e.scenario_objectives = objective;
    e.constraints.clear();
    for (unsigned int c = 0; c < constraints.size(); ++c)
      e.constraints.push_back(
        constraints[c].at_most ?
          *std::max_element(constraint[c].begin(), constraint[c].end()) :
          *std::min_element(constraint[c].begin(), constraint[c].end()));
  }

  std::vector<unsigned int>
  OptimisationProblem::evaluate_batch(
    const std::vector<std::vector<double>> &points)
  {
    const int signal = stop_requested(mpi_communicator);
    AssertThrow(signal == 0,
                ExcStopped("Stopped by " + signal_name(signal) +
                           ": the evaluations done are kept; tkr-wear "
                           "--resume " +
                           parameters.parameter_file +
                           " continues the optimisation."));
    const unsigned int        first = evaluations.size();
    std::vector<unsigned int> indices, fresh;
    std::vector<Run>          runs;
    for (const std::vector<double> &u : points)
      indices.push_back(add_evaluation(u, fresh, runs));

    std::vector<CaseRunner::Outcome> outcomes;
    try
      {
        outcomes = run_all(runner, runs);
      }
    catch (...)
      {
        // A stop (or an error): the new evaluations are not evaluations
        // yet (their runs' checkpoints are; --resume continues them).
        if (!fresh.empty())
          evaluations.resize(fresh.front());
        throw;
      }
    const unsigned int n_runs = std::max<std::size_t>(1, scenarios.size());
    auto               next   = outcomes.begin();
    for (const unsigned int index : fresh)
      {
        Evaluation                      &e = evaluations[index];
        std::vector<CaseRunner::Outcome> own(1);
        if (testing())
          {
            const auto results = test_results(e.u);
            own[0].results.assign(results.begin(), results.end());
          }
        else
          {
            own.assign(next, next + n_runs);
            next += n_runs;
          }
        combine(own, e);
        if (is_root)
          write_evaluation(index, e);
      }
    if (is_root)
      for (unsigned int i = first; i < evaluations.size(); ++i)
        std::cout << evaluation_line(name(i), evaluations[i]) << std::endl;
    AssertThrow(evaluations[0].status == "done",
                ExcInputError("The start of the optimisation (the base "
                              "file's values, " +
                              directory(0) +
                              ") failed: " + evaluations[0].reason));
    return indices;
  }

  // An earlier evaluation at u, one that --resume reads back, or a new one
  // (its runs added to @p runs, its index to @p fresh; the test function
  // has no runs, only the parameter file).
  unsigned int
  OptimisationProblem::add_evaluation(const std::vector<double> &u,
                                      std::vector<unsigned int> &fresh,
                                      std::vector<Run>          &runs)
  {
    for (unsigned int i = evaluations.size(); i-- > 0;)
      if (evaluations[i].u == u)
        return i;
    const unsigned int     index = evaluations.size();
    Evaluation             e;
    const std::vector<Run> own   = evaluation_runs(directory(index), u, {}, e);
    bool                   found = false;
    std::string            error;
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
      e = Utilities::MPI::broadcast(mpi_communicator, e, 0);
    else
      {
        fresh.push_back(index);
        if (testing())
          on_root(
            [&]() {
              runner.write_parameter_file(own[0].directory,
                                          own[0].entries,
                                          own[0].label + " (test function)");
            },
            mpi_communicator);
        else
          runs.insert(runs.end(), own.begin(), own.end());
      }
    evaluations.push_back(e);
    return index;
  }

  unsigned int
  OptimisationProblem::evaluate(const std::vector<double> &u)
  {
    return evaluate_batch({u})[0];
  }

  std::string
  OptimisationProblem::evaluation_line(const std::string &label,
                                       const Evaluation  &e) const
  {
    std::ostringstream line;
    line << label << ":";
    for (unsigned int i = 0; i < variables.size(); ++i)
      line << (i ? "," : "") << " " << variables[i].input << " = "
           << format_number(e.x[i], 6);
    if (e.status == "done")
      {
        line << " -> " << objective_key << " = "
             << format_number(e.objective, 6);
        for (unsigned int s = 0; s < e.scenario_objectives.size(); ++s)
          line << (s ? ", " : " (") << scenarios[s].name << " "
               << format_number(e.scenario_objectives[s], 6)
               << (s + 1 == scenarios.size() ? ")" : "");
        for (unsigned int c = 0; c < constraints.size(); ++c)
          line << ", " << constraints[c].key << " = "
               << format_number(e.constraints[c], 6);
        line << (e.feasible(constraints) ? "" : " (infeasible)");
      }
    else
      line << " -> FAILED: " << e.reason;
    if (e.resumed)
      line << " (read back)";
    return line.str();
  }

  // The start and the best design on the verification's mesh: both runs at
  // once where there are groups for them.
  void
  OptimisationProblem::verify()
  {
    verification.clear();
    if (!verification_runner)
      return;
    const unsigned int        b     = best();
    std::vector<unsigned int> which = {0};
    if (b != 0)
      which.push_back(b);
    const std::vector<std::string> labels = {"verify-start", "verify-best"};
    std::vector<Run>               runs;
    verification.resize(which.size());
    for (unsigned int k = 0; k < which.size(); ++k)
      {
        const std::vector<Run> own =
          evaluation_runs(parameters.output.directory + "/" + labels[k],
                          evaluations[which[k]].u,
                          verification_entries,
                          verification[k]);
        runs.insert(runs.end(), own.begin(), own.end());
      }
    const Parameters::Optimisation &o = parameters.optimisation;
    if (is_root)
      std::cout << "Verification: the start" << (b != 0 ? " and the best" : "")
                << " again"
                << (o.verification_generator_arguments.empty() ?
                      "" :
                      " with the mesh of " + o.verification_generator_arguments)
                << (o.verification_entries.empty() ?
                      "" :
                      " with " + o.verification_entries)
                << std::endl;
    std::vector<CaseRunner::Outcome> outcomes;
    try
      {
        outcomes = run_all(*verification_runner, runs);
      }
    catch (...)
      {
        verification.clear();
        throw;
      }
    const unsigned int n_runs = runs.size() / which.size();
    for (unsigned int k = 0; k < which.size(); ++k)
      {
        combine(std::vector<CaseRunner::Outcome>(outcomes.begin() + k * n_runs,
                                                 outcomes.begin() +
                                                   (k + 1) * n_runs),
                verification[k]);
        if (is_root)
          std::cout << evaluation_line(labels[k], verification[k]) << std::endl;
      }
    if (b == 0)
      {
        const Evaluation start = verification[0];
        verification.push_back(start);
      }
  }
} // namespace TKR::Problems
