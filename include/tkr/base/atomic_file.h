// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_base_atomic_file_h
#define tkr_base_atomic_file_h

#include <functional>
#include <string>

namespace TKR
{
  /**
   * Write @p filename whole or not at all: @p write fills the temporary file
   * whose name it is given (@p filename + ".tmp"), which then replaces
   * @p filename by a rename, atomic on POSIX file systems. A reader (a
   * resumed run, a study reading a case) or a run killed while writing never
   * leaves a half-written file. A failure is an ExcInputError naming the
   * file.
   */
  void
  write_atomically(const std::string                              &filename,
                   const std::function<void(const std::string &)> &write);

  /** write_atomically() of the text @p text. */
  void
  write_atomically(const std::string &filename, const std::string &text);
} // namespace TKR

#endif
