// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <deal.II/base/function.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/timer.h>

#include <deal.II/numerics/vector_tools.h>

#include <tkr/base/exceptions.h>
#include <tkr/gait/condyle_arcs.h>
#include <tkr/mesh/mesh.h>
#include <tkr/output/wear_output.h>
#include <tkr/problems/gait_cycle.h>

#include <algorithm>
#include <iomanip>
#include <limits>

namespace TKR::Problems
{
  using namespace dealii;

  GaitCycle::GaitCycle(TwoBodyModel           &model,
                       const StepGroups       &groups,
                       const Parameters::Gait &gait,
                       const std::string      &name)
    : model(model)
    , groups(groups)
    , gait(gait)
    , name(name)
  {}

  void
  GaitCycle::setup(const bool report_model)
  {
    const auto &parameters = model.parameters();
    const auto &pcout      = model.pcout();
    protocol               = Gait::create_protocol(gait, model.triangulation());
    const std::string &file = protocol->waveform().file();
    if (!name.empty())
      pcout << "Activity " << name << ": ";
    pcout << "Waveform <"
          << (parameters.output.testing ? file.substr(file.rfind('/') + 1) :
                                          file)
          << ">: " << protocol->waveform().n_rows() << " rows, "
          << protocol->description() << std::endl
          << protocol->setup_text() << std::endl;

    const auto &dof_handler = model.elasticity().get_dof_handler();
    if (report_model)
      pcout << "Degrees of freedom: " << dof_handler.n_dofs()
            << ", MPI ranks: " << Utilities::MPI::n_mpi_processes(model.world())
            << " in " << groups.n_groups << " step group(s)" << std::endl;
    is_femur_vertex =
      Mesh::material_vertices(model.triangulation(), Mesh::MaterialIds::femur);

    // The femur is clamped on its fixation surface (in its co-rotated
    // frame); the tibia's support is the protocol's.
    dirichlet.clear();
    VectorTools::interpolate_boundary_values(model.mapping(),
                                             dof_handler,
                                             Mesh::BoundaryIds::femur_fixation,
                                             Functions::ZeroFunction<3>(3),
                                             dirichlet);
    protocol->add_constraints(dof_handler, dirichlet, pcout);
    dirichlet.close();

    model.setup_contact_surfaces();
    if (report_model)
      check_flexion_axis();

    const unsigned int n_steps = gait.steps_per_cycle;
    records.assign(n_steps, Wear::StepRecord());
    reports.assign(n_steps, Gait::StepReport());
    starts.assign(n_steps, Gait::StepStart());
    setup_solver();
    pose_equations = protocol->pose_equations();
    if (parameters.output.vtu_interval > 0)
      step_series =
        std::make_unique<Output::VtuSeries>(parameters.output.directory,
                                            name.empty() ? "step" :
                                                           "step_" + name,
                                            groups.communicator,
                                            model.world());
  }

  // The flexion axis should be the centre of both condyles' distal arcs;
  // said on the screen where it is far from one (doc/gait.md).
  void
  GaitCycle::check_flexion_axis() const
  {
    const std::vector<Point<3>> positions = model.geometry().vertex_positions();
    std::vector<Point<3>>       femur;
    for (const auto &node : model.master_surface().nodes())
      femur.push_back(positions[node.vertex]);
    const std::string warning =
      Gait::flexion_axis_warning(Gait::distal_arcs(femur),
                                 gait.flexion_axis_point,
                                 flexion_axis_limit);
    if (!warning.empty())
      model.pcout() << warning << std::endl;
  }

