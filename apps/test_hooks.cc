// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.
//
// tkr-wear-test: tkr-wear with the fault injection that two tests need
// (cli/one_rank_error, scripts/study). With TKR_TEST_ERROR_ON_RANK=R in the
// environment, rank R of a wear run raises an input error alone, as a
// rank-local failure would, while the other ranks go on into the set-up.
// Linked only into tkr-wear-test: tkr-wear and libtkr do not contain it.

#include <deal.II/base/mpi.h>

#include <tkr/base/exceptions.h>
#include <tkr/problems/wear_problem.h>

#include <cstdlib>
#include <string>

namespace
{
  [[maybe_unused]] const bool installed = []() {
    TKR::Problems::WearProblem::start_hook = [](const MPI_Comm world) {
      if (const char *rank = std::getenv("TKR_TEST_ERROR_ON_RANK"))
        AssertThrow(std::to_string(
                      dealii::Utilities::MPI::this_mpi_process(world)) != rank,
                    TKR::ExcInputError(
                      "TKR_TEST_ERROR_ON_RANK: an error raised on rank " +
                      std::string(rank) + " alone."));
    };
    return true;
  }();
} // namespace
