// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <deal.II/base/function.h>
#include <deal.II/base/timer.h>

#include <deal.II/numerics/vector_tools.h>

#include <tkr/base/exceptions.h>
#include <tkr/mesh/mesh.h>
#include <tkr/output/wear_output.h>
#include <tkr/problems/gait_cycle.h>
#include <tkr/wear/archard.h>

#include <iomanip>
#include <limits>

namespace TKR::Problems
{
  using namespace dealii;

  GaitCycle::GaitCycle(TwoBodyModel &model, const StepGroups &groups)
    : model(model)
    , groups(groups)
  {}

  void
  GaitCycle::setup()
  {
    const auto &parameters = model.parameters();
    auto       &pcout      = model.pcout();
    waveform = std::make_unique<Gait::Waveform>(parameters.gait.waveform_file);
    const Gait::InferiorSurface surface =
      Gait::measure_inferior_surface(model.triangulation());
    gait_loads = std::make_unique<Gait::GaitLoads>(parameters.gait, surface);
    tibia_pose =
      std::make_unique<Gait::TibiaPose>(parameters.gait, *gait_loads);
    pcout << "Tibia inferior surface: " << surface.area
          << " mm^2, insert width " << surface.width << " mm" << std::endl;

    const auto &dof_handler = model.elasticity().get_dof_handler();
    pcout << "Degrees of freedom: " << dof_handler.n_dofs()
          << ", MPI ranks: " << Utilities::MPI::n_mpi_processes(model.world())
          << " in " << groups.n_groups << " step group(s)" << std::endl;
    is_femur_vertex =
      Mesh::material_vertices(model.triangulation(), Mesh::MaterialIds::femur);

    // The femur is clamped on its fixation surface (in its co-rotated
    // frame); the tibia has no displacement condition.
    dirichlet.clear();
    VectorTools::interpolate_boundary_values(model.mapping(),
                                             dof_handler,
                                             Mesh::BoundaryIds::femur_fixation,
                                             Functions::ZeroFunction<3>(3),
                                             dirichlet);
    if (parameters.gait.rigid_tray)
      {
        const unsigned int n_tied =
          tibia_pose->add_tray_constraints(dof_handler, dirichlet);
        pcout << "Tibial tray: rigid (no sagittal tilt), " << n_tied
              << " inferior nodes tied to 5 DoFs" << std::endl;
      }
    dirichlet.close();

    model.setup_contact_surfaces();

    const unsigned int n_steps = parameters.gait.steps_per_cycle;
    records.assign(n_steps, Wear::StepRecord());
    reports.assign(n_steps, Wear::StepReport());
    starts.assign(n_steps, Wear::StepStart());
    setup_solver();
    if (parameters.output.vtu_interval > 0)
      step_series =
        std::make_unique<Output::VtuSeries>(parameters.output.directory,
                                            "step",
                                            groups.communicator,
                                            model.world());
  }

  // The stiffness (with the springs) is the same in every step and pose
  // update; the rigid part of the tibia's motion is read through linear
  // functionals that every solve evaluates.
  void
  GaitCycle::setup_solver()
  {
    const auto &parameters = model.parameters();
    Timer       setup_timer;
    const bool  first = !solver;
    if (first)
      solver =
        Contact::create_contact_solver(parameters,
                                       model.elasticity(),
                                       model.coupling(),
                                       groups.communicator,
                                       ConditionalOStream(std::cout, false),
                                       model.timer());
    solver->setup(model.geometry().stiffness_mapping(),
                  dirichlet,
                  tibia_pose->springs());
    for (const auto &functional : tibia_pose->motion_functionals())
      solver->add_observation(
        model.elasticity().load_vector(model.mapping(), dirichlet, functional));
    solver->set_load_basis(model.mapping(), tibia_pose->load_basis());
    if (!first)
      return;
    model.pcout() << "Contact solver: " << solver->description();
    if (!parameters.output.testing)
      model.pcout() << ", set up in " << std::fixed << std::setprecision(1)
                    << setup_timer.wall_time() << " s" << std::defaultfloat
                    << std::setprecision(6);
    model.pcout() << std::endl;
  }

  std::vector<Point<3>>
  GaitCycle::step_positions(const Gait::RigidMotion &femur_motion,
                            const Tensor<1, 3>      &tibia_translation) const
  {
    std::vector<Point<3>> positions = model.geometry().vertex_positions();
    for (unsigned int v = 0; v < positions.size(); ++v)
      if (is_femur_vertex[v])
        positions[v] = femur_motion(positions[v]) - tibia_translation;
    return positions;
  }

