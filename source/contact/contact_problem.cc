// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <deal.II/base/function.h>
#include <deal.II/base/timer.h>

#include <deal.II/numerics/vector_tools.h>

#include <tkr/base/exceptions.h>
#include <tkr/contact/condensed_solver.h>
#include <tkr/contact/contact_problem.h>
#include <tkr/contact/hertz.h>
#include <tkr/contact/ipopt_solver.h>
#include <tkr/mesh/mesh.h>
#include <tkr/output/solution_output.h>

#include <iomanip>
#include <sstream>

namespace TKR::Contact
{
  using namespace dealii;

  namespace
  {
    /** Boundary id given to the free faces that get rollers. */
    constexpr types::boundary_id roller_id = 5;
  } // namespace

  ContactProblem::ContactProblem(const Parameters::AllParameters &parameters,
                                 const MPI_Comm mpi_communicator)
    : parameters(parameters)
    , mpi_communicator(mpi_communicator)
    , pcout(std::cout, Utilities::MPI::this_mpi_process(mpi_communicator) == 0)
    // Rank 0's times; the MPI variant of TimerOutput would print a warning
    // whenever an input error unwinds the stack.
    , timer(pcout,
            parameters.output.testing ? TimerOutput::never :
                                        TimerOutput::summary,
            TimerOutput::wall_times)
    , triangulation(mpi_communicator,
                    Triangulation<3>::none,
                    /*allow_artificial_cells=*/false,
                    parallel::shared::Triangulation<3>::partition_metis)
    , elasticity(triangulation,
                 parameters.materials,
                 parameters.linear_solver,
                 parameters.mesh.fe_degree,
                 mpi_communicator,
                 timer)
  {}

  void
  ContactProblem::make_grid()
  {
    TimerOutput::Scope scope(timer, "read mesh");
    Mesh::read_mesh(parameters.mesh, triangulation);
    const int axis = parameters.static_contact.roller_axis;
    if (axis >= 0)
      for (const auto &cell : triangulation.active_cell_iterators())
        for (const auto f : cell->face_indices())
          if (cell->face(f)->at_boundary() &&
              cell->face(f)->boundary_id() == Mesh::BoundaryIds::free)
            {
              // The face normal is parallel to the axis if the face's
              // vertices share that coordinate.
              const auto   face = cell->face(f);
              const double x0   = face->vertex(0)[axis];
              bool         flat = true;
              for (const auto v : face->vertex_indices())
                flat = flat && std::abs(face->vertex(v)[axis] - x0) <
                                 1e-10 * cell->diameter();
              if (flat)
                face->set_boundary_id(roller_id);
            }
    Output::report_mesh(pcout,
                        summary,
                        Mesh::compute_statistics(triangulation),
                        parameters.mesh.file,
                        parameters.output.testing);
  }

  void
  ContactProblem::setup_system()
  {
    elasticity.distribute_dofs();
    const auto &dof_handler = elasticity.get_dof_handler();
    pcout << "Degrees of freedom: " << dof_handler.n_dofs() << ", MPI ranks: "
          << Utilities::MPI::n_mpi_processes(mpi_communicator) << std::endl;
    summary.set("dofs", static_cast<unsigned long long>(dof_handler.n_dofs()));

    // Dirichlet data on all DoFs (every rank knows every constraint).
    const auto &sc = parameters.static_contact;
    dirichlet.clear();
    Vector<double> femur_displacement(3);
    for (unsigned int d = 0; d < 3; ++d)
      femur_displacement(d) = sc.femur_displacement[d];
    VectorTools::interpolate_boundary_values(mapping,
                                             dof_handler,
                                             Mesh::BoundaryIds::femur_fixation,
                                             Functions::ConstantFunction<3>(
                                               femur_displacement),
                                             dirichlet);
    if (sc.tibia_inferior == Parameters::TibiaSupport::clamped)
      VectorTools::interpolate_boundary_values(
        mapping,
        dof_handler,
        Mesh::BoundaryIds::tibia_inferior,
        Functions::ZeroFunction<3>(3),
        dirichlet);
    if (sc.roller_axis >= 0)
      {
        ComponentMask mask(3, false);
        mask.set(sc.roller_axis, true);
        VectorTools::interpolate_boundary_values(mapping,
                                                 dof_handler,
                                                 roller_id,
                                                 Functions::ZeroFunction<3>(3),
                                                 dirichlet,
                                                 mask);
      }
    dirichlet.close();

    // A loaded tibia: the axial force as a uniform traction on its inferior
    // surface, and in-plane springs spread over the same surface.
    loads = Elasticity::BoundaryLoads();
    if (sc.tibia_inferior == Parameters::TibiaSupport::loaded)
      {
        const double area = Mesh::compute_statistics(triangulation)
                              .boundary_area[Mesh::BoundaryIds::tibia_inferior];
        loads.tractions[Mesh::BoundaryIds::tibia_inferior] =
          Tensor<1, 3>({0., 0., sc.axial_force / area});
        Tensor<2, 3> spring;
        spring[0][0] = spring[1][1] = sc.tangential_spring / area;
        loads.springs[Mesh::BoundaryIds::tibia_inferior] = spring;
      }

    {
      TimerOutput::Scope scope(timer, "mortar coupling");
      slave = std::make_unique<Mortar::ContactSurface>(
        dof_handler,
        Mesh::BoundaryIds::tibia_contact);
      master = std::make_unique<Mortar::ContactSurface>(
        dof_handler,
        Mesh::BoundaryIds::femur_contact);
      coupling = std::make_unique<Mortar::MortarCoupling>(*slave, *master);
      coupling->reinit(triangulation.get_vertices(),
                       parameters.contact_solver.search_distance);
    }
    const auto &cs = coupling->statistics();
    pcout << "Mortar coupling: " << cs.n_slave_faces << " slave faces, "
          << cs.n_master_faces << " master faces, " << cs.n_overlapping_pairs
          << " overlapping face pairs, " << cs.n_covered_nodes << " of "
          << slave->nodes().size() << " slave nodes face the femur"
          << std::endl;
    check_initial_gaps();

    // The condensed active set and Ipopt set up their own systems.
    const auto algorithm = parameters.contact_solver.algorithm;
    if (algorithm == Parameters::ContactAlgorithm::active_set ||
        algorithm == Parameters::ContactAlgorithm::automatic)
      {
        solver = std::make_unique<ActiveSetSolver>(
          elasticity,
          *coupling,
          parameters.contact_solver,
          parameters.materials.tibia.youngs_modulus,
          mpi_communicator,
          pcout,
          timer,
          parameters.output.testing);
        solver->setup(dirichlet);
      }
  }

