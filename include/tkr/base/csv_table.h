// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_base_csv_table_h
#define tkr_base_csv_table_h

#include <string>
#include <vector>

namespace TKR
{
  /**
   * A table of numbers read from a CSV file by column name: the gait
   * waveforms (Gait::Waveform) and the wear laws' tables
   * (Wear::PiecewiseLinear). Lines that are empty or start with '#' are
   * comments; the first other line is the header naming the columns; every
   * further line is a row of as many comma-separated numbers. The table
   * keeps the columns asked for, in that order (the file's other columns
   * are ignored), and the line of each row for messages. Every defect is
   * an ExcInputError naming the file (as "the <what> <file>") and the line.
   */
  class CsvTable
  {
  public:
    /**
     * Read @p filename, keeping the columns @p required (each must be in
     * the header) and those of @p optional that are there.
     * @p header_hint is put in parentheses after "a header naming the
     * columns" when the first line is numbers rather than names; @p help is
     * appended to the message about a missing column (e.g. where the format is
     * documented).
     */
    CsvTable(const std::string              &filename,
             const std::string              &what,
             const std::vector<std::string> &required,
             const std::vector<std::string> &optional    = {},
             const std::string              &header_hint = "",
             const std::string              &help        = "");

    /** Number of rows. */
    unsigned int
    n_rows() const
    {
      return values.size();
    }

    /** Whether column @p name was read (always true for a required one). */
    bool
    has_column(const std::string &name) const;

    /** The value of column @p name in row @p row. */
    double
    operator()(const unsigned int row, const std::string &name) const;

    /** Row @p row's values of the columns read, required ones first, in
     *  the order they were asked for. */
    const std::vector<double> &
    row(const unsigned int row) const
    {
      return values[row];
    }

    /** "Line <n> of the <what> <file>: ", the start of a message about
     *  row @p row. */
    std::string
    where(const unsigned int row) const;

    /** "The <what> <file>", the start of a message about the whole table. */
    std::string
    name() const;

  private:
    /** The columns of @p header at @p line to keep (names and indices). */
    void
    find_columns(const std::string              &header,
                 const unsigned int              line,
                 const std::vector<std::string> &required,
                 const std::vector<std::string> &optional,
                 const std::string              &header_hint,
                 const std::string              &help);

    const std::string filename;
    const std::string what;
    /** The columns read and their index in the file. */
    std::vector<std::string>         names;
    std::vector<unsigned int>        columns;
    std::vector<std::vector<double>> values;
    std::vector<unsigned int>        lines;
  };

  /**
   * @p text as a field of a CSV file: as it is, or in double quotes (its
   * quotes doubled, line breaks as spaces) if it holds a comma, a quote or
   * a line break.
   */
  std::string
  csv_field(const std::string &text);
} // namespace TKR

#endif
