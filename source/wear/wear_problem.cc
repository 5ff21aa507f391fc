// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/base/timer.h>

#include <deal.II/fe/fe_values.h>

#include <deal.II/numerics/vector_tools.h>

#include <tkr/contact/condensed_solver.h>

#include <tkr/base/exceptions.h>
#include <tkr/base/mpi.h>
#include <tkr/mesh/mesh.h>
#include <tkr/output/solution_output.h>
#include <tkr/wear/wear_problem.h>

#include <fstream>
#include <iomanip>
#include <map>

namespace TKR::Wear
{
  using namespace dealii;

  StepGroups::StepGroups(const MPI_Comm world, const unsigned int requested)
  {
    const unsigned int n_ranks = Utilities::MPI::n_mpi_processes(world);
    const unsigned int rank    = Utilities::MPI::this_mpi_process(world);
    n_groups       = (requested == 0 ? n_ranks : std::min(requested, n_ranks));
    index          = rank * n_groups / n_ranks;
    const int ierr = MPI_Comm_split(world, index, rank, &communicator);
    AssertThrowMPI(ierr);
    is_group_root = Utilities::MPI::this_mpi_process(communicator) == 0;
  }

  StepGroups::~StepGroups()
  {
    MPI_Comm_free(&communicator);
  }

  WearProblem::WearProblem(const Parameters::AllParameters &parameters,
                           const MPI_Comm                   mpi_communicator)
    : parameters(parameters)
    , world(mpi_communicator)
    , groups(mpi_communicator, parameters.gait.step_groups)
    , pcout(std::cout, Utilities::MPI::this_mpi_process(world) == 0)
    , timer(pcout,
            parameters.output.testing ? TimerOutput::never :
                                        TimerOutput::summary,
            TimerOutput::wall_times)
    , triangulation(groups.communicator,
                    Triangulation<3>::none,
                    /*allow_artificial_cells=*/false,
                    parallel::shared::Triangulation<3>::partition_metis)
    , elasticity(triangulation,
                 parameters.materials,
                 parameters.linear_solver,
                 parameters.mesh.fe_degree,
                 groups.communicator,
                 timer)
    , n_steps(parameters.gait.steps_per_cycle)
  {}

  void
  WearProblem::make_grid()
  {
    TimerOutput::Scope scope(timer, "read mesh");
    Mesh::read_mesh(parameters.mesh, triangulation);
    Output::report_mesh(pcout,
                        summary,
                        Mesh::compute_statistics(triangulation),
                        parameters.mesh.file,
                        parameters.output.testing);
    is_femur_vertex.assign(triangulation.n_vertices(), false);
    for (const auto &cell : triangulation.active_cell_iterators())
      if (cell->material_id() == Mesh::MaterialIds::femur)
        for (const auto v : cell->vertex_indices())
          is_femur_vertex[cell->vertex_index(v)] = true;

    const Gait::InferiorSurface surface =
      Gait::measure_inferior_surface(triangulation);
    gait_loads = std::make_unique<Gait::GaitLoads>(parameters.gait, surface);
    pcout << "Tibia inferior surface: " << surface.area
          << " mm^2, insert width " << surface.width << " mm" << std::endl;
  }

