// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <deal.II/base/mpi.h>

#include <deal.II/numerics/data_out.h>

#include <tkr/base/atomic_file.h>
#include <tkr/base/exceptions.h>
#include <tkr/base/mpi.h>
#include <tkr/base/process.h>
#include <tkr/mesh/mesh.h>
#include <tkr/output/solution_output.h>
#include <tkr/output/wear_output.h>

#include <cstdio>
#include <cstdlib>
#include <iomanip>
#include <sstream>

namespace TKR::Output
{
  using namespace dealii;

  namespace
  {
    /** steps.csv's columns of every protocol, after its inputs. */
    const std::vector<ResultColumn<Gait::StepReport>> &
    step_columns()
    {
      using Report = Gait::StepReport;
      // clang-format off
      static const std::vector<ResultColumn<Report>> table = {
        member_column<Report>({"active_nodes", "", "-", {}, "nodes in contact"},
         &Report::active_nodes),
        member_column<Report>({"newton_iterations", "", "-", {}, "active-set iterations of the step (a trace)", {}, true},
         &Report::newton_iterations),
        member_column<Report>({"pose_updates", "", "-", {}, "pose updates of the step (a trace)", {}, true},
         &Report::pose_updates),
        member_column<Report>({"max_pressure_MPa", "", "MPa", {}, "the largest nodal contact pressure"},
         &Report::max_pressure),
        member_column<Report>({"contact_force_N", "", "N", {}, "the magnitude of the contact force"},
         &Report::contact_force),
        member_column<Report>({"contact_area_mm2", "", "mm^2", {}, "the contact area"},
         &Report::contact_area),
        member_column<Report>({"converged", "", "-", {}, "1 if the step converged (contact, pose and load balance), else 0"},
         &Report::converged)};
      // clang-format on
      return table;
    }

    // The protocols' inputs go at 15, their pose at 30 (Gait::Protocol).
    // clang-format off
    [[maybe_unused]] const bool declared =
      ResultSchema::declare(
        "steps.csv",
        10,
        {
        {"step", "", "-", {}, "the step, from 0"},
        {"percent", "", "%", {}, "the instant in the gait cycle"}}) &&
      ResultSchema::declare("steps.csv", 20, fields_of(step_columns())) &&
      ResultSchema::declare(
        "wear_map.csv",
        10,
        {
        {"x", "", "mm", {}, "node position, medial-lateral"},
        {"y", "", "mm", {}, "node position, anterior-posterior"},
        {"z", "", "mm", {}, "node position, proximal"},
        {"depth_mm", "", "mm", {}, "accumulated wear depth at the node"},
        {"cross_shear", "", "-", {}, "the cross-shear ratio of the node's sliding in the last computed cycle (doc/wear.md, \"Cross-shear\"); absent when a resumed run computed no cycle"}}) &&
      ResultSchema::declare(
        "wear_map_faces.csv",
        10,
        {
        {"n0", "", "-", {}, "0-based index of the face's first node in the data rows of `wear_map.csv` (row 0 = the first row after the header)"},
        {"n1", "", "-", {}, "the second node, in cyclic order around the face"},
        {"n2", "", "-", {}, "the third node"},
        {"n3", "", "-", {}, "the fourth node"}});
    // clang-format on

    /** The names of @p file's columns, joined by commas, but @p left_out. */
    std::string
    header(const std::string &file, const std::string &left_out = "")
    {
      std::string names;
      for (const ResultField &field : ResultSchema::fields(file))
        if (field.name != left_out)
          names += (names.empty() ? "" : ",") + field.name;
      return names;
    }

    /** wear_history.csv on this rank (write_wear_history() on rank 0). */
    void
    write_history_file(const std::string                    &directory,
                       const std::vector<Wear::BlockResult> &rows,
                       const std::vector<std::string>       &activities,
                       const bool                            testing);
  } // namespace

