// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.
//
// The files of Problem = optimisation: each evaluation's evaluation.json,
// optimisation.csv, optimisation.json (in the ResultSchema), best.prm.

#include <tkr/base/atomic_file.h>
#include <tkr/base/csv_table.h>
#include <tkr/base/exceptions.h>
#include <tkr/base/result_schema.h>
#include <tkr/output/summary.h>
#include <tkr/problems/optimisation_problem.h>

#include <boost/property_tree/json_parser.hpp>
#include <boost/property_tree/ptree.hpp>

#include <filesystem>
#include <iomanip>
#include <sstream>

namespace TKR::Problems
{
  namespace
  {
    // The keys of optimisation.json.
    // clang-format off
    [[maybe_unused]] const bool declared = ResultSchema::declare(
      "optimisation.json",
      21,
      {
      {"problem", "string", "-", {}, "`optimisation`"},
      {"method", "string", "-", {}, "`Optimisation/Method`"},
      {"objective", "string", "-", {}, "`Optimisation/Objective`"},
      {"constraints", "string", "-", {}, "`Optimisation/Constraints`"},
      {"evaluations", "integer", "-", {}, "evaluations (wear runs, or the test function's) of the method"},
      {"failed_evaluations", "integer", "-", {}, "evaluations whose run failed or did not converge"},
      {"stop_reason", "string", "-", {}, "why the method stopped (NLopt's result)"},
      {"feasible", "boolean", "-", {}, "the best evaluation satisfies every constraint"},
      {"best_evaluation", "string", "-", {}, "the best evaluation's directory, `eval-NNNN`"},
      {"best_objective", "number", "-", {}, "its objective (the result's unit)"},
      {"best_inputs", "object", "-", {}, "its variables' values by path"},
      {"start_objective", "number", "-", {}, "the objective of the start (the base file's values), `eval-0000`"},
      {"scenario_weights", "object", "-", {}, "with `Optimisation/Scenarios`: each scenario's weight by name"},
      {"start_scenario_objectives", "object", "-", {}, "with scenarios: the start's objective in each scenario"},
      {"best_scenario_objectives", "object", "-", {}, "with scenarios: the best design's objective in each scenario"},
      {"verification_status", "string", "-", {}, "with a verification (`Optimisation/Verification ...`): `done`, or `failed: ` and why (a run of the start or the best design failed)"},
      {"verification_start_objective", "number", "-", {}, "the start's objective in the verification (e.g. on the next finer mesh)"},
      {"verification_best_objective", "number", "-", {}, "the best design's objective in the verification"},
      {"verification_best_constraints", "object", "-", {}, "the best design's constraint results in the verification, by key"},
      {"verification_best_feasible", "boolean", "-", {}, "the best design satisfies every constraint in the verification too"},
      {"verification_best_improves", "boolean", "-", {}, "the best design is better than the start in the verification too"}});
    // clang-format on

  } // namespace

  // The evaluation's file: what --resume reads back.
  void
  OptimisationProblem::write_evaluation(const unsigned int index,
                                        const Evaluation  &e) const
  {
    std::ostringstream json;
    json << std::setprecision(17) << "{\n  \"status\": \"" << e.status
         << "\",\n  \"reason\": " << Output::json_string(e.reason)
         << ",\n  \"u\": [";
    for (unsigned int i = 0; i < e.u.size(); ++i)
      json << (i ? ", " : "") << e.u[i];
    json << "],\n  \"objective\": " << e.objective << ",\n  \"constraints\": [";
    for (unsigned int c = 0; c < e.constraints.size(); ++c)
      json << (c ? ", " : "") << e.constraints[c];
    json << "],\n  \"scenario_objectives\": [";
    for (unsigned int s = 0; s < e.scenario_objectives.size(); ++s)
      json << (s ? ", " : "") << e.scenario_objectives[s];
    json << "],\n  \"wall_time_s\": " << e.wall_time << "\n}\n";
    write_atomically(directory(index) + "/evaluation.json", json.str());
  }