  void
  WearProblem::setup_system()
  {
    waveform = std::make_unique<Gait::Waveform>(parameters.gait.waveform_file);
    elasticity.distribute_dofs();
    const auto &dof_handler = elasticity.get_dof_handler();
    pcout << "Degrees of freedom: " << dof_handler.n_dofs()
          << ", MPI ranks: " << Utilities::MPI::n_mpi_processes(world) << " in "
          << groups.n_groups << " step group(s)" << std::endl;
    summary.set("dofs", static_cast<unsigned long long>(dof_handler.n_dofs()));

    // The femur is clamped on its fixation surface (in its co-rotated
    // frame); the tibia has no displacement condition.
    dirichlet.clear();
    VectorTools::interpolate_boundary_values(mapping,
                                             dof_handler,
                                             Mesh::BoundaryIds::femur_fixation,
                                             Functions::ZeroFunction<3>(3),
                                             dirichlet);
    if (parameters.gait.rigid_tray)
      add_tray_constraints();
    dirichlet.close();

    slave = std::make_unique<Mortar::ContactSurface>(
      dof_handler,
      Mesh::BoundaryIds::tibia_contact);
    master = std::make_unique<Mortar::ContactSurface>(
      dof_handler,
      Mesh::BoundaryIds::femur_contact);
    coupling = std::make_unique<Mortar::MortarCoupling>(*slave, *master);
    const auto algorithm = parameters.contact_solver.algorithm;
    AssertThrow(algorithm != Parameters::ContactAlgorithm::ipopt,
                ExcInputError("Problem = wear cannot use Contact solver/"
                              "Solver = ipopt (a reference for single "
                              "contact solves); use auto, active set or "
                              "condensed active set."));
    if (algorithm == Parameters::ContactAlgorithm::active_set)
      {
        solver = std::make_unique<Contact::ActiveSetSolver>(
          elasticity,
          *coupling,
          parameters.contact_solver,
          parameters.materials.tibia.youngs_modulus,
          groups.communicator,
          ConditionalOStream(std::cout, false),
          timer,
          parameters.output.testing);
        pcout << "Contact solver: active set, AMG-preconditioned CG"
              << std::endl;
      }
    else
      {
        // The stiffness (with the springs) is the same in every step and
        // pose update: factorise it once.
        condensed = std::make_unique<Contact::CondensedActiveSetSolver>(
          elasticity,
          *coupling,
          parameters.contact_solver,
          parameters.materials.tibia.youngs_modulus,
          groups.communicator,
          ConditionalOStream(std::cout, false),
          timer);
        Timer factorisation_timer;
        condensed->factorize(mapping,
                             dirichlet,
                             step_loads(waveform->at(0.), Tensor<1, 3>()));
        // The rigid part of the tibia's motion (inferior_motion()) as
        // functionals that every solve evaluates: the work of unit
        // tractions (mean displacement) and of the torque traction
        // (best-fitting rotation about z, in degrees).
        const auto    &surface = gait_loads->inferior_surface();
        const Point<3> c       = surface.centroid;
        std::array<Elasticity::BoundaryLoads::TractionField, 4> tractions;
        for (unsigned int d = 0; d < 3; ++d)
          tractions[d] = [d, area = surface.area](const Point<3> &) {
            Tensor<1, 3> t;
            t[d] = 1. / area;
            return t;
          };
        tractions[3] = [c, J = surface.J](const Point<3> &x) {
          return Tensor<1, 3>({-(x[1] - c[1]) / J, (x[0] - c[0]) / J, 0.}) *
                 (180. / numbers::PI);
        };
        for (const auto &traction : tractions)
          {
            Elasticity::BoundaryLoads functional;
            functional.traction_fields[Mesh::BoundaryIds::tibia_inferior] =
              traction;
            elasticity.assemble_rhs(mapping, dirichlet, functional);
            condensed->add_observation(elasticity.get_system_rhs());
          }
        pcout << "Contact solver: condensed active set (sparse LU of the "
                 "stiffness";
        if (!parameters.output.testing)
          pcout << ", " << std::fixed << std::setprecision(1)
                << factorisation_timer.wall_time() << " s" << std::defaultfloat
                << std::setprecision(6);
        pcout << ")" << std::endl;
      }
    records.assign(n_steps, StepRecord());
    reports.assign(n_steps, StepReport());
    if (parameters.output.vtu_interval > 0)
      step_series =
        std::make_unique<Output::VtuSeries>(parameters.output.directory,
                                            "step",
                                            groups.communicator);
  }

