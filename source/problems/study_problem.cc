// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <deal.II/base/mpi.h>

#include <tkr/base/atomic_file.h>
#include <tkr/base/csv_table.h>
#include <tkr/base/exceptions.h>
#include <tkr/base/result_schema.h>
#include <tkr/output/summary.h>
#include <tkr/output/wear_output.h>
#include <tkr/problems/study_problem.h>

#include <boost/property_tree/json_parser.hpp>
#include <boost/property_tree/ptree.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>

namespace TKR::Problems
{
  using namespace dealii;

  namespace
  {
    /** A case's status.json: its fields and its results (the text of
     *  each value), both empty if the file is absent or broken. */
    struct CaseStatus
    {
      std::map<std::string, std::string> fields, results;
    };

    CaseStatus
    read_case_status(const std::string &filename)
    {
      CaseStatus status;
      if (!std::filesystem::exists(filename))
        return status;
      try
        {
          boost::property_tree::ptree tree;
          boost::property_tree::read_json(filename, tree);
          for (const auto &[key, node] : tree)
            status.fields[key] = node.get_value<std::string>();
          if (const auto results = tree.get_child_optional("results"))
            for (const auto &[key, node] : *results)
              status.results[key] = node.get_value<std::string>();
        }
      catch (const std::exception &)
        {
          status = CaseStatus();
        }
      return status;
    }

    /**
     * A case's status.json as the study lists it: failed with "not run"
     * if there is none; a done case without one of result_keys (a
     * status.json of an older tkr-wear, or edited) failed with a reason
     * naming the key.
     */
    CaseStatus
    listed_case_status(const std::string &status_file)
    {
      CaseStatus read   = read_case_status(status_file);
      auto      &status = read.fields;
      if (status.empty())
        status = {{"status", "failed"}, {"reason", "not run"}};
      for (const std::string &key : ResultSchema::study_results())
        if (status["status"] == "done" && read.results.count(key) == 0)
          status = {{"status", "failed"},
                    {"reason",
                     "<" + status_file + "> has no result " + key +
                       ": run the case again (delete the file and "
                       "--resume the study)"},
                    {"wall_time_s", status["wall_time_s"]}};
      return read;
    }

    /**
     * The cases' queue: a counter on rank 0 of the job that each group's
     * rank 0 increments atomically (MPI_Fetch_and_op, passive target), or
     * a plain counter if there is one group.
     */
    class CaseQueue
    {
    public:
      CaseQueue(const MPI_Comm communicator, const bool shared)
      {
        if (!shared)
          return;
        const bool is_root =
          Utilities::MPI::this_mpi_process(communicator) == 0;
        int ierr = MPI_Win_create(is_root ? &counter : nullptr,
                                  is_root ? sizeof(int) : 0,
                                  sizeof(int),
                                  MPI_INFO_NULL,
                                  communicator,
                                  &window);
        AssertThrowMPI(ierr);
        ierr = MPI_Win_lock_all(0, window);
        AssertThrowMPI(ierr);
      }

      ~CaseQueue()
      {
        if (window == MPI_WIN_NULL)
          return;
        MPI_Win_unlock_all(window);
        MPI_Win_free(&window);
      }

      CaseQueue(const CaseQueue &) = delete;
      CaseQueue &
      operator=(const CaseQueue &) = delete;

      /** The next case for @p group (all its ranks get the same). */
      unsigned int
      next(const StepGroups &group)
      {
        int index = 0;
        if (window == MPI_WIN_NULL)
          index = counter++;
        else if (group.is_group_root)
          {
            const int one = 1;
            int       ierr =
              MPI_Fetch_and_op(&one, &index, MPI_INT, 0, 0, MPI_SUM, window);
            AssertThrowMPI(ierr);
            ierr = MPI_Win_flush(0, window);
            AssertThrowMPI(ierr);
          }
        return Utilities::MPI::broadcast(group.communicator, index, 0);
      }

    private:
      int     counter = 0;
      MPI_Win window  = MPI_WIN_NULL;
    };
    /** The row of case @p c with the status @p read in study.csv and its
     *  object in study.json (wall times unless @p testing). */
    void
    write_case_row(const StudyCase  &c,
                   const CaseStatus &read,
                   const bool        testing,
                   std::ostream     &csv,
                   std::ostream     &json)
    {
      auto status = read.fields;
      csv << c.name;
      json << "\n    {\"case\": " << Output::json_string(c.name)
           << ", \"inputs\": {";
      for (unsigned int j = 0; j < c.inputs.size(); ++j)
        {
          csv << "," << csv_field(c.inputs[j].second);
          json << (j == 0 ? "" : ", ") << Output::json_string(c.inputs[j].first)
               << ": " << Output::json_string(c.inputs[j].second);
        }
      csv << "," << status["status"];
      json << "}, \"status\": " << Output::json_string(status["status"])
           << ", \"reason\": " << Output::json_string(status["reason"]);
      for (const std::string &key : ResultSchema::study_results())
        {
          const std::string value =
            status["status"] == "done" ? read.results.at(key) : "";
          csv << "," << value;
          if (!value.empty())
            json << ", " << Output::json_string(key) << ": " << value;
        }
      if (!testing)
        {
          csv << "," << status["wall_time_s"];
          json << ", \"wall_time_s\": " << status["wall_time_s"];
        }
      csv << "," << csv_field(status["reason"]) << "\n";
      json << "}";
    }
  } // namespace

