// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <tkr/base/exceptions.h>
#include <tkr/base/process.h>

#include <cstdio>

namespace TKR
{
  std::string
  shell_quote(const std::string &argument)
  {
    std::string quoted = "'";
    for (const char c : argument)
      quoted += (c == '\'' ? std::string("'\\''") : std::string(1, c));
    return quoted + "'";
  }

  std::string
  run_process(const std::vector<std::string> &arguments,
              const std::string              &what)
  {
    std::string command;
    for (const std::string &argument : arguments)
      command += (command.empty() ? "" : " ") + shell_quote(argument);
    std::string output;
    FILE       *pipe = popen((command + " 2>&1").c_str(), "r");
    AssertThrow(pipe != nullptr,
                ExcInputError(what + ": cannot run <" + command + ">."));
    char buffer[4096];
    while (std::fgets(buffer, sizeof(buffer), pipe) != nullptr)
      output += buffer;
    const int status = pclose(pipe);
    if (status != 0)
      {
        std::string last = output.substr(0, output.find_last_not_of('\n') + 1);
        last             = last.substr(last.find_last_of('\n') + 1);
        AssertThrow(false,
                    ExcInputError(what + ": <" + command +
                                  "> failed (exit "
                                  "status " +
                                  std::to_string(status) + "): " + last));
      }
    return output;
  }
} // namespace TKR
