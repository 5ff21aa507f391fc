// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_base_registry_h
#define tkr_base_registry_h

#include <tkr/base/exceptions.h>

#include <map>
#include <string>

namespace TKR
{
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
   * factory all come from here, and nothing else lists the models.
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

  private:
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