  double
  GaitCycle::touching_lift(const std::vector<Point<3>> &positions) const
  {
    const double radius = model.parameters().contact_solver.search_distance;
    double       lift   = std::numeric_limits<double>::max();
    for (const auto &femur_node : model.master_surface().nodes())
      {
        const Point<3> &f       = positions[femur_node.vertex];
        double          nearest = radius * radius;
        double          height  = std::numeric_limits<double>::max();
        for (const auto &tibia_node : model.slave_surface().nodes())
          {
            const Point<3> &t = positions[tibia_node.vertex];
            const double    d =
              (f[0] - t[0]) * (f[0] - t[0]) + (f[1] - t[1]) * (f[1] - t[1]);
            if (d < nearest)
              {
                nearest = d;
                height  = f[2] - t[2];
              }
          }
        lift = std::min(lift, height);
      }
    return lift;
  }

  // The meshes' facets may leave the bodies overlapping slightly; more than
  // the overlap tolerance is a mesh (or flexion axis) error.
  void
  GaitCycle::check_initial_overlap() const
  {
    const double min_gap = Contact::smallest_gap(model.coupling()).first;
    AssertThrow(min_gap >= -model.parameters().contact_solver.overlap_tolerance,
                ExcInputError("At 0 % of the cycle the femur penetrates the "
                              "insert by " +
                              format_number(-min_gap) +
                              " mm, more than the Overlap tolerance. Check "
                              "the mesh and the flexion axis point."));
  }

  // One gait step: the femur's position for the flexion angle, then the
  // pose iteration, each iteration a mortar coupling on the moved geometry
  // and a contact solve. Every step starts from the same state (no pose,
  // the initial active set), whichever steps its group solved before: the
  // result then does not depend on how the steps are distributed.
  void
  GaitCycle::solve_step(const unsigned int step,
                        const bool         print,
                        const bool         keep_for_output)
  {
    const auto             &parameters = model.parameters();
    Timer                   step_timer;
    const Gait::GaitState   gait   = waveform->at(100. * step / n_steps());
    const Gait::RigidMotion motion = gait_loads->femur_motion(gait);

    // A warm start from where the step ended in the previous block, or
    // rest (the tibia lifted to touch the femur if that is far from it:
    // touching_lift()).
    Contact::ContactState state;
    Gait::PoseState       pose;
    if (parameters.wear.warm_start && !starts[step].active.empty())
      {
        state.active = starts[step].active;
        pose         = starts[step].pose;
      }
    else
      {
        const double lift = touching_lift(step_positions(motion, {}));
        if (lift > 0.5 * parameters.contact_solver.search_distance &&
            lift < std::numeric_limits<double>::max())
          pose.translation[2] = lift;
      }
    // The coupling window (Mortar::CouplingWindow) follows the face
    // clearances of the step's previous solve, if the step is warm started
    // (from the previous block): a cold step's first solves are too far
    // from its end for a narrow window. A solve that leaves it is repeated
    // on the whole search distance.
    Mortar::CouplingWindow window;
    window.width = parameters.contact_solver.coupling_window;
    if (parameters.wear.warm_start)
      window.face_clearance = starts[step].face_clearance;
    const bool use_window = window.width > 0 && !window.face_clearance.empty();
    const auto couple = [&](const Gait::PoseState &pose, const bool narrow) {
      TimerOutput::Scope scope(model.timer(), "mortar coupling");
      model.coupling().reinit(step_positions(motion, pose.translation),
                              parameters.contact_solver.search_distance,
                              motion.rotation,
                              narrow ? &window : nullptr);
    };
    Contact::ContactStatistics statistics;
    unsigned int               newton_iterations = 0, n_solves = 0;
    const auto                 solve = [&](const Gait::PoseState &pose,
                           Gait::InferiorMotion  &inferior) {
      bool narrow = use_window;
      couple(pose, narrow);
      if (narrow && model.coupling().statistics().n_covered_nodes == 0)
        {
          narrow = false;
          couple(pose, narrow);
        }
      AssertThrow(model.coupling().statistics().n_covered_nodes > 0,
                  ExcInputError("Gait step " + std::to_string(step) +
                                ": no part of tibia_contact faces "
                                                "femur_contact within the search "
                                                "distance; check the flexion axis point."));
      if (step == 0 && n_solves == 0)
        check_initial_overlap();
      ++n_solves;
      const auto contact_solve = [&]() {
        statistics =
          solver->solve(model.mapping(),
                        tibia_pose->load_coefficients(gait, pose),
                        parameters.contact_solver.initial_contact_distance,
                        state);
        newton_iterations += statistics.newton_iterations;
      };
      contact_solve();
      if (narrow && !model.coupling().window_holds(state.displacement,
                                                   state.master_displacement))
        {
          ++window_misses;
          couple(pose, false);
          contact_solve();
        }
      if (window.width > 0)
        window.face_clearance =
          model.coupling().face_clearances(state.displacement,
                                           state.master_displacement);
      inferior = Gait::TibiaPose::motion_from({{solver->observation(0),
                                                solver->observation(1),
                                                solver->observation(2),
                                                solver->observation(3)}});
      return statistics.converged;
    };
    const Gait::PoseIteration iteration = tibia_pose->iterate(pose, solve);

    records[step] =
      Wear::make_step_record(model.coupling(), state, motion, pose.translation);
    Wear::StepReport &report = reports[step];
    report.percent           = gait.percent;
    report.flexion           = gait.flexion;
    report.axial_force       = gait.axial_force;
    report.ap_force          = gait.ap_force;
    report.ie_torque         = gait.ie_torque;
    report.active_nodes      = statistics.n_active;
    report.newton_iterations = newton_iterations;
    report.pose_updates      = iteration.n_updates;
    report.tibia_pose        = pose.translation;
    report.ie_rotation       = iteration.motion.rotation_z;
    report.max_pressure      = statistics.max_pressure;
    report.contact_force     = statistics.contact_force.norm();
    report.contact_area      = statistics.contact_area;
    report.converged         = statistics.converged && iteration.converged;
    report.pose_converged    = iteration.converged;
    report.wall_time         = step_timer.wall_time();
    starts[step]             = {pose, state.active, window.face_clearance};
    if (groups.n_groups == 1 && (print || !report.converged))
      model.pcout() << Output::step_line(step,
                                         report,
                                         parameters.output.testing)
                    << std::endl;
    // The step's VTU needs the slip to the next step: it is written after
    // the cycle (output_steps()).
    if (keep_for_output && parameters.output.vtu_interval > 0 &&
        step % parameters.output.vtu_interval == 0)
      {
        saved_steps[step] = {solver->compute_solution(), state, motion};
      }
  }

