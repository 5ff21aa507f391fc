// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <deal.II/base/function.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/timer.h>

#include <deal.II/numerics/vector_tools.h>

#include <tkr/base/exceptions.h>
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

    const unsigned int n_steps = gait.steps_per_cycle;
    records.assign(n_steps, Wear::StepRecord());
    reports.assign(n_steps, Gait::StepReport());
    starts.assign(n_steps, Gait::StepStart());
    setup_solver();
    // The pose is solved with the contact where the protocol names its
    // unknowns and the solver has the columns (doc/gait.md).
    pose_equations = protocol->pose_equations();
    if (!gait.coupled_pose || !solver->can_solve_pose())
      pose_equations.unknowns.clear();
    if (parameters.output.vtu_interval > 0)
      step_series =
        std::make_unique<Output::VtuSeries>(parameters.output.directory,
                                            name.empty() ? "step" :
                                                           "step_" + name,
                                            groups.communicator,
                                            model.world());
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
                        StepProgress          &progress) const
  {
    const auto &parameters = model.parameters();
    progress.window.width  = parameters.contact_solver.coupling_window;
    if (parameters.wear.warm_start)
      progress.window.face_clearance = starts[step].face_clearance;
    progress.use_window =
      progress.window.width > 0 && !progress.window.face_clearance.empty();
    if (parameters.wear.warm_start && !starts[step].empty())
      {
        progress.state.active = starts[step].active;
        return starts[step].predicted_pose();
      }
    const double lift = touching_lift(
      step_positions(protocol->motion(input, protocol->rest_pose(input, 0.))));
    if (lift > 0.5 * parameters.contact_solver.search_distance &&
        lift < std::numeric_limits<double>::max())
      return protocol->rest_pose(input, lift);
    return protocol->rest_pose(input, 0.);
  }

  // A solve that leaves the coupling window is repeated on the whole
  // search distance.
  bool
  GaitCycle::contact_solve(const unsigned int     step,
                           const Gait::StepInput &input,
                           const Gait::Pose      &pose,
                           StepProgress          &progress)
  {
    const auto                &parameters = model.parameters();
    const Gait::RelativeMotion motion     = protocol->motion(input, pose);
    bool                       narrow     = progress.use_window;
    couple(motion, narrow ? &progress.window : nullptr);
    if (narrow && model.coupling().statistics().n_covered_nodes == 0)
      {
        narrow = false;
        couple(motion, nullptr);
      }
    check_coupling(step, progress);
    ++progress.n_solves;
    const std::vector<double> coefficients =
      protocol->load_coefficients(input, pose);
    const auto solve = [&]() {
      progress.statistics =
        solver->solve(model.mapping(),
                      coefficients,
                      parameters.contact_solver.initial_contact_distance,
                      progress.state);
      progress.newton_iterations += progress.statistics.newton_iterations;
    };
    solve();
    auto &state = progress.state;
    if (narrow && !model.coupling().window_holds(state.displacement,
                                                 state.master_displacement))
      {
        ++window_misses;
        couple(motion, nullptr);
        solve();
      }
    finish_solve(progress);
    return progress.statistics.converged;
  }

  void
  GaitCycle::check_coupling(const unsigned int  step,
                            const StepProgress &progress) const
  {
    AssertThrow(model.coupling().statistics().n_covered_nodes > 0,
                ExcInputError("Gait step " + std::to_string(step) +
                              ": no part of tibia_contact faces "
                              "femur_contact within the search "
                              "distance; check the flexion axis point."));
    if (check_overlap && step == 0 && progress.n_solves == 0)
      check_initial_overlap();
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
    Gait::Pose            pose = start_step(step, input, progress);
    const Gait::PoseSolve pose_solve =
      !pose_equations.unknowns.empty() ?
        coupled_pose_solve(step, input, pose, progress) :
        protocol->solve_pose(input,
                             pose,
                             [&](const Gait::Pose   &at,
                                 Gait::Observations &observed) {
                               const bool converged =
                                 contact_solve(step, input, at, progress);
                               observed = progress.observations;
                               return converged;
                             });

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
    report.max_pressure      = stats.max_pressure;
    report.contact_force     = stats.contact_force.norm();
    report.contact_resultant = stats.contact_force;
    report.contact_moment    = stats.contact_moment;
    report.contact_area      = stats.contact_area;
    report.converged         = stats.converged && pose_solve.converged;
    report.pose_converged    = pose_solve.converged;
    report.pose_residual     = pose_solve.residual;
    report.pose_fallbacks    = pose_solve.n_fallbacks;
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
    check_overlap = initial_geometry;
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
    for (const std::string &message :
         Utilities::MPI::all_gather(model.world(), error))
      AssertThrow(message.empty(), ExcInputError(message));
    signal = Utilities::MPI::max(signal, model.world());
    AssertThrow(signal == 0, ExcStopped(signal_name(signal)));
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

  namespace
  {
    /** A step's record, report and end state, for the exchange. */
    struct StepResult
    {
      unsigned int     step = 0;
      Wear::StepRecord record;
      Gait::StepReport report;
      Gait::StepStart  start;

      template <class Archive>
      void
      serialize(Archive &archive, const unsigned int)
      {
        archive &step &record &report &start;
      }
    };
  } // namespace

  // Each step's results are taken from the one rank that lists it (the
  // root of the step group that solved it; the others list none).
  void
  GaitCycle::gather_steps(const std::vector<unsigned int> &own_steps)
  {
    std::vector<StepResult> mine;
    for (const unsigned int step : own_steps)
      mine.push_back({step, records[step], reports[step], starts[step]});
    for (const auto &from_rank : all_gather_objects(model.world(), mine))
      for (const auto &result : from_rank)
        {
          records[result.step] = result.record;
          reports[result.step] = result.report;
          starts[result.step]  = result.start;
        }
  }

  unsigned int
  GaitCycle::peak_load_step() const
  {
    const auto columns = protocol->input_columns();
    const auto axial =
      std::find(columns.begin(), columns.end(), "axial_force_N");
    const auto load = [&](const Gait::StepReport &report) {
      return axial != columns.end() ?
               report.input.values[axial - columns.begin()] :
               report.contact_force;
    };
    return std::max_element(reports.begin(),
                            reports.end(),
                            [&](const auto &a, const auto &b) {
                              return load(a) < load(b);
                            }) -
           reports.begin();
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
