// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_base_process_h
#define tkr_base_process_h

#include <string>
#include <vector>

namespace TKR
{
  /** @p argument quoted for a POSIX shell (single quotes, any character). */
  std::string
  shell_quote(const std::string &argument);

  /**
   * Run the program and @p arguments (each quoted, shell_quote()) through
   * the shell and return its standard output and error together. If it
   * cannot be started or exits with a status other than 0: an
   * ExcInputError that names @p what, the command and the last line of
   * its output. The one way tkr-wear runs another program (the study's
   * mesh generator, the plot scripts).
   */
  std::string
  run_process(const std::vector<std::string> &arguments,
              const std::string              &what);
} // namespace TKR

#endif
