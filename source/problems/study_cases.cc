// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <deal.II/base/utilities.h>

#include <tkr/base/exceptions.h>
#include <tkr/problems/study_cases.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <numeric>
#include <random>
#include <regex>
#include <sstream>

namespace TKR::Problems
{
  using namespace dealii;

  namespace
  {
    /** How a study sets an entry: `=`, `+=` (to the base) or `*=`. */
    struct Setting
    {
      /** As written, e.g. "Gait/Flexion axis point[1]". */
      std::string input;
      std::string op;
      /** The values (grid, cases file) or the distribution (sampling). */
      std::vector<std::string> values;
      /** "FILE:LINE" of the study entry that names it. */
      std::string place;
      /** The subsection of that entry (for the messages). */
      std::string owner = "Study";
    };

    std::string
    number_text(const double value)
    {
      char buffer[64];
      std::snprintf(buffer, sizeof(buffer), "%.12g", value);
      return buffer;
    }

    /** `PATH op VALUES` items separated by ';' of the study entry. */
    std::vector<Setting>
    parse_settings(const std::string &text,
                   const std::string &place,
                   const bool         split_values)
    {
      std::vector<Setting> settings;
      for (const std::string &item : Utilities::split_string_list(text, ';'))
        {
          Setting           setting;
          const std::size_t equal = item.find('=');
          AssertThrow(equal != std::string::npos && equal > 0,
                      ExcInputError("Study " + place + ": <" + item +
                                    "> is not PATH = VALUES (or PATH += "
                                    "..., PATH *= ...)."));
          const char before   = item[equal - 1];
          const bool combined = (before == '+' || before == '*');
          setting.op          = combined ? std::string(1, before) + "=" : "=";
          setting.input =
            Utilities::trim(item.substr(0, combined ? equal - 1 : equal));
          const std::string values = Utilities::trim(item.substr(equal + 1));
          setting.values           = split_values ?
                                       Utilities::split_string_list(values, ',') :
                                       std::vector<std::string>{values};
          AssertThrow(!setting.input.empty() && !values.empty(),
                      ExcInputError("Study " + place + ": <" + item +
                                    "> names no entry or no value."));
          setting.place = place;
          settings.push_back(setting);
        }
      return settings;
    }

    /** The rows of a CSV file of cases: a header of entry paths. */
    std::vector<Setting>
    read_cases_file(const std::string &filename, unsigned int &n_rows)
    {
      std::ifstream in(filename);
      AssertThrow(in.good(),
                  ExcInputError("Study/Cases file: cannot open <" + filename +
                                ">."));
      std::vector<Setting> columns;
      std::string          line;
      unsigned int         number = 0;
      n_rows                      = 0;
      while (std::getline(in, line))
        {
          ++number;
          line = Utilities::trim(line);
          if (line.empty() || line[0] == '#')
            continue;
          const auto fields = Utilities::split_string_list(line, ',');
          if (columns.empty())
            {
              for (const std::string &field : fields)
                columns.push_back({field, "=", {}, filename + ":1"});
              continue;
            }
          AssertThrow(fields.size() == columns.size(),
                      ExcInputError(
                        filename + ":" + std::to_string(number) + ": " +
                        std::to_string(fields.size()) + " values for " +
                        std::to_string(columns.size()) + " columns."));
          for (unsigned int c = 0; c < fields.size(); ++c)
            {
              columns[c].values.push_back(fields[c]);
              columns[c].place = filename + ":" + std::to_string(number);
            }
          ++n_rows;
        }
      AssertThrow(n_rows > 0,
                  ExcInputError("Study/Cases file <" + filename +
                                "> has no cases (a header of entry paths, "
                                "then one row per case)."));
      return columns;
    }

    /** A distribution `name(a, b)` at the probability @p u. */
    double
    sample(const Setting &setting, const double u)
    {
      static const std::regex form(R"(^\s*([a-z-]+)\s*\((.*)\)\s*$)");
      std::smatch             match;
      const std::string      &text = setting.values[0];
      std::vector<double>     arguments;
      const bool              parsed = std::regex_match(text, match, form);
      if (parsed)
        for (const std::string &a :
             Utilities::split_string_list(match[2].str(), ','))
          arguments.push_back(Utilities::string_to_double(a));
      const std::string name = parsed ? match[1].str() : "";
      const bool        valid =
        (name == "uniform" || name == "normal" || name == "log-normal") &&
        arguments.size() == 2 &&
        (name == "uniform" ? arguments[1] >= arguments[0] : arguments[1] > 0);
      AssertThrow(valid,
                  ExcInputError("Study " + setting.place + ": <" +
                                setting.input + " " + setting.op + " " + text +
                                ">: a distribution is uniform(a, b) with a <= "
                                "b, normal(mean, sd) or log-normal(mu, "
                                "sigma) with sd, sigma > 0."));
      if (name == "uniform")
        return arguments[0] + (arguments[1] - arguments[0]) * u;
      const double z =
        arguments[0] + arguments[1] * standard_normal_quantile(u);
      return name == "normal" ? z : std::exp(z);
    }

