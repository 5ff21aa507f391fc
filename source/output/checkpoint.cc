// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.
//
// The one file that writes and reads checkpoints of the wear run (as
// ASPECT keeps its checkpoint_restart.cc): HDF5, rank-independent data.

#include <deal.II/base/hdf5.h>
#include <deal.II/base/mpi.h>

#include <tkr/base/atomic_file.h>
#include <tkr/base/exceptions.h>
#include <tkr/base/mpi.h>
#include <tkr/output/checkpoint.h>
#include <tkr/wear/run_result.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <sstream>

namespace TKR::Output
{
  using namespace dealii;

  namespace
  {
    // 4: pose_fallbacks; format 3 (without it) is read as 0 fallbacks.
    // 5: the steps' poses one block before (the extrapolated warm start);
    // formats 3 and 4 are read without them (the first block after the
    // resume then starts from the last poses).
    // 6: the activities of a mix; formats 3 to 5 are read without (no mix).
    // 7: the steps cut back and their sub-steps; formats 3 to 6 are read as
    // none.
    constexpr unsigned int format_version = 7, oldest_format = 3;
    /** The first format with the cut-back counts. */
    constexpr unsigned int cut_back_format = 7;
    /** The first format with the activities of a mix. */
    constexpr unsigned int activities_format = 6;
    /** The first format with pose_fallbacks. */
    constexpr unsigned int pose_fallbacks_format = 4;
    /** The first format with the previous poses of the steps. */
    constexpr unsigned int previous_pose_format = 5;
    // The datasets of the results hold a record's values in the order of
    // its columns (Wear::block_columns() and the others, the schema).
    const unsigned int n_history_columns  = Wear::block_columns().size();
    const unsigned int n_side_columns     = 2 * Wear::side_columns().size();
    const unsigned int n_activity_columns = Wear::activity_columns().size();
    const unsigned int n_failed_columns   = Wear::failed_step_columns().size();

    /** @p record's values, in the order of @p columns, after @p values. */
    template <typename Record>
    void
    append(std::vector<double>                     &values,
           const std::vector<ResultColumn<Record>> &columns,
           const Record                            &record)
    {
      for (const auto &column : columns)
        values.push_back(column.get(record));
    }

    /** The record whose values (in the order of @p columns) start at
     *  @p values. */
    template <typename Record>
    Record
    record(const std::vector<ResultColumn<Record>> &columns,
           const double                            *values)
    {
      Record result;
      for (unsigned int i = 0; i < columns.size(); ++i)
        columns[i].set(result, values[i]);
      return result;
    }

    /** A dataset of @p values with the dimensions @p dimensions. */
    template <typename T>
    void
    write_dataset(HDF5::Group                &file,
                  const std::string          &name,
                  const std::vector<T>       &values,
                  const std::vector<hsize_t> &dimensions)
    {
      if (values.empty())
        return;
      auto dataset = file.create_dataset<T>(name, dimensions);
      dataset.write(values);
    }

    template <typename T>
    std::vector<T>
    read_dataset(const HDF5::Group &file, const std::string &name)
    {
      return file.open_dataset(name).read<std::vector<T>>();
    }

    std::vector<double>
    flatten(const std::vector<Tensor<1, 3>> &vectors)
    {
      std::vector<double> values;
      values.reserve(3 * vectors.size());
      for (const auto &v : vectors)
        values.insert(values.end(), {v[0], v[1], v[2]});
      return values;
    }

    std::vector<Tensor<1, 3>>
    unflatten(const std::vector<double> &values)
    {
      std::vector<Tensor<1, 3>> vectors(values.size() / 3);
      for (unsigned int i = 0; i < vectors.size(); ++i)
        for (unsigned int d = 0; d < 3; ++d)
          vectors[i][d] = values[3 * i + d];
      return vectors;
    }
  } // namespace

  std::string
  checkpoint_file(const std::string &directory)
  {
    return directory + "/checkpoint.h5";
  }


