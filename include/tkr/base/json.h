// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_base_json_h
#define tkr_base_json_h

#include <string>

namespace TKR
{
  /**
   * @p text as a JSON string: quoted, with quotes, backslashes and control
   * characters escaped.
   */
  std::string
  json_string(const std::string &text);
} // namespace TKR

#endif
