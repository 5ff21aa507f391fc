// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_problems_optimisation_problem_h
#define tkr_problems_optimisation_problem_h

#include <tkr/base/mpi.h>
#include <tkr/output/summary.h>
#include <tkr/parameters/parameters.h>
#include <tkr/problems/case_runner.h>

#include <boost/serialization/string.hpp>
#include <boost/serialization/vector.hpp>

#include <exception>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace TKR::Problems
{
  /**
   * `Problem = optimisation` (doc/optimisation.md): the values of some
   * entries of a wear run (the variables, within bounds) that minimise or
   * maximise one of its results (the objective) with others within limits
   * (the constraints), by a derivative-free method of NLopt (COBYLA or
   * BOBYQA) on the variables scaled to 0 .. 1. Each evaluation is a wear
   * run of the base parameter file with the variables set (CaseRunner: on
   * all ranks, in <Output/Directory>/eval-NNNN, its mesh regenerated if
   * there is a mesh generator), kept with its log and its results; a
   * failed or unconverged run is a failed point for the method (worse than
   * every done one, every constraint violated), never a good one. With
   * --resume the method is replayed (it is deterministic) and the
   * evaluations with an evaluation.json are read instead of run. At the
   * end: optimisation.csv (every evaluation), optimisation.json (the best
   * design), best.prm (and best.msh with a mesh generator).
   */
  class OptimisationProblem
  {
  public:
    /**
     * Checks every input before any run: the variables' paths against the
     * base file, their bounds and the start within them, the objective and
     * the constraints against the result schema (ExcInputError naming the
     * file, line and entry).
     */
    OptimisationProblem(const Parameters::AllParameters &parameters,
                        const MPI_Comm                   mpi_communicator,
                        const bool                       resume);

    /** Run the method; true if it found a feasible design. */
    bool
    run();

    /** A variable: its path as the entry names it, bounds, scale, start. */
    struct Variable
    {
      std::string input;
      double      lower = 0, upper = 0;
      bool        log   = false;
      double      start = 0;

      /** The value at the unit coordinate @p u (0: lower, 1: upper). */
      double
      value(const double u) const;

      /** The unit coordinate of the value @p x. */
      double
      unit(const double x) const;
    };

    /** A constraint `KEY <= VALUE` (at_most) or `KEY >= VALUE`. */
    struct Constraint
    {
      std::string key;
      bool        at_most = true;
      double      value   = 0;

      /** How far @p result violates it, relative to |VALUE| (if not 0):
       *  <= 0 if it holds. */
      double
      violation(const double result) const;
    };

    /** A scenario (Optimisation/Scenarios): a file included in its runs. */
    struct Scenario
    {
      std::string name, file;
      double      weight = 1;
    };

    /** One evaluation. */
    struct Evaluation
    {
      /** The variables' unit coordinates and values. */
      std::vector<double> u, x;
      /** done or failed (with the reason). */
      std::string status = "done", reason;
      /**
       * The objective's and the constraints' results (done only), the
       * scenarios' combined; the objective of each scenario.
       */
      double              objective = 0;
      std::vector<double> constraints, scenario_objectives;
      /** Seconds of its runs (summed over the scenarios). */
      double wall_time = 0;
      /** Read from its evaluation.json (--resume). */
      bool resumed = false;

      /** Done and every constraint holds (within 1e-9). */
      bool
      feasible(const std::vector<Constraint> &constraints) const;

      template <class Archive>
      void
      serialize(Archive &archive, const unsigned int)
      {
        archive &u &x &status &reason &objective &constraints
          &scenario_objectives &wall_time &resumed;
      }
    };

  private:
    /** Whether the test function replaces the wear runs. */
    bool
    testing() const
    {
      return parameters.optimisation.test_function != "none";
    }

    /** `Optimisation/ENTRY (FILE:LINE)` for the messages. */
    std::string
    place(const std::string &entry) const;

    /**
     * The inputs, checked (ExcInputError with place()): the variables, the
     * objective and constraints, the initial design and the scenarios, the
     * verification.
     */
    void
    parse_variables();
    void
    parse_results();
    void
    parse_scenarios();
    void
    parse_verification();

    /** Refuse @p key (named at @p where) if it is not a number of the
     *  results. */
    void
    check_result_key(const std::string &key, const std::string &where) const;

    /** The first line on the screen; without --resume the evaluations of
     *  an earlier run deleted. */
    void
    announce() const;

    /** The method's start: the base file's values, or the best of them
     *  and the initial design (evaluated first). */
    std::vector<double>
    start_point();

    /** NLopt's method from @p u; why it stopped. */
    std::string
    run_method(std::vector<double> u);

    /** A wear run of an evaluation (one per scenario). */
    struct Run
    {
      std::string                        directory, include, label;
      std::map<std::string, std::string> entries;
    };

    /** The evaluation at @p u (an earlier one at the same point, or a new
     *  one); its index. */
    unsigned int
    evaluate(const std::vector<double> &u);

    /**
     * The evaluations at the unit points @p points: an earlier one at the
     * same point, one --resume reads back, or new ones whose runs (one per
     * scenario each) go over the rank groups at once (run_all()); their
     * indices. Prints a line per new evaluation.
     */
    std::vector<unsigned int>
    evaluate_batch(const std::vector<std::vector<double>> &points);

    /**
     * The evaluation at @p u: an earlier one, one --resume reads back, or
     * a new one, whose index goes to @p fresh and its runs to @p runs.
     */
    unsigned int
    add_evaluation(const std::vector<double> &u,
                   std::vector<unsigned int> &fresh,
                   std::vector<Run>          &runs);

    /**
     * The runs of the variables at @p u (their values into @p e) with the
     * entries @p extra, in @p directory (in DIRECTORY/NAME per scenario).
     */
    std::vector<Run>
    evaluation_runs(const std::string                        &directory,
                    const std::vector<double>                &u,
                    const std::map<std::string, std::string> &extra,
                    Evaluation                               &e) const;

    /**
     * @p runs by @p runner over groups of Ranks per evaluation ranks (one
     * group for one run), each group's parameter files by its rank 0;
     * their outcomes on every rank. A stop signal ends them with their
     * checkpoints (ExcStopped).
     */
    std::vector<CaseRunner::Outcome>
    run_all(const CaseRunner &runner, const std::vector<Run> &runs) const;

    /**
     * The results of @p e from its runs' @p outcomes (one per scenario, in
     * order): failed if one failed; the objective combined, each
     * constraint's worst value.
     */
    void
    combine(const std::vector<CaseRunner::Outcome> &outcomes,
            Evaluation                             &e) const;

    /** The start and the best design again with the verification's mesh
     *  and entries (verify-start, verify-best). */
    void
    verify();

    /** The line of evaluation @p e named @p label on the screen. */
    std::string
    evaluation_line(const std::string &label, const Evaluation &e) const;

    /** The results of the test function at @p u. */
    std::map<std::string, double>
    test_results(const std::vector<double> &u) const;

    /** What the method minimises at evaluation @p index. */
    double
    merit(const unsigned int index) const;

    /** The best feasible evaluation (the least violation if none). */
    unsigned int
    best() const;

    /** Evaluation @p index's name, `eval-NNNN`, and its directory. */
    std::string
    name(const unsigned int index) const;
    std::string
    directory(const unsigned int index) const;

    /** Write evaluation @p index's evaluation.json (@p e); read it
     *  (resume). */
    void
    write_evaluation(const unsigned int index, const Evaluation &e) const;
    bool
    read_evaluation(const unsigned int         index,
                    const std::vector<double> &u,
                    Evaluation                &evaluation) const;

    /** The verification's numbers into @p json, and the screen's words on
     *  them. */
    std::string
    verification_verdict(Output::Summary &json) const;

    /** optimisation.csv; best.prm (and best.msh) of evaluation @p b. */
    void
    write_table() const;
    void
    write_best_prm(const unsigned int b) const;

    /** optimisation.csv, optimisation.json, best.prm (rank 0). */
    void
    write_results(const std::string &stop_reason) const;

    /** NLopt's callbacks: the objective and constraint @p c. */
    static double
    objective_callback(unsigned n, const double *u, double *, void *data);
    static double
    constraint_callback(unsigned n, const double *u, double *, void *data);

    const Parameters::AllParameters parameters;
    const MPI_Comm                  mpi_communicator;
    const bool                      resume;
    const bool                      is_root;
    const CaseRunner                runner;
    /** The verification's runs (their own generator arguments). */
    std::unique_ptr<CaseRunner> verification_runner;
    /** The verification's entries (path -> value). */
    std::map<std::string, std::string> verification_entries;
    /** verify()'s evaluations of the start and the best design. */
    std::vector<Evaluation> verification;
    std::vector<Scenario>   scenarios;
    std::vector<Variable>   variables;
    std::string             objective_key;
    bool                    maximise = false;
    std::vector<Constraint> constraints;
    std::vector<Evaluation> evaluations;
    /** An exception of a callback, rethrown after NLopt returns. */
    std::exception_ptr pending;
    /** (this, constraint index) for each constraint's callback. */
    std::vector<std::pair<OptimisationProblem *, unsigned int>> constraint_data;
  };
} // namespace TKR::Problems

#endif