  namespace
  {
    void
    write_counters(HDF5::File &file, const Wear::WearRunState &state)
    {
      file.set_attribute("block", state.block);
      file.set_attribute("cycles", state.cycles);
      file.set_attribute("cycles_per_block", state.cycles_per_block);
      file.set_attribute("stiffness_block", state.stiffness_block);
      file.set_attribute("volume", state.volume);
      file.set_attribute("volume_medial", state.volume_medial);
      file.set_attribute("volume_lateral", state.volume_lateral);
      file.set_attribute("contact_solves", double(state.contact_solves));
      file.set_attribute("newton_iterations", double(state.newton_iterations));
      file.set_attribute("steps", double(state.steps));
      file.set_attribute("pose_fallbacks", double(state.pose_fallbacks));
      file.set_attribute("cut_back_steps", double(state.cut_back_steps));
      file.set_attribute("sub_steps", double(state.sub_steps));
      file.set_attribute("converged", state.converged);
      file.set_attribute("max_pressure", state.max_pressure);
      file.set_attribute("first_cycle_mass", state.first_cycle_mass);
      file.set_attribute("wall_time", state.wall_time);
      file.set_attribute("n_vertices",
                         static_cast<unsigned int>(state.depth.size()));
      file.set_attribute("n_steps",
                         static_cast<unsigned int>(state.step_starts.size()));
    }

    void
    read_counters(const HDF5::File &file, Wear::WearRunState &state)
    {
      state.block            = file.get_attribute<unsigned int>("block");
      state.cycles           = file.get_attribute<double>("cycles");
      state.cycles_per_block = file.get_attribute<double>("cycles_per_block");
      state.stiffness_block =
        file.get_attribute<unsigned int>("stiffness_block");
      state.volume         = file.get_attribute<double>("volume");
      state.volume_medial  = file.get_attribute<double>("volume_medial");
      state.volume_lateral = file.get_attribute<double>("volume_lateral");
      state.contact_solves =
        std::llround(file.get_attribute<double>("contact_solves"));
      state.newton_iterations =
        std::llround(file.get_attribute<double>("newton_iterations"));
      state.steps = std::llround(file.get_attribute<double>("steps"));
      state.pose_fallbacks =
        file.get_attribute<unsigned int>("format_version") <
            pose_fallbacks_format ?
          0 :
          std::llround(file.get_attribute<double>("pose_fallbacks"));
      const bool cut_back =
        file.get_attribute<unsigned int>("format_version") >= cut_back_format;
      state.cut_back_steps =
        cut_back ? std::llround(file.get_attribute<double>("cut_back_steps")) :
                   0;
      state.sub_steps =
        cut_back ? std::llround(file.get_attribute<double>("sub_steps")) : 0;
      state.converged        = file.get_attribute<bool>("converged");
      state.max_pressure     = file.get_attribute<double>("max_pressure");
      state.first_cycle_mass = file.get_attribute<double>("first_cycle_mass");
      state.wall_time        = file.get_attribute<double>("wall_time");
    }

    // Warm starts: the pose (the protocol's numbers, opaque here) and the
    // active set of every step.
    void
    write_step_starts(HDF5::File                         &file,
                      const std::vector<Gait::StepStart> &starts)
    {
      const hsize_t n_steps   = starts.size();
      const hsize_t n_nodes   = n_steps > 0 ? starts[0].active.size() : 0;
      const hsize_t pose_size = n_steps > 0 ? starts[0].pose.values.size() : 0;
      file.set_attribute("pose_size", static_cast<unsigned int>(pose_size));
      std::vector<double>       poses, previous;
      std::vector<unsigned int> active;
      for (const auto &start : starts)
        {
          const auto &p = start.pose.values;
          AssertThrow(p.size() == pose_size,
                      ExcMessage("Poses of different sizes."));
          poses.insert(poses.end(), p.begin(), p.end());
          // (NaN: no previous pose)
          for (unsigned int k = 0; k < pose_size; ++k)
            previous.push_back(start.previous.values.size() == pose_size ?
                                 start.previous.values[k] :
                                 std::numeric_limits<double>::quiet_NaN());
          AssertThrow(start.active.size() == n_nodes,
                      ExcMessage("Active sets of different sizes."));
          active.insert(active.end(), start.active.begin(), start.active.end());
        }
      write_dataset(file, "step_pose", poses, {n_steps, pose_size});
      write_dataset(file, "step_previous_pose", previous, {n_steps, pose_size});
      write_dataset(file, "step_active", active, {n_steps, n_nodes});
    }

