// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <deal.II/base/utilities.h>

#include <tkr/base/exceptions.h>

#include "parameter_file.h"

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

namespace TKR::Parameters::internal
{
  using namespace dealii;

  namespace
  {
    /** A line without its comment (from an unescaped '#'), trimmed. */
    std::string
    strip(const std::string &line)
    {
      std::size_t end = 0;
      while (end < line.size() &&
             !(line[end] == '#' && (end == 0 || line[end - 1] != '\\')))
        ++end;
      return Utilities::trim(line.substr(0, end));
    }

    /** Runs of blanks in a name collapsed to one (as ParameterHandler). */
    std::string
    collapse(const std::string &name)
    {
      std::string result;
      for (const char c : Utilities::trim(name))
        if (!(c == ' ' && !result.empty() && result.back() == ' '))
          result += c;
      return result;
    }

    /** True if @p file exists and is readable. */
    bool
    readable(const std::filesystem::path &file)
    {
      return std::ifstream(file).good();
    }
  } // namespace

  ParameterText::ParameterText(
    const std::string                                      &filename,
    const std::vector<std::pair<std::string, std::string>> &moved)
  {
    append(filename, 0);
    rename_moved(moved);
    find_setters();
  }

  ParameterText::ParameterText(
    const std::vector<std::string>                         &filenames,
    const std::vector<std::pair<std::string, std::string>> &moved)
  {
    for (const std::string &filename : filenames)
      append(filename, 0);
    rename_moved(moved);
    find_setters();
  }

  std::vector<std::string>
  ParameterText::entries_set() const
  {
    std::vector<std::string> entries;
    for (const auto &[entry, line] : setter)
      entries.push_back(entry);
    return entries;
  }

  void
  ParameterText::append(const std::string &filename, const unsigned int depth)
  {
    AssertThrow(depth < 20,
                ExcInputError("The parameter file <" + filename +
                              "> is included in itself (include cycle)."));
    std::ifstream in(filename);
    AssertThrow(in.good(),
                ExcInputError("Cannot open the parameter file <" + filename +
                              ">: it does not exist or is not readable."));
    const std::filesystem::path directory =
      std::filesystem::path(filename).parent_path();
    std::string  line;
    unsigned int number = 0;
    while (std::getline(in, line))
      {
        ++number;
        const std::string content = strip(line);
        if (content.rfind("include ", 0) == 0 ||
            content.rfind("INCLUDE ", 0) == 0)
          {
            const std::string     name = Utilities::trim(content.substr(8));
            std::filesystem::path file(name);
            if (file.is_relative() && readable(directory / file))
              file = directory / file;
            AssertThrow(
              readable(file),
              ExcInputError(
                "Line <" + std::to_string(number) + "> of file <" + filename +
                ">: cannot open the included file <" + name + "> (looked in <" +
                (directory.empty() ? std::string(".") : directory.string()) +
                "> and in the working directory)."));
            append(file.string(), depth + 1);
            continue;
          }
        expanded += line + '\n';
        origin.emplace_back(filename, number);
      }
  }

  // ParameterHandler's reading: `subsection NAME` opens, `end` closes, a
  // trailing backslash joins the next line.
  std::vector<ParameterText::LogicalLine>
  ParameterText::logical_lines() const
  {
    std::vector<LogicalLine> lines;
    std::istringstream       in(expanded);
    std::vector<std::string> path;
    std::string              line, joined;
    unsigned int             number = 0, first = 0;
    while (std::getline(in, line))
      {
        ++number;
        if (joined.empty())
          first = number - 1;
        const std::string content = strip(line);
        if (!content.empty() && content.back() == '\\')
          {
            joined += content.substr(0, content.size() - 1) + ' ';
            continue;
          }
        LogicalLine logical{first,
                            number,
                            Utilities::trim(joined + content),
                            path,
                            ""};
        joined.clear();
        const std::string &text = logical.text;
        if (text.rfind("subsection ", 0) == 0)
          path.push_back(collapse(text.substr(11)));
        else if (text == "end" && !path.empty())
          path.pop_back();
        else if (text.rfind("set ", 0) == 0 &&
                 text.find('=') != std::string::npos)
          {
            for (const auto &name : path)
              logical.entry += name + '/';
            logical.entry += collapse(text.substr(4, text.find('=') - 4));
          }
        lines.push_back(std::move(logical));
      }
    return lines;
  }