  // The simulator holds the insert in a tray that translates (x, y, z),
  // rotates about z (IE) and ab/adducts (about y), but does not tilt in the
  // sagittal plane. The inferior surface (flat, z = z_A) then moves as
  //   u = u_A + theta_z e_z x (x - x_A) + theta_y e_y x (x - x_A),
  // with theta_z = -(u_Bx - u_Ax)/(y_B - y_A) and
  // theta_y = -(u_Cz - u_Az)/(x_C - x_A) from three anchor nodes: A near the
  // centroid, B far from it in y, C far from it in x. Every other node of
  // the surface gets three constraint lines on these five DoFs.
  void
  WearProblem::add_tray_constraints()
  {
    const auto &dof_handler = elasticity.get_dof_handler();
    std::map<unsigned int, std::array<types::global_dof_index, 3>> nodes;
    for (const auto &cell : dof_handler.active_cell_iterators())
      for (const auto f : cell->face_indices())
        if (cell->face(f)->at_boundary() &&
            cell->face(f)->boundary_id() == Mesh::BoundaryIds::tibia_inferior)
          for (const auto v : cell->face(f)->vertex_indices())
            {
              std::array<types::global_dof_index, 3> dofs;
              for (unsigned int c = 0; c < 3; ++c)
                dofs[c] = cell->face(f)->vertex_dof_index(v, c);
              nodes[cell->face(f)->vertex_index(v)] = dofs;
            }
    const auto    &vertices = triangulation.get_vertices();
    const Point<3> centroid = gait_loads->inferior_centroid();
    unsigned int   A        = nodes.begin()->first;
    for (const auto &[v, dofs] : nodes)
      if (vertices[v].distance(centroid) < vertices[A].distance(centroid))
        A = v;
    unsigned int B = A, C = A;
    for (const auto &[v, dofs] : nodes)
      {
        if (std::abs(vertices[v][1] - vertices[A][1]) >
            std::abs(vertices[B][1] - vertices[A][1]))
          B = v;
        if (std::abs(vertices[v][0] - vertices[A][0]) >
            std::abs(vertices[C][0] - vertices[A][0]))
          C = v;
      }
    const Point<3> &a    = vertices[A];
    const double    dy_B = vertices[B][1] - a[1], dx_C = vertices[C][0] - a[0];
    for (const auto &[v, dofs] : nodes)
      AssertThrow(std::abs(vertices[v][2] - a[2]) <
                    1e-6 * (std::abs(dy_B) + std::abs(dx_C)),
                  ExcInputError("Gait/Tibial tray = rigid needs a flat "
                                "tibia_inferior surface (z = const)."));
    const auto &dA = nodes[A], &dB = nodes[B], &dC = nodes[C];
    for (const auto &[v, dofs] : nodes)
      {
        if (v == A)
          continue;
        const double dx = vertices[v][0] - a[0], dy = vertices[v][1] - a[1];
        // u_x = u_Ax + (u_Bx - u_Ax) dy / dy_B
        if (v != B)
          {
            dirichlet.add_line(dofs[0]);
            dirichlet.add_entry(dofs[0], dA[0], 1. - dy / dy_B);
            dirichlet.add_entry(dofs[0], dB[0], dy / dy_B);
          }
        // u_y = u_Ay - (u_Bx - u_Ax) dx / dy_B
        dirichlet.add_line(dofs[1]);
        dirichlet.add_entry(dofs[1], dA[1], 1.);
        dirichlet.add_entry(dofs[1], dA[0], dx / dy_B);
        dirichlet.add_entry(dofs[1], dB[0], -dx / dy_B);
        // u_z = u_Az + (u_Cz - u_Az) dx / dx_C
        if (v != C)
          {
            dirichlet.add_line(dofs[2]);
            dirichlet.add_entry(dofs[2], dA[2], 1. - dx / dx_C);
            dirichlet.add_entry(dofs[2], dC[2], dx / dx_C);
          }
      }
    pcout << "Tibial tray: rigid (no sagittal tilt), " << nodes.size()
          << " inferior nodes tied to 5 DoFs" << std::endl;
  }

