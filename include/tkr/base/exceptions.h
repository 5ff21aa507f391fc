// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_base_exceptions_h
#define tkr_base_exceptions_h

#include <deal.II/base/exceptions.h>

#include <string>

namespace TKR
{
  /**
   * The exception for everything a user can get wrong: a parameter file that
   * does not parse, a mesh that lacks a physical group, bodies that do not
   * touch. The message is a complete sentence meant for the user; the
   * application prints it alone (without deal.II's stack trace) and exits
   * with a non-zero code. Throw it with `AssertThrow(cond,
   * ExcInputError(message))`.
   */
  DeclException1(ExcInputError, std::string, << arg1);

  /**
   * A run stopped by SIGTERM or SIGUSR1 (a cluster's time limit,
   * stop_requested()) after writing what `--resume` continues from; the
   * message says what was kept. The application prints it and exits with
   * stopped_exit_code.
   */
  DeclException1(ExcStopped, std::string, << arg1);

  /** The exit code of a run stopped by a signal (doc/cluster.md). */
  constexpr int stopped_exit_code = 3;

  /**
   * The message of an exception without deal.II's header (file, line,
   * function, condition): what ExceptionBase::print_info() writes, trimmed.
   */
  std::string
  exception_message(const dealii::ExceptionBase &exc);

  /** A number with @p digits significant digits, for messages. */
  std::string
  format_number(const double value, const unsigned int digits = 3);
} // namespace TKR

#endif
