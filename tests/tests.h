// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.
//
// A small replacement for deal.II's tests/tests.h (which is not installed):
// initlog() sends deallog to the file "output", which the test driver then
// compares with NAME.output. MPI tests write from rank 0 only.

#ifndef tkr_tests_h
#define tkr_tests_h

#include <deal.II/base/logstream.h>
#include <deal.II/base/mpi.h>

#include <fstream>
#include <iomanip>

using namespace dealii;

/** Route deallog to the file "output" (on rank 0 of MPI_COMM_WORLD). */
inline void
initlog()
{
  static std::ofstream logfile;
  if (!Utilities::MPI::job_supports_mpi() ||
      Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) == 0)
    {
      logfile.open("output");
      deallog.attach(logfile,
                     /*print_job_id=*/true,
                     std::ios::showpoint | std::ios::left);
    }
  deallog.depth_console(0);
}

/** "yes"/"no", for printing a check whose exact numbers are round-off. */
inline const char *
yes_no(const bool condition)
{
  return condition ? "yes" : "no";
}

#endif