  // One gait step: the femur's position for the flexion angle, the mortar
  // coupling on that geometry, the loads of the step, and the contact
  // solve.
  //
  // Under load control the tibia moves by millimetres (AP and ML sliding in
  // the dishes, rising and sinking with the femur), which a small-
  // displacement contact model, linearised at the reference position,
  // cannot follow. So the tibia's reference position carries a rigid
  // translation (its pose): after a solve, the mean displacement of its
  // articular surface is added to the pose and the step is solved again on
  // the moved geometry, until that correction is below the pose tolerance.
  // The springs act on pose plus displacement.
  void
  WearProblem::solve_step(const unsigned int step)
  {
    Timer                 step_timer;
    const Gait::GaitState gait = waveform->at(100. * step / n_steps);
    const Tensor<2, 3>    R    = gait_loads->femur_rotation(gait);
    const Point<3>       &P    = parameters.gait.flexion_axis_point;
    const RigidMotion     motion{R, P - R * P};
    const auto           &nodes = coupling->slave_nodes();

    // Every step starts from the same state (no pose, the initial active
    // set), whichever steps its group solved before: the result then does
    // not depend on how the steps are distributed over step groups.
    state      = Contact::ContactState();
    tibia_pose = Tensor<1, 3>();

    Contact::ContactStatistics statistics;
    unsigned int               n_pose_updates = 0, newton_iterations = 0;
    bool                       pose_converged = false;
    double                     relaxation     = 1.;
    Tensor<1, 3>               previous_correction;
    InferiorMotion             tibia_motion;
    // The two-rate restraints' excess force and torque over their inner
    // rate (which K holds), iterated with the pose. Each update moves them
    // by the fraction k / k_beyond towards the value at the present
    // position: a fixed-point iteration whose contraction then holds even
    // without any help from the contact.
    const auto  &gait_parameters = parameters.gait;
    double       restraint_force = 0, restraint_torque = 0;
    const double force_damping = gait_parameters.ap_spring_stiffness /
                                 gait_parameters.ap_spring_stiffness_beyond;
    const double torque_damping = gait_parameters.ie_spring_stiffness /
                                  gait_parameters.ie_spring_stiffness_beyond;
    // The rotation tolerance: the pose tolerance at the insert's rim.
    const double rotation_tolerance =
      gait_parameters.pose_tolerance /
      (0.5 * gait_loads->inferior_surface().width) * 180. / numbers::PI;
    for (unsigned int pose_iteration = 0;; ++pose_iteration)
      {
        std::vector<Point<3>> positions = triangulation.get_vertices();
        for (unsigned int v = 0; v < positions.size(); ++v)
          positions[v] = is_femur_vertex[v] ? motion(positions[v]) :
                                              positions[v] + tibia_pose;
        {
          TimerOutput::Scope scope(timer, "mortar coupling");
          coupling->reinit(positions,
                           parameters.contact_solver.search_distance,
                           R);
        }
        AssertThrow(coupling->statistics().n_covered_nodes > 0,
                    ExcInputError("Gait step " + std::to_string(step) +
                                  ": no part of tibia_contact faces "
                                  "femur_contact within the search "
                                  "distance; check the flexion axis point."));
        if (step == 0 && pose_iteration == 0)
          check_initial_overlap();

        if (solver)
          solver->setup(dirichlet);
        if (state.active.size() != nodes.size())
          state = Contact::ContactState();
        const Elasticity::BoundaryLoads loads =
          step_loads(gait, tibia_pose, restraint_force, restraint_torque);
        const double initial_distance =
          parameters.contact_solver.initial_contact_distance;
        statistics =
          solver ? solver->solve(mapping, loads, initial_distance, state) :
                   condensed->solve(mapping, loads, initial_distance, state);
        newton_iterations += statistics.newton_iterations;

        // The rigid part of the tibia's displacement (on its inferior
        // surface) moves the pose; the restraints follow the position.
        if (condensed)
          {
            for (unsigned int d = 0; d < 3; ++d)
              tibia_motion.mean[d] = condensed->observation(d);
            tibia_motion.rotation_z = condensed->observation(3);
          }
        else
          tibia_motion = inferior_motion();
        const Tensor<1, 3> mean = tibia_motion.mean;
        const double       force_change =
          gait_loads->ap_restraint_excess(tibia_pose[1] + mean[1]) -
          restraint_force;
        const double torque_change =
          gait_loads->ie_restraint_excess(tibia_motion.rotation_z) -
          restraint_torque;
        pose_converged =
          mean.norm() <= gait_parameters.pose_tolerance &&
          std::abs(force_change) <= gait_parameters.ap_spring_stiffness_beyond *
                                      gait_parameters.pose_tolerance &&
          std::abs(torque_change) <=
            gait_parameters.ie_spring_stiffness_beyond * rotation_tolerance;
        if (!statistics.converged || pose_converged ||
            pose_iteration + 1 >= max_pose_iterations)
          break;
        restraint_force += force_damping * force_change;
        restraint_torque += torque_damping * torque_change;
        // A correction that reverses the previous one means the fixed-point
        // iteration overshoots: relax it.
        if (mean * previous_correction < 0)
          relaxation *= 0.5;
        previous_correction = relaxation * mean;
        tibia_pose += previous_correction;
        ++n_pose_updates;
      }

    // The record holds the tibia's full displacement (pose plus elastic).
    records[step] = make_step_record(*coupling, state, motion);
    for (auto &u : records[step].displacement)
      u += tibia_pose;
    StepReport &report       = reports[step];
    report.percent           = gait.percent;
    report.flexion           = gait.flexion;
    report.axial_force       = gait.axial_force;
    report.ap_force          = gait.ap_force;
    report.ie_torque         = gait.ie_torque;
    report.active_nodes      = statistics.n_active;
    report.newton_iterations = newton_iterations;
    report.pose_updates      = n_pose_updates;
    report.tibia_pose        = tibia_pose;
    report.ie_rotation       = tibia_motion.rotation_z;
    report.max_pressure      = statistics.max_pressure;
    report.contact_force     = statistics.contact_force.norm();
    report.contact_area      = statistics.contact_area;
    report.converged         = statistics.converged && pose_converged;
    report.pose_converged    = pose_converged;
    report.wall_time         = step_timer.wall_time();
    if (groups.n_groups == 1)
      print_step(step);
    // The step's VTU needs the slip to the next step: it is written after
    // the cycle (output_results()).
    if (parameters.output.vtu_interval > 0 &&
        step % parameters.output.vtu_interval == 0)
      {
        if (condensed)
          condensed->compute_solution();
        saved_steps[step] = {elasticity.get_solution(), state, motion};
      }
  }