  StudyProblem::StudyProblem(const Parameters::AllParameters &parameters,
                             const MPI_Comm                   mpi_communicator,
                             const bool                       resume)
    : parameters(parameters)
    , mpi_communicator(mpi_communicator)
    , resume(resume)
    , is_root(Utilities::MPI::this_mpi_process(mpi_communicator) == 0)
    , runner("Study",
             parameters.study.base_file,
             parameters.study.mesh_generator,
             parameters.study.mesh_generator_arguments,
             resume,
             mpi_communicator)
  {
    cases = make_study_cases(parameters, runner.base());
    const unsigned int n_ranks =
      Utilities::MPI::n_mpi_processes(mpi_communicator);
    AssertThrow(n_ranks % parameters.study.ranks_per_case == 0,
                ExcInputError("Study/Ranks per case = " +
                              std::to_string(parameters.study.ranks_per_case) +
                              " does not divide the " +
                              std::to_string(n_ranks) +
                              " MPI ranks of the job into groups."));
  }

  std::string
  StudyProblem::case_directory(const unsigned int index) const
  {
    return parameters.output.directory + "/" + cases[index].name;
  }

  void
  StudyProblem::write_case_files() const
  {
    on_root(
      [&]() {
        for (unsigned int i = 0; i < cases.size(); ++i)
          {
            const std::string directory = case_directory(i);
            runner.write_parameter_file(
              directory,
              cases[i].entries,
              cases[i].name + " of the study <" + parameters.parameter_file +
                ">: tkr-wear case.prm repeats it alone.");
            if (!resume)
              std::filesystem::remove(directory + "/status.json");
          }
      },
      mpi_communicator);
  }

  bool
  StudyProblem::run()
  {
    const unsigned int n_ranks =
      Utilities::MPI::n_mpi_processes(mpi_communicator);
    const unsigned int n_groups = n_ranks / parameters.study.ranks_per_case;
    if (is_root)
      std::cout
        << "Study <" << parameters.parameter_file << ">: " << cases.size()
        << " cases of <"
        << std::filesystem::path(parameters.study.base_file).filename().string()
        << ">, " << n_groups << " group(s) of "
        << parameters.study.ranks_per_case << " rank(s)"
        << (resume ? ", resumed" : "") << std::endl;
    write_case_files();

    const StepGroups group(mpi_communicator, n_groups);
    // Used by nothing but the check after a case's error (run_case()).
    MPI_Comm  error_communicator;
    const int ierr = MPI_Comm_dup(group.communicator, &error_communicator);
    AssertThrowMPI(ierr);
    // A stop signal: each group ends its case (with its checkpoint) or
    // takes no new one; cases without a status are continued by --resume.
    int signal = 0;
    {
      CaseQueue queue(mpi_communicator, n_groups > 1);
      for (unsigned int index = queue.next(group); index < cases.size();
           index              = queue.next(group))
        if ((signal = stop_requested(group.communicator)) != 0 ||
            run_case(index, group, error_communicator))
          {
                         signal = std::max(signal, stop_requested(group.communicator));
                         break;
          }
    }
    MPI_Comm_free(&error_communicator);

    MPI_Barrier(mpi_communicator);
    signal = Utilities::MPI::max(signal, mpi_communicator);
    AssertThrow(signal == 0,
                ExcStopped("Stopped by " + signal_name(signal) +
                           ": the cases done are kept (status.json), the "
                           "interrupted ones have their checkpoints; "
                           "tkr-wear --resume " +
                           parameters.parameter_file +
                           " continues the study."));
    unsigned int n_failed = 0;
    if (is_root)
      n_failed = output_results();
    n_failed = Utilities::MPI::broadcast(mpi_communicator, n_failed, 0);
    if (parameters.output.plots)
      {
        const std::string error =
          Output::run_script("plot-study",
                             {parameters.output.directory},
                             parameters.output.directory + "/plot-study.log",
                             mpi_communicator);
        if (is_root && !error.empty())
          std::cout << "Warning: " << error << std::endl;
      }
    return n_failed == 0;
  }