    /**
     * Set @p setting's entry of @p entries to @p value (by its operator,
     * on the value the case has so far or the base's).
     */
    void
    apply(const Setting                   &setting,
          const std::string               &value,
          const Parameters::AllParameters &base,
          StudyCase                       &study_case)
    {
      static const std::regex component(R"(^(.*)\[([0-9]+)\]$)");
      std::smatch             match;
      const bool indexed = std::regex_match(setting.input, match, component);
      const std::string path = indexed ? match[1].str() : setting.input;
      // An entry that moved into a model's subsection (e.g. Wear/Wear
      // coefficient, now Wear/Archard/Wear coefficient) sets its new
      // path(s).
      bool moved = false;
      for (const auto &[from, to] : Parameters::moved_entries())
        if (path == from)
          {
            Setting renamed = setting;
            renamed.input =
              to + (indexed ? "[" + match[2].str() + "]" : std::string());
            apply(renamed, value, base, study_case);
            moved = true;
          }
      if (moved)
        return;
      const std::string what = setting.owner + " " + setting.place + ": " +
                               study_case.name + " sets <" + setting.input +
                               "> " + setting.op + " <" + value + ">";
      const auto known = base.entries.find(path);
      AssertThrow(known != base.entries.end() && path != "Problem",
                  ExcInputError(what + ", but <" + path +
                                "> is not an entry of the parameter file "
                                "(tkr-wear --print-parameters lists every "
                                "entry; write Subsection/Entry)."));
      std::string &current =
        study_case.entries.emplace(path, known->second).first->second;
      std::vector<std::string> parts =
        indexed ? Utilities::split_string_list(current, ',') :
                  std::vector<std::string>{current};
      const unsigned int index = indexed ? std::stoul(match[2].str()) : 0;
      AssertThrow(index < parts.size(),
                  ExcInputError(what + ", but <" + path + "> = <" + current +
                                "> has " + std::to_string(parts.size()) +
                                " components (counted from 0)."));
      std::string result = value;
      if (setting.op != "=")
        {
          double a = 0, b = 0;
          try
            {
              a = Utilities::string_to_double(parts[index]);
              b = Utilities::string_to_double(value);
            }
          catch (...)
            {
              AssertThrow(false,
                          ExcInputError(what + ": " + setting.op +
                                        " needs numbers (the base value is <" +
                                        parts[index] + ">)."));
            }
          result = number_text(setting.op == "+=" ? a + b : a * b);
        }
      parts[index] = result;
      current      = parts[0];
      for (unsigned int i = 1; i < parts.size(); ++i)
        current += ", " + parts[i];
      study_case.inputs.emplace_back(setting.input, result);
    }
  } // namespace

  void
  set_case_input(const std::string               &input,
                 const std::string               &value,
                 const Parameters::AllParameters &base,
                 const std::string               &owner,
                 const std::string               &place,
                 StudyCase                       &study_case)
  {
    Setting setting;
    setting.input = input;
    setting.op    = "=";
    setting.place = place;
    setting.owner = owner;
    apply(setting, value, base, study_case);
  }