  // The loads of a gait step on the tibia in its pose: the gait's
  // tractions, the restraint springs acting on pose plus displacement (the
  // pose part is a traction), and a stabilisation spring on the
  // displacement relative to the pose only, so that no linear system is
  // singular while the active set is still wrong; it vanishes as the pose
  // converges. The springs are the same in every step.
  Elasticity::BoundaryLoads
  WearProblem::step_loads(const Gait::GaitState &gait,
                          const Tensor<1, 3>    &pose,
                          const double           restraint_force,
                          const double           restraint_torque) const
  {
    Elasticity::BoundaryLoads loads = gait_loads->loads(gait);
    Tensor<2, 3>              axial_spring;
    axial_spring[2][2] =
      parameters.gait.axial_stabilisation_spring / gait_loads->inferior_area();
    const auto id        = Mesh::BoundaryIds::tibia_inferior;
    loads.springs[id]    = axial_spring;
    const auto springs   = loads.spring_fields.at(id);
    const auto tractions = loads.traction_fields.at(id);
    const auto restraint =
      gait_loads->restraint_traction(restraint_force, restraint_torque);
    loads.traction_fields[id] = [=](const Point<3> &x) {
      return tractions(x) - springs(x) * pose + restraint(x);
    };
    return loads;
  }

  // The rigid part of the tibia's displacement, measured on its inferior
  // surface (far from the contact's local deformation): the mean
  // displacement, and the rotation about z that fits it best,
  // theta = int (dx u_y - dy u_x) / int (dx^2 + dy^2) about the centroid.
  InferiorMotion
  WearProblem::inferior_motion() const
  {
    const auto                      &dof_handler = elasticity.get_dof_handler();
    FEFaceValues<3>                  fe_face_values(mapping,
                                   dof_handler.get_fe(),
                                   QGauss<2>(2),
                                   update_values | update_quadrature_points |
                                     update_JxW_values);
    std::vector<Tensor<1, 3>>        values(fe_face_values.n_quadrature_points);
    const FEValuesExtractors::Vector displacement(0);
    const Point<3>                  &c = gait_loads->inferior_centroid();
    // integral of u (3), of the rotation's numerator, and the area.
    std::vector<double> integrals(5, 0.);
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        for (const auto f : cell->face_indices())
          if (cell->face(f)->at_boundary() &&
              cell->face(f)->boundary_id() == Mesh::BoundaryIds::tibia_inferior)
            {
              fe_face_values.reinit(cell, f);
              fe_face_values[displacement]
                .get_function_values(elasticity.get_solution(), values);
              for (const unsigned int q :
                   fe_face_values.quadrature_point_indices())
                {
                  const double    JxW = fe_face_values.JxW(q);
                  const Point<3> &x   = fe_face_values.quadrature_point(q);
                  for (unsigned int d = 0; d < 3; ++d)
                    integrals[d] += values[q][d] * JxW;
                  integrals[3] += ((x[0] - c[0]) * values[q][1] -
                                   (x[1] - c[1]) * values[q][0]) *
                                  JxW;
                  integrals[4] += JxW;
                }
            }
    sum_over_ranks(integrals, groups.communicator);
    InferiorMotion motion;
    for (unsigned int d = 0; d < 3; ++d)
      motion.mean[d] = integrals[d] / integrals[4];
    motion.rotation_z =
      integrals[3] / gait_loads->inferior_surface().J * 180. / numbers::PI;
    return motion;
  }

