// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.
//
// Vector-valued parameter entries ("x, y, z"), shared by the parameter
// files of this folder (not part of the library's interface).

#ifndef tkr_source_parameters_vector_entry_h
#define tkr_source_parameters_vector_entry_h

#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/tensor.h>
#include <deal.II/base/utilities.h>

namespace TKR::Parameters::internal
{
  /** Pattern of a vector "x, y, z". */
  inline dealii::Patterns::List
  vector_pattern()
  {
    return dealii::Patterns::List(dealii::Patterns::Double(), 3, 3, ",");
  }

  /** Read a "x, y, z" entry; the pattern has already been checked. */
  inline dealii::Tensor<1, 3>
  get_vector(dealii::ParameterHandler &prm, const std::string &name)
  {
    const std::vector<double> values = dealii::Utilities::string_to_double(
      dealii::Utilities::split_string_list(prm.get(name), ','));
    dealii::Tensor<1, 3> result;
    for (unsigned int d = 0; d < 3; ++d)
      result[d] = values[d];
    return result;
  }
} // namespace TKR::Parameters::internal

#endif
