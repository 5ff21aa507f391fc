// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_base_result_schema_h
#define tkr_base_result_schema_h

#include <functional>
#include <ostream>
#include <string>
#include <vector>

namespace TKR
{
  /**
   * One result: a key of a JSON result file or a column of a CSV one
   * (doc/output.md, "Result files"), with what a reader needs to know of
   * it. In a name, `NAME` stands for an activity's name in a mix
   * (`activity_NAME_mass_loss_mg`) and `SIDE` for `medial` and `lateral`
   * (expanded when declared).
   */
  struct ResultField
  {
    std::string name;
    /** JSON: string, integer, number, boolean, list or object; CSV: empty
     *  (every column is a number, a count or 1/0). */
    std::string type;
    /** mm, mm^3, mg, MPa, N, N m, deg, %, s, cycles; "-" for a ratio or a
     *  count. */
    std::string unit;
    /** The `Problem`s (summary.json) or gait protocols (steps.csv) whose
     *  runs write it; empty: every run that writes the file. */
    std::vector<std::string> writers;
    /** What it is, one line (doc/output.md says the same). */
    std::string meaning;
    /** The fields of a list's objects (summary.json). */
    std::vector<std::string> fields = {};
    /** An iteration or solve count of a solver: how it got there, not what
     *  it computed (left out of the files tests compare). */
    bool trace = false;
    /** Its place (1, 2, ...) among the results a study lists per case
     *  (study.csv, study.json); 0: not listed. */
    unsigned int study = 0;
    /** A wall time: absent under `Output/Testing`. */
    bool timing = false;
  };

  /**
   * A column of a table of records (Record: one row, e.g. a block of the
   * wear history): its field, and how the value is read from a record and
   * written back (the checkpoint reads rows back).
   */
  template <typename Record>
  struct ResultColumn
  {
    ResultField                           field;
    std::function<double(const Record &)> get;
    std::function<void(Record &, double)> set;
  };

  /** A column of @p Record's member @p member (any arithmetic type). */
  template <typename Record, typename T>
  ResultColumn<Record>
  member_column(ResultField field, T Record::*member)
  {
    return {std::move(field),
            [member](const Record &r) {
              return static_cast<double>(r.*member);
            },
            [member](Record &r, const double value) {
              r.*member = static_cast<T>(value);
            }};
  }

  /**
   * The fields of @p table (a table of results: entries with a `field`,
   * e.g. ResultColumn): those that are ResultField::timing (@p timing), or
   * the others.
   */
  template <typename Table>
  std::vector<ResultField>
  fields_of(const Table &table, const bool timing = false)
  {
    std::vector<ResultField> fields;
    for (const auto &entry : table)
      if (entry.field.timing == timing)
        fields.push_back(entry.field);
    return fields;
  }

  /**
   * @p pattern with its placeholder (`SIDE` or `NAME`, the first) replaced
   * by @p value: a side's or an activity's field name.
   */
  std::string
  with_name(std::string pattern, const std::string &value);

  /**
   * The schema of every result file: the one definition of every result
   * that the program writes, from which the files' headers come, that
   * `tkr-wear --print-schema` prints, that python/tkr_results.py loads
   * and that tests/output_schema checks doc/output.md against.
   *
   * The owner of a result declares it in its own file (a wear run's
   * results in run_result.cc, a protocol's in its own file, the contact
   * problem's in contact_problem.cc), during the library's static
   * initialisation. A file's fields are ordered by the position their
   * owner gives (then by the owner's name, then as declared): the order of the
   * files' columns and of doc/output.md's tables. A field declared by two
   * owners (the same name and file) is one field with both writers.
   */
  class ResultSchema
  {
  public:
    /**
     * Declare @p fields of the result file @p file at @p position for
     * @p owner (a model's name: the order of two models' fields at the
     * same position); true (for a static initialiser). Throws if a field
     * of the same name is declared again with another type, unit or
     * meaning.
     */
    static bool
    declare(const std::string              &file,
            double                          position,
            const std::vector<ResultField> &fields,
            const std::string              &owner = "");

    /**
     * Declare fields of @p file at @p position that come from other
     * fields (a study's columns are results of summary.json): @p fields
     * is called when the file's fields are asked for, after every
     * declaration. True.
     */
    static bool
    declare_derived(const std::string                               &file,
                    double                                           position,
                    const std::function<std::vector<ResultField>()> &fields);

    /** The fields of @p file, in order; empty for an unknown file. */
    static std::vector<ResultField>
    fields(const std::string &file);

    /** The result files, by name. */
    static std::vector<std::string>
    files();

    /**
     * The field of @p file that @p name is (`NAME` matching an activity's
     * name), or null.
     */
    static const ResultField *
    find(const std::string &file, const std::string &name);

    /** The names of summary.json's fields that a study lists per case. */
    static std::vector<std::string>
    study_results();

    /** The whole schema as JSON (`tkr-wear --print-schema`). */
    static void
    print(std::ostream &out);
  };
} // namespace TKR

#endif