    std::vector<Gait::StepStart>
    read_step_starts(const HDF5::File &file, const unsigned int n_steps)
    {
      const auto poses  = read_dataset<double>(file, "step_pose");
      const auto active = read_dataset<unsigned int>(file, "step_active");
      const unsigned int n_nodes = n_steps > 0 ? active.size() / n_steps : 0;
      const unsigned int pose_size =
        file.get_attribute<unsigned int>("pose_size");
      const auto previous =
        file.get_attribute<unsigned int>("format_version") <
            previous_pose_format ?
          std::vector<double>(poses.size(),
                              std::numeric_limits<double>::quiet_NaN()) :
          read_dataset<double>(file, "step_previous_pose");
      std::vector<Gait::StepStart> starts(n_steps);
      for (unsigned int s = 0; s < n_steps; ++s)
        {
          starts[s].pose.values.assign(poses.begin() + s * pose_size,
                                       poses.begin() + (s + 1) * pose_size);
          if (pose_size > 0 && !std::isnan(previous[s * pose_size]))
            starts[s].previous.values.assign(previous.begin() + s * pose_size,
                                             previous.begin() +
                                               (s + 1) * pose_size);
          starts[s].active.assign(active.begin() + s * n_nodes,
                                  active.begin() + (s + 1) * n_nodes);
        }
      return starts;
    }

    void
    write_history(HDF5::File &file, const std::vector<Wear::BlockResult> &rows)
    {
      std::vector<double> history, sides;
      for (const auto &r : rows)
        {
          append(history, Wear::block_columns(), r);
          append(sides, Wear::side_columns(), r.medial);
          append(sides, Wear::side_columns(), r.lateral);
        }
      write_dataset(file, "history", history, {rows.size(), n_history_columns});
      write_dataset(file, "sides", sides, {rows.size(), n_side_columns});
    }

    std::vector<Wear::BlockResult>
    read_history(const HDF5::File &file)
    {
      std::vector<Wear::BlockResult> rows;
      const auto history = read_dataset<double>(file, "history");
      for (unsigned int i = 0; i + n_history_columns <= history.size();
           i += n_history_columns)
        // (the sides below; the activities: read_activities())
        rows.push_back(record(Wear::block_columns(), &history[i]));
      const auto sides = read_dataset<double>(file, "sides");
      for (unsigned int i = 0;
           i < rows.size() && n_side_columns * (i + 1) <= sides.size();
           ++i)
        {
          const double *s = &sides[n_side_columns * i];
          rows[i].medial  = record(Wear::side_columns(), s);
          rows[i].lateral =
            record(Wear::side_columns(), s + Wear::side_columns().size());
        }
      return rows;
    }

    void
    write_failed_steps(HDF5::File                          &file,
                       const std::vector<Wear::FailedStep> &failed)
    {
      file.set_attribute("n_failed_steps",
                         static_cast<unsigned int>(failed.size()));
      std::vector<double> values;
      for (const auto &f : failed)
        append(values, Wear::failed_step_columns(), f);
      write_dataset(file,
                    "failed_steps",
                    values,
                    {failed.size(), n_failed_columns});
    }

    std::vector<Wear::FailedStep>
    read_failed_steps(const HDF5::File &file)
    {
      std::vector<Wear::FailedStep> failed;
      if (file.get_attribute<unsigned int>("n_failed_steps") == 0)
        return failed;
      const auto values = read_dataset<double>(file, "failed_steps");
      for (unsigned int i = 0; i + n_failed_columns <= values.size();
           i += n_failed_columns)
        failed.push_back(record(Wear::failed_step_columns(), &values[i]));
      return failed;
    }