  // A `set` of a moved entry becomes `subsection ... set ... end` lines
  // that set each new path instead, all with the origin of the old line.
  void
  ParameterText::rename_moved(
    const std::vector<std::pair<std::string, std::string>> &moved)
  {
    std::istringstream       in(expanded);
    std::vector<std::string> physical;
    for (std::string line; std::getline(in, line);)
      physical.push_back(line);
    std::string                                       text;
    std::vector<std::pair<std::string, unsigned int>> where;
    for (const LogicalLine &line : logical_lines())
      {
        std::vector<std::string> targets;
        for (const auto &[from, to] : moved)
          if (!line.entry.empty() && line.entry == from)
            targets.push_back(to);
        if (targets.empty())
          {
            for (unsigned int l = line.first; l < line.last; ++l)
              {
                text += physical[l] + '\n';
                where.push_back(origin[l]);
              }
            continue;
          }
        const std::string value =
          Utilities::trim(line.text.substr(line.text.find('=') + 1));
        const std::string name = line.entry.substr(line.entry.rfind('/') + 1);
        std::string       now;
        for (const std::string &to : targets)
          {
            // The subsections of the new path below the line's own.
            const auto parts = Utilities::split_string_list(to, '/');
            for (unsigned int p = line.path.size(); p + 1 < parts.size(); ++p)
              {
                text += "subsection " + parts[p] + '\n';
                where.push_back(origin[line.first]);
              }
            text += "set " + name + " = " + value + '\n';
            where.push_back(origin[line.first]);
            for (unsigned int p = line.path.size(); p + 1 < parts.size(); ++p)
              {
                text += "end\n";
                where.push_back(origin[line.first]);
              }
            now += (now.empty() ? "" : " and ") + to;
          }
        notes.push_back(origin[line.first].first + ":" +
                        std::to_string(origin[line.first].second) + " sets " +
                        line.entry + ", which is now " + now +
                        "; read there (write it there instead).");
      }
    expanded = text;
    origin   = where;
  }

  // The subsection path of every `set` line, as ParameterHandler reads it.
  void
  ParameterText::find_setters()
  {
    for (const LogicalLine &line : logical_lines())
      if (!line.entry.empty())
        setter[line.entry] = line.first;
  }

  std::string
  ParameterText::locate(const std::string &message) const
  {
    static const std::regex line_of_file("Line <([0-9]+)> of file <[^>]*>");
    std::smatch             match;
    if (!std::regex_search(message, match, line_of_file))
      return message;
    const unsigned int line = std::stoul(match[1].str());
    if (line == 0 || line > origin.size())
      return message;
    const auto &[file, number] = origin[line - 1];
    return match.prefix().str() + "Line <" + std::to_string(number) +
           "> of file <" + file + ">" + match.suffix().str();
  }

  std::string
  ParameterText::directory_of(const std::string &path) const
  {
    const auto it = setter.find(path);
    if (it == setter.end())
      return "";
    return std::filesystem::path(origin[it->second].first)
      .parent_path()
      .string();
  }

  std::string
  ParameterText::place_of(const std::string &path) const
  {
    const auto it = setter.find(path);
    if (it == setter.end())
      return "";
    return origin[it->second].first + ":" +
           std::to_string(origin[it->second].second);
  }

  namespace
  {
    /** Enter the subsections of @p path in @p prm; returns the entry name
     *  and how many subsections were entered. */
    std::pair<std::string, unsigned int>
    enter_path(ParameterHandler &prm, const std::string &path)
    {
      const auto parts = Utilities::split_string_list(path, '/');
      for (unsigned int i = 0; i + 1 < parts.size(); ++i)
        prm.enter_subsection(parts[i]);
      return {parts.back(), parts.size() - 1};
    }
  } // namespace

  std::string
  get_entry(ParameterHandler &prm, const std::string &path)
  {
    const auto [name, depth] = enter_path(prm, path);
    const std::string value  = prm.get(name);
    for (unsigned int i = 0; i < depth; ++i)
      prm.leave_subsection();
    return value;
  }

  void
  set_entry(ParameterHandler  &prm,
            const std::string &path,
            const std::string &value)
  {
    const auto [name, depth] = enter_path(prm, path);
    prm.set(name, value);
    for (unsigned int i = 0; i < depth; ++i)
      prm.leave_subsection();
  }

  // ShortPRM output is `subsection NAME`, `set NAME = VALUE` and `end`
  // lines only.
  std::map<std::string, std::string>
  list_entries(const ParameterHandler &prm)
  {
    std::ostringstream out;
    prm.print_parameters(out, ParameterHandler::ShortPRM);
    std::istringstream                 in(out.str());
    std::map<std::string, std::string> entries;
    std::vector<std::string>           path;
    std::string                        line;
    while (std::getline(in, line))
      {
        const std::string content = Utilities::trim(line);
        if (content.rfind("subsection ", 0) == 0)
          path.push_back(Utilities::trim(content.substr(11)));
        else if (content == "end" && !path.empty())
          path.pop_back();
        else if (content.rfind("set ", 0) == 0)
          {
            const std::size_t equals = content.find('=');
            std::string       entry;
            for (const auto &name : path)
              entry += name + '/';
            entry += Utilities::trim(content.substr(4, equals - 4));
            entries[entry] = Utilities::trim(content.substr(equals + 1));
          }
      }
    return entries;
  }

  std::string
  resolve_path(const std::string &path, const std::string &directory)
  {
    const std::filesystem::path file(path);
    if (path.empty() || file.is_absolute())
      return path;
    for (const std::filesystem::path &base :
         {std::filesystem::path(directory),
          std::filesystem::path(),
          std::filesystem::path(TKR_SOURCE_DIR)})
      if (readable(base / file))
        return (base / file).lexically_normal().string();
    return path;
  }
} // namespace TKR::Parameters::internal
