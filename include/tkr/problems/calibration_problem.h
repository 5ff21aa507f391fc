// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_problems_calibration_problem_h
#define tkr_problems_calibration_problem_h

#include <tkr/base/mpi.h>
#include <tkr/parameters/parameters.h>
#include <tkr/problems/calibration_fit.h>
#include <tkr/wear/run_result.h>
#include <tkr/wear/tables.h>

#include <string>
#include <vector>

namespace TKR::Problems
{
  /**
   * `Problem = calibration` (doc/calibration.md): fit `Calibration/Fit`
   * (the Archard coefficient, the run-in's factor and length) to the
   * measured mass loss of one or more designs by least squares, with as
   * few wear runs as the model allows. A wear law linear in its
   * coefficient wears the geometry by the same path whatever k and run-in
   * are, only faster or slower: the mass loss is a function M(tau) of
   * tau = k F(c), F the run-in's integral. One run per design at the base
   * values gives M; the fit evaluates any k and run-in on it without a
   * run (Calibration::MassCurve). A second run per design at the fitted
   * values checks that (the blocks' discretisation, a tau beyond the
   * first run's end); if its masses differ from the prediction by more
   * than `Tolerance`, the fit is repeated on it, up to `Maximum runs`.
   * Confidence intervals from the specimens' own fits (Student's t over
   * their scatter), or from the residuals with one specimen. Output:
   * calibration.csv (residual per point), calibration_curves.csv,
   * calibration.json, calibrated.prm and calibration.png.
   */
  class CalibrationProblem
  {
  public:
    CalibrationProblem(const Parameters::AllParameters &parameters,
                       const MPI_Comm                   mpi_communicator);

    /** Fit; true if the fit was verified within `Tolerance`. */
    bool
    run();

  private:
    /** One design: its base run, measured points, specimens' names. */
    struct Design
    {
      std::string               name, base_file, measured_file;
      Parameters::AllParameters base;
      /** The base's value of the entry that scales its law's rate (the
       *  Archard coefficient, the table scale). */
      double coefficient = 1;
      /** The base's run-in (empty: none). */
      Wear::PiecewiseLinear run_in;
      /** The last measured cycles. */
      double end_cycles = 0;
      /** The measured file says (in a comment) its data are illustrative. */
      bool                     illustrative = false;
      std::vector<std::string> specimens;
    };

    /** The values of one run or fit: coefficient, run-in factor, length
     *  (the fitted ones from x, the others the base's or the start's). */
    struct Values
    {
      double coefficient = 1, run_in_factor = 1, run_in_length = 1;
      /** Whether the run-in is the calibration's (else the base's). */
      bool fitted_run_in = false;
    };

    void
    read_design(const Parameters::Calibration::Design &files);

    /** Refuse (one message) a fit the measured points cannot determine. */
    void
    check_identifiable() const;

    /** The values of @p x (fitted quantities in the order of the fit). */
    Values
    values(const std::vector<double> &x) const;

    /** The effective cycles F(c) of @p values for design @p d. */
    double
    effective_cycles(const Values      &values,
                     const unsigned int d,
                     double             c) const;

    /** The wear runs of round @p round at @p x; each design's M(tau). */
    std::vector<Calibration::MassCurve>
    run_round(const unsigned int round, const std::vector<double> &x);

    /** The wear run of @p directory/case.prm (its screen output in
     *  log.txt); an error if it did not converge. */
    Wear::RunResult
    run_wear(const std::string &directory,
             const unsigned int round,
             const std::string &name) const;

    /** The mass loss at @p point predicted from @p curves at @p x. */
    double
    predict(const std::vector<Calibration::MassCurve> &curves,
            const std::vector<double>                 &x,
            const Calibration::Point                  &point) const;

    /** The fit on @p curves from @p start. */
    Calibration::FitResult
    fit_on(const std::vector<Calibration::MassCurve> &curves,
           const std::vector<Calibration::Point>     &points,
           const std::vector<double>                 &start) const;

    /** The fitted values' confidence interval and where it comes from. */
    struct Interval
    {
      std::vector<double> lower, upper;
      std::string         from;
      /** Each specimen's own fit (if the interval comes from them). */
      std::vector<std::vector<double>> specimens;
    };

    /** The number of specimens of all designs. */
    unsigned int
    n_specimens() const;

    /** Each specimen's own fit (on @p curves, from @p result), or none if
     *  there is one specimen or one cannot determine the entries alone. */
    std::vector<std::vector<double>>
    specimen_fits(const std::vector<Calibration::MassCurve> &curves,
                  const Calibration::FitResult              &result) const;

    /** The interval of @p result (fitted on @p curves). */
    Interval
    interval(const std::vector<Calibration::MassCurve> &curves,
             const Calibration::FitResult              &result) const;

    /** calibration.csv and calibration_curves.csv (rank 0); the
     *  specimens' names and the screen's residual table. */
    std::pair<std::vector<std::string>, std::string>
    write_tables(const std::vector<Calibration::MassCurve> &check,
                 const Calibration::FitResult              &result,
                 const Interval                            &interval) const;

    /** calibrated-entries.prm (the fitted entries), calibrated.prm (the
     *  first design with them), calibrated-run-in.csv (rank 0). */
    void
    write_calibrated_prm(const Calibration::FitResult &result,
                         const bool                    illustrative) const;

    /** calibration.json (rank 0; doc/calibration.md). */
    void
    write_json(const Calibration::FitResult &result,
               const Interval               &interval,
               const unsigned int            runs,
               const double                  mismatch,
               const double                  rms,
               const bool                    illustrative) const;

    /** calibration.{csv,json}, calibration_curves.csv, calibrated.prm,
     *  calibration.png and the screen table (rank 0). */
    void
    output_results(const std::vector<Calibration::MassCurve> &check_curves,
                   const Calibration::FitResult              &result,
                   const Interval                            &interval,
                   const unsigned int                         runs,
                   const double                               mismatch) const;

    const Parameters::AllParameters parameters;
    const MPI_Comm                  mpi_communicator;
    const bool                      is_root;
    std::vector<Design>             designs;
    std::vector<Calibration::Point> points;
    double                          largest_mass = 0;
    /** The fitted entry that scales the wear rate (the Archard
     *  coefficient, a table's scale), "" if none is fitted. */
    std::string rate_entry;
  };
} // namespace TKR::Problems

#endif