  std::string
  step_line(const unsigned int      step,
            const Gait::StepReport &r,
            const Gait::Protocol   &protocol,
            const bool              testing)
  {
    std::ostringstream line;
    line << "  step " << std::setw(3) << step << " (" << std::fixed
         << std::setprecision(1) << std::setw(5) << r.input.percent
         << " %): " << protocol.input_text(r) << ", " << std::setw(4)
         << r.active_nodes << " active, ";
    // (the solver's iterations are a trace: not in a test's output)
    if (!testing)
      line << std::setw(2) << r.newton_iterations << " Newton/"
           << r.pose_updates << " pose, ";
    line << protocol.pose_text(r) << ", max p " << std::setprecision(2)
         << std::setw(6) << r.max_pressure << " MPa"
         << (r.converged      ? "" :
             r.pose_converged ? "  NOT CONVERGED" :
                                "  POSE NOT CONVERGED");
    if (r.sub_steps > 0)
      line << ", cut back: " << r.sub_steps << " sub-steps";
    if (!testing)
      line << ", " << std::setprecision(2) << r.wall_time << " s";
    return line.str();
  }

  void
  write_steps_csv(const std::string                   &directory,
                  const std::vector<Gait::StepReport> &reports,
                  const Gait::Protocol                &protocol,
                  const MPI_Comm                       mpi_communicator,
                  const std::string                   &name)
  {
    if (Utilities::MPI::this_mpi_process(mpi_communicator) != 0)
      return;
    std::ostringstream csv;
    csv << "step,percent";
    for (const auto &column : protocol.input_columns())
      csv << ',' << column;
    for (const auto &column : step_columns())
      csv << ',' << column.field.name;
    for (const auto &column : protocol.pose_columns())
      csv << ',' << column;
    csv << '\n' << std::setprecision(10);
    for (unsigned int i = 0; i < reports.size(); ++i)
      {
        const Gait::StepReport &r = reports[i];
        csv << i << ',' << r.input.percent;
        for (const double value : r.input.values)
          csv << ',' << value;
        for (const auto &column : step_columns())
          csv << ',' << column.get(r);
        for (const double value : r.pose_values)
          csv << ',' << value;
        csv << '\n';
      }
    write_atomically(directory + "/steps" + (name.empty() ? "" : "_" + name) +
                       ".csv",
                     csv.str());
  }

  void
  write_run_result(const Wear::RunResult &result, Summary &summary)
  {
    for (const auto &[key, value] : result.named_values())
      summary.set(key, value);
    if (!result.run_in.empty())
      {
        // The run-in factor's points, for mass_loss.png (scripts/plot-wear).
        std::vector<Summary::Record> points;
        for (const auto &[cycles, factor] : result.run_in)
          points.push_back({{"cycles", cycles}, {"factor", factor}});
        summary.set("run_in_factor", points);
      }
    std::vector<Summary::Record> failed;
    for (const auto &f : result.failed_steps)
      {
        Summary::Record record;
        for (const auto &column : Wear::failed_step_columns())
          record.emplace_back(column.field.name, column.get(f));
        failed.push_back(record);
      }
    summary.set("unconverged_steps", failed);
  }

  void
  write_wear_history(const std::string                    &directory,
                     const std::vector<Wear::BlockResult> &rows,
                     const std::vector<std::string>       &activities,
                     const bool                            testing,
                     const MPI_Comm                        mpi_communicator)
  {
    on_root([&]() { write_history_file(directory, rows, activities, testing); },
            mpi_communicator);
  }

  namespace
  {
    void
    write_history_file(const std::string                    &directory,
                       const std::vector<Wear::BlockResult> &rows,
                       const std::vector<std::string>       &activities,
                       const bool                            testing)
    {
      // The block's columns, each side's, each activity's, then the wall
      // time (none under Output/Testing).
      const auto own = [testing](const ResultField &field, const bool last) {
        return field.timing == last && !(testing && field.timing);
      };
      std::ostringstream csv;
      std::string        header;
      for (const bool last : {false, true})
        {
          for (const auto &column : Wear::block_columns())
            if (own(column.field, last))
              header += ',' + column.field.name;
          if (last)
            break;
          for (const std::string side : {"medial", "lateral"})
            for (const auto &column : Wear::side_columns())
              header += ',' + with_name(column.field.name, side);
          for (const std::string &a : activities)
            for (const auto &column : Wear::activity_columns())
              header += ',' + with_name(column.field.name, a);
        }
      csv << header.substr(1) << '\n' << std::setprecision(10);
      for (const auto &r : rows)
        {
          std::string separator;
          for (const bool last : {false, true})
            {
              for (const auto &column : Wear::block_columns())
                if (own(column.field, last))
                  {
                    csv << separator << column.get(r);
                    separator = ",";
                  }
              if (last)
                break;
              for (const auto &side : {r.medial, r.lateral})
                for (const auto &column : Wear::side_columns())
                  csv << ',' << column.get(side);
              for (unsigned int a = 0; a < activities.size(); ++a)
                for (const auto &column : Wear::activity_columns())
                  csv << ','
                      << column.get(a < r.activities.size() ?
                                      r.activities[a] :
                                      Wear::ActivityResult());
            }
          csv << '\n';
        }
      write_atomically(directory + "/wear_history.csv", csv.str());
    }
  } // namespace

