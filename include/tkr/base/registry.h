// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_base_registry_h
#define tkr_base_registry_h

#include <deal.II/base/parameter_handler.h>

#include <tkr/base/exceptions.h>

#include <any>
#include <functional>
#include <map>
#include <string>
#include <typeinfo>
#include <utility>
#include <vector>

namespace TKR
{
  /**
   * A model's own entries (ASPECT's plugin pattern): the subsection of the
   * kind's subsection they live in (e.g. `Archard` in `Wear`), how they
   * are declared and parsed there (into the model's own parameter type,
   * held as a std::any), which of them are input files (taken from the
   * directory of the file that sets them, recorded by checksum in a
   * checkpoint), and which of them lived in the kind's subsection itself
   * before the model had its own (read there still, with a note).
   */
  struct ModelEntries
  {
    /** The subsection; empty: the model has no entries. */
    std::string subsection;
    /** Declare the entries (the subsection entered). */
    std::function<void(dealii::ParameterHandler &)> declare;
    /** Parse them (the subsection entered) into the model's parameters. */
    std::function<std::any(const dealii::ParameterHandler &)> parse;
    /** The entries that are input files. */
    std::vector<std::string> files;
    /** The entries that were the kind's before (same names). */
    std::vector<std::string> moved;
  };

  /**
   * Every registered model's parameters (ModelEntries::parse), by the
   * model's name: the model of a run reads its own with get().
   */
  class ModelParameters
  {
  public:
    /** The parameters of the model @p name, of its type @p T. */
    template <typename T>
    const T &
    get(const std::string &name) const
    {
      const auto it = values.find(name);
      AssertThrow(it != values.end() && std::any_cast<T>(&it->second),
                  dealii::ExcMessage("No parameters of type " +
                                     std::string(typeid(T).name()) +
                                     " for the model <" + name + ">."));
      return *std::any_cast<T>(&it->second);
    }

    /** Set the parameters of the model @p name (e.g. in a test). */
    template <typename T>
    void
    set(const std::string &name, T parameters)
    {
      values[name] = std::move(parameters);
    }

  private:
    std::map<std::string, std::any> values;
  };

  /**
   * The models of one kind that registered themselves (ASPECT's plugin
   * pattern): a wear law, a gait protocol. A @p Plugin has a `name`, the
   * value of the `.prm` entry that selects it, and a `documentation`, the
   * phrase that describes it in that entry; the rest (how it is made, what
   * it needs) is the kind's own. Each model's .cc file adds its plugin while
   * the library's static objects are initialised:
   *
   *     [[maybe_unused]] const bool registered =
   *       Registry<WearLawPlugin>::add({"archard", "Archard's law ...", ...});
   *
   * so that the entry's Patterns::Selection, its documentation and the
   * factory all come from here, and nothing else lists the models. Its
   * `entries` (ModelEntries) are the model's own subsection.
   */
  template <typename Plugin>
  class Registry
  {
  public:
    /** Add @p plugin; returns true. A name added twice is a bug. */
    static bool
    add(const Plugin &plugin)
    {
      const bool is_new = plugins().emplace(plugin.name, plugin).second;
      AssertThrow(is_new,
                  dealii::ExcMessage("<" + plugin.name +
                                     "> is registered twice."));
      return true;
    }

    /**
     * The plugin called @p name; an unknown name is an input error that
     * names @p entry (e.g. `Wear/Wear law`) and the known names.
     */
    static const Plugin &
    get(const std::string &name, const std::string &entry)
    {
      const auto plugin = plugins().find(name);
      AssertThrow(plugin != plugins().end(),
                  ExcInputError("Unknown " + entry + " <" + name +
                                ">; the known ones: " + names(", ") + "."));
      return plugin->second;
    }

