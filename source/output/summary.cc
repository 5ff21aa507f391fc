// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <tkr/base/atomic_file.h>
#include <tkr/base/exceptions.h>
#include <tkr/base/mpi.h>
#include <tkr/base/result_schema.h>
#include <tkr/output/summary.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>

namespace TKR::Output
{
  Summary::Summary(const std::string &file)
    : file(file)
  {}

  void
  Summary::set_raw(const std::string &key, const std::string &json_value)
  {
    AssertThrow(file.empty() || ResultSchema::find(file, key) != nullptr,
                dealii::ExcMessage("The result <" + key + "> of <" + file +
                                   "> is not in the result schema: declare "
                                   "it where it is computed "
                                   "(ResultSchema::declare)."));
    for (auto &entry : entries)
      if (entry.first == key)
        {
          entry.second = json_value;
          return;
        }
    entries.emplace_back(key, json_value);
  }

  namespace
  {
    std::string
    number(const double value)
    {
      if (!std::isfinite(value))
        return "null";
      std::ostringstream out;
      out << std::setprecision(12) << value;
      return out.str();
    }

    std::string
    object(const Summary::Record &record)
    {
      std::string json = "{";
      for (unsigned int i = 0; i < record.size(); ++i)
        json += (i > 0 ? ", " : "") + json_string(record[i].first) + ": " +
                number(record[i].second);
      return json + "}";
    }
  } // namespace

  void
  Summary::set(const std::string &key, const double value)
  {
    set_raw(key, number(value));
  }

  void
  Summary::set(const std::string &key, const Record &record)
  {
    set_raw(key, object(record));
  }

  void
  Summary::set(const std::string &key, const std::vector<Record> &records)
  {
    std::string json = "[";
    for (unsigned int r = 0; r < records.size(); ++r)
      json += (r > 0 ? ", " : "") + object(records[r]);
    set_raw(key, json + "]");
  }

  void
  Summary::set(const std::string &key, const int value)
  {
    set_raw(key, std::to_string(value));
  }

  void
  Summary::set(const std::string &key, const unsigned int value)
  {
    set_raw(key, std::to_string(value));
  }

  void
  Summary::set(const std::string &key, const unsigned long long value)
  {
    set_raw(key, std::to_string(value));
  }

  void
  Summary::set(const std::string &key, const bool value)
  {
    set_raw(key, value ? "true" : "false");
  }

  void
  Summary::set(const std::string &key, const std::string &value)
  {
    set_raw(key, json_string(value));
  }

  void
  Summary::set(const std::string &key, const char *value)
  {
    set(key, std::string(value));
  }

  std::string
  Summary::to_json() const
  {
    std::string json = "{\n";
    for (unsigned int i = 0; i < entries.size(); ++i)
      json += "  " + json_string(entries[i].first) + ": " + entries[i].second +
              (i + 1 < entries.size() ? ",\n" : "\n");
    return json + "}\n";
  }

  void
  Summary::write(const std::string &directory,
                 const MPI_Comm     mpi_communicator) const
  {
    on_root([&]() { write_atomically(directory + "/summary.json", to_json()); },
            mpi_communicator);
  }

  void
  create_directory(const std::string &directory,
                   const MPI_Comm     mpi_communicator)
  {
    std::string error;
    if (dealii::Utilities::MPI::this_mpi_process(mpi_communicator) == 0)
      {
        std::error_code code;
        std::filesystem::create_directories(directory, code);
        if (code || !std::filesystem::is_directory(directory))
          error = "Cannot create the output directory <" + directory +
                  ">: " + (code ? code.message() : "not a directory") + ".";
      }
    error = dealii::Utilities::MPI::broadcast(mpi_communicator, error, 0);
    AssertThrow(error.empty(), ExcInputError(error));
  }
} // namespace TKR::Output
