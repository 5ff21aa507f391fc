// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_problems_study_problem_h
#define tkr_problems_study_problem_h

#include <tkr/base/mpi.h>
#include <tkr/parameters/parameters.h>
#include <tkr/problems/case_runner.h>
#include <tkr/problems/study_cases.h>

#include <string>
#include <utility>
#include <vector>

namespace TKR::Problems
{
  /**
   * `Problem = study` (doc/studies.md): the cases of make_study_cases(),
   * each a WearProblem of the base parameter file with its entries
   * overridden, run by groups of `Ranks per case` ranks (StepGroups) that
   * take the next case from a queue shared over MPI (an atomic counter in
   * an MPI window on rank 0), so that cases of unequal cost keep every
   * group busy. Case i runs in <Output/Directory>/case-NNNN with its own
   * parameter file (case.prm: `tkr-wear case.prm` repeats it alone), its
   * screen output in log.txt and its outcome in status.json (done or
   * failed with the reason: an input error, a solve that did not
   * converge, a distorted mesh, ...); a failed case does not stop the
   * others. With resume, cases with a status are skipped and the others
   * continue from their checkpoints. At the end rank 0 writes study.csv
   * and study.json (each case's inputs, results from its summary.json,
   * status and wall time) and, with `Output/Plots`, scripts/plot-study's
   * plots.
   */
  class StudyProblem
  {
  public:
    StudyProblem(const Parameters::AllParameters &parameters,
                 const MPI_Comm                   mpi_communicator,
                 const bool                       resume);

    /** Run every case; true if every case is done (none failed). */
    bool
    run();

  private:
    /** Run case @p index on this group; its status record. True if a
     *  stop signal ended it (no status: --resume continues it). */
    bool
    run_case(const unsigned int index,
             const StepGroups  &group,
             const MPI_Comm     error_communicator);

    /**
     * Every case's directory and parameter file (rank 0), before any group
     * starts; without a resume the cases' old status files go.
     */
    void
    write_case_files() const;

    /** study.csv, study.json and the screen table (rank 0). */
    unsigned int
    output_results() const;

    std::string
    case_directory(const unsigned int index) const;

    const Parameters::AllParameters parameters;
    const MPI_Comm                  mpi_communicator;
    const bool                      resume;
    const bool                      is_root;
    /** Writes and runs the cases. */
    const CaseRunner       runner;
    std::vector<StudyCase> cases;
  };
} // namespace TKR::Problems

#endif