  bool
  GaitCycle::solve(const bool print_steps, const bool keep_for_output)
  {
    const std::vector<unsigned int> steps = groups.own_items(n_steps());
    saved_steps.clear();
    for (const unsigned int step : steps)
      solve_step(step, print_steps, keep_for_output);
    {
      TimerOutput::Scope scope(model.timer(), "collect steps");
      Wear::gather_steps(groups.is_group_root ? steps :
                                                std::vector<unsigned int>(),
                         records,
                         reports,
                         starts,
                         model.world());
    }
    bool converged = true;
    for (unsigned int step = 0; step < n_steps(); ++step)
      {
        if (groups.n_groups > 1 && (print_steps || !reports[step].converged))
          model.pcout() << Output::step_line(step,
                                             reports[step],
                                             model.parameters().output.testing)
                        << std::endl;
        converged = converged && reports[step].converged;
      }
    return converged;
  }

  // The slip and wear of each tibia node over the interval to the next
  // step need both steps' records: the VTU files are written after the
  // cycle.
  void
  GaitCycle::output_steps()
  {
    TimerOutput::Scope scope(model.timer(), "output");
    const double       k = 1e-3 * model.parameters().wear.wear_coefficient;
    for (const auto &[step, saved] : saved_steps)
      {
        Output::StepFields fields;
        fields.slave_surface = &model.slave_surface();
        fields.state         = &saved.state;
        fields.femur_motion  = saved.motion;
        fields.wear_to_next =
          Wear::interval_wear_depth(records[step],
                                    records[(step + 1) % n_steps()],
                                    k,
                                    &fields.slip_to_next);
        for (double &depth : fields.wear_to_next)
          depth *= 1e9; // mm -> pm
        Output::write_step(model.elasticity(),
                           saved.solution,
                           model.mapping(),
                           fields,
                           *step_series,
                           step);
      }
    step_series->write_record();
  }
} // namespace TKR::Problems
