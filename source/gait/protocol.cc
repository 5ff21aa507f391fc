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
} // namespace TKR::Gait