    /** The activities of a mix: their depth, volumes and history. */
    void
    write_activities(HDF5::File &file, const Wear::WearRunState &state)
    {
      const hsize_t n = state.activity_volume.size();
      file.set_attribute("n_activities", static_cast<unsigned int>(n));
      if (n == 0)
        return;
      std::vector<double> depth, volume, history;
      for (unsigned int a = 0; a < n; ++a)
        {
          depth.insert(depth.end(),
                       state.activity_depth[a].begin(),
                       state.activity_depth[a].end());
          append(volume, Wear::activity_columns(), state.activity_volume[a]);
        }
      for (const auto &row : state.history)
        for (unsigned int a = 0; a < n; ++a)
          {
            append(history,
                   Wear::activity_columns(),
                   a < row.activities.size() ? row.activities[a] :
                                               Wear::ActivityResult());
          }
      write_dataset(file, "activity_depth", depth, {n, state.depth.size()});
      write_dataset(file, "activity_volume", volume, {n, n_activity_columns});
      write_dataset(file,
                    "activity_history",
                    history,
                    {state.history.size(), n * n_activity_columns});
    }

    /** The activities of a mix (after read_history()). */
    void
    read_activities(const HDF5::File &file, Wear::WearRunState &state)
    {
      if (file.get_attribute<unsigned int>("format_version") <
          activities_format)
        return;
      const unsigned int n = file.get_attribute<unsigned int>("n_activities");
      if (n == 0)
        return;
      const auto depth   = read_dataset<double>(file, "activity_depth");
      const auto volume  = read_dataset<double>(file, "activity_volume");
      const auto history = read_dataset<double>(file, "activity_history");
      const unsigned int n_vertices = state.depth.size();
      AssertThrow(depth.size() == n * n_vertices &&
                    volume.size() == n * n_activity_columns &&
                    history.size() ==
                      state.history.size() * n * n_activity_columns,
                  ExcInputError("The checkpoint's activity datasets are "
                                "incomplete."));
      for (unsigned int a = 0; a < n; ++a)
        {
          state.activity_depth.emplace_back(depth.begin() + a * n_vertices,
                                            depth.begin() +
                                              (a + 1) * n_vertices);
          state.activity_volume.push_back(
            record(Wear::activity_columns(), &volume[a * n_activity_columns]));
        }
      for (unsigned int r = 0; r < state.history.size(); ++r)
        for (unsigned int a = 0; a < n; ++a)
          state.history[r].activities.push_back(
            record(Wear::activity_columns(),
                   &history[(r * n + a) * n_activity_columns]));
    }

    /** The checkpoint was written by this format and these parameters. */
    void
    check_origin(const HDF5::File                &file,
                 const std::string               &filename,
                 const Parameters::AllParameters &parameters)
    {
      const auto version = file.get_attribute<unsigned int>("format_version");
      AssertThrow(version >= oldest_format && version <= format_version,
                  ExcInputError("The checkpoint <" + filename +
                                "> was written by another version of "
                                "tkr-wear (checkpoint format " +
                                std::to_string(version) + ", this one reads " +
                                std::to_string(oldest_format) + " to " +
                                std::to_string(format_version) + ")."));
      check_state_parameters(filename,
                             file.get_attribute<std::string>("parameters"),
                             parameters);
    }
  } // namespace

  void
  write_checkpoint(const std::string               &directory,
                   const Wear::WearRunState        &state,
                   const Parameters::AllParameters &parameters,
                   const MPI_Comm                   mpi_communicator)
  {
    on_root(
      [&]() {
        write_atomically(
          checkpoint_file(directory),
          [&](const std::string &temporary) {
            HDF5::File file(temporary, HDF5::File::FileAccessMode::create);
            file.set_attribute("format_version", format_version);
            file.set_attribute("parameters", state_parameters_text(parameters));
            write_counters(file, state);
            const hsize_t n_vertices = state.depth.size();
            write_dataset(file,
                          "displacement",
                          flatten(state.displacement),
                          {n_vertices, 3});
            write_dataset(file,
                          "stiffness_displacement",
                          flatten(state.stiffness_displacement),
                          {n_vertices, 3});
            write_dataset(file, "depth", state.depth, {n_vertices});
            write_step_starts(file, state.step_starts);
            write_history(file, state.history);
            write_failed_steps(file, state.failed_steps);
            write_activities(file, state);
          });
      },
      mpi_communicator);
  }

