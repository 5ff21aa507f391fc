// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.
//
// The result files of Problem = study (StudyProblem): study.csv, study.json
// and each case's status.json, declared in the ResultSchema.

#include <tkr/base/result_schema.h>

#include <string>
#include <vector>

namespace TKR::Problems
{
  namespace
  {
    /**
     * The results of a case that study.csv and study.json list: the
     * results of summary.json that are ResultField::study (kept in the
     * case's status.json), with their type in a JSON file (@p json).
     */
    std::vector<ResultField>
    study_fields(const bool json)
    {
      std::vector<ResultField> fields;
      for (const std::string &name : ResultSchema::study_results())
        {
          ResultField field = *ResultSchema::find("summary.json", name);
          field.meaning     = "the case's `summary.json` value" +
                          std::string(field.trace ? " (a trace)" : "");
          field.writers.clear();
          field.study = 0;
          if (!json)
            field.type.clear();
          fields.push_back(field);
        }
      return fields;
    }

    // study.csv, study.json (its keys, and those of each object of its
    // `cases`: "study.json cases") and status.json; the results of a case
    // are the results of summary.json that are ResultField::study.
    // clang-format off
    [[maybe_unused]] const bool declared =
      ResultSchema::declare(
        "study.csv",
        10,
        {
        {"case", "", "-", {}, "the case, `case-NNNN` (its directory)"},
        {"status", "", "-", {}, "`done` or `failed`"}}) &&
      ResultSchema::declare_derived("study.csv",
                                    50,
                                    [] { return study_fields(false); }) &&
      ResultSchema::declare(
        "study.csv",
        90,
        {
        {"wall_time_s", "", "s", {}, "the case's wall time (`status.json`); absent under `Output/Testing = true`", {}, false, false, true},
        {"reason", "", "-", {}, "why a case failed (the run's error message), empty if done"}}) &&
      ResultSchema::declare(
        "study.json",
        10,
        {
        {"study", "string", "-", {}, "the study file"},
        {"base", "string", "-", {}, "its `Study/Base parameter file`"},
        {"cases", "list", "-", {}, "one object per case (below)"},
        {"done", "integer", "-", {}, "cases done"},
        {"failed", "integer", "-", {}, "cases failed (or not run)"}}) &&
      ResultSchema::declare(
        "study.json cases",
        10,
        {
        {"case", "string", "-", {}, "the case, `case-NNNN`"},
        {"inputs", "object", "-", {}, "the case's values (strings) by entry path"},
        {"status", "string", "-", {}, "`done` or `failed`"},
        {"reason", "string", "-", {}, "why it failed, empty if done"}}) &&
      ResultSchema::declare_derived("study.json cases",
                                    50,
                                    [] { return study_fields(true); }) &&
      ResultSchema::declare(
        "study.json cases",
        90,
        {
        {"wall_time_s", "number", "s", {}, "the case's wall time; absent under `Output/Testing = true`", {}, false, false, true}}) &&
      ResultSchema::declare(
        "status.json",
        10,
        {
        {"case", "string", "-", {}, "the case, `case-NNNN`"},
        {"status", "string", "-", {}, "`done` or `failed`"},
        {"reason", "string", "-", {}, "why it failed, empty if done"},
        {"resumed", "boolean", "-", {}, "whether the case continued from its checkpoint"},
        {"wall_time_s", "number", "-", {}, "the case's wall time (s)"},
        {"results", "object", "-", {}, "a done case's results: every scalar key of its `summary.json` (the run's `Wear::RunResult`) with the same value; `study.csv` and `study.json` are written from these, and a done case that lacks one of theirs is listed as failed with a reason naming the key"}});
    // clang-format on
  } // namespace
} // namespace TKR::Problems