  bool
  StudyProblem::run_case(const unsigned int index,
                         const StepGroups  &group,
                         const MPI_Comm     error_communicator)
  {
    const std::string status_file = case_directory(index) + "/status.json";
    bool              skip        = false;
    if (group.is_group_root)
      skip = resume && !read_case_status(status_file).fields.empty();
    if (Utilities::MPI::broadcast(group.communicator, skip, 0))
      return false;

    const double              start   = MPI_Wtime();
    const CaseRunner::Outcome outcome = runner.run(case_directory(index),
                                                   cases[index].entries,
                                                   group,
                                                   cases[index].name);
    // Stopped on every rank of the group (the stop is agreed in it): no
    // status, so that --resume continues the case.
    if (outcome.status == "stopped")
      return true;
    // An error raised on some ranks of the group only leaves the others
    // waiting in the case forever (they hold no exception): end the study
    // (the cases done stay done; --resume continues it). A run that did not
    // converge fails on every rank of the group: all arrive at once.
    if (outcome.status == "failed" &&
        !all_ranks_arrive(error_communicator, error_grace_seconds))
      {
        std::cerr << "tkr-wear: " << cases[index].name << ": error on rank "
                  << Utilities::MPI::this_mpi_process(mpi_communicator)
                  << " that the other ranks of its group did not raise "
                     "within "
                  << error_grace_seconds << " s; ending the study (--resume "
                  << "continues it): " << outcome.reason << std::endl;
        MPI_Abort(mpi_communicator, 1);
      }
    const double wall_time = MPI_Wtime() - start;
    if (!group.is_group_root)
      return false;
    // The case's status and, if it is done, its results: what the study's
    // table is written from (output_results()).
    Output::Summary json("status.json");
    json.set("case", cases[index].name);
    json.set("status", outcome.status);
    json.set("reason", outcome.reason);
    json.set("resumed", outcome.resumed);
    json.set("wall_time_s", wall_time);
    if (outcome.status == "done")
      json.set("results", outcome.results);
    write_atomically(status_file, json.to_json());
    if (!parameters.output.testing)
      {
        std::ostringstream line;
        line << cases[index].name << " " << outcome.status << " in "
             << std::fixed << std::setprecision(1) << wall_time << " s (group "
             << group.index << ")";
        for (const auto &[key, value] : outcome.results)
          if (key == "mass_loss_mg")
            line << ": mass loss " << std::defaultfloat << std::setprecision(12)
                 << value << " mg";
        std::cout << line.str() + "\n" << std::flush;
      }
    return false;
  }

  unsigned int
  StudyProblem::output_results() const
  {
    std::vector<std::string> inputs;
    for (const auto &[name, value] : cases.front().inputs)
      inputs.push_back(name);
    std::ostringstream csv, json;
    csv << "case";
    for (const std::string &name : inputs)
      csv << "," << csv_field(name);
    csv << ",status";
    for (const std::string &key : ResultSchema::study_results())
      csv << "," << key;
    if (!parameters.output.testing)
      csv << ",wall_time_s";
    csv << ",reason\n";
    json << "{\n  \"study\": " << Output::json_string(parameters.parameter_file)
         << ",\n  \"base\": " << Output::json_string(parameters.study.base_file)
         << ",\n  \"cases\": [";

    // The screen table shows the inputs that differ between cases.
    std::vector<bool> varies(inputs.size(), false);
    for (const StudyCase &c : cases)
      for (unsigned int j = 0; j < inputs.size(); ++j)
        varies[j] =
          varies[j] || c.inputs[j].second != cases.front().inputs[j].second;
    std::cout << "Cases:" << std::endl;
    unsigned int n_failed = 0;
    for (unsigned int i = 0; i < cases.size(); ++i)
      {
        const CaseStatus read =
          listed_case_status(case_directory(i) + "/status.json");
        auto status = read.fields;
        if (status["status"] != "done")
          ++n_failed;
        json << (i == 0 ? "" : ",");
        write_case_row(cases[i], read, parameters.output.testing, csv, json);

        std::cout << "  " << cases[i].name << "  " << std::setw(6)
                  << status["status"];
        for (unsigned int j = 0; j < cases[i].inputs.size(); ++j)
          if (varies[j])
            std::cout << "  " << cases[i].inputs[j].first << " = "
                      << cases[i].inputs[j].second;
        if (status["status"] == "done")
          std::cout << "  mass loss " << read.results.at("mass_loss_mg")
                    << " mg";
        else
          std::cout << "  (" << status["reason"] << ")";
        std::cout << std::endl;
      }
    json << "\n  ],\n  \"done\": " << cases.size() - n_failed
         << ",\n  \"failed\": " << n_failed << "\n}\n";
    write_atomically(parameters.output.directory + "/study.csv", csv.str());
    write_atomically(parameters.output.directory + "/study.json", json.str());
    std::cout << cases.size() - n_failed << " of " << cases.size()
              << " cases done, " << n_failed << " failed; results in <"
              << parameters.output.directory << "/study.csv>" << std::endl;
    return n_failed;
  }
} // namespace TKR::Problems