  bool
  OptimisationProblem::read_evaluation(const unsigned int         index,
                                       const std::vector<double> &u,
                                       Evaluation &evaluation) const
  {
    const std::string file = directory(index) + "/evaluation.json";
    if (!std::filesystem::exists(file))
      return false;
    boost::property_tree::ptree tree;
    boost::property_tree::read_json(file, tree);
    std::vector<double> stored;
    for (const auto &[key, node] : tree.get_child("u"))
      stored.push_back(node.get_value<double>());
    AssertThrow(stored == u,
                ExcInputError("--resume: <" + file +
                              "> is of another point than the method asks "
                              "for now (the optimisation's inputs changed): "
                              "start again without --resume."));
    evaluation.status    = tree.get<std::string>("status");
    evaluation.reason    = tree.get<std::string>("reason");
    evaluation.objective = tree.get<double>("objective");
    for (const auto &[key, node] : tree.get_child("constraints"))
      evaluation.constraints.push_back(node.get_value<double>());
    if (const auto list = tree.get_child_optional("scenario_objectives"))
      for (const auto &[key, node] : *list)
        evaluation.scenario_objectives.push_back(node.get_value<double>());
    evaluation.wall_time = tree.get<double>("wall_time_s");
    evaluation.resumed   = true;
    return true;
  }

  // The verification's numbers into @p json; what the screen says about
  // them (a loud warning where they do not confirm the optimum).
  std::string
  OptimisationProblem::verification_verdict(Output::Summary &json) const
  {
    if (verification.empty())
      return "";
    const Evaluation  &start = verification[0], &best_design = verification[1];
    std::ostringstream text;
    if (start.status != "done" || best_design.status != "done")
      {
        const std::string reason = start.status != "done" ?
                                     "the start: " + start.reason :
                                     "the best design: " + best_design.reason;
        json.set("verification_status", "failed: " + reason);
        text << "WARNING: the verification failed (" << reason
             << "): the optimum is not confirmed." << std::endl;
        return text.str();
      }
    Output::Summary::Record results;
    for (unsigned int c = 0; c < constraints.size(); ++c)
      results.emplace_back(constraints[c].key, best_design.constraints[c]);
    const bool feasible = best_design.feasible(constraints);
    const bool improves = maximise ? best_design.objective >= start.objective :
                                     best_design.objective <= start.objective;
    json.set("verification_status", "done");
    json.set("verification_start_objective", start.objective);
    json.set("verification_best_objective", best_design.objective);
    json.set("verification_best_constraints", results);
    json.set("verification_best_feasible", feasible);
    json.set("verification_best_improves", improves);
    text << "Verification: " << objective_key << " = "
         << format_number(best_design.objective, 12) << " (start "
         << format_number(start.objective, 12) << ")";
    for (unsigned int c = 0; c < constraints.size(); ++c)
      text << ", " << constraints[c].key << " = "
           << format_number(best_design.constraints[c], 12);
    text << std::endl;
    if (!feasible)
      text << "WARNING: the best design VIOLATES a constraint in the "
              "verification: the optimum does not hold there."
           << std::endl;
    if (!improves)
      text << "WARNING: the best design is NOT better than the start in the "
              "verification."
           << std::endl;
    return text.str();
  }

  // optimisation.csv: every evaluation.
  void
  OptimisationProblem::write_table() const
  {
    const bool         no_times = parameters.output.testing;
    std::ostringstream csv;
    csv << "evaluation,status";
    for (const Variable &v : variables)
      csv << "," << csv_field(v.input);
    csv << "," << objective_key;
    for (const Scenario &s : scenarios)
      csv << "," << csv_field(objective_key + "@" + s.name);
    for (const Constraint &c : constraints)
      csv << "," << c.key;
    csv << ",feasible,best_objective" << (no_times ? "" : ",wall_time_s")
        << ",reason\n";
    bool   any_feasible = false;
    double best_so_far  = 0;
    for (unsigned int i = 0; i < evaluations.size(); ++i)
      {
        const Evaluation &e    = evaluations[i];
        const bool        done = e.status == "done";
        csv << name(i) << "," << e.status;
        for (const double x : e.x)
          csv << "," << format_number(x, 12);
        csv << "," << (done ? format_number(e.objective, 12) : "");
        for (unsigned int s = 0; s < scenarios.size(); ++s)
          csv << ","
              << (done ? format_number(e.scenario_objectives[s], 12) : "");
        for (const double c : e.constraints)
          csv << "," << (done ? format_number(c, 12) : "");
        const bool feasible = e.feasible(constraints);
        if (feasible &&
            (!any_feasible || (maximise ? e.objective > best_so_far :
                                          e.objective < best_so_far)))
          best_so_far = e.objective;
        any_feasible = any_feasible || feasible;
        csv << "," << (feasible ? 1 : 0) << ","
            << (any_feasible ? format_number(best_so_far, 12) : "");
        if (!no_times)
          csv << "," << format_number(e.wall_time, 12);
        csv << "," << csv_field(e.reason) << "\n";
      }
    write_atomically(parameters.output.directory + "/optimisation.csv",
                     csv.str());
  }