  // The meshes' facets may leave the bodies overlapping slightly; more than
  // the overlap tolerance is a mesh (or flexion axis) error.
  void
  WearProblem::check_initial_overlap() const
  {
    double min_gap = std::numeric_limits<double>::max();
    for (const auto &node : coupling->slave_nodes())
      if (node.covered)
        min_gap = std::min(min_gap, node.weighted_gap / node.D);
    AssertThrow(min_gap >= -parameters.contact_solver.overlap_tolerance,
                ExcInputError("At 0 % of the cycle the femur penetrates the "
                              "insert by " +
                              format_number(-min_gap) +
                              " mm, more than the Overlap tolerance. Check "
                              "the mesh and the flexion axis point."));
  }

  void
  WearProblem::collect_steps()
  {
    TimerOutput::Scope  scope(timer, "collect steps");
    const unsigned int  n          = coupling->slave_nodes().size();
    const unsigned int  per_record = 12 + 10 * n;
    const unsigned int  per_report = 16;
    std::vector<double> data(n_steps * (per_record + per_report), 0.);
    for (unsigned int step = groups.index; step < n_steps;
         step += groups.n_groups)
      {
        if (!groups.is_group_root)
          break;
        double           *d = &data[step * (per_record + per_report)];
        const StepRecord &r = records[step];
        for (unsigned int a = 0; a < 3; ++a)
          {
            for (unsigned int b = 0; b < 3; ++b)
              *d++ = r.femur_motion.rotation[a][b];
            *d++ = r.femur_motion.translation[a];
          }
        for (unsigned int j = 0; j < n; ++j)
          {
            *d++ = r.pressure[j];
            for (unsigned int a = 0; a < 3; ++a)
              {
                *d++ = r.femur_point[j][a];
                *d++ = r.displacement[j][a];
                *d++ = r.normal[j][a];
              }
          }
        const StepReport &p = reports[step];
        for (const double value : {p.percent,
                                   p.flexion,
                                   p.axial_force,
                                   p.ap_force,
                                   p.ie_torque,
                                   double(p.active_nodes),
                                   double(p.newton_iterations),
                                   p.max_pressure,
                                   p.contact_force,
                                   p.contact_area,
                                   p.converged ? 1. : 0.,
                                   p.tibia_pose[0],
                                   p.tibia_pose[1],
                                   p.tibia_pose[2],
                                   p.ie_rotation,
                                   double(p.pose_updates)})
          *d++ = value;
      }
    sum_over_ranks(data, world);

    for (unsigned int step = 0; step < n_steps; ++step)
      {
        const double *d = &data[step * (per_record + per_report)];
        StepRecord    r;
        for (unsigned int a = 0; a < 3; ++a)
          {
            for (unsigned int b = 0; b < 3; ++b)
              r.femur_motion.rotation[a][b] = *d++;
            r.femur_motion.translation[a] = *d++;
          }
        r.pressure.resize(n);
        r.femur_point.resize(n);
        r.displacement.resize(n);
        r.normal.resize(n);
        for (unsigned int j = 0; j < n; ++j)
          {
            r.pressure[j] = *d++;
            for (unsigned int a = 0; a < 3; ++a)
              {
                r.femur_point[j][a]  = *d++;
                r.displacement[j][a] = *d++;
                r.normal[j][a]       = *d++;
              }
          }
        records[step]       = r;
        StepReport &p       = reports[step];
        p.percent           = d[0];
        p.flexion           = d[1];
        p.axial_force       = d[2];
        p.ap_force          = d[3];
        p.ie_torque         = d[4];
        p.active_nodes      = std::lround(d[5]);
        p.newton_iterations = std::lround(d[6]);
        p.max_pressure      = d[7];
        p.contact_force     = d[8];
        p.contact_area      = d[9];
        p.converged         = d[10] > 0.5;
        for (unsigned int a = 0; a < 3; ++a)
          p.tibia_pose[a] = d[11 + a];
        p.ie_rotation  = d[14];
        p.pose_updates = std::lround(d[15]);
      }
  }

