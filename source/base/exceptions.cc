// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <tkr/base/exceptions.h>

#include <iomanip>
#include <sstream>

namespace TKR
{
  std::string
  exception_message(const dealii::ExceptionBase &exc)
  {
    std::ostringstream out;
    exc.print_info(out);
    std::string message = out.str();
    // print_info() indents its text and ends it with a newline.
    const auto first = message.find_first_not_of(" \t\n");
    const auto last  = message.find_last_not_of(" \t\n");
    if (first == std::string::npos)
      return exc.get_exc_name();
    return message.substr(first, last - first + 1);
  }

  std::string
  format_number(const double value, const unsigned int digits)
  {
    std::ostringstream out;
    out << std::setprecision(digits) << value;
    return out.str();
  }
} // namespace TKR
