// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <tkr/base/atomic_file.h>
#include <tkr/base/exceptions.h>

#include <cstdio>
#include <fstream>

namespace TKR
{
  void
  write_atomically(const std::string                              &filename,
                   const std::function<void(const std::string &)> &write)
  {
    const std::string temporary = filename + ".tmp";
    write(temporary);
    AssertThrow(std::rename(temporary.c_str(), filename.c_str()) == 0,
                ExcInputError("Cannot write <" + filename + ">."));
  }

  void
  write_atomically(const std::string &filename, const std::string &text)
  {
    write_atomically(filename, [&text](const std::string &temporary) {
      std::ofstream out(temporary);
      out << text;
      AssertThrow(out.good(),
                  ExcInputError("Cannot write <" + temporary + ">."));
    });
  }
} // namespace TKR
