// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <tkr/base/exceptions.h>
#include <tkr/base/json.h>
#include <tkr/base/result_schema.h>

#include <algorithm>
#include <map>
#include <tuple>

namespace TKR
{
  namespace
  {
    /** A declared field and where it goes in its file. */
    struct Declared
    {
      ResultField  field;
      double       position;
      std::string  owner;
      unsigned int sequence;

      auto
      key() const
      {
        return std::tie(position, owner, sequence);
      }
    };

    // A function-local static: the owners declare their results during the
    // static initialisation of the library, in no set order; the order of
    // a file's fields is the declared positions'.
    std::map<std::string, std::vector<Declared>> &
    schema()
    {
      static std::map<std::string, std::vector<Declared>> all;
      return all;
    }

    using Derived =
      std::pair<double, std::function<std::vector<ResultField>()>>;

    /** The derived fields of each file (declare_derived()). */
    std::map<std::string, std::vector<Derived>> &
    derived()
    {
      static std::map<std::string, std::vector<Derived>> all;
      return all;
    }

    /** Whether @p name is the field @p pattern (`NAME`: an activity). */
    bool
    matches(const std::string &pattern, const std::string &name)
    {
      const auto at = pattern.find("NAME");
      if (at == std::string::npos)
        return pattern == name;
      const std::string prefix = pattern.substr(0, at);
      const std::string suffix = pattern.substr(at + 4);
      return name.size() > prefix.size() + suffix.size() &&
             name.compare(0, prefix.size(), prefix) == 0 &&
             name.compare(name.size() - suffix.size(), suffix.size(), suffix) ==
               0;
    }

    std::string
    json_list(const std::vector<std::string> &words)
    {
      std::string json = "[";
      for (unsigned int i = 0; i < words.size(); ++i)
        json += (i > 0 ? ", " : "") + json_string(words[i]);
      return json + "]";
    }
  } // namespace

  std::string
  with_name(std::string pattern, const std::string &value)
  {
    const auto at = std::min(pattern.find("SIDE"), pattern.find("NAME"));
    AssertThrow(at != std::string::npos,
                dealii::ExcMessage("<" + pattern + "> has no SIDE or NAME."));
    return pattern.replace(at, 4, value);
  }

  bool
  ResultSchema::declare(const std::string              &file,
                        const double                    position,
                        const std::vector<ResultField> &fields,
                        const std::string              &owner)
  {
    auto &declared = schema()[file];
    // A side's fields (`SIDE_...`): the medial side's, then the lateral's,
    // as the files have them.
    std::vector<ResultField> expanded;
    for (const std::string side : {"", "medial", "lateral"})
      for (const ResultField &field : fields)
        if (side.empty() == (field.name.find("SIDE") == std::string::npos))
          {
            ResultField f = field;
            for (std::string *text : {&f.name, &f.meaning})
              for (auto at = text->find("SIDE"); at != std::string::npos;
                   at      = text->find("SIDE"))
                text->replace(at, 4, side);
            expanded.push_back(f);
          }
    for (const ResultField &f : expanded)
      {
        Declared   next{f,
                      position,
                      owner,
                      static_cast<unsigned int>(declared.size())};
        const auto same = std::find_if(declared.begin(),
                                       declared.end(),
                                       [&](const Declared &d) {
                                         return d.field.name == f.name;
                                       });
        if (same == declared.end())
          {
            declared.push_back(next);
            continue;
          }
        AssertThrow(same->field.type == f.type && same->field.unit == f.unit &&
                      same->field.meaning == f.meaning,
                    dealii::ExcMessage("The result <" + f.name + "> of <" +
                                       file +
                                       "> is declared twice with another "
                                       "type, unit or meaning."));
        auto &writers = same->field.writers;
        for (const std::string &w : f.writers)
          if (std::find(writers.begin(), writers.end(), w) == writers.end())
            writers.push_back(w);
        // (in an order that does not depend on the declarations')
        std::sort(writers.begin(), writers.end());
        same->field.trace  = same->field.trace || f.trace;
        same->field.study  = std::max(same->field.study, f.study);
        same->field.timing = same->field.timing || f.timing;
        if (next.key() < same->key())
          {
            same->position = next.position;
            same->owner    = next.owner;
            same->sequence = next.sequence;
          }
      }
    return true;
  }

  bool
  ResultSchema::declare_derived(
    const std::string                               &file,
    const double                                     position,
    const std::function<std::vector<ResultField>()> &fields)
  {
    schema()[file];
    derived()[file].emplace_back(position, fields);
    return true;
  }

  std::vector<ResultField>
  ResultSchema::fields(const std::string &file)
  {
    const auto it = schema().find(file);
    if (it == schema().end())
      return {};
    std::vector<Declared> declared = it->second;
    for (const auto &[position, fields] : derived()[file])
      for (const ResultField &field : fields())
        declared.push_back(
          {field, position, "", static_cast<unsigned int>(declared.size())});
    std::stable_sort(declared.begin(),
                     declared.end(),
                     [](const Declared &a, const Declared &b) {
                       return a.key() < b.key();
                     });
    std::vector<ResultField> result;
    for (const Declared &d : declared)
      result.push_back(d.field);
    return result;
  }

  std::vector<std::string>
  ResultSchema::files()
  {
    std::vector<std::string> names;
    for (const auto &[file, fields] : schema())
      names.push_back(file);
    return names;
  }

  const ResultField *
  ResultSchema::find(const std::string &file, const std::string &name)
  {
    const auto it = schema().find(file);
    if (it == schema().end())
      return nullptr;
    // A fixed name first: `activity_NAME_share` must not take a name that
    // is its own field.
    for (const bool with_pattern : {false, true})
      for (const Declared &d : it->second)
        if ((d.field.name.find("NAME") != std::string::npos) == with_pattern &&
            matches(d.field.name, name))
          return &d.field;
    return nullptr;
  }

  std::vector<std::string>
  ResultSchema::study_results()
  {
    std::vector<ResultField> listed;
    for (const ResultField &field : fields("summary.json"))
      if (field.study > 0)
        listed.push_back(field);
    std::stable_sort(listed.begin(),
                     listed.end(),
                     [](const ResultField &a, const ResultField &b) {
                       return a.study < b.study;
                     });
    std::vector<std::string> names;
    for (const ResultField &field : listed)
      names.push_back(field.name);
    return names;
  }

  void
  ResultSchema::print(std::ostream &out)
  {
    out << "{\n  \"files\": {";
    const auto names = files();
    for (unsigned int f = 0; f < names.size(); ++f)
      {
        out << (f > 0 ? "," : "") << "\n    " << json_string(names[f]) << ": [";
        const auto all = fields(names[f]);
        for (unsigned int i = 0; i < all.size(); ++i)
          {
            const ResultField &field = all[i];
            out << (i > 0 ? "," : "")
                << "\n      {\"name\": " << json_string(field.name)
                << ", \"type\": " << json_string(field.type)
                << ", \"unit\": " << json_string(field.unit)
                << ", \"written_by\": " << json_list(field.writers)
                << ", \"fields\": " << json_list(field.fields)
                << ", \"trace\": " << (field.trace ? "true" : "false")
                << ", \"study\": " << field.study
                << ", \"timing\": " << (field.timing ? "true" : "false")
                << ", \"meaning\": " << json_string(field.meaning) << "}";
          }
        out << "\n    ]";
      }
    out << "\n  }\n}\n";
  }
} // namespace TKR
