// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_problems_study_cases_h
#define tkr_problems_study_cases_h

#include <tkr/parameters/parameters.h>

#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

/**
 * The cases of a study (`Problem = study`, doc/studies.md): which entries
 * of the base parameter file each case overrides, and with what value.
 */
namespace TKR::Problems
{
  /** One case: its name and the entries it sets. */
  struct StudyCase
  {
    /** "case-0000", "case-0001", ... */
    std::string name;
    /**
     * The varied inputs as the study names them (e.g. "Gait/Flexion axis
     * point[1]") with the value the case gives them (a component of a
     * vector entry, the product of `*=`), in the order of the study file.
     */
    std::vector<std::pair<std::string, std::string>> inputs;
    /** The entries the case's parameter file sets: path -> full value. */
    std::map<std::string, std::string> entries;
  };

  /**
   * The cases of @p study (its `subsection Study`) on the base run
   * @p base: the product of the grid's factors (the last one varying
   * fastest), the rows of the cases file and the samples, in this order
   * (so each grid point gets the same samples). ExcInputError naming the
   * study file's line, the case, the entry and the value for an entry the
   * base file does not have, a component out of range, or a value `+=` or
   * `*=` cannot use.
   */
  std::vector<StudyCase>
  make_study_cases(const Parameters::AllParameters &study,
                   const Parameters::AllParameters &base);

  /**
   * Set the input @p input of @p study_case (an entry "Subsection/Entry"
   * of @p base, "PATH[i]" for a component of a vector entry, or a moved
   * entry's old path) to @p value, as a study's `PATH = VALUE` does.
   * ExcInputError naming @p owner (a subsection), @p place ("FILE:LINE"),
   * the case, the entry and the value for an entry @p base does not have
   * or a component out of range.
   */
  void
  set_case_input(const std::string               &input,
                 const std::string               &value,
                 const Parameters::AllParameters &base,
                 const std::string               &owner,
                 const std::string               &place,
                 StudyCase                       &study_case);

  /**
   * The quantile of the standard normal distribution at @p p in (0, 1)
   * (Acklam's rational approximation refined by one Halley step on
   * std::erfc: about 1e-15 relative).
   */
  double
  standard_normal_quantile(const double p);

  /**
   * @p n_samples points in (0, 1)^@p n_dimensions from the generator
   * mt19937_64 seeded with @p seed: a Latin hypercube (each dimension's
   * interval cut into n_samples strata, one point in each, the strata of
   * the dimensions paired by random permutations) or, if @p latin_hypercube
   * is false, independent uniform points. Indexed [sample][dimension].
   */
  std::vector<std::vector<double>>
  unit_samples(const unsigned int n_samples,
               const unsigned int n_dimensions,
               const unsigned int seed,
               const bool         latin_hypercube);

  /**
   * std::cout and std::cerr into a run's log file (on @p is_group_root,
   * the rank that writes) or a string (the other ranks) while the guard
   * lives: a study's case, a calibration's wear run.
   */
  class CaseOutput
  {
  public:
    CaseOutput(const std::string &filename, const bool is_group_root)
    {
      if (is_group_root)
        file.open(filename);
      std::streambuf *target = is_group_root ?
                                 static_cast<std::streambuf *>(file.rdbuf()) :
                                 static_cast<std::streambuf *>(other.rdbuf());
      out                    = std::cout.rdbuf(target);
      err                    = std::cerr.rdbuf(target);
    }
    ~CaseOutput()
    {
      std::cout.flush();
      std::cerr.flush();
      std::cout.rdbuf(out);
      std::cerr.rdbuf(err);
    }

  private:
    std::ofstream      file;
    std::ostringstream other;
    std::streambuf    *out;
    std::streambuf    *err;
  };

  /**
   * The text of a case's parameter file: include @p base_file, then the
   * @p includes, then set @p entries except those of the mesh generator
   * (`Generator/...`).
   */
  std::string
  case_parameter_text(const std::string                        &base_file,
                      const std::vector<std::string>           &includes,
                      const std::map<std::string, std::string> &entries,
                      const std::string                        &comment);
} // namespace TKR::Problems

#endif
