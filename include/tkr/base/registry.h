// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_base_registry_h
#define tkr_base_registry_h

#include <deal.II/base/parameter_handler.h>

#include <tkr/base/exceptions.h>

#include <any>
#include <functional>
#include <map>
#include <ostream>
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
   * checkpoint), which of them lived in the kind's subsection itself
   * before the model had its own (read there still, with a note), which
   * one scales the model's rate (what Problem = calibration fits), and
   * what a run still lacks with the parsed entries.
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
    /**
     * The entry that is a factor on the model's rate (a wear law's
     * coefficient or its table's scale); empty: none.
     */
    std::string rate = {};
    /**
     * What a run of the model lacks with its parsed parameters: "ENTRY,
     * why" (an entry of its subsection), or empty. Null: nothing.
     */
    std::function<std::string(const std::any &)> missing = {};
    /**
     * Entries of the subsection, with values, that make a run of the model
     * (a file relative to the sources, which a parameter file finds
     * there): what `tkr-wear --model-example` prints and the tests of
     * every model run. Empty: the defaults do.
     */
    std::vector<std::pair<std::string, std::string>> example = {};
    /**
     * Words that tests and documentation select models by, e.g.
     * "rate-changes-with-wear" (a wear law whose rate per cycle changes
     * as wear changes the contact, e.g. grows with the contact area: a
     * block's rate is not its first cycle's, and blocks must be shorter).
     */
    std::vector<std::string> traits = {};
    /**
     * Entries of the kind's own section (e.g. `Gait/Waveform file`), with
     * values, that the example also needs: printed with the example.
     */
    std::vector<std::pair<std::string, std::string>> section_example = {};
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
      const T *value = std::any_cast<T>(&of(name));
      AssertThrow(value != nullptr,
                  dealii::ExcMessage("No parameters of type " +
                                     std::string(typeid(T).name()) +
                                     " for the model <" + name + ">."));
      return *value;
    }

    /**
     * The parameters of the model @p name as parsed (empty if it has no
     * entries).
     */
    const std::any &
    of(const std::string &name) const
    {
      static const std::any none;
      const auto            it = values.find(name);
      return it == values.end() ? none : it->second;
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
   * What the parameter files see of the models of one kind, whatever
   * their interface: each one's name, documentation and own entries
   * (ModelEntries). Registry<Plugin>::add() enters every model here as
   * well, under its Plugin's kind, so that the parameters layer declares,
   * parses and checks the models' entries through this class alone,
   * without including the layers that define the models.
   */
  class ModelKind
  {
  public:
    /** What one model shows of itself. */
    struct Model
    {
      std::string  name;
      std::string  documentation;
      ModelEntries entries;
    };

    /**
     * The kind called @p kind ("wear law", "gait protocol"), empty until
     * its first model registers.
     */
    static ModelKind &
    get(const std::string &kind);

    /**
     * Add @p model to the kind whose models are chosen by the entry
     * @p selector of the subsection @p section ("Wear", "Wear law"); a
     * name added twice is a bug.
     */
    void
    add(const std::string &section,
        const std::string &selector,
        const Model       &model);

    /**
     * Throws unless some model of this kind registered itself. The models
     * register while libtkr's static objects are initialised; linked from
     * a static libtkr, the object files that nobody references (every
     * model's) would be left out, and with them every model: then this
     * says so instead of offering an empty choice.
     */
    void
    check_registered() const;

    /** The names joined by @p separator (`|`: a Patterns::Selection). */
    std::string
    names(const std::string &separator = "|") const;

    /** @p intro, then "name = documentation" of each model, ";"-joined. */
    std::string
    documentation(const std::string &intro) const;

    /**
     * Declare each model's own subsection inside the kind's subsection,
     * which @p prm has entered.
     */
    void
    declare_parameters(dealii::ParameterHandler &prm) const;

    /** Parse every model's own subsection (@p prm in the kind's). */
    ModelParameters
    parse_parameters(dealii::ParameterHandler &prm) const;

    /**
     * Throws an input error that names the selecting entry and the known
     * models if no model is called @p name.
     */
    void
    check_known(const std::string &name) const;

    /**
     * Throws an input error if the model @p name lacks an input with
     * @p parameters (ModelEntries::missing), or if no model is called so.
     */
    void
    check(const std::string &name, const ModelParameters &parameters) const;

    /** Per model, "SECTION/Subsection/" of its own entries. */
    std::map<std::string, std::string>
    subsections() const;

    /** Per model with one, the path of its rate entry (ModelEntries). */
    std::map<std::string, std::string>
    rate_entries() const;

    /**
     * The entries that moved into a model's subsection, as (old path, new
     * path) pairs ("Wear/Wear coefficient", "Wear/Archard/Wear
     * coefficient"); an old entry several models took has several pairs.
     */
    std::vector<std::pair<std::string, std::string>>
    moved_entries() const;

    /** The paths ("SECTION/Subsection/Entry") of every model's input files. */
    std::vector<std::string>
    file_entries() const;

    /** "SECTION/SELECTOR", the entry that chooses the model. */
    std::string
    selector_path() const;

    /**
     * Every kind with its models, one line per model: "KIND: NAME", and
     * its traits in parentheses (`tkr-wear --list-models`).
     */
    static void
    list(std::ostream &out);

    /**
     * The parameter file text that selects the model @p name (of any
     * kind) with its example entries (`tkr-wear --model-example NAME`);
     * an unknown name is an input error.
     */
    static std::string
    example(const std::string &name);

  private:
    explicit ModelKind(const std::string &kind);

    /** Every kind, by name. */
    static std::map<std::string, ModelKind> &
    kinds();

    /** "SECTION/Subsection/@p entry" of @p model's own entry. */
    std::string
    own_path(const Model &model, const std::string &entry) const;

    std::string                  kind, section, selector;
    std::map<std::string, Model> models;
  };

  /**
   * The models of one kind that registered themselves (ASPECT's plugin
   * pattern): a wear law, a gait protocol. A @p Plugin has a `name`, the
   * value of the `.prm` entry that selects it, a `documentation`, the
   * phrase that describes it in that entry, and its `entries`
   * (ModelEntries, its own subsection); the rest (how it is made, what it
   * needs) is the kind's own. The Plugin type names its kind, the
   * subsection of the kind and the entry that selects a model in static
   * members `kind`, `section` and `selector`. Each model's .cc file adds
   * its plugin while the library's static objects are initialised:
   *
   *     [[maybe_unused]] const bool registered =
   *       Registry<WearLawPlugin>::add({"archard", "Archard's law ...", ...});
   *
   * so that the entry's Patterns::Selection, its documentation and the
   * factory all come from here, and nothing else lists the models. What
   * the parameter files see of them is in ModelKind::get(Plugin::kind).
   */
  template <typename Plugin>
  class Registry
  {
  public:
    /** Add @p plugin; returns true. A name added twice is a bug. */
    static bool
    add(const Plugin &plugin)
    {
      kind().add(Plugin::section,
                 Plugin::selector,
                 {plugin.name, plugin.documentation, plugin.entries});
      plugins().emplace(plugin.name, plugin);
      return true;
    }

    /**
     * The plugin called @p name; an unknown name is an input error that
     * names the selecting entry and the known names.
     */
    static const Plugin &
    get(const std::string &name)
    {
      kind().check_known(name);
      return plugins().at(name);
    }

    /** The kind as the parameter files see it. */
    static ModelKind &
    kind()
    {
      return ModelKind::get(Plugin::kind);
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