  // best.prm: the best evaluation's parameter file with its own output
  // directory; best.msh, its mesh, with a mesh generator.
  void
  OptimisationProblem::write_best_prm(const unsigned int b) const
  {
    const std::string &out = parameters.output.directory;
    const Evaluation  &e   = evaluations[b];
    // (with scenarios: the first scenario's run)
    const std::string best_run =
      directory(b) + (scenarios.empty() ? "" : "/" + scenarios[0].name);
    std::ostringstream prm;
    prm << "# The best design of the optimisation <"
        << parameters.parameter_file << ">: " << name(b) << " ("
        << objective_key << " = " << format_number(e.objective, 12)
        << (e.feasible(constraints) ? "" : ", INFEASIBLE") << ")"
        << (scenarios.empty() ?
              "" :
              ", its scenario " + scenarios[0].name +
                " (the others: " + name(b) + "/NAME/case.prm)")
        << ". tkr-wear best.prm runs it again.\ninclude "
        << std::filesystem::absolute(best_run + "/case.prm").string()
        << "\nsubsection Output\n  set Directory = " << out << "/best\nend\n";
    write_atomically(out + "/best.prm", prm.str());
    if (std::filesystem::exists(best_run + "/mesh.msh"))
      std::filesystem::copy_file(
        best_run + "/mesh.msh",
        out + "/best.msh",
        std::filesystem::copy_options::overwrite_existing);
  }

  void
  OptimisationProblem::write_results(const std::string &stop_reason) const
  {
    const Parameters::Optimisation &o   = parameters.optimisation;
    const std::string              &out = parameters.output.directory;
    const unsigned int              b   = best();
    write_table();
    const Evaluation       &e = evaluations[b];
    Output::Summary         json("optimisation.json");
    Output::Summary::Record inputs;
    for (unsigned int i = 0; i < variables.size(); ++i)
      inputs.emplace_back(variables[i].input, e.x[i]);
    unsigned int failed = 0;
    for (const Evaluation &f : evaluations)
      failed += f.status != "done";
    json.set("problem", "optimisation");
    json.set("method", o.method);
    json.set("objective", o.objective);
    json.set("constraints", o.constraints);
    json.set("evaluations", static_cast<unsigned int>(evaluations.size()));
    json.set("failed_evaluations", failed);
    json.set("stop_reason", stop_reason);
    json.set("feasible", e.feasible(constraints));
    json.set("best_evaluation", name(b));
    json.set("best_objective", e.objective);
    json.set("best_inputs", inputs);
    json.set("start_objective", evaluations[0].objective);
    if (!scenarios.empty())
      {
        Output::Summary::Record weights, start, best_design;
        for (unsigned int s = 0; s < scenarios.size(); ++s)
          {
            weights.emplace_back(scenarios[s].name, scenarios[s].weight);
            start.emplace_back(scenarios[s].name,
                               evaluations[0].scenario_objectives[s]);
            if (e.status == "done")
              best_design.emplace_back(scenarios[s].name,
                                       e.scenario_objectives[s]);
          }
        json.set("scenario_weights", weights);
        json.set("start_scenario_objectives", start);
        json.set("best_scenario_objectives", best_design);
      }
    const std::string verdict = verification_verdict(json);
    write_atomically(out + "/optimisation.json", json.to_json());

    write_best_prm(b);
    std::cout << "Best: " << name(b) << ", " << objective_key << " = "
              << format_number(e.objective, 12) << " (start "
              << format_number(evaluations[0].objective, 12) << ")"
              << (e.feasible(constraints) ? "" : ": NO FEASIBLE DESIGN FOUND")
              << "; " << evaluations.size() << " evaluations (" << failed
              << " failed), " << stop_reason << ". " << out
              << "/best.prm runs it." << std::endl
              << verdict;
  }
} // namespace TKR::Problems
