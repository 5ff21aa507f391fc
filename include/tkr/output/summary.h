// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_output_summary_h
#define tkr_output_summary_h

#include <deal.II/base/mpi.h>

#include <tkr/base/json.h>

#include <string>
#include <utility>
#include <vector>

namespace TKR::Output
{
  /**
   * The machine-readable record of a run, written as `summary.json`
   * (DESIGN.md section 6). Keys keep the order in which they were first
   * set; setting a key again replaces its value. Only rank 0 writes.
   */
  class Summary
  {
  public:
    /**
     * A record of the result file @p file of the ResultSchema: a key it
     * does not declare is an error (a result is declared where it is
     * computed). Empty: any key (a file outside the schema).
     */
    explicit Summary(const std::string &file = "");

    void
    set(const std::string &key, const double value);
    void
    set(const std::string &key, const int value);
    void
    set(const std::string &key, const unsigned int value);
    void
    set(const std::string &key, const unsigned long long value);
    void
    set(const std::string &key, const bool value);
    void
    set(const std::string &key, const std::string &value);
    void
    set(const std::string &key, const char *value);

    /** One record: named numbers, in their order. */
    using Record = std::vector<std::pair<std::string, double>>;

    /** A record, written as an object. */
    void
    set(const std::string &key, const Record &record);

    /** A list of records, written as an array of objects. */
    void
    set(const std::string &key, const std::vector<Record> &records);

    /** The JSON text. */
    std::string
    to_json() const;

    /** Write `directory/summary.json` on rank 0 of @p mpi_communicator
     *  (atomically: a reader never sees half a file). */
    void
    write(const std::string &directory, const MPI_Comm mpi_communicator) const;

  private:
    void
    set_raw(const std::string &key, const std::string &json_value);

    std::string                                      file;
    std::vector<std::pair<std::string, std::string>> entries;
  };

  /** Create @p directory (and its parents) on rank 0; throw if impossible. */
  void
  create_directory(const std::string &directory,
                   const MPI_Comm     mpi_communicator);

  using TKR::json_string;
} // namespace TKR::Output

#endif
