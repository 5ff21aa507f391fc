// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <tkr/base/exceptions.h>
#include <tkr/gait/gait_loads.h>
#include <tkr/gait/protocol.h>

#include <algorithm>
#include <cmath>

namespace TKR::Gait
{
  using namespace dealii;

  Observations::Observations(std::vector<std::string> names,
                             std::vector<double>      values)
    : names(std::move(names))
    , values(std::move(values))
  {
    AssertDimension(this->names.size(), this->values.size());
  }

  double
  Observations::operator[](const std::string &name) const
  {
    const auto it = std::find(names.begin(), names.end(), name);
    AssertThrow(it != names.end(),
                ExcMessage("No observation named <" + name + ">."));
    return values[it - names.begin()];
  }

  StepInput
  waveform_input(const Waveform &waveform, const double percent)
  {
    StepInput input;
    input.percent = percent - 100. * std::floor(percent / 100.);
    input.values  = waveform.at(percent);
    return input;
  }

  std::unique_ptr<Protocol>
  create_protocol(const Parameters::Gait &parameters,
                  const Triangulation<3> &triangulation)
  {
    return Protocols::get(parameters.control)
      .create(parameters,
              parameters.protocols.of(parameters.control),
              measure_inferior_surface(triangulation));
  }
  bool
  declare_results(const std::string &name, const ProtocolResults &results)
  {
    const auto written = [&name](std::vector<ResultField> fields,
                                 const std::string       &prefix = "") {
      for (ResultField &field : fields)
        {
          field.writers = {name};
          field.name    = prefix + field.name;
        }
      return fields;
    };
    // Mixes' per-activity results carry the writer `wear` (the problem).
    auto per_activity = written(results.cycle, "activity_NAME_");
    for (ResultField &field : per_activity)
      {
        field.meaning = "of a mix, `" + field.name.substr(14) +
                        "` of the activity's last cycle (" + name + " control)";
        field.writers = {"wear"};
      }
    auto cycle = written(results.cycle);
    for (ResultField &field : cycle)
      field.writers = {"wear"};
    // The positions between the wear run's own results (run_result.cc).
    return ResultSchema::declare("steps.csv",
                                 15,
                                 written(results.inputs),
                                 name) &&
           ResultSchema::declare("steps.csv",
                                 30,
                                 written(results.pose),
                                 name) &&
           ResultSchema::declare("summary.json", 23, per_activity, name) &&
           ResultSchema::declare("summary.json", 24, cycle, name);
  }

  std::vector<std::string>
  names(const std::vector<ResultField> &fields)
  {
    std::vector<std::string> result;
    for (const ResultField &field : fields)
      result.push_back(field.name);
    return result;
  }
} // namespace TKR::Gait
