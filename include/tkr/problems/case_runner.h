// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_problems_case_runner_h
#define tkr_problems_case_runner_h

#include <tkr/base/mpi.h>
#include <tkr/parameters/parameters.h>

#include <boost/serialization/string.hpp>
#include <boost/serialization/utility.hpp>
#include <boost/serialization/vector.hpp>

#include <map>
#include <string>
#include <utility>
#include <vector>

namespace TKR::Problems
{
  /**
   * The wear runs of a study's cases and of an optimisation's evaluations:
   * a base parameter file (Problem = wear) with some entries overridden,
   * each run in a directory of its own with its parameter file (case.prm:
   * `tkr-wear case.prm` repeats it alone), its mesh from a mesh generator
   * if there is one (the entries `Generator/NAME` become its `--set
   * NAME=VALUE` arguments; doc/studies.md), its screen output in log.txt.
   */
  class CaseRunner
  {
  public:
    /** How a run ended: "done", "failed" (with the reason) or "stopped"
     *  (a stop signal: its checkpoint written), whether it was resumed,
     *  and its results (Wear::RunResult::named_values()). */
    struct Outcome
    {
      std::string                                 status  = "done", reason;
      bool                                        resumed = false;
      std::vector<std::pair<std::string, double>> results;
      /** Seconds of the run. */
      double wall_time = 0;

      template <class Archive>
      void
      serialize(Archive &archive, const unsigned int)
      {
        archive &status &reason &resumed &results &wall_time;
      }
    };

    /**
     * The runs of @p base_file (checked: Problem = wear), their meshes by
     * @p generator with its fixed @p generator_arguments (separated by
     * white space; none if empty), both entries of the subsection
     * @p section (for the messages: `SECTION/Base parameter file`,
     * `SECTION/Mesh generator`); with @p resume a run continues from its
     * checkpoint. Collective on @p communicator (the generator lists its
     * parameters on its rank 0).
     */
    CaseRunner(const std::string &section,
               const std::string &base_file,
               const std::string &generator,
               const std::string &generator_arguments,
               const bool         resume,
               const MPI_Comm     communicator);

    /**
     * The base run's parameters, with the generator's parameters as
     * entries `Generator/NAME` (their base values): what a case's entries
     * may set.
     */
    const Parameters::AllParameters &
    base() const
    {
      return varied;
    }

    /**
     * Write @p directory/case.prm: the base file, the mesh generator's
     * mesh.prm if there is one, the file @p include if not empty, then
     * @p entries (with Output/Directory = @p directory) and @p comment at
     * the top. Call on one rank.
     */
    void
    write_parameter_file(const std::string                 &directory,
                         std::map<std::string, std::string> entries,
                         const std::string                 &comment,
                         const std::string                 &include = "") const;

    /**
     * The mesh (if there is a generator) and the wear run of
     * @p directory/case.prm with the entries @p entries (their Generator/
     * ones for the mesh) on @p group; the run's output in its log.txt. An
     * error of the run is its failure, its message the reason (one line,
     * also in log.txt after @p label).
     */
    Outcome
    run(const std::string                        &directory,
        const std::map<std::string, std::string> &entries,
        const StepGroups                         &group,
        const std::string                        &label) const;

  private:
    /** The generator and its fixed arguments. */
    std::vector<std::string>
    generator_command() const;

    /** The mesh of @p directory by the generator (group's rank 0). */
    void
    make_mesh(const std::string                        &directory,
              const std::map<std::string, std::string> &entries,
              const StepGroups                         &group) const;

    const std::string         section;
    const std::string         base_file;
    const std::string         generator;
    const std::string         generator_arguments;
    const bool                resume;
    Parameters::AllParameters varied;
  };
} // namespace TKR::Problems

#endif