  // The stiffness (with the springs) is the same in every step and pose
  // update; what the pose solve reads of the displacement are linear
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
                  protocol->springs());
    observation_names.clear();
    for (const auto &[name, functional] : protocol->observations())
      {
        solver->add_observation(model.elasticity().load_vector(model.mapping(),
                                                               dirichlet,
                                                               functional));
        observation_names.push_back(name);
      }
    solver->set_load_basis(model.mapping(), protocol->load_basis());
    solver->prefetch(groups.peers);
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
  GaitCycle::step_positions(const Gait::RelativeMotion &motion) const
  {
    std::vector<Point<3>> positions = model.geometry().vertex_positions();
    for (unsigned int v = 0; v < positions.size(); ++v)
      if (is_femur_vertex[v])
        positions[v] = motion(positions[v]);
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

  // The first cycle's solves (or the first after a checkpoint's resume)
  // have nothing before them to say which compliance columns they will
  // need, and the step groups solve interleaved steps: each group would
  // compute nearly all of them itself (98 % of the same nodes on the
  // medium mesh). So each group couples its steps where they will start
  // (rest, lifted to touch as start_step() does, or a checkpoint's warm
  // start) and notes the nodes within expected_clearance of the femur
  // there: solve()'s prefetch() computes their columns in full batches,
  // each group a share, and the steps compute only what that missed.
  // (1 mm: on the medium mesh 2,222 nodes noted for the 1,780 the first
  // cycle used, 80-90 missed per group; 0.5 mm missed 280.) The results
  // do not depend on it but in round-off: a column solved in a batch of
  // another size differs in its last bits.
  void
  GaitCycle::expect_contact()
  {
    constexpr double expected_clearance = 1.;
    const auto      &parameters         = model.parameters();
    for (const unsigned int step : groups.own_items(n_steps()))
      {
        const Gait::StepInput input = protocol->input(100. * step / n_steps());
        const Gait::Pose      pose =
          parameters.wear.warm_start && !starts[step].empty() ?
                 starts[step].predicted_pose() :
                 protocol->rest_pose(input, cold_lift(input));
        const Gait::RelativeMotion motion = protocol->motion(input, pose);
        {
          TimerOutput::Scope scope(model.timer(), "mortar coupling");
          model.coupling().reinit(step_positions(motion),
                                  expected_clearance,
                                  motion.rotation(),
                                  nullptr);
        }
        std::vector<unsigned int> near;
        const auto               &nodes = model.coupling().slave_nodes();
        for (unsigned int j = 0; j < nodes.size(); ++j)
          if (nodes[j].covered &&
              nodes[j].weighted_gap <= expected_clearance * nodes[j].D)
            near.push_back(j);
        solver->expect(near);
      }
  }

  // A cold step starts from rest, or lifted to touch if the femur is
  // higher than half the search distance (touching_lift()).
  double
  GaitCycle::cold_lift(const Gait::StepInput &input) const
  {
    const double lift = touching_lift(
      step_positions(protocol->motion(input, protocol->rest_pose(input, 0.))));
    return lift > 0.5 * model.parameters().contact_solver.search_distance &&
               lift < std::numeric_limits<double>::max() ?
             lift :
             0.;
  }

  // The facets of the meshes (a CAD export's chords, the straight sides of
  // split cells) may leave the bodies overlapping slightly in the initial
  // geometry. Both protocols leave the tray's axial position free, so such
  // an overlap is not an error: the first step starts from the tray
  // lowered by it, and the solve finds the equilibrium from there. An
  // overlap larger than `Gait/Largest initial overlap` is more than facets
  // explain (a misplaced body, a wrong flexion axis or unit) and is refused
  // with where it is.
  double
  GaitCycle::take_up_initial_overlap(const Gait::StepInput &input,
                                     const Gait::Pose      &pose)
  {
    couple(protocol->motion(input, pose), nullptr);
    if (model.coupling().statistics().n_covered_nodes == 0)
      return 0; // (the step's first solve says so)
    const auto [min_gap, closest] = Contact::smallest_gap(model.coupling());
    if (min_gap >= 0)
      return 0;
    const Point<3> where =
      model.geometry()
        .vertex_positions()[model.slave_surface().nodes()[closest].vertex];
    AssertThrow(-min_gap <= gait.largest_initial_overlap,
                ExcInputError(
                  "At 0 % of the cycle the femur penetrates the insert by " +
                  format_number(-min_gap) + " mm at (" +
                  format_number(where[0]) + ", " + format_number(where[1]) +
                  ", " + format_number(where[2]) +
                  "), more than the Largest initial overlap of " +
                  format_number(gait.largest_initial_overlap) +
                  " mm that faceted surfaces explain: the bodies are "
                  "misplaced. Move the femur up by the overlap "
                  "(scripts/mesh-implant places it on the final meshes), "
                  "or check the mesh's units and the Flexion axis point."));
    initial_overlap = -min_gap;
    return -min_gap;
  }

  void
  GaitCycle::couple(const Gait::RelativeMotion   &motion,
                    const Mortar::CouplingWindow *window)
  {
    TimerOutput::Scope scope(model.timer(), "mortar coupling");
    model.coupling().reinit(step_positions(motion),
                            model.parameters().contact_solver.search_distance,
                            motion.rotation(),
                            window);
  }

  // A warm start from where the step ended in the previous block (moved on
  // by its change over the block before: StepStart::predicted_pose()), or rest
  // (the tibia lifted to touch the femur if that is far from it). The
  // coupling window (Mortar::CouplingWindow) follows the face clearances
  // of the step's previous solve, if the step is warm started: a cold
  // step's first solves are too far from its end for a narrow window.
  Gait::Pose
  GaitCycle::start_step(const unsigned int     step,
                        const Gait::StepInput &input,
                        StepProgress          &progress)
  {
    const auto &parameters       = model.parameters();
    progress.window.width        = parameters.contact_solver.coupling_window;
    const Gait::StepStart &start = cycle_starts[step];
    if (parameters.wear.warm_start)
      progress.window.face_clearance = start.face_clearance;
    progress.use_window =
      progress.window.width > 0 && !progress.window.face_clearance.empty();
    if (parameters.wear.warm_start && !start.empty())
      {
        progress.state.active = start.active;
        return start.predicted_pose();
      }
    double lift = cold_lift(input);
    if (check_overlap && step == 0)
      lift -= take_up_initial_overlap(input, protocol->rest_pose(input, lift));
    return protocol->rest_pose(input, lift);
  }

  void
  GaitCycle::check_coupling(const unsigned int step) const
  {
    AssertThrow(model.coupling().statistics().n_covered_nodes > 0,
                ExcInputError("Gait step " + std::to_string(step) +
                              ": no part of tibia_contact faces "
                              "femur_contact within the search "
                              "distance; check the flexion axis point."));
  }

  void
  GaitCycle::finish_solve(StepProgress &progress) const
  {
    const auto &state = progress.state;
    if (progress.window.width > 0)
      progress.window.face_clearance =
        model.coupling().face_clearances(state.displacement,
                                         state.master_displacement);
    std::vector<double> values;
    for (unsigned int i = 0; i < observation_names.size(); ++i)
      values.push_back(solver->observation(i));
    progress.observations = Gait::Observations(observation_names, values);
  }

  // One gait step: the protocol's pose solve, each of its contact solves a
  // mortar coupling on the moved geometry and a solve; then the record
  // for the wear and the report. Every step starts from the same state
  // (start_step()), whichever steps its group solved before: the result
  // then does not depend on how the steps are distributed.
  void
  GaitCycle::solve_step(const unsigned int step,
                        const bool         print,
                        const bool         keep_for_output)
  {
    const auto           &parameters = model.parameters();
    Timer                 step_timer;
    const Gait::StepInput input = protocol->input(100. * step / n_steps());
    StepProgress          progress;
    Gait::Pose            pose       = start_step(step, input, progress);
    Gait::PoseSolve       pose_solve = solve_pose(step, input, pose, progress);
    if (!pose_solve.converged)
      pose_solve = cut_back(step, input, pose_solve, pose, progress);

    const Gait::RelativeMotion motion = protocol->motion(input, pose);
    const auto                &state  = progress.state;
    const auto                &stats  = progress.statistics;
    records[step] = Wear::make_step_record(model.coupling(), state, motion);
    Gait::StepReport &report = reports[step];
    report                   = Gait::StepReport();
    report.input             = input;
    report.active_nodes      = stats.n_active;
    report.newton_iterations = progress.newton_iterations;
    report.pose_updates      = pose_solve.n_updates;
    report.contact_solves    = progress.n_solves;
    report.max_pressure      = stats.max_pressure;
    report.contact_force     = stats.contact_force.norm();
    report.contact_resultant = stats.contact_force;
    report.contact_moment    = stats.contact_moment;
    report.contact_area      = stats.contact_area;
    report.converged         = stats.converged && pose_solve.converged;
    report.pose_converged    = pose_solve.converged;
    report.pose_residual     = pose_solve.residual;
    report.pose_fallbacks    = pose_solve.n_fallbacks;
    report.sub_steps         = pose_solve.n_sub_steps;
    report.contact_converged = stats.converged;
    report.wall_time         = step_timer.wall_time();
    protocol->report(pose, progress.observations, report);
    Gait::StepStart &start = starts[step];
    start.previous         = std::move(start.pose);
    start.pose             = progress.refined.empty() ? pose : progress.refined;
    start.active           = state.active;
    start.face_clearance   = progress.window.face_clearance;
    if (groups.n_groups == 1 && (print || !report.converged))
      model.pcout() << Output::step_line(step,
                                         report,
                                         *protocol,
                                         parameters.output.testing)
                    << std::endl;
    // The step's VTU needs the slip to the next step: it is written after
    // the cycle (output_steps()).
    if (keep_for_output && parameters.output.vtu_interval > 0 &&
        step % parameters.output.vtu_interval == 0)
      saved_steps[step] = {solver->compute_solution(), state, motion};
  }

  // A step's pose may fail to converge from its start: a cold start far
  // from the equilibrium, an active set that changes by much between the
  // start and the end (swing to stance, the femur onto a rim). The
  // elastic frictionless contact has one solution whatever the path, so
  // the step is approached along the cycle from the instant before,
  // through the inputs in between, each sub-step starting where the one
  // before ended (close to its solution: one or two Newton steps). Every
  // solve is counted in the step's report (its pose updates); the step's
  // result is the last sub-step's, which is the step itself.
  Gait::PoseSolve
  GaitCycle::cut_back(const unsigned int     step,
                      const Gait::StepInput &input,
                      const Gait::PoseSolve &failed,
                      Gait::Pose            &pose,
                      StepProgress          &progress)
  {
    const unsigned int n        = n_steps();
    const unsigned int previous = (step + n - 1) % n;
    // (the instant before step 0 is the cycle's last step, one step early)
    const double          from  = 100. * (double(step) - 1.) / n;
    const double          to    = input.percent;
    Gait::PoseSolve       total = failed;
    StepProgress          at_progress;
    const Gait::StepInput at_input = protocol->input(from);
    Gait::Pose            at_pose = start_step(previous, at_input, at_progress);
    const auto            add     = [&](const Gait::PoseSolve &solve) {
      total.n_updates += solve.n_updates + 1;
      total.n_fallbacks += solve.n_fallbacks;
    };
    Gait::PoseSolve solve =
      solve_pose(previous, at_input, at_pose, at_progress);
    add(solve);
    double done = 0, size = 0.5;
    while (solve.converged && done < 1.)
      {
        const double    next       = std::min(1., done + size);
        StepProgress    trial      = at_progress;
        Gait::Pose      trial_pose = at_pose;
        Gait::StepInput trial_input =
          next < 1. ? protocol->input(from + next * (to - from)) : input;
        trial.n_solves = trial.newton_iterations = 0;
        trial.refined                            = Gait::Pose();
        solve = solve_pose(step, trial_input, trial_pose, trial);
        add(solve);
        if (solve.converged)
          {
            ++total.n_sub_steps;
            trial.n_solves += at_progress.n_solves;
            trial.newton_iterations += at_progress.newton_iterations;
            done        = next;
            at_progress = std::move(trial);
            at_pose     = std::move(trial_pose);
            size        = std::min(2. * size, 0.5);
          }
        else if (size > smallest_sub_step)
          {
            at_progress.n_solves += trial.n_solves;
            at_progress.newton_iterations += trial.newton_iterations;
            size /= 2;
            solve.converged = true; // (try the smaller sub-step)
          }
      }
    if (!solve.converged || done < 1.)
      {
        total.converged   = false;
        total.n_sub_steps = 0;
        return total;
      }
    at_progress.n_solves += progress.n_solves;
    at_progress.newton_iterations += progress.newton_iterations;
    progress        = std::move(at_progress);
    pose            = std::move(at_pose);
    total.converged = true;
    total.residual  = solve.residual;
    return total;
  }

  // A step may raise an input error (e.g. no contact within the search
  // distance) in its step group only: the groups agree on it before the
  // next collective operation, so that every rank stops with the message
  // instead of some waiting forever for the others.
  bool
  GaitCycle::solve(const bool print_steps,
                   const bool keep_for_output,
                   const bool initial_geometry)
  {
    const std::vector<unsigned int> steps = groups.own_items(n_steps());
    saved_steps.clear();
    check_overlap   = initial_geometry;
    initial_overlap = 0;
    cycle_starts    = starts;
    solver->new_cycle();
    // (decided alike on every rank: prefetch() is collective)
    if (groups.n_groups > 1 &&
        Utilities::MPI::max(solver->wants_expectations() ? 1 : 0,
                            model.world()) == 1)
      {
        expect_contact();
        solver->prefetch(groups.peers);
      }
    std::string error;
    int         signal = 0;
    try
      {
        // A stop signal ends the cycle between steps (every rank of a
        // group at the same step: the check is collective in the group).
        for (const unsigned int step : steps)
          if ((signal = stop_requested(groups.communicator)) == 0)
            solve_step(step, print_steps, keep_for_output);
          else
            break;
      }
    catch (const ExcInputError &exc)
      {
        error = exception_message(exc);
      }
    {
      // (where the step group that finished first waits for the others)
      TimerOutput::Scope scope(model.timer(), "step groups' wait");
      for (const std::string &message :
           Utilities::MPI::all_gather(model.world(), error))
        AssertThrow(message.empty(), ExcInputError(message));
    }
    signal = Utilities::MPI::max(signal, model.world());
    AssertThrow(signal == 0, ExcStopped(signal_name(signal)));
    initial_overlap = Utilities::MPI::max(initial_overlap, model.world());
    if (initial_overlap > 0)
      model.pcout() << (name.empty() ? "" : "Activity " + name + ": ")
                    << "At 0 % of the cycle the femur overlaps the insert by "
                    << format_number(initial_overlap)
                    << " mm (the meshes' facets): step 0 started from the "
                       "tray lowered by it."
                    << std::endl;
    {
      TimerOutput::Scope scope(model.timer(), "collect steps");
      gather_steps(groups.is_group_root ? steps : std::vector<unsigned int>());
    }
    bool converged = true;
    for (unsigned int step = 0; step < n_steps(); ++step)
      {
        if (groups.n_groups > 1 && (print_steps || !reports[step].converged))
          model.pcout() << Output::step_line(step,
                                             reports[step],
                                             *protocol,
                                             model.parameters().output.testing)
                        << std::endl;
        converged = converged && reports[step].converged;
      }
    return converged;
  }

  // The slip and wear of each tibia node over the interval to the next
  // step come from the wear law's result for the cycle: the VTU files are
  // written after it.
  void
  GaitCycle::output_steps(const Wear::CycleWear &wear)
  {
    TimerOutput::Scope scope(model.timer(), "output");
    for (const auto &[step, saved] : saved_steps)
      {
        Output::StepFields fields;
        fields.slave_surface = &model.slave_surface();
        fields.state         = &saved.state;
        fields.femur_motion  = saved.motion.femur;
        fields.slip_to_next  = wear.interval_slip[step];
        fields.wear_to_next  = wear.interval_depth[step];
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
