// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.
//
// tkr-wear: the command-line front end. It reads the parameter file, chooses
// the problem and reports errors; everything else lives in the library.

#include <deal.II/base/mpi.h>

#include <tkr/base/exceptions.h>
#include <tkr/base/mpi.h>
#include <tkr/base/registry.h>
#include <tkr/base/result_schema.h>
#include <tkr/elasticity/blas_kernel.h>
#include <tkr/parameters/parameters.h>
#include <tkr/problems/calibration_problem.h>
#include <tkr/problems/contact_problem.h>
#include <tkr/problems/elasticity_problem.h>
#include <tkr/problems/optimisation_problem.h>
#include <tkr/problems/study_problem.h>
#include <tkr/problems/wear_problem.h>

#include <iostream>
#include <string>

namespace
{
  void
  print_usage(std::ostream &out)
  {
    out
      << "Usage: tkr-wear FILE.prm           run the problem the file describes\n"
      << "       tkr-wear --resume FILE.prm  continue a wear run from the "
         "checkpoint in its output directory\n"
      << "                                   (a study: skip the finished "
         "cases, continue the others)\n"
      << "       tkr-wear --print-parameters write the documented default "
         "parameter file\n"
      << "       tkr-wear --list-models      the models of each kind (wear "
         "laws, gait protocols)\n"
      << "       tkr-wear --model-example NAME\n"
      << "                                   the entries that run the model "
         "NAME with its example inputs\n"
      << "       tkr-wear --print-schema     every result file's keys and "
         "columns (JSON; doc/output.md)\n"
      << "       tkr-wear --help             this text\n"
      << "SIGTERM or SIGUSR1 stops a wear run or a study with a checkpoint "
         "(exit code 3;\n--resume continues it; doc/cluster.md).\n"
      << "Run in parallel with: mpirun -np N tkr-wear FILE.prm\n";
  }

  /** Run the problem; returns the process exit code. */
  int
  run(const std::string &filename,
      const bool         resume,
      const MPI_Comm     mpi_communicator)
  {
    using namespace TKR;
    const Parameters::AllParameters parameters =
      Parameters::read_parameters(filename);
    if (dealii::Utilities::MPI::this_mpi_process(mpi_communicator) == 0)
      {
        for (const std::string &note : parameters.notes)
          std::cout << "Note: " << note << std::endl;
        const std::string blas = Elasticity::BlasKernel::note();
        if (!blas.empty() && !parameters.output.testing)
          std::cout << "BLAS: " << blas << std::endl;
      }
    const bool stoppable =
      parameters.problem == Parameters::ProblemType::wear ||
      parameters.problem == Parameters::ProblemType::study ||
      parameters.problem == Parameters::ProblemType::optimisation;
    AssertThrow(!resume || stoppable,
                ExcInputError("--resume continues a wear run (Problem = "
                              "wear), a study or an optimisation; <" +
                              filename + "> sets Problem = " +
                              Parameters::to_string(parameters.problem) + "."));
    // A cluster's time limit: a wear run, a study or an optimisation stops
    // with a checkpoint (doc/cluster.md).
    if (stoppable)
      install_stop_handlers();
    switch (parameters.problem)
      {
        case Parameters::ProblemType::elasticity:
          {
            Problems::ElasticityProblem problem(parameters, mpi_communicator);
            return problem.run() ? 0 : 1;
          }
        case Parameters::ProblemType::contact:
          {
            Problems::ContactProblem problem(parameters, mpi_communicator);
            return problem.run() ? 0 : 1;
          }
        case Parameters::ProblemType::wear:
          {
            Problems::WearProblem problem(parameters, mpi_communicator, resume);
            return problem.run() ? 0 : 1;
          }
        case Parameters::ProblemType::study:
          {
            Problems::StudyProblem problem(parameters,
                                           mpi_communicator,
                                           resume);
            return problem.run() ? 0 : 1;
          }
        case Parameters::ProblemType::calibration:
          {
            Problems::CalibrationProblem problem(parameters, mpi_communicator);
            return problem.run() ? 0 : 1;
          }
        case Parameters::ProblemType::optimisation:
          {
            Problems::OptimisationProblem problem(parameters,
                                                  mpi_communicator,
                                                  resume);
            return problem.run() ? 0 : 1;
          }
      }
    return 1;
  }
} // namespace