  void
  WearProblem::compute_wear()
  {
    // k is given in mm^3/(N m); slips are in mm.
    wear_depth =
      cycle_wear_depth(records, 1e-3 * parameters.wear.wear_coefficient, &slip);
    const double volume    = worn_volume(wear_depth, *coupling);
    const double mass      = parameters.materials.tibia.density * volume;
    double       max_depth = 0, area = 0, worn_area = 0;
    // The wear area counts the nodes whose depth, extrapolated linearly to
    // the Cycles of the parameter file, exceeds the wear-area threshold.
    for (unsigned int j = 0; j < wear_depth.size(); ++j)
      {
        const double D = coupling->slave_nodes()[j].D;
        max_depth      = std::max(max_depth, wear_depth[j]);
        area += D;
        if (wear_depth[j] * parameters.wear.cycles >
            parameters.wear.wear_area_threshold)
          worn_area += D;
      }
    unsigned int n_iterations = 0, n_converged = 0;
    double       max_pressure = 0, max_area = 0;
    for (const auto &r : reports)
      {
        n_iterations += r.newton_iterations;
        n_converged += r.converged;
        max_pressure = std::max(max_pressure, r.max_pressure);
        max_area     = std::max(max_area, r.contact_area);
      }

    pcout << "Wear of one cycle (Archard, k = "
          << parameters.wear.wear_coefficient << " mm^3/(N m)):" << std::endl
          << "  volume loss:       " << volume << " mm^3" << std::endl
          << "  mass loss:         " << mass << " mg" << std::endl
          << "  max wear depth:    " << 1e6 * max_depth << " nm" << std::endl
          << "  peak pressure:     " << max_pressure << " MPa (over the cycle)"
          << std::endl
          << "  max contact area:  " << max_area << " mm^2" << std::endl
          << "  wear area:         " << 100. * worn_area / area
          << " % of tibia_contact (depth x " << parameters.wear.cycles
          << " cycles > " << parameters.wear.wear_area_threshold << " mm)"
          << std::endl
          << "  linear extrapolation to " << parameters.wear.cycles
          << " cycles without geometry update: "
          << mass * parameters.wear.cycles << " mg" << std::endl
          << "  contact solves: " << n_steps << ", converged: " << n_converged
          << ", mean Newton iterations: " << double(n_iterations) / n_steps
          << std::endl;

    summary.set("cycles", 1);
    summary.set("mass_loss_mg", mass);
    summary.set("volume_loss_mm3", volume);
    summary.set("max_wear_depth_mm", max_depth);
    summary.set("wear_area_percent", 100. * worn_area / area);
    summary.set("max_pressure_MPa", max_pressure);
    summary.set("max_contact_area_mm2", max_area);
    summary.set("contact_solves", n_steps);
    summary.set("converged_solves", n_converged);
    summary.set("mean_newton_iterations", double(n_iterations) / n_steps);
    summary.set("linear_extrapolation_cycles", parameters.wear.cycles);
    summary.set("linear_extrapolation_mass_loss_mg",
                mass * parameters.wear.cycles);
    summary.set("converged", n_converged == n_steps);
  }

  // A step's VTU: the contact state, the motion of every point in the
  bool
  WearProblem::run()
  {
    Timer wall_timer(world, /*sync_lap_times=*/true);
    pcout << "tkr-wear: ISO 14243-1 gait cycle and Archard wear (Problem = "
             "wear)"
          << std::endl;
    AssertThrow(parameters.mesh.fe_degree == 1,
                ExcInputError(
                  "Problem = wear needs Finite element degree = 1."));
    Output::create_directory(parameters.output.directory, world);
    summary.set("problem", Parameters::to_string(parameters.problem));
    make_grid();
    setup_system();

    pcout << "Gait cycle, " << n_steps << " steps:" << std::endl;
    for (unsigned int step = groups.index; step < n_steps;
         step += groups.n_groups)
      solve_step(step);
    collect_steps();
    if (groups.n_groups > 1)
      for (unsigned int step = 0; step < n_steps; ++step)
        print_step(step);
    compute_wear();
    output_results();

    summary.set("step_groups", groups.n_groups);
    Output::finish_run(summary,
                       parameters.output.directory,
                       world,
                       wall_timer.wall_time(),
                       pcout);
    bool converged = true;
    for (const auto &r : reports)
      converged = converged && r.converged;
    return converged;
  }
} // namespace TKR::Wear
