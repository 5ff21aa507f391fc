// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.
//
// Reading a parameter file: its `include` lines, where each entry was set,
// and relative paths (private to source/parameters/).

#ifndef tkr_parameters_parameter_file_h
#define tkr_parameters_parameter_file_h

#include <deal.II/base/parameter_handler.h>

#include <tkr/parameters/parameters.h>

#include <map>
#include <string>
#include <utility>
#include <vector>

namespace TKR::Parameters::internal
{
  /**
   * A parameter file with its `include FILE` lines replaced by the lines
   * of FILE (recursively), FILE taken from the directory of the file that
   * includes it, then from the working directory. Each line of the text
   * remembers the file and line it came from, so that a message of
   * ParameterHandler about a line of the text can name the real place,
   * and so that the file that set an entry is known (a relative path in
   * it is taken from that file's directory).
   */
  class ParameterText
  {
  public:
    /**
     * Read @p filename (ExcInputError if it or an include is missing); a
     * `set` of an entry that moved (@p moved: old path, new path; one old
     * path may have several new ones) sets the new path(s) instead, with a
     * note.
     */
    ParameterText(
      const std::string                                      &filename,
      const std::vector<std::pair<std::string, std::string>> &moved = {});

    /**
     * The files @p filenames one after the other (e.g. a parameter file and
     * an activity's file on top of it), as the constructor above does.
     */
    ParameterText(
      const std::vector<std::string>                         &filenames,
      const std::vector<std::pair<std::string, std::string>> &moved = {});

    /** The paths of the entries a `set` line of the text sets. */
    std::vector<std::string>
    entries_set() const;

    /** "FILE:LINE sets OLD, which is now NEW ..." per moved entry read. */
    const std::vector<std::string> &
    moved_notes() const
    {
      return notes;
    }

    /** The expanded text. */
    const std::string &
    text() const
    {
      return expanded;
    }

    /**
     * @p message with "Line <N> of file <NAME>" (N a line of the expanded
     * text, NAME the name it was parsed under) replaced by the file and
     * line that line came from.
     */
    std::string
    locate(const std::string &message) const;

    /**
     * The directory of the file whose line set the entry @p path (e.g.
     * "Mesh/File") last, "" if no line sets it.
     */
    std::string
    directory_of(const std::string &path) const;

    /**
     * "FILE:LINE" of the line that set the entry @p path last, "" if no
     * line sets it.
     */
    std::string
    place_of(const std::string &path) const;

  private:
    /** Append the lines of @p filename; @p depth counts nested includes. */
    void
    append(const std::string &filename, const unsigned int depth);

    /** A line as ParameterHandler reads it (continuations joined). */
    struct LogicalLine
    {
      /** Its lines in the text: [first, last). */
      unsigned int first, last;
      /** The joined line without comment, trimmed. */
      std::string text;
      /** The subsections it is in. */
      std::vector<std::string> path;
      /** The entry path a `set` line sets, else empty. */
      std::string entry;
    };

    /** The logical lines of the text. */
    std::vector<LogicalLine>
    logical_lines() const;

    /** Replace the `set` lines of @p moved entries (see the constructor). */
    void
    rename_moved(const std::vector<std::pair<std::string, std::string>> &moved);

    /** Record for every `set` line the entry it sets. */
    void
    find_setters();

    std::string expanded;
    /** Per line of the text: the file and the line number there. */
    std::vector<std::pair<std::string, unsigned int>> origin;
    /** Per entry path: the line of the text that set it last. */
    std::map<std::string, unsigned int> setter;
    /** The notes of rename_moved(). */
    std::vector<std::string> notes;
  };

  /** The value of the entry @p path ("Subsection/.../Entry") of @p prm. */
  std::string
  get_entry(dealii::ParameterHandler &prm, const std::string &path);

  /** Set the entry @p path of @p prm to @p value (its pattern checked). */
  void
  set_entry(dealii::ParameterHandler &prm,
            const std::string        &path,
            const std::string        &value);

  /** Every entry of @p prm as "Subsection/.../Entry" -> value. */
  std::map<std::string, std::string>
  list_entries(const dealii::ParameterHandler &prm);

  /**
   * A relative @p path taken from @p directory (if that has the file),
   * else from the working directory (if it has it), else from the
   * directory of the tkr-wear sources (the bundled meshes and data); the
   * first that exists. An absolute path, or one found nowhere, is
   * returned as it is.
   */
  std::string
  resolve_path(const std::string &path, const std::string &directory);

  /**
   * Parse @p text (read from @p filename) into @p prm, every relative path
   * of a file entry taken from the directory of the file that set it;
   * ExcInputError naming the file and line of a bad line.
   */
  void
  parse_text(dealii::ParameterHandler &prm,
             const ParameterText      &text,
             const std::string        &filename);

  /**
   * The activity mix of @p gait (its `Activities`, paths resolved) of the
   * parameter file @p filename: each activity's gait is @p filename's
   * with the activity's file read on top. Empty without a mix.
   * ExcInputError for a malformed list, shares that do not add up to 1,
   * an activity file that sets entries outside `Gait` (or `Activities`,
   * `Step groups`, `Medial side`), or a missing waveform file.
   */
  std::vector<Activity>
  read_mix(const std::string &filename, const Gait &gait);
} // namespace TKR::Parameters::internal

#endif