  // Refuse geometries that cannot work: bodies that overlap, and a loaded
  // tibia (held only by contact) that does not touch the femur.
  void
  ContactProblem::check_initial_gaps() const
  {
    double       min_gap = std::numeric_limits<double>::max();
    unsigned int closest = 0;
    for (unsigned int j = 0; j < coupling->slave_nodes().size(); ++j)
      {
        const auto &node = coupling->slave_nodes()[j];
        if (node.covered && node.weighted_gap / node.D < min_gap)
          {
            min_gap = node.weighted_gap / node.D;
            closest = j;
          }
      }
    const bool loaded = parameters.static_contact.tibia_inferior ==
                        Parameters::TibiaSupport::loaded;
    AssertThrow(coupling->statistics().n_covered_nodes > 0 || !loaded,
                ExcInputError(
                  "With Tibia inferior = loaded the tibia is held only by "
                  "contact, but no part of tibia_contact faces femur_contact "
                  "within the search distance (" +
                  Utilities::to_string(
                    parameters.contact_solver.search_distance) +
                  " mm): the bodies do not touch and the problem is "
                  "singular."));
    if (coupling->statistics().n_covered_nodes == 0)
      return;
    const Point<3> &x =
      triangulation.get_vertices()[slave->nodes()[closest].vertex];
    const std::string where = "(" + format_number(x[0]) + ", " +
                              format_number(x[1]) + ", " + format_number(x[2]) +
                              ")";
    AssertThrow(min_gap >= -parameters.contact_solver.overlap_tolerance,
                ExcInputError("The bodies overlap by " +
                              format_number(-min_gap) +
                              " mm (at the tibia node " + where +
                              "), more than the Overlap tolerance of " +
                              Utilities::to_string(
                                parameters.contact_solver.overlap_tolerance) +
                              " mm. Check the mesh positions."));
    AssertThrow(!loaded ||
                  min_gap <= parameters.contact_solver.initial_contact_distance,
                ExcInputError(
                  "With Tibia inferior = loaded the tibia is held only by "
                  "contact, but the bodies do not touch: the smallest gap is " +
                  format_number(min_gap) + " mm (at the tibia node " + where +
                  "), more than the Initial contact distance "
                  "of " +
                  Utilities::to_string(
                    parameters.contact_solver.initial_contact_distance) +
                  " mm, so the problem would be singular. Move the bodies "
                  "together or raise the Initial contact distance."));
  }

