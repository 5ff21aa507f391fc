// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <deal.II/base/utilities.h>

#include <tkr/base/csv_table.h>
#include <tkr/base/exceptions.h>

#include <algorithm>
#include <fstream>

namespace TKR
{
  using namespace dealii;

  CsvTable::CsvTable(const std::string              &filename,
                     const std::string              &what,
                     const std::vector<std::string> &required,
                     const std::vector<std::string> &optional,
                     const std::string              &header_hint,
                     const std::string              &help)
    : filename(filename)
    , what(what)
  {
    std::ifstream in(filename);
    AssertThrow(in.good(),
                ExcInputError("Cannot open the " + what + " <" + filename +
                              ">: it does not exist or is not readable."));
    std::string  line;
    unsigned int line_number = 0, n_fields = 0;
    while (std::getline(in, line))
      {
        ++line_number;
        const std::string trimmed = Utilities::trim(line);
        if (trimmed.empty() || trimmed[0] == '#')
          continue;
        const auto fields = Utilities::split_string_list(trimmed, ',');
        if (n_fields == 0)
          {
            find_columns(trimmed,
                         line_number,
                         required,
                         optional,
                         header_hint,
                         help);
            n_fields = fields.size();
            continue;
          }
        const std::string at = "Line <" + std::to_string(line_number) +
                               "> of the " + what + " <" + filename + ">: ";
        AssertThrow(fields.size() == n_fields,
                    ExcInputError(at + "expected " + std::to_string(n_fields) +
                                  " comma-separated values (one per column "
                                  "of the header), found " +
                                  std::to_string(fields.size()) + "."));
        std::vector<double> numbers;
        try
          {
            numbers = Utilities::string_to_double(fields);
          }
        catch (...)
          {
            AssertThrow(false, ExcInputError(at + "a value is not a number."));
          }
        std::vector<double> kept;
        for (const unsigned int c : columns)
          kept.push_back(numbers[c]);
        values.push_back(std::move(kept));
        lines.push_back(line_number);
      }
    AssertThrow(n_fields > 0,
                ExcInputError(name() + " has no header line naming its "
                                       "columns."));
  }

  void
  CsvTable::find_columns(const std::string              &header,
                         const unsigned int              line,
                         const std::vector<std::string> &required,
                         const std::vector<std::string> &optional,
                         const std::string              &header_hint,
                         const std::string              &help)
  {
    const auto        found = Utilities::split_string_list(header, ',');
    const std::string at    = "Line <" + std::to_string(line) + "> of the " +
                           what + " <" + filename + ">: ";
    bool numbers = true;
    try
      {
        Utilities::string_to_double(found);
      }
    catch (...)
      {
        numbers = false;
      }
    AssertThrow(!numbers,
                ExcInputError(at +
                              "the first line that is not a comment must "
                              "be a header naming the columns" +
                              (header_hint.empty() ? std::string() :
                                                     " (" + header_hint + ")") +
                              ", not numbers."));
    std::string list;
    for (const auto &n : found)
      list += (list.empty() ? "" : ", ") + n;
    for (const auto &name : required)
      AssertThrow(std::find(found.begin(), found.end(), name) != found.end(),
                  ExcInputError(at + "the header (" + list +
                                ") has no column named " + name +
                                "; the columns are found by their names in "
                                "the first line that is not a comment" +
                                (help.empty() ? "" : " (" + help + ")") + "."));
    std::vector<std::string> wanted = required;
    wanted.insert(wanted.end(), optional.begin(), optional.end());
    for (const auto &name : wanted)
      {
        const auto it = std::find(found.begin(), found.end(), name);
        if (it == found.end())
          continue;
        names.push_back(name);
        columns.push_back(it - found.begin());
      }
  }

  bool
  CsvTable::has_column(const std::string &name) const
  {
    return std::find(names.begin(), names.end(), name) != names.end();
  }

  double
  CsvTable::operator()(const unsigned int row, const std::string &name) const
  {
    const auto it = std::find(names.begin(), names.end(), name);
    Assert(it != names.end(), ExcMessage("Column " + name + " was not read."));
    return values[row][it - names.begin()];
  }

  std::string
  CsvTable::where(const unsigned int row) const
  {
    return "Line <" + std::to_string(lines[row]) + "> of the " + what + " <" +
           filename + ">: ";
  }

  std::string
  CsvTable::name() const
  {
    return "The " + what + " <" + filename + ">";
  }

  std::string
  csv_field(const std::string &text)
  {
    if (text.find_first_of(",\"\n") == std::string::npos)
      return text;
    std::string out = "\"";
    for (const char c : text)
      out += (c == '"'  ? std::string("\"\"") :
              c == '\n' ? std::string(" ") :
                          std::string(1, c));
    return out + "\"";
  }
} // namespace TKR
