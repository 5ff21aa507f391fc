// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

// `Gait/Activities`: an activity mix (doc/gait.md, Activity mixes).

#include <deal.II/base/utilities.h>

#include <tkr/base/exceptions.h>
#include <tkr/parameters/parameters.h>

#include "parameter_file.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <set>

namespace TKR::Parameters
{
  using namespace dealii;

  namespace
  {
    /** What the list should look like, for the messages. */
    const std::string list_form =
      " (Gait/Activities is NAME: SHARE[: FILE.prm] per activity, "
      "separated by ';', e.g. \"walking: 0.9; stair ascent: 0.1: "
      "stair.prm\"; doc/gait.md)";

    /**
     * The activities of the list @p activities with their name, share and
     * file (no gait yet).
     */
    std::vector<Activity>
    parse_list(const std::string &activities)
    {
      std::vector<Activity> mix;
      for (const std::string &item :
           Utilities::split_string_list(activities, ';'))
        {
          if (item.empty())
            continue;
          const std::vector<std::string> parts =
            Utilities::split_string_list(item, ':');
          AssertThrow((parts.size() == 2 || parts.size() == 3) &&
                        !parts[0].empty() && !parts[1].empty(),
                      ExcInputError("Gait/Activities: <" + item +
                                    "> is not NAME: SHARE[: FILE.prm]" +
                                    list_form + "."));
          Activity activity;
          activity.name = parts[0];
          for (const char c : activity.name)
            {
              AssertThrow(std::isalnum(static_cast<unsigned char>(c)) ||
                            c == ' ' || c == '-' || c == '_',
                          ExcInputError("Gait/Activities: the name <" +
                                        activity.name +
                                        "> may only have letters, digits, "
                                        "spaces, '-' and '_' (it names the "
                                        "activity's columns and files)."));
              activity.slug += std::isalnum(static_cast<unsigned char>(c)) ?
                                 static_cast<char>(std::tolower(
                                   static_cast<unsigned char>(c))) :
                                 '_';
            }
          try
            {
              std::size_t end = 0;
              activity.share  = std::stod(parts[1], &end);
              AssertThrow(end == parts[1].size(), ExcInputError(""));
            }
          catch (...)
            {
              AssertThrow(false,
                          ExcInputError("Gait/Activities: the share <" +
                                        parts[1] + "> of <" + activity.name +
                                        "> is not a number."));
            }
          if (parts.size() == 3)
            activity.file = parts[2];
          mix.push_back(activity);
        }
      return mix;
    }

    /** Refuse repeated names, shares outside (0, 1] or not adding up to 1. */
    void
    check_shares(const std::vector<Activity> &mix)
    {
      std::set<std::string> slugs;
      double                sum = 0;
      std::string           shares;
      for (const auto &activity : mix)
        {
          AssertThrow(slugs.insert(activity.slug).second,
                      ExcInputError("Gait/Activities: two activities are "
                                    "named <" +
                                    activity.name +
                                    "> (names must differ also after "
                                    "spaces and '-' become '_' and capitals "
                                    "small letters)."));
          AssertThrow(activity.share > 0 && activity.share <= 1,
                      ExcInputError("Gait/Activities: the share of <" +
                                    activity.name + "> is " +
                                    format_number(activity.share, 6) +
                                    "; a share is a fraction of the cycles, "
                                    "in (0, 1]."));
          sum += activity.share;
          shares +=
            (shares.empty() ? "" : " + ") + format_number(activity.share, 6);
        }
      AssertThrow(std::abs(sum - 1) <= 1e-9,
                  ExcInputError("Gait/Activities: the shares " + shares +
                                " add up to " + format_number(sum, 10) +
                                ", not 1: every cycle of the test belongs to "
                                "one activity. Correct the shares."));
    }

    /**
     * The gait of @p activity: @p filename with the activity's file on top;
     * refuse an activity file that sets entries that are not the
     * activity's.
     */
    Gait
    read_activity_gait(const std::string &filename, const Activity &activity)
    {
      const internal::ParameterText own(activity.file, moved_entries());
      std::string                   foreign;
      for (const std::string &entry : own.entries_set())
        if (entry.rfind("Gait/", 0) != 0 || entry == "Gait/Activities" ||
            entry == "Gait/Step groups" || entry == "Gait/Medial side")
          foreign += (foreign.empty() ? "" : ", ") + entry + " (" +
                     own.place_of(entry) + ")";
      AssertThrow(foreign.empty(),
                  ExcInputError(
                    "Gait/Activities: the file <" + activity.file +
                    "> of the activity <" + activity.name + "> sets " +
                    foreign +
                    ". An activity's file sets only entries of subsection "
                    "Gait that belong to the activity (not Activities, "
                    "Step groups or Medial side); the rest of the run is "
                    "the main parameter file's."));
      const internal::ParameterText text({filename, activity.file},
                                         moved_entries());
      ParameterHandler              prm;
      AllParameters::declare_parameters(prm);
      internal::parse_text(prm, text, filename);
      Gait gait;
      gait.parse_parameters(prm);
      gait.activities.clear();
      return gait;
    }
  } // namespace

  std::string
  Activity::resolve_files(const std::string &activities,
                          const std::string &directory)
  {
    std::string resolved;
    for (const std::string &item :
         Utilities::split_string_list(activities, ';'))
      {
        std::vector<std::string> parts =
          Utilities::split_string_list(item, ':');
        if (parts.size() == 3)
          parts[2] = internal::resolve_path(parts[2], directory);
        resolved += resolved.empty() ? "" : "; ";
        for (unsigned int i = 0; i < parts.size(); ++i)
          resolved += (i > 0 ? ": " : "") + parts[i];
      }
    return resolved;
  }

  std::vector<Activity>
  AllParameters::activities() const
  {
    if (!mix.empty())
      return mix;
    Activity single;
    single.gait = gait;
    return {single};
  }

  namespace internal
  {
    std::vector<Activity>
    read_mix(const std::string &filename, const Gait &gait)
    {
      std::vector<Activity> mix = parse_list(gait.activities);
      if (mix.empty())
        return mix;
      check_shares(mix);
      for (auto &activity : mix)
        {
          activity.gait = activity.file.empty() ?
                            gait :
                            read_activity_gait(filename, activity);
          activity.gait.activities.clear();
          AssertThrow(std::filesystem::exists(activity.gait.waveform_file),
                      ExcInputError("Gait/Activities: the waveform file <" +
                                    activity.gait.waveform_file +
                                    "> of the activity <" + activity.name +
                                    "> does not exist."));
        }
      return mix;
    }
  } // namespace internal
} // namespace TKR::Parameters