int
main(int argc, char *argv[])
{
  using namespace dealii;
  // (may execute the program again, before MPI starts)
  TKR::Elasticity::BlasKernel::select(argv);
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  const MPI_Comm                   mpi_communicator = MPI_COMM_WORLD;
  const bool is_root = Utilities::MPI::this_mpi_process(mpi_communicator) == 0;

  const std::string argument = (argc >= 2 ? argv[1] : "");
  const bool        resume   = (argc == 3 && argument == "--resume");
  const bool        example  = (argc == 3 && argument == "--model-example");
  if ((argc != 2 && !resume && !example) || argument == "--help" ||
      argument == "-h")
    {
      const bool asked = (argc == 2);
      if (is_root)
        print_usage(asked ? std::cout : std::cerr);
      return asked ? 0 : 2;
    }
  if (argument == "--print-parameters")
    {
      if (is_root)
        TKR::Parameters::print_default_parameters(std::cout);
      return 0;
    }
  if (argument == "--print-schema")
    {
      if (is_root)
        TKR::ResultSchema::print(std::cout);
      return 0;
    }
  if (argument == "--list-models")
    {
      if (is_root)
        TKR::ModelKind::list(std::cout);
      return 0;
    }
  if (example)
    try
      {
        const std::string text = TKR::ModelKind::example(argv[2]);
        if (is_root)
          std::cout << text;
        return 0;
      }
    catch (const TKR::ExcInputError &exc)
      {
        if (is_root)
          std::cerr << "tkr-wear: error: " << TKR::exception_message(exc)
                    << std::endl;
        return 1;
      }

  // Used by nothing but the check after an error (TKR::all_ranks_arrive).
  MPI_Comm  error_communicator;
  const int ierr = MPI_Comm_dup(mpi_communicator, &error_communicator);
  AssertThrowMPI(ierr);
  try
    {
      const int code =
        run(resume ? argv[2] : argument, resume, mpi_communicator);
      MPI_Comm_free(&error_communicator);
      return code;
    }
  catch (const TKR::ExcStopped &exc)
    {
      // Raised on every rank: the stop is agreed collectively.
      MPI_Comm_free(&error_communicator);
      if (is_root)
        std::cout << "tkr-wear: " << TKR::exception_message(exc)
                  << " (exit code " << TKR::stopped_exit_code << ")"
                  << std::endl;
      return TKR::stopped_exit_code;
    }
  catch (const TKR::ExcInputError &exc)
    {
      // Every rank normally reads the same input and fails the same way. An
      // error raised on some ranks only would leave the others waiting
      // forever in their next collective operation: after a grace time for
      // the others to raise it too, this rank says so and ends the run.
      if (!TKR::all_ranks_arrive(error_communicator, TKR::error_grace_seconds))
        {
          std::cerr << "tkr-wear: error on rank "
                    << Utilities::MPI::this_mpi_process(mpi_communicator)
                    << " (the other ranks did not raise it within "
                    << TKR::error_grace_seconds
                    << " s; ending them): " << TKR::exception_message(exc)
                    << std::endl;
          MPI_Abort(mpi_communicator, 1);
        }
      MPI_Comm_free(&error_communicator);
      if (is_root)
        std::cerr << "tkr-wear: error: " << TKR::exception_message(exc)
                  << std::endl;
      return 1;
    }
  catch (const std::exception &exc)
    {
      std::cerr << "tkr-wear: internal error on rank "
                << Utilities::MPI::this_mpi_process(mpi_communicator) << ":\n"
                << exc.what() << std::endl;
      MPI_Abort(mpi_communicator, 2);
    }
  return 2;
}