  // The motion field is the displacement in the global frame: the femur's
  // elastic displacement is stored in its co-rotated frame, so its points
  // move by M(X) + R u - X.
  void
  write_step(const Elasticity::LinearElasticity  &elasticity,
             const TrilinosWrappers::MPI::Vector &solution,
             const Mapping<3>                    &mapping,
             const StepFields                    &fields,
             VtuSeries                           &series,
             const unsigned int                   index)
  {
    const auto              &dof_handler = elasticity.get_dof_handler();
    const auto              &state       = *fields.state;
    const Gait::RigidMotion &motion      = fields.femur_motion;
    Vector<double>           motion_field(dof_handler.n_dofs());
    std::vector<types::global_dof_index> dofs(3);
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        for (const auto v : cell->vertex_indices())
          {
            Tensor<1, 3> u;
            for (unsigned int c = 0; c < 3; ++c)
              {
                dofs[c] = cell->vertex_dof_index(v, c);
                u[c]    = solution[dofs[c]];
              }
            const Point<3>    &X = cell->vertex(v);
            const Tensor<1, 3> d =
              cell->material_id() == Mesh::MaterialIds::femur ?
                Tensor<1, 3>(motion(X) + motion.rotation * u - X) :
                u;
            for (unsigned int c = 0; c < 3; ++c)
              motion_field(dofs[c]) = d[c];
          }
    write_solution(
      elasticity,
      solution,
      mapping,
      series,
      index,
      index,
      {{fields.slave_surface,
        {"contact_pressure", "gap", "active"},
        {state.pressure,
         state.gap,
         std::vector<double>(state.active.begin(), state.active.end())}},
       {fields.slave_surface,
        {"slip_to_next_mm", "wear_to_next_pm"},
        {fields.slip_to_next, fields.wear_to_next}}},
      [&](DataOut<3> &data_out) {
        data_out.add_data_vector(
          motion_field,
          std::vector<std::string>(3, "motion"),
          DataOut<3>::type_dof_data,
          std::vector<DataComponentInterpretation::DataComponentInterpretation>(
            3,
            DataComponentInterpretation::component_is_part_of_vector));
      });
  }

  void
  write_worn_tibia(const unsigned int            piece,
                   const unsigned int            n_pieces,
                   const Geometry::WornGeometry &geometry,
                   const WornTibiaFields        &fields,
                   VtuSeries                    &series,
                   const unsigned int            index,
                   const double                  cycles)
  {
    const auto    &dof_handler = geometry.get_dof_handler();
    Vector<double> displacement(dof_handler.n_dofs());
    const auto     u = geometry.vertex_displacements();
    for (const auto &cell : dof_handler.active_cell_iterators())
      for (const auto v : cell->vertex_indices())
        for (unsigned int c = 0; c < 3; ++c)
          displacement(cell->vertex_dof_index(v, c)) =
            u[cell->vertex_index(v)][c];
    VertexFields vertex_fields(dof_handler.get_triangulation());
    for (const auto &[name, values] : fields)
      vertex_fields.add(name, values);

    // The tibia's locally owned cells of this piece only: the piece-th of
    // n_pieces consecutive shares of the tibia's cells.
    using Iterator = typename Triangulation<3>::cell_iterator;
    std::vector<bool> in_piece(dof_handler.get_triangulation().n_active_cells(),
                               false);
    {
      std::vector<unsigned int> tibia_cells;
      for (const auto &cell :
           dof_handler.get_triangulation().active_cell_iterators())
        if (cell->material_id() == Mesh::MaterialIds::tibia)
          tibia_cells.push_back(cell->active_cell_index());
      const std::uint64_t n_tibia = tibia_cells.size();
      for (std::uint64_t k = 0; k < n_tibia; ++k)
        in_piece[tibia_cells[k]] = k * n_pieces / n_tibia == piece;
    }
    const auto selected = [&in_piece](const Iterator &cell) {
      return cell->is_active() && cell->is_locally_owned() &&
             in_piece[cell->active_cell_index()];
    };
    DataOut<3> data_out;
    data_out.set_cell_selection(
      [selected](const Triangulation<3> &tria) -> Iterator {
        for (Iterator cell = tria.begin(); cell != tria.end(); ++cell)
          if (selected(cell))
            return cell;
        return tria.end();
      },
      [selected](const Triangulation<3> &tria,
                 const Iterator         &previous) -> Iterator {
        Iterator cell = previous;
        for (++cell; cell != tria.end(); ++cell)
          if (selected(cell))
            return cell;
        return tria.end();
      });
    data_out.attach_dof_handler(dof_handler);
    vertex_fields.attach(data_out);
    data_out.add_data_vector(
      displacement,
      std::vector<std::string>(3, "wear_displacement"),
      DataOut<3>::type_dof_data,
      std::vector<DataComponentInterpretation::DataComponentInterpretation>(
        3,
        DataComponentInterpretation::component_is_part_of_vector));
    data_out.build_patches(geometry.get_mapping(), 1);
    series.write(data_out, index, cycles);
  }