  namespace
  {
    /**
     * Throw ExcInputError if HDF5 cannot open @p filename for reading and
     * writing (as deal.II's HDF5::File does), e.g. because another process
     * holds its lock: deal.II's wrappers do not check, and every read
     * would return garbage.
     */
    void
    check_can_open(const std::string &filename)
    {
      H5E_auto2_t report;
      void       *report_data;
      H5Eget_auto2(H5E_DEFAULT, &report, &report_data);
      H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
      const hid_t file = H5Fopen(filename.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
      H5Eset_auto2(H5E_DEFAULT, report, report_data);
      AssertThrow(file >= 0,
                  ExcInputError("Cannot open the checkpoint <" + filename +
                                "> with HDF5 (not an HDF5 file, not "
                                "writable, or locked by another process)."));
      H5Fclose(file);
    }

    /** The checkpoint @p filename, read by this rank alone. */
    Wear::WearRunState
    read_checkpoint_file(const std::string               &filename,
                         const unsigned int               n_vertices,
                         const unsigned int               n_steps,
                         const Parameters::AllParameters &parameters)
    {
      AssertThrow(std::filesystem::exists(filename),
                  ExcInputError("--resume: there is no checkpoint <" +
                                filename +
                                "> (Output/Checkpoint interval > 0 writes "
                                "one every that many blocks)."));
      check_can_open(filename);
      // Every error is caught while the file is open and thrown after it is
      // closed: deal.II's HDF5 objects abort the program if they are
      // destroyed during stack unwinding.
      Wear::WearRunState state;
      std::string        error;
      try
        {
          HDF5::File file(filename, HDF5::File::FileAccessMode::open);
          try
            {
              check_origin(file, filename, parameters);
              AssertThrow(
                file.get_attribute<unsigned int>("n_vertices") == n_vertices &&
                  file.get_attribute<unsigned int>("n_steps") == n_steps,
                ExcInputError("The checkpoint <" + filename +
                              "> belongs to another mesh or gait (vertices, "
                              "steps per cycle) than the parameter file."));
              read_counters(file, state);
              state.displacement =
                unflatten(read_dataset<double>(file, "displacement"));
              state.stiffness_displacement =
                unflatten(read_dataset<double>(file, "stiffness_displacement"));
              state.depth        = read_dataset<double>(file, "depth");
              state.step_starts  = read_step_starts(file, n_steps);
              state.history      = read_history(file);
              state.failed_steps = read_failed_steps(file);
              read_activities(file, state);
            }
          catch (const ExcInputError &exc)
            {
              error = exception_message(exc);
            }
          catch (const std::exception &exc)
            {
              error =
                "Cannot read the checkpoint <" + filename + ">: " + exc.what();
            }
        }
      catch (const std::exception &exc)
        {
          error =
            "Cannot read the checkpoint <" + filename + ">: " + exc.what();
        }
      AssertThrow(error.empty(), ExcInputError(error));
      AssertThrow(state.depth.size() == n_vertices &&
                    state.displacement.size() == n_vertices,
                  ExcInputError("The checkpoint <" + filename +
                                "> is incomplete."));
      return state;
    }
  } // namespace

  Wear::WearRunState
  read_checkpoint(const std::string               &directory,
                  const unsigned int               n_vertices,
                  const unsigned int               n_steps,
                  const Parameters::AllParameters &parameters,
                  const MPI_Comm                   mpi_communicator)
  {
    const std::string  filename = checkpoint_file(directory);
    Wear::WearRunState state;
    in_turn(
      [&]() {
        state = read_checkpoint_file(filename, n_vertices, n_steps, parameters);
      },
      mpi_communicator);
    return state;
  }
} // namespace TKR::Output
