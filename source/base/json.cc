// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <tkr/base/json.h>

#include <cstdio>

namespace TKR
{
  std::string
  json_string(const std::string &text)
  {
    std::string result = "\"";
    for (const char c : text)
      if (c == '"' || c == '\\')
        result += std::string("\\") + c;
      else if (c == '\n')
        result += "\\n";
      else if (static_cast<unsigned char>(c) < 0x20)
        {
          char escaped[7];
          std::snprintf(escaped,
                        sizeof(escaped),
                        "\\u%04x",
                        static_cast<unsigned int>(c));
          result += escaped;
        }
      else
        result += c;
    return result + "\"";
  }
} // namespace TKR
