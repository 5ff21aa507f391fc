// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <tkr/base/registry.h>

namespace TKR
{
  ModelKind::ModelKind(const std::string &kind)
    : kind(kind)
  {}

  // A function-local static: the models register themselves during the
  // static initialisation of the library, in no set order.
  std::map<std::string, ModelKind> &
  ModelKind::kinds()
  {
    static std::map<std::string, ModelKind> all;
    return all;
  }

  ModelKind &
  ModelKind::get(const std::string &kind)
  {
    auto it = kinds().find(kind);
    if (it == kinds().end())
      it = kinds().emplace(kind, ModelKind(kind)).first;
    return it->second;
  }

  void
  ModelKind::list(std::ostream &out)
  {
    for (const auto &[kind, models] : kinds())
      for (const auto &[name, model] : models.models)
        {
          out << kind << ": " << name;
          std::string separator = " (";
          for (const std::string &trait : model.entries.traits)
            {
              out << separator << trait;
              separator = ", ";
            }
          out << (model.entries.traits.empty() ? "" : ")") << '\n';
        }
  }

  std::string
  ModelKind::example(const std::string &name)
  {
    std::string known;
    for (const auto &[kind, models] : kinds())
      {
        const auto model = models.models.find(name);
        if (model == models.models.end())
          {
            known += (known.empty() ? "" : ", ") + models.names(", ");
            continue;
          }
        const ModelEntries &entries = model->second.entries;
        std::string text = "# " + kind + " " + name + " with its example " +
                           "entries (tkr-wear --model-example " + name +
                           ")\nsubsection " + models.section + "\n  set " +
                           models.selector + " = " + name + "\n";
        for (const auto &[entry, value] : entries.section_example)
          text += "  set " + entry + " = " + value + "\n";
        if (!entries.example.empty())
          {
            text += "  subsection " + entries.subsection + "\n";
            for (const auto &[entry, value] : entries.example)
              text += "    set " + entry + " = " + value + "\n";
            text += "  end\n";
          }
        return text + "end\n";
      }
    AssertThrow(false,
                ExcInputError("--model-example: no model is called <" + name +
                              ">; the known ones: " + known + "."));
    return "";
  }

  void
  ModelKind::add(const std::string &new_section,
                 const std::string &new_selector,
                 const Model       &model)
  {
    AssertThrow(models.empty() ||
                  (section == new_section && selector == new_selector),
                dealii::ExcMessage("The " + kind +
                                   " models disagree on their subsection."));
    section           = new_section;
    selector          = new_selector;
    const bool is_new = models.emplace(model.name, model).second;
    AssertThrow(is_new,
                dealii::ExcMessage("<" + model.name +
                                   "> is registered twice."));
  }

  void
  ModelKind::check_registered() const
  {
    AssertThrow(!models.empty(),
                dealii::ExcMessage(
                  "No " + kind +
                  " is registered: the models register themselves when "
                  "libtkr is loaded, which needs libtkr as a shared "
                  "library (CMakeLists.txt: add_library(tkr SHARED ...)), "
                  "not a static one."));
  }

  std::string
  ModelKind::names(const std::string &separator) const
  {
    std::string text;
    for (const auto &[name, model] : models)
      text += (text.empty() ? "" : separator) + name;
    return text;
  }

  std::string
  ModelKind::documentation(const std::string &intro) const
  {
    std::string text = intro, separator;
    for (const auto &[name, model] : models)
      {
        text += separator + name + " = " + model.documentation;
        separator = "; ";
      }
    return text + ".";
  }

  void
  ModelKind::declare_parameters(dealii::ParameterHandler &prm) const
  {
    for (const auto &[name, model] : models)
      if (!model.entries.subsection.empty())
        {
          prm.enter_subsection(model.entries.subsection);
          model.entries.declare(prm);
          prm.leave_subsection();
        }
  }

  ModelParameters
  ModelKind::parse_parameters(dealii::ParameterHandler &prm) const
  {
    ModelParameters parameters;
    for (const auto &[name, model] : models)
      if (!model.entries.subsection.empty())
        {
          prm.enter_subsection(model.entries.subsection);
          parameters.set(name, model.entries.parse(prm));
          prm.leave_subsection();
        }
    return parameters;
  }

  void
  ModelKind::check_known(const std::string &name) const
  {
    AssertThrow(models.count(name) == 1,
                ExcInputError("Unknown " + selector_path() + " <" + name +
                              ">; the known ones: " + names(", ") + "."));
  }

  void
  ModelKind::check(const std::string     &name,
                   const ModelParameters &parameters) const
  {
    check_known(name);
    const auto          model   = models.find(name);
    const ModelEntries &entries = model->second.entries;
    if (!entries.missing)
      return;
    const std::string missing = entries.missing(parameters.of(name));
    AssertThrow(missing.empty(),
                ExcInputError(selector_path() + " = " + name + " needs " +
                              own_path(model->second, missing)));
  }

  std::map<std::string, std::string>
  ModelKind::subsections() const
  {
    std::map<std::string, std::string> paths;
    for (const auto &[name, model] : models)
      if (!model.entries.subsection.empty())
        paths[name] = own_path(model, "");
    return paths;
  }

  std::map<std::string, std::string>
  ModelKind::rate_entries() const
  {
    std::map<std::string, std::string> paths;
    for (const auto &[name, model] : models)
      if (!model.entries.rate.empty())
        paths[name] = own_path(model, model.entries.rate);
    return paths;
  }

  std::vector<std::pair<std::string, std::string>>
  ModelKind::moved_entries() const
  {
    std::vector<std::pair<std::string, std::string>> moved;
    for (const auto &[name, model] : models)
      for (const std::string &entry : model.entries.moved)
        moved.emplace_back(section + "/" + entry, own_path(model, entry));
    return moved;
  }

  std::vector<std::string>
  ModelKind::file_entries() const
  {
    std::vector<std::string> files;
    for (const auto &[name, model] : models)
      for (const std::string &entry : model.entries.files)
        files.push_back(own_path(model, entry));
    return files;
  }

  std::string
  ModelKind::selector_path() const
  {
    return section + "/" + selector;
  }

  std::string
  ModelKind::own_path(const Model &model, const std::string &entry) const
  {
    return section + "/" + model.entries.subsection + "/" + entry;
  }
} // namespace TKR