  double
  standard_normal_quantile(const double p)
  {
    AssertThrow(p > 0 && p < 1, ExcMessage("probability not in (0, 1)"));
    static const double a[]  = {-3.969683028665376e+01,
                                2.209460984245205e+02,
                                -2.759285104469687e+02,
                                1.383577518672690e+02,
                                -3.066479806614716e+01,
                                2.506628277459239e+00};
    static const double b[]  = {-5.447609879822406e+01,
                                1.615858368580409e+02,
                                -1.556989798598866e+02,
                                6.680131188771972e+01,
                                -1.328068155288572e+01};
    static const double c[]  = {-7.784894002430293e-03,
                                -3.223964580411365e-01,
                                -2.400758277161838e+00,
                                -2.549732539343734e+00,
                                4.374664141464968e+00,
                                2.938163982698783e+00};
    static const double d[]  = {7.784695709041462e-03,
                                3.224671290700398e-01,
                                2.445134137142996e+00,
                                3.754408661907416e+00};
    const auto          tail = [&](const double q) {
      return (((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q +
              c[5]) /
             ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1);
    };
    const double low = 0.02425;
    double       x;
    if (p < low)
      x = tail(std::sqrt(-2 * std::log(p)));
    else if (p > 1 - low)
      x = -tail(std::sqrt(-2 * std::log(1 - p)));
    else
      {
        const double q = p - 0.5, r = q * q;
        x = (((((a[0] * r + a[1]) * r + a[2]) * r + a[3]) * r + a[4]) * r +
             a[5]) *
            q /
            (((((b[0] * r + b[1]) * r + b[2]) * r + b[3]) * r + b[4]) * r + 1);
      }
    // One Halley step on Phi(x) = p.
    const double e = 0.5 * std::erfc(-x / std::sqrt(2.)) - p;
    const double u = e * std::sqrt(2 * M_PI) * std::exp(x * x / 2);
    return x - u / (1 + x * u / 2);
  }

  std::vector<std::vector<double>>
  unit_samples(const unsigned int n_samples,
               const unsigned int n_dimensions,
               const unsigned int seed,
               const bool         latin_hypercube)
  {
    // The generator's output is fixed by the standard; the mappings to
    // (0, 1) and to a permutation are written out here (the library's
    // distributions and std::shuffle may differ between implementations).
    std::mt19937_64 generator(seed);
    const auto      uniform = [&]() {
      return ((generator() >> 11) + 0.5) * 0x1.0p-53;
    };
    std::vector<std::vector<double>> points(n_samples,
                                            std::vector<double>(n_dimensions));
    for (unsigned int j = 0; j < n_dimensions; ++j)
      {
        std::vector<unsigned int> stratum(n_samples);
        std::iota(stratum.begin(), stratum.end(), 0);
        if (latin_hypercube)
          for (unsigned int k = n_samples; k > 1; --k)
            std::swap(stratum[k - 1], stratum[generator() % k]);
        for (unsigned int i = 0; i < n_samples; ++i)
          points[i][j] =
            latin_hypercube ? (stratum[i] + uniform()) / n_samples : uniform();
      }
    return points;
  }

  std::vector<StudyCase>
  make_study_cases(const Parameters::AllParameters &study,
                   const Parameters::AllParameters &base)
  {
    const Parameters::Study &s     = study.study;
    const auto               place = [&](const std::string &entry) {
      const auto it = study.places.find("Study/" + entry);
      return it == study.places.end() ? study.parameter_file : it->second;
    };
    const std::vector<Setting> grid =
      parse_settings(s.grid, place("Grid"), true);
    unsigned int               n_rows   = 1;
    const std::vector<Setting> rows     = s.cases_file.empty() ?
                                            std::vector<Setting>() :
                                            read_cases_file(s.cases_file, n_rows);
    const bool                 sampling = (s.sampling != "none");
    const std::vector<Setting> distributions =
      parse_settings(s.distributions, place("Distributions"), false);
    AssertThrow(
      sampling == (s.samples > 0) && sampling == !distributions.empty(),
      ExcInputError("Study " + place("Sampling") +
                    ": Sampling, Samples and Distributions go together (a "
                    "sampling method, a number of samples above 0 and at "
                    "least one distribution), or none of them."));
    const unsigned int n_samples = sampling ? s.samples : 1;
    const auto         points    = unit_samples(n_samples,
                                     distributions.size(),
                                     s.seed,
                                     s.sampling == "latin hypercube");

    unsigned int n_grid = 1;
    for (const Setting &factor : grid)
      n_grid *= factor.values.size();
    std::vector<StudyCase> cases;
    for (unsigned int g = 0; g < n_grid; ++g)
      for (unsigned int r = 0; r < n_rows; ++r)
        for (unsigned int i = 0; i < n_samples; ++i)
          {
            StudyCase study_case;
            char      name[32];
            std::snprintf(name, sizeof(name), "case-%04zu", cases.size());
            study_case.name = name;
            // The grid index in mixed radix, the last factor fastest.
            std::vector<unsigned int> digit(grid.size());
            for (unsigned int f = grid.size(), rest = g; f-- > 0;)
              {
                digit[f] = rest % grid[f].values.size();
                rest /= grid[f].values.size();
              }
            for (unsigned int f = 0; f < grid.size(); ++f)
              apply(grid[f], grid[f].values[digit[f]], base, study_case);
            for (const Setting &column : rows)
              apply(column, column.values[r], base, study_case);
            for (unsigned int j = 0; j < distributions.size(); ++j)
              apply(distributions[j],
                    number_text(sample(distributions[j], points[i][j])),
                    base,
                    study_case);
            cases.push_back(study_case);
          }
    return cases;
  }

  std::string
  case_parameter_text(const std::string                        &base_file,
                      const std::vector<std::string>           &includes,
                      const std::map<std::string, std::string> &entries,
                      const std::string                        &comment)
  {
    std::ostringstream text;
    text << "# " << comment << "\ninclude " << base_file << "\n";
    for (const std::string &file : includes)
      text << "include " << file << "\n";
    for (const auto &[path, value] : entries)
      {
        if (path.rfind("Generator/", 0) == 0)
          continue;
        const auto   parts = Utilities::split_string_list(path, '/');
        unsigned int depth = 0;
        for (; depth + 1 < parts.size(); ++depth)
          text << std::string(2 * depth, ' ') << "subsection " << parts[depth]
               << "\n";
        text << std::string(2 * depth, ' ') << "set " << parts.back() << " = "
             << value << "\n";
        while (depth-- > 0)
          text << std::string(2 * depth, ' ') << "end\n";
      }
    return text.str();
  }
} // namespace TKR::Problems
