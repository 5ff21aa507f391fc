// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.
//
// The output of the wear problem: the screen line of a step, steps.csv,
// wear_history.csv and the VTU files of the steps and of the cycle's wear.

#include <deal.II/numerics/data_out.h>

#include <tkr/mesh/mesh.h>
#include <tkr/output/solution_output.h>
#include <tkr/wear/wear_problem.h>

#include <algorithm>
#include <fstream>
#include <iomanip>
#include <sstream>

namespace TKR::Wear
{
  using namespace dealii;

  void
  WearProblem::print_step(const unsigned int step) const
  {
    const StepReport  &r = reports[step];
    std::ostringstream line;
    line << "  step " << std::setw(3) << step << " (" << std::fixed
         << std::setprecision(1) << std::setw(5) << r.percent << " %): flexion "
         << std::setw(5) << r.flexion << " deg, axial " << std::setw(6)
         << std::setprecision(0) << r.axial_force << " N, " << std::setw(4)
         << r.active_nodes << " active, " << std::setw(2) << r.newton_iterations
         << " Newton/" << r.pose_updates << " pose, tibia y "
         << std::setprecision(2) << std::setw(5) << r.tibia_pose[1] << " z "
         << std::setw(5) << r.tibia_pose[2] << " mm, max p " << std::setw(6)
         << r.max_pressure << " MPa"
         << (r.converged      ? "" :
             r.pose_converged ? "  NOT CONVERGED" :
                                "  POSE NOT CONVERGED");
    if (!parameters.output.testing)
      line << ", " << std::setprecision(2) << r.wall_time << " s";
    pcout << line.str() << std::endl;
  }

  // Every group root puts the records and reports of its own steps into
  // flat arrays, zero elsewhere; one sum over all ranks gives everybody
  // everything. (Only group roots contribute, so nothing counts twice.)

  // global frame (the femur's elastic displacement is stored in its
  // co-rotated frame: ParaView's "warp by vector" with it shows the femur
  // in its flexed position), and the slip and wear of each tibia node over
  // the interval to the next step.
  void
  WearProblem::output_step(const unsigned int step)
  {
    const SavedStep   &saved       = saved_steps.at(step);
    const RigidMotion &motion      = saved.motion;
    const auto        &dof_handler = elasticity.get_dof_handler();
    elasticity.set_solution(saved.solution);
    const Vector<double> contact =
      Output::surface_fields(*slave,
                             {saved.state.pressure,
                              saved.state.gap,
                              std::vector<double>(saved.state.active.begin(),
                                                  saved.state.active.end())},
                             dof_handler.n_dofs());
    std::vector<double>       slip;
    const std::vector<double> depth =
      interval_wear_depth(records[step],
                          records[(step + 1) % n_steps],
                          1e-3 * parameters.wear.wear_coefficient,
                          &slip);
    std::vector<double> depth_pm(depth.size());
    for (unsigned int j = 0; j < depth.size(); ++j)
      depth_pm[j] = 1e9 * depth[j];
    const Vector<double> interval =
      Output::surface_fields(*slave,
                             {slip, depth_pm, {}},
                             dof_handler.n_dofs());
    Vector<double>                       motion_field(dof_handler.n_dofs());
    std::vector<types::global_dof_index> dofs(3);
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        for (const auto v : cell->vertex_indices())
          {
            Tensor<1, 3> u;
            for (unsigned int c = 0; c < 3; ++c)
              {
                dofs[c] = cell->vertex_dof_index(v, c);
                u[c]    = saved.solution[dofs[c]];
              }
            const Point<3>    &X = cell->vertex(v);
            const Tensor<1, 3> d =
              cell->material_id() == Mesh::MaterialIds::femur ?
                Tensor<1, 3>(motion(X) + motion.rotation * u - X) :
                u;
            for (unsigned int c = 0; c < 3; ++c)
              motion_field(dofs[c]) = d[c];
          }
    Output::write_solution(
      elasticity,
      mapping,
      *step_series,
      step,
      step,
      [&](DataOut<3> &data_out) {
        data_out.add_data_vector(contact,
                                 std::vector<std::string>{"contact_pressure",
                                                          "gap",
                                                          "active"},
                                 DataOut<3>::type_dof_data);
        data_out.add_data_vector(interval,
                                 std::vector<std::string>{"slip_to_next_mm",
                                                          "wear_to_next_pm",
                                                          "unused"},
                                 DataOut<3>::type_dof_data);
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
  WearProblem::output_results()
  {
    TimerOutput::Scope scope(timer, "output");
    for (const auto &saved : saved_steps)
      output_step(saved.first);
    if (Utilities::MPI::this_mpi_process(world) == 0)
      {
        std::ofstream csv(parameters.output.directory + "/steps.csv");
        csv << "step,percent,flexion_deg,axial_force_N,ap_force_N,"
               "ie_torque_Nm,active_nodes,newton_iterations,max_pressure_MPa,"
               "contact_force_N,contact_area_mm2,converged,ap_position_mm,"
               "ie_rotation_deg\n";
        for (unsigned int i = 0; i < n_steps; ++i)
          {
            const StepReport &r = reports[i];
            csv << i << ',' << r.percent << ',' << r.flexion << ','
                << r.axial_force << ',' << r.ap_force << ',' << r.ie_torque
                << ',' << r.active_nodes << ',' << r.newton_iterations << ','
                << r.max_pressure << ',' << r.contact_force << ','
                << r.contact_area << ',' << r.converged << ','
                << r.tibia_pose[1] << ',' << r.ie_rotation << '\n';
          }
        std::ofstream history(parameters.output.directory +
                              "/wear_history.csv");
        history << "cycles,volume_mm3,mass_mg,max_depth_mm\n"
                << "1," << worn_volume(wear_depth, *coupling) << ','
                << parameters.materials.tibia.density *
                     worn_volume(wear_depth, *coupling)
                << ','
                << *std::max_element(wear_depth.begin(), wear_depth.end())
                << '\n';
      }
    if (parameters.output.vtu_interval == 0 || groups.index != 0)
      return;
    // The wear of the cycle on the tibia (group 0 writes it).
    std::vector<double> depth_nm(wear_depth.size());
    for (unsigned int j = 0; j < wear_depth.size(); ++j)
      depth_nm[j] = 1e6 * wear_depth[j];
    const Vector<double> wear =
      Output::surface_fields(*slave,
                             {depth_nm, slip, {}},
                             elasticity.get_dof_handler().n_dofs());
    Output::VtuSeries series(parameters.output.directory,
                             "wear",
                             groups.communicator);
    Output::write_solution(elasticity,
                           mapping,
                           series,
                           0,
                           0.,
                           [&](DataOut<3> &data_out) {
                             data_out.add_data_vector(
                               wear,
                               std::vector<std::string>{"wear_depth_nm",
                                                        "slip_mm",
                                                        "unused"},
                               DataOut<3>::type_dof_data);
                           });
  }
} // namespace TKR::Wear