  ContactStatistics
  ContactProblem::solve()
  {
    TimerOutput::Scope scope(timer, "contact solve");
    if (parameters.contact_solver.algorithm ==
        Parameters::ContactAlgorithm::ipopt)
      {
        pcout << "Contact solve (Ipopt, interior point):" << std::endl;
        IpoptSolver ipopt(elasticity,
                          *coupling,
                          1e-2 * parameters.contact_solver.tolerance,
                          parameters.materials.tibia.youngs_modulus,
                          mpi_communicator,
                          timer);
        return ipopt.solve(mapping, dirichlet, loads, state);
      }
    if (parameters.contact_solver.algorithm ==
        Parameters::ContactAlgorithm::condensed_active_set)
      {
        pcout << "Contact solve (condensed active set):" << std::endl;
        CondensedActiveSetSolver condensed(
          elasticity,
          *coupling,
          parameters.contact_solver,
          parameters.materials.tibia.youngs_modulus,
          mpi_communicator,
          pcout,
          timer);
        condensed.factorize(mapping, dirichlet, loads);
        const ContactStatistics statistics =
          condensed.solve(mapping,
                          loads,
                          parameters.contact_solver.initial_contact_distance,
                          state);
        condensed.compute_solution();
        return statistics;
      }
    pcout << "Contact solve (active set):" << std::endl;
    return solver->solve(mapping,
                         loads,
                         parameters.contact_solver.initial_contact_distance,
                         state);
  }

  // Solve the same discrete problem with Ipopt and compare: displacements
  // relative to the largest displacement, pressures relative to the
  // largest pressure. The active-set solution stays the result.
  void
  ContactProblem::cross_check_with_ipopt()
  {
    const TrilinosWrappers::MPI::Vector active_set_solution(
      elasticity.get_solution());
    const ContactState active_set_state = state;

    ContactState            ipopt_state;
    IpoptSolver             ipopt(elasticity,
                      *coupling,
                      1e-2 * parameters.contact_solver.tolerance,
                      parameters.materials.tibia.youngs_modulus,
                      mpi_communicator,
                      timer);
    const ContactStatistics statistics =
      ipopt.solve(mapping, dirichlet, loads, ipopt_state);

    double max_u = 0, du = 0, max_p = 0, dp = 0;
    for (unsigned int i = 0; i < active_set_solution.size(); ++i)
      {
        max_u = std::max(max_u, std::abs(active_set_solution[i]));
        du    = std::max(du,
                      std::abs(active_set_solution[i] -
                               elasticity.get_solution()[i]));
      }
    for (unsigned int j = 0; j < state.pressure.size(); ++j)
      {
        max_p = std::max(max_p, std::abs(active_set_state.pressure[j]));
        dp    = std::max(dp,
                      std::abs(active_set_state.pressure[j] -
                               ipopt_state.pressure[j]));
      }
    unsigned int n_differ = 0;
    for (unsigned int j = 0; j < state.active.size(); ++j)
      n_differ += (active_set_state.active[j] != ipopt_state.active[j]);

    pcout << "Cross-check with Ipopt: "
          << (statistics.converged ? "converged" : "did NOT converge")
          << std::endl
          << "  displacement difference / max displacement below 1e-6: "
          << (du < 1e-6 * max_u ? "yes" : "no") << std::endl
          << "  pressure difference / max pressure below 1e-6:         "
          << (dp < 1e-6 * max_p ? "yes" : "no") << std::endl
          << "  nodes whose active status differs:                     "
          << n_differ << std::endl;
    summary.set("ipopt_displacement_difference", du / max_u);
    summary.set("ipopt_pressure_difference", dp / max_p);

    // Restore the active-set result.
    state = active_set_state;
    elasticity.set_solution(active_set_solution);
  }

  void
  ContactProblem::report(const ContactStatistics &statistics)
  {
    const double radius = std::sqrt(statistics.contact_area / numbers::PI);
    const double force  = statistics.contact_force.norm();
    pcout << "Contact "
          << (statistics.converged ? "converged" : "did NOT converge") << " in "
          << statistics.newton_iterations << " active-set iterations"
          << std::endl
          << "  active nodes:       " << statistics.n_active << std::endl
          << "  contact force:      " << force << " N" << std::endl
          << "  contact area:       " << statistics.contact_area << " mm^2"
          << std::endl
          << "  contact radius:     " << radius << " mm (sqrt(area/pi))"
          << std::endl
          << "  max pressure:       " << statistics.max_pressure << " MPa"
          << std::endl;
    summary.set("converged", statistics.converged);
    summary.set("max_pressure_MPa", statistics.max_pressure);
    summary.set("contact_area_mm2", statistics.contact_area);
    summary.set("contact_radius_mm", radius);
    summary.set("contact_force_N", force);
    summary.set("active_nodes", statistics.n_active);
    summary.set("newton_iterations", statistics.newton_iterations);
    summary.set("cg_iterations", statistics.linear_iterations);
  }