    /**
     * Throws unless some model of this kind (@p kind, e.g. "wear law")
     * registered itself. The models register while libtkr's static objects
     * are initialised; linked from a static libtkr, the object files that
     * nobody references (every model's) would be left out, and with them
     * every model: then this says so instead of offering an empty choice.
     */
    static void
    check_registered(const std::string &kind)
    {
      AssertThrow(!plugins().empty(),
                  dealii::ExcMessage(
                    "No " + kind +
                    " is registered: the models register themselves when "
                    "libtkr is loaded, which needs libtkr as a shared "
                    "library (CMakeLists.txt: add_library(tkr SHARED ...)), "
                    "not a static one."));
    }

    /** The names joined by @p separator (`|`: a Patterns::Selection). */
    static std::string
    names(const std::string &separator = "|")
    {
      std::string text;
      for (const auto &[name, plugin] : plugins())
        text += (text.empty() ? "" : separator) + name;
      return text;
    }

    /** @p intro, then "name = documentation" of each plugin, ";"-joined. */
    static std::string
    documentation(const std::string &intro)
    {
      std::string text = intro, separator;
      for (const auto &[name, plugin] : plugins())
        {
          text += separator + name + " = " + plugin.documentation;
          separator = "; ";
        }
      return text + ".";
    }

    /**
     * Declare each model's own subsection (ModelEntries) inside the kind's
     * subsection, which @p prm has entered.
     */
    static void
    declare_parameters(dealii::ParameterHandler &prm)
    {
      for (const auto &[name, plugin] : plugins())
        if (!plugin.entries.subsection.empty())
          {
            prm.enter_subsection(plugin.entries.subsection);
            plugin.entries.declare(prm);
            prm.leave_subsection();
          }
    }

    /** Parse every model's own subsection (@p prm in the kind's). */
    static ModelParameters
    parse_parameters(dealii::ParameterHandler &prm)
    {
      ModelParameters parameters;
      for (const auto &[name, plugin] : plugins())
        if (!plugin.entries.subsection.empty())
          {
            prm.enter_subsection(plugin.entries.subsection);
            parameters.set(name, plugin.entries.parse(prm));
            prm.leave_subsection();
          }
      return parameters;
    }

    /**
     * Per model, "KIND/Subsection/" of its own entries (@p kind: the
     * kind's subsection, e.g. "Wear").
     */
    static std::map<std::string, std::string>
    subsections(const std::string &kind)
    {
      std::map<std::string, std::string> paths;
      for (const auto &[name, plugin] : plugins())
        if (!plugin.entries.subsection.empty())
          paths[name] = own_path(kind, plugin, "");
      return paths;
    }

    /**
     * The entries that moved into a model's subsection, as (old path, new
     * path) pairs ("Wear/Wear coefficient", "Wear/Archard/Wear
     * coefficient"); an old entry several models took has several pairs.
     */
    static std::vector<std::pair<std::string, std::string>>
    moved_entries(const std::string &kind)
    {
      std::vector<std::pair<std::string, std::string>> moved;
      for (const auto &[name, plugin] : plugins())
        for (const std::string &entry : plugin.entries.moved)
          moved.emplace_back(kind + "/" + entry, own_path(kind, plugin, entry));
      return moved;
    }

    /** The paths ("KIND/Subsection/Entry") of every model's input files. */
    static std::vector<std::string>
    file_entries(const std::string &kind)
    {
      std::vector<std::string> files;
      for (const auto &[name, plugin] : plugins())
        for (const std::string &entry : plugin.entries.files)
          files.push_back(own_path(kind, plugin, entry));
      return files;
    }

  private:
    /** "KIND/Subsection/@p entry" of @p plugin's own entry. */
    static std::string
    own_path(const std::string &kind,
             const Plugin      &plugin,
             const std::string &entry)
    {
      return kind + "/" + plugin.entries.subsection + "/" + entry;
    }

    // A function-local static: the models register themselves during the
    // static initialisation of the library, in no set order.
    static std::map<std::string, Plugin> &
    plugins()
    {
      static std::map<std::string, Plugin> registered;
      return registered;
    }
  };
} // namespace TKR

#endif