  void
  write_wear_map(const std::string            &directory,
                 const Mortar::ContactSurface &surface,
                 const Geometry::WornGeometry &geometry,
                 const std::vector<double>    &cross_shear,
                 const MPI_Comm                mpi_communicator,
                 const std::string            &name,
                 const std::vector<double>    *activity_depth)
  {
    if (Utilities::MPI::this_mpi_process(mpi_communicator) != 0)
      return;
    const auto &x = geometry.vertex_positions();
    const auto &depth =
      activity_depth ? *activity_depth : geometry.wear_depth();
    const bool         with_cs = cross_shear.size() == surface.nodes().size();
    std::ostringstream nodes;
    nodes << header("wear_map.csv", with_cs ? "" : "cross_shear") << '\n'
          << std::setprecision(10);
    for (unsigned int j = 0; j < surface.nodes().size(); ++j)
      {
        const unsigned int v = surface.nodes()[j].vertex;
        nodes << x[v][0] << ',' << x[v][1] << ',' << x[v][2] << ',' << depth[v];
        if (with_cs)
          nodes << ',' << cross_shear[j];
        nodes << '\n';
      }
    write_atomically(directory + "/wear_map" +
                       (name.empty() ? "" : "_" + name) + ".csv",
                     nodes.str());
    if (!name.empty())
      return;
    // deal.II numbers a face's vertices lexicographically: 0, 1, 3, 2 go
    // around it.
    std::ostringstream faces;
    faces << header("wear_map_faces.csv") << '\n';
    for (const auto &face : surface.faces())
      faces << face.nodes[0] << ',' << face.nodes[1] << ',' << face.nodes[3]
            << ',' << face.nodes[2] << '\n';
    write_atomically(directory + "/wear_map_faces.csv", faces.str());
  }

  std::string
  make_plots(const std::string &directory,
             const std::string &measured_file,
             const MPI_Comm     mpi_communicator)
  {
    std::vector<std::string> arguments = {directory};
    if (!measured_file.empty())
      arguments.insert(arguments.end(), {"--measured", measured_file});
    return run_script("plot-wear",
                      arguments,
                      directory + "/plot-wear.log",
                      mpi_communicator);
  }

  std::string
  run_script(const std::string              &script,
             const std::vector<std::string> &arguments,
             const std::string              &log_file,
             const MPI_Comm                  mpi_communicator)
  {
    std::string error;
    if (Utilities::MPI::this_mpi_process(mpi_communicator) == 0)
      {
        std::vector<std::string> command = {std::string(TKR_SOURCE_DIR) +
                                            "/scripts/" + script};
        command.insert(command.end(), arguments.begin(), arguments.end());
        std::string output;
        try
          {
            output = run_process(command, "scripts/" + script);
          }
        catch (const ExcInputError &exc)
          {
            error  = exception_message(exc) + " (see <" + log_file + ">)";
            output = error + "\n";
          }
        write_atomically(log_file, output);
      }
    return Utilities::MPI::broadcast(mpi_communicator, error, 0);
  }
} // namespace TKR::Output
