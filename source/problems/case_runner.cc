// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <deal.II/base/mpi.h>

#include <tkr/base/atomic_file.h>
#include <tkr/base/exceptions.h>
#include <tkr/base/process.h>
#include <tkr/problems/case_runner.h>
#include <tkr/problems/study_cases.h>
#include <tkr/problems/wear_problem.h>

#include <cctype>
#include <filesystem>
#include <iostream>
#include <sstream>

namespace TKR::Problems
{
  using namespace dealii;

  CaseRunner::CaseRunner(const std::string &section,
                         const std::string &base_file,
                         const std::string &generator,
                         const std::string &generator_arguments,
                         const bool         resume,
                         const MPI_Comm     communicator)
    : section(section)
    , base_file(std::filesystem::absolute(base_file).string())
    , generator(generator)
    , generator_arguments(generator_arguments)
    , resume(resume)
  {
    std::string problem = section;
    problem[0]          = std::tolower(problem[0]);
    AssertThrow(!base_file.empty(),
                ExcInputError("Problem = " + problem + " needs " + section +
                              "/Base parameter file: the wear run that it "
                              "varies."));
    varied = Parameters::read_parameters(base_file);
    AssertThrow(varied.problem == Parameters::ProblemType::wear,
                ExcInputError(
                  section + "/Base parameter file <" + base_file +
                  "> sets Problem = " + Parameters::to_string(varied.problem) +
                  "; its runs vary a wear run (Problem = wear)."));
    // The generator's parameters count as entries Generator/NAME of the
    // base (for += and *=, and to refuse a name it does not have).
    if (generator.empty())
      return;
    std::string listing;
    on_root(
      [&]() {
        std::vector<std::string> command = generator_command();
        command.push_back("--print");
        listing = run_process(command, section + "/Mesh generator");
      },
      communicator);
    listing = Utilities::MPI::broadcast(communicator, listing, 0);
    std::istringstream in(listing);
    for (std::string line; std::getline(in, line);)
      if (const auto equal = line.find('='); equal != std::string::npos)
        varied.entries["Generator/" + line.substr(0, equal)] =
          line.substr(equal + 1);
  }

  std::vector<std::string>
  CaseRunner::generator_command() const
  {
    std::vector<std::string> command = {generator};
    std::istringstream       arguments(generator_arguments);
    for (std::string argument; arguments >> argument;)
      command.push_back(argument);
    return command;
  }

  void
  CaseRunner::write_parameter_file(const std::string                 &directory,
                                   std::map<std::string, std::string> entries,
                                   const std::string                 &comment,
                                   const std::string &include) const
  {
    std::filesystem::create_directories(directory);
    entries["Output/Directory"] = directory;
    std::vector<std::string> includes;
    if (!generator.empty())
      includes.push_back("mesh.prm");
    if (!include.empty())
      includes.push_back(include);
    write_atomically(
      directory + "/case.prm",
      case_parameter_text(base_file, includes, entries, comment));
  }

  // The mesh (on the group's rank 0; its error on every rank of the group),
  // by the generator with the run's Generator/ entries.
  void
  CaseRunner::make_mesh(const std::string                        &directory,
                        const std::map<std::string, std::string> &entries,
                        const StepGroups                         &group) const
  {
    if (generator.empty())
      return;
    std::string error;
    if (group.is_group_root)
      try
        {
          std::vector<std::string> command = generator_command();
          for (const auto &[path, value] : entries)
            if (path.rfind("Generator/", 0) == 0)
              command.insert(command.end(),
                             {"--set", path.substr(10) + "=" + value});
          command.insert(
            command.end(),
            {"-o", directory + "/mesh.msh", "--prm", directory + "/mesh.prm"});
          std::cout << run_process(command, "the mesh generator");
        }
      catch (const ExcInputError &exc)
        {
          error = exception_message(exc);
        }
    error = Utilities::MPI::broadcast(group.communicator, error, 0);
    AssertThrow(error.empty(), ExcInputError(error));
  }

  // The run's output in its log.txt; an error of the run is its failure,
  // its message the reason (on one line: deal.II's messages of the
  // parameter checks span several).
  CaseRunner::Outcome
  CaseRunner::run(const std::string                        &directory,
                  const std::map<std::string, std::string> &entries,
                  const StepGroups                         &group,
                  const std::string                        &label) const
  {
    Outcome      outcome;
    const double start = MPI_Wtime();
    CaseOutput   output(directory + "/log.txt", group.is_group_root);
    try
      {
        make_mesh(directory, entries, group);
        const Parameters::AllParameters case_parameters =
          Parameters::read_parameters(directory + "/case.prm");
        outcome.resumed =
          resume && std::filesystem::exists(directory + "/checkpoint.h5");
        WearProblem problem(case_parameters,
                            group.communicator,
                            outcome.resumed);
        const bool  converged = problem.run();
        outcome.results       = problem.result().named_values();
        if (!converged)
          {
            outcome.status = "failed";
            outcome.reason = "a contact solve, pose iteration or load balance "
                             "did not converge (log.txt; summary.json lists "
                             "the steps)";
          }
      }
    catch (const ExcStopped &exc)
      {
        // Its checkpoint written: --resume continues the run.
        outcome.status = "stopped";
        outcome.reason = exception_message(exc);
      }
    catch (const ExceptionBase &exc)
      {
        outcome.status = "failed";
        outcome.reason = exception_message(exc);
      }
    catch (const std::exception &exc)
      {
        outcome.status = "failed";
        outcome.reason = exc.what();
      }
    std::istringstream words(outcome.reason);
    outcome.reason.clear();
    for (std::string word; words >> word;)
      outcome.reason += (outcome.reason.empty() ? "" : " ") + word;
    if (!outcome.reason.empty())
      std::cout << label << ": " << outcome.reason << std::endl;
    outcome.wall_time = MPI_Wtime() - start;
    return outcome;
  }
} // namespace TKR::Problems