  // Hertz's solution for the computed force, and a fit of Hertz's elliptic
  // profile to the nodal pressures. Distances are measured from the
  // pressure-weighted centre of the contact (in y only for the cylinder).
  void
  ContactProblem::compare_with_hertz(const ContactStatistics &statistics)
  {
    const auto &verification = parameters.verification;
    const bool  is_sphere    = verification.analytic_solution ==
                           Parameters::AnalyticSolution::hertz_sphere;
    const double E_star = Hertz::effective_modulus(parameters.materials.femur,
                                                   parameters.materials.tibia);
    const double F      = statistics.contact_force.norm();
    const Hertz::Solution exact =
      is_sphere ? Hertz::sphere(F, verification.radius, E_star) :
                  Hertz::cylinder(F,
                                  verification.cylinder_length,
                                  verification.radius,
                                  E_star);

    const auto &vertices = triangulation.get_vertices();
    Point<3>    centre;
    double      weight = 0;
    for (unsigned int j = 0; j < state.active.size(); ++j)
      if (state.active[j])
        {
          centre += state.pressure[j] * vertices[slave->nodes()[j].vertex];
          weight += state.pressure[j];
        }
    centre /= weight;
    std::vector<double> r, p;
    for (unsigned int j = 0; j < state.active.size(); ++j)
      if (state.active[j])
        {
          Tensor<1, 3> d = vertices[slave->nodes()[j].vertex] - centre;
          d[2]           = 0;
          if (!is_sphere)
            d[0] = 0;
          r.push_back(d.norm());
          p.push_back(state.pressure[j]);
        }
    const Hertz::Solution fitted = Hertz::fit(r, p);
    const double          area_measure =
      is_sphere ? std::sqrt(statistics.contact_area / numbers::PI) :
                           statistics.contact_area / (2. * verification.cylinder_length);

    pcout << "Hertz " << (is_sphere ? "sphere" : "cylinder (plane strain)")
          << " for the computed force (E* = " << E_star << " MPa):" << std::endl
          << "  " << (is_sphere ? "contact radius" : "half-width    ")
          << ":  Hertz " << exact.a << " mm, fitted " << fitted.a
          << " mm (ratio " << fitted.a / exact.a << "), from area "
          << area_measure << " mm (ratio " << area_measure / exact.a << ")"
          << std::endl
          << "  peak pressure :  Hertz " << exact.p0 << " MPa, max nodal "
          << statistics.max_pressure << " MPa (ratio "
          << statistics.max_pressure / exact.p0 << "), fitted " << fitted.p0
          << " MPa (ratio " << fitted.p0 / exact.p0 << ")" << std::endl;
    summary.set("hertz_radius_mm", exact.a);
    summary.set("hertz_max_pressure_MPa", exact.p0);
    summary.set("fitted_radius_mm", fitted.a);
    summary.set("fitted_max_pressure_MPa", fitted.p0);
    summary.set("radius_ratio_fitted", fitted.a / exact.a);
    summary.set("radius_ratio_area", area_measure / exact.a);
    summary.set("max_pressure_ratio", statistics.max_pressure / exact.p0);
  }

  void
  ContactProblem::output_results()
  {
    TimerOutput::Scope scope(timer, "output");
    // Contact pressure, gap and active flag at the slave nodes.
    const Vector<double> contact =
      Output::surface_fields(*slave,
                             {state.pressure,
                              state.gap,
                              std::vector<double>(state.active.begin(),
                                                  state.active.end())},
                             elasticity.get_dof_handler().n_dofs());
    Output::VtuSeries series(parameters.output.directory,
                             "solution",
                             mpi_communicator);
    Output::write_solution(elasticity,
                           mapping,
                           series,
                           0,
                           0.,
                           [&](DataOut<3> &data_out) {
                             data_out.add_data_vector(
                               contact,
                               std::vector<std::string>{"contact_pressure",
                                                        "gap",
                                                        "active"},
                               DataOut<3>::type_dof_data);
                           });
  }

  bool
  ContactProblem::run()
  {
    Timer wall_timer(mpi_communicator, /*sync_lap_times=*/true);
    pcout << "tkr-wear: static two-body contact (Problem = contact)"
          << std::endl;
    Output::create_directory(parameters.output.directory, mpi_communicator);
    summary.set("problem", Parameters::to_string(parameters.problem));

    make_grid();
    setup_system();
    const ContactStatistics statistics = solve();
    report(statistics);
    if (parameters.verification.cross_check_with_ipopt &&
        parameters.contact_solver.algorithm !=
          Parameters::ContactAlgorithm::ipopt)
      cross_check_with_ipopt();
    if (parameters.verification.analytic_solution !=
        Parameters::AnalyticSolution::none)
      compare_with_hertz(statistics);
    if (parameters.output.vtu_interval > 0)
      output_results();

    Output::finish_run(summary,
                       parameters.output.directory,
                       mpi_communicator,
                       wall_timer.wall_time(),
                       pcout);
    return statistics.converged;
  }
} // namespace TKR::Contact
