// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.
//
// The parameters a checkpoint records (the ones that determine the wear
// state) and the check of a resume against them.

#include <tkr/base/exceptions.h>
#include <tkr/output/checkpoint.h>

#include <algorithm>
#include <cstdint>
#include <fstream>
#include <iomanip>
#include <sstream>

namespace TKR::Output
{
  using namespace dealii;

  namespace
  {
    /** FNV-1a (64 bit) of the bytes of @p file, in hex ("" if unreadable). */
    std::string
    checksum(const std::string &file)
    {
      std::ifstream in(file, std::ios::binary);
      if (!in.good())
        return "";
      std::uint64_t hash = 14695981039346656037ull;
      char          c;
      while (in.get(c))
        {
          hash ^= static_cast<unsigned char>(c);
          hash *= 1099511628211ull;
        }
      std::ostringstream text;
      text << std::hex << std::setw(16) << std::setfill('0') << hash;
      return text.str();
    }

    /** The state parameters as "entry = value" lines. */
    std::string
    to_text(const std::map<std::string, std::string> &entries)
    {
      std::string text;
      for (const auto &[entry, value] : entries)
        text += entry + " = " + value + "\n";
      return text;
    }

    /** The lines of to_text() back as entries. */
    std::map<std::string, std::string>
    from_text(const std::string &text)
    {
      std::map<std::string, std::string> entries;
      std::istringstream                 in(text);
      std::string                        line;
      while (std::getline(in, line))
        if (const auto equals = line.find(" = "); equals != std::string::npos)
          entries[line.substr(0, equals)] = line.substr(equals + 3);
      return entries;
    }

    /**
     * State entries added to the program after checkpoints were first
     * written, with the value that means what a checkpoint without the entry
     * did (the behaviour before the entry existed).
     */
    const std::map<std::string, std::string> &
    entries_added_later()
    {
      static const std::map<std::string, std::string> added = {
        {"Wear/Archard cs/Cross-shear table (checksum)", ""},
        {"Wear/Area/Cross-shear table (checksum)", ""},
        {"Wear/Run-in file (checksum)", ""},
        {"Gait/Displacement control/AP displacement sign", "1"},
        {"Gait/Displacement control/IE rotation sign", "1"},
        {"Gait/Femur AP offset", "0"},
        {"Gait/Channel scales", ""},
        {"Wear/Cross-shear definition", "work tensor"},
        {"Wear/Archard cs/Table scale", "1"},
        {"Wear/Area/Table scale", "1"}};
      return added;
    }

    /**
     * @p recorded with the entries that moved into a model's subsection
     * since (Parameters::moved_entries()) also under their new paths, so
     * that a checkpoint written before the move compares with today's.
     */
    std::map<std::string, std::string>
    with_moved_entries(std::map<std::string, std::string> recorded)
    {
      const std::string suffix = " (checksum)";
      for (const auto &[from, to] : Parameters::moved_entries())
        for (const std::string &tail : {std::string(), suffix})
          if (const auto it = recorded.find(from + tail); it != recorded.end())
            recorded.emplace(to + tail, it->second);
      return recorded;
    }

    /** Refuse a checkpoint whose state parameters differ from @p now. */
    void
    check_parameters(const std::string                        &filename,
                     const std::map<std::string, std::string> &then,
                     const std::map<std::string, std::string> &now)
    {
      for (const auto &[entry, value] : now)
        {
          const auto it = then.find(entry);
          if (it == then.end())
            if (const auto added = entries_added_later().find(entry);
                added != entries_added_later().end() && added->second == value)
              continue;
          if (it != then.end() && it->second == value)
            continue;
          const auto shown = [](const std::string &v) {
            return v.empty() ? std::string("(empty)") : v;
          };
          AssertThrow(
            false,
            ExcInputError(
              "--resume: the checkpoint <" + filename + "> was written with " +
              entry + " = " +
              (it == then.end() ? "(not recorded)" : shown(it->second)) +
              ", but the parameter file sets " + shown(value) +
              ". A run can only be resumed with the entries that "
              "determine its wear state unchanged (doc/wear.md, Restart); "
              "change it back, or start a new run in another "
              "Output/Directory."));
        }
    }
  } // namespace

  void
  check_state_parameters(const std::string               &filename,
                         const std::string               &recorded,
                         const Parameters::AllParameters &parameters)
  {
    check_parameters(filename,
                     with_moved_entries(from_text(recorded)),
                     state_parameters(parameters));
  }

  std::map<std::string, std::string>
  state_parameters(const Parameters::AllParameters &parameters)
  {
    std::map<std::string, std::string> state;
    const auto starts_with = [](const std::string &s, const std::string &p) {
      return s.rfind(p, 0) == 0;
    };
    // The models' input files count by their content (checksum), not by
    // their paths; the entries of the laws and protocols the run does not
    // use do not count.
    const std::vector<std::string> files = Parameters::model_file_entries();
    const std::vector<std::string> unused =
      Parameters::unselected_model_subsections(parameters);
    const auto of_the_run = [&](const std::string &entry) {
      return std::none_of(unused.begin(),
                          unused.end(),
                          [&](const std::string &subsection) {
                            return starts_with(entry, subsection);
                          });
    };
    const auto counts = [&](const std::string &entry) {
      return std::find(files.begin(), files.end(), entry) == files.end() &&
             of_the_run(entry);
    };
    for (const auto &[entry, value] : parameters.entries)
      if (((starts_with(entry, "Mesh/") && entry != "Mesh/File") ||
           starts_with(entry, "Materials/") ||
           (starts_with(entry, "Gait/") && entry != "Gait/Step groups" &&
            entry != "Gait/Waveform file" && entry != "Gait/Pose derivatives" &&
            entry != "Gait/Activities" &&
            entry != "Gait/Largest initial overlap") ||
           (starts_with(entry, "Wear/") && entry != "Wear/Cycles" &&
            entry != "Wear/Distortion limit" &&
            entry != "Wear/Halve step on distortion" &&
            entry != "Wear/Run-in file")) &&
          counts(entry))
        state[entry] = value;
    state["Mesh/File (checksum)"] = checksum(parameters.mesh.file);
    state["Gait/Waveform file (checksum)"] =
      checksum(parameters.gait.waveform_file);
    state["Wear/Run-in file (checksum)"] =
      checksum(parameters.wear.run_in_file);
    for (const std::string &entry : files)
      if (of_the_run(entry))
        state[entry + " (checksum)"] = checksum(parameters.entries.at(entry));
    // The mix by its activities' shares and the contents of their files
    // (not their paths).
    for (const auto &activity : parameters.mix)
      {
        const std::string prefix = "Gait/Activities/" + activity.slug + "/";
        state[prefix + "Share"]  = format_number(activity.share, 15);
        state[prefix + "File (checksum)"] = checksum(activity.file);
        state[prefix + "Waveform file (checksum)"] =
          checksum(activity.gait.waveform_file);
      }
    return state;
  }

  std::string
  state_parameters_text(const Parameters::AllParameters &parameters)
  {
    return to_text(state_parameters(parameters));
  }
} // namespace TKR::Output
