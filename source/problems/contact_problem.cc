// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <deal.II/base/function.h>
#include <deal.II/base/timer.h>

#include <deal.II/numerics/vector_tools.h>

#include <tkr/base/exceptions.h>
#include <tkr/base/result_schema.h>
#include <tkr/contact/hertz.h>
#include <tkr/contact/ipopt_solver.h>
#include <tkr/mesh/mesh.h>
#include <tkr/output/solution_output.h>
#include <tkr/problems/contact_problem.h>

#include <sstream>

namespace TKR::Problems
{
  namespace
  {
    // The contact problem's keys of summary.json (two_body_model.cc).
    // clang-format off
    [[maybe_unused]] const bool declared = ResultSchema::declare(
      "summary.json",
      60,
      {
        {"max_pressure_MPa", "number", "MPa", {"contact"}, "the largest nodal contact pressure: of the static solve (contact), of every step computed (wear)"},
        {"covered_area_mm2", "number", "mm^2", {"contact"}, "the area of `tibia_contact` that faces `femur_contact` (the mortar coupling)"},
        {"contact_area_mm2", "number", "mm^2", {"contact"}, "the area of the active (contact) set"},
        {"contact_radius_mm", "number", "mm", {"contact"}, "sqrt(`contact_area_mm2` / pi)"},
        {"contact_force_N", "number", "N", {"contact"}, "the magnitude of the contact force"},
        {"active_nodes", "integer", "-", {"contact"}, "nodes in contact"},
        {"newton_iterations", "integer", "-", {"contact"}, "active-set iterations (a trace)", {}, true},
        {"cg_iterations", "integer", "-", {"contact"}, "CG iterations: of the elasticity solve; of the AMG-CG active set (contact, only when it used CG) (a trace)", {}, true},
        {"computed_columns", "integer", "-", {"contact"}, "compliance columns the condensed active set computed (only when it computed some)"},
        {"axial_force_balance", "number", "-", {"contact"}, "minus the contact force's z component over the axial force: 1 when the contact carries the load; only with a loaded tibia (`Static contact/Tibia inferior = loaded`)"},
        {"ipopt_displacement_difference", "number", "-", {"contact"}, "largest displacement difference to the Ipopt solution over the largest displacement; only with `Verification/Cross-check with Ipopt`"},
        {"ipopt_pressure_difference", "number", "-", {"contact"}, "the same for the contact pressure"},
        {"hertz_radius_mm", "number", "mm", {"contact"}, "Hertz's contact radius (half-width for the cylinder) for the computed force; only with `Verification/Analytic solution`"},
        {"hertz_max_pressure_MPa", "number", "MPa", {"contact"}, "Hertz's peak pressure for the computed force"},
        {"fitted_radius_mm", "number", "mm", {"contact"}, "the radius (half-width) of Hertz's profile fitted to the nodal pressures"},
        {"fitted_max_pressure_MPa", "number", "MPa", {"contact"}, "the peak pressure of that fit"},
        {"radius_ratio_fitted", "number", "-", {"contact"}, "`fitted_radius_mm` / `hertz_radius_mm`"},
        {"radius_ratio_area", "number", "-", {"contact"}, "the radius (half-width) from the contact area over Hertz's"},
        {"max_pressure_ratio", "number", "-", {"contact"}, "`max_pressure_MPa` / `hertz_max_pressure_MPa`"},
        {"hertz_within_tolerance", "boolean", "-", {"contact"}, "the fitted radius and peak pressure within `Verification/Hertz tolerance` of Hertz's"}});
    // clang-format on
  } // namespace

  using namespace dealii;
  using Contact::ContactStatistics;

  namespace
  {
    /** Boundary id given to the free faces that get rollers. */
    constexpr types::boundary_id roller_id = 5;

    /**
     * Give the free faces whose normal is parallel to @p axis (their
     * vertices share that coordinate) the roller id.
     */
    void
    mark_roller_faces(Triangulation<3> &triangulation, const int axis)
    {
      for (const auto &cell : triangulation.active_cell_iterators())
        for (const auto f : cell->face_indices())
          if (cell->face(f)->at_boundary() &&
              cell->face(f)->boundary_id() == Mesh::BoundaryIds::free)
            {
              const auto   face = cell->face(f);
              const double x0   = face->vertex(0)[axis];
              bool         flat = true;
              for (const auto v : face->vertex_indices())
                flat = flat && std::abs(face->vertex(v)[axis] - x0) <
                                 1e-10 * cell->diameter();
              if (flat)
                face->set_boundary_id(roller_id);
            }
    }
  } // namespace

  ContactProblem::ContactProblem(const Parameters::AllParameters &parameters,
                                 const MPI_Comm mpi_communicator)
    : model(parameters, mpi_communicator, mpi_communicator)
  {}

  // Dirichlet data on all DoFs (every rank knows every constraint): the
  // femur's displacement on femur_fixation, a clamped tibia_inferior, the
  // rollers.
  void
  ContactProblem::setup_constraints()
  {
    const auto &sc          = model.parameters().static_contact;
    const auto &dof_handler = model.elasticity().get_dof_handler();
    dirichlet.clear();
    Vector<double> femur_displacement(3);
    for (unsigned int d = 0; d < 3; ++d)
      femur_displacement(d) = sc.femur_displacement[d];
    VectorTools::interpolate_boundary_values(model.mapping(),
                                             dof_handler,
                                             Mesh::BoundaryIds::femur_fixation,
                                             Functions::ConstantFunction<3>(
                                               femur_displacement),
                                             dirichlet);
    if (sc.tibia_inferior == Parameters::TibiaSupport::clamped)
      VectorTools::interpolate_boundary_values(
        model.mapping(),
        dof_handler,
        Mesh::BoundaryIds::tibia_inferior,
        Functions::ZeroFunction<3>(3),
        dirichlet);
    if (sc.roller_axis >= 0)
      {
        ComponentMask mask(3, false);
        mask.set(sc.roller_axis, true);
        VectorTools::interpolate_boundary_values(model.mapping(),
                                                 dof_handler,
                                                 roller_id,
                                                 Functions::ZeroFunction<3>(3),
                                                 dirichlet,
                                                 mask);
      }
    dirichlet.close();
  }

  // A loaded tibia: the axial force as a uniform traction on its inferior
  // surface, and in-plane springs spread over the same surface.
  void
  ContactProblem::setup_loads()
  {
    const auto &sc = model.parameters().static_contact;
    loads          = Elasticity::BoundaryLoads();
    if (sc.tibia_inferior == Parameters::TibiaSupport::loaded)
      {
        const double area = Mesh::compute_statistics(model.triangulation())
                              .boundary_area[Mesh::BoundaryIds::tibia_inferior];
        loads.tractions[Mesh::BoundaryIds::tibia_inferior] =
          Tensor<1, 3>({0., 0., sc.axial_force / area});
        Tensor<2, 3> spring;
        spring[0][0] = spring[1][1] = sc.tangential_spring / area;
        loads.springs[Mesh::BoundaryIds::tibia_inferior] = spring;
      }
  }

  void
  ContactProblem::setup_system()
  {
    const auto &parameters = model.parameters();
    model.distribute_dofs();
    const auto &dof_handler = model.elasticity().get_dof_handler();
    model.pcout() << "Degrees of freedom: " << dof_handler.n_dofs()
                  << ", MPI ranks: "
                  << Utilities::MPI::n_mpi_processes(model.communicator())
                  << std::endl;

    setup_constraints();
    setup_loads();

    {
      TimerOutput::Scope scope(model.timer(), "mortar coupling");
      model.setup_contact_surfaces();
      model.coupling().reinit(model.geometry().vertex_positions(),
                              parameters.contact_solver.search_distance);
    }
    const auto &cs = model.coupling().statistics();
    model.pcout() << "Mortar coupling: " << cs.n_slave_faces << " slave faces, "
                  << cs.n_master_faces << " master faces, "
                  << cs.n_overlapping_pairs << " overlapping face pairs, "
                  << cs.n_covered_nodes << " of "
                  << model.slave_surface().nodes().size()
                  << " slave nodes face the femur" << std::endl
                  << "  covered area (tibia_contact facing femur_contact): "
                  << cs.covered_area << " of " << cs.slave_area << " mm^2"
                  << std::endl;
    model.summary().set("covered_area_mm2", cs.covered_area);
    check_initial_gaps();

    solver = Contact::create_contact_solver(parameters,
                                            model.elasticity(),
                                            model.coupling(),
                                            model.communicator(),
                                            model.pcout(),
                                            model.timer());
    solver->setup(model.mapping(), dirichlet, loads);
  }

  // Refuse geometries that cannot work: bodies that overlap, and a loaded
  // tibia (held only by contact) that does not touch the femur.
  void
  ContactProblem::check_initial_gaps() const
  {
    const auto &parameters        = model.parameters();
    const auto [min_gap, closest] = Contact::smallest_gap(model.coupling());
    const bool loaded             = parameters.static_contact.tibia_inferior ==
                        Parameters::TibiaSupport::loaded;
    const auto &cs = model.coupling().statistics();
    AssertThrow(cs.n_covered_nodes > 0,
                ExcInputError(
                  "No part of tibia_contact faces femur_contact within the "
                  "search distance (" +
                  Utilities::to_string(
                    parameters.contact_solver.search_distance) +
                  " mm): covered area 0 of " + format_number(cs.slave_area) +
                  " mm^2, so no contact can be computed. Check that the "
                  "bodies are placed against each other and that the "
                  "contact groups are the articular surfaces."));
    const Point<3> &x =
      model.geometry()
        .vertex_positions()[model.slave_surface().nodes()[closest].vertex];
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

  // How far the Femur displacement closes the gap at slave node @p node:
  // its component against the node's normal (mm).
  double
  ContactProblem::closure_at(const unsigned int node) const
  {
    return -(model.parameters().static_contact.femur_displacement *
             model.coupling().slave_nodes()[node].normal);
  }

  // Where the first Newton step starts. A femur displacement that closes
  // the smallest gap by an approach delta leaves, in Hertz's solution,
  // the nodes whose initial gap (beyond the smallest) is at most delta / 2
  // in contact: the contact radius sqrt(R delta) is 1/sqrt(2) of the radius
  // sqrt(2 R delta) of the rigid overlap. Starting there saves the Newton
  // steps that grow the set from the few nodes within the Initial contact
  // distance (on the 259k-DoF Hertz sphere, 2 steps instead of 4). The
  // entry stays the lower bound; the converged set does not depend on it.
  double
  ContactProblem::initial_contact_distance() const
  {
    const auto  &parameters = model.parameters();
    const double entry = parameters.contact_solver.initial_contact_distance;
    const auto [min_gap, closest] = Contact::smallest_gap(model.coupling());
    if (closest == numbers::invalid_unsigned_int)
      return entry;
    const double half_approach =
      0.5 * (closure_at(closest) - std::max(min_gap, 0.));
    if (half_approach <= entry)
      return entry;
    if (!parameters.output.testing)
      model.pcout() << "  first active set: the nodes within "
                    << format_number(half_approach)
                    << " mm of the smallest gap (half the femur's approach)"
                    << std::endl;
    return half_approach;
  }

  ContactStatistics
  ContactProblem::solve()
  {
    TimerOutput::Scope scope(model.timer(), "contact solve");
    model.pcout() << "Contact solve (" << solver->name() << "):" << std::endl;
    const ContactStatistics statistics =
      solver->solve(model.mapping(), loads, initial_contact_distance(), state);
    solution = solver->compute_solution();
    check_contact_found(statistics);
    return statistics;
  }

  // No silent zero: a clamped tibia under a femur displacement that closes
  // the smallest gap must touch it. Without any active node the result is
  // an error if the displacement closes the gap, a warning with the
  // numbers if it does not (then zero contact is the right answer).
  void
  ContactProblem::check_contact_found(
    const Contact::ContactStatistics &statistics) const
  {
    if (statistics.n_active > 0)
      return;
    const auto [min_gap, closest] = Contact::smallest_gap(model.coupling());
    const Tensor<1, 3> &d =
      model.parameters().static_contact.femur_displacement;
    const double    closure = closure_at(closest);
    const Point<3> &x =
      model.geometry()
        .vertex_positions()[model.slave_surface().nodes()[closest].vertex];
    std::ostringstream message;
    message << "The femur displacement (" << d[0] << ", " << d[1] << ", "
            << d[2] << ") mm closes the smallest initial gap, "
            << format_number(min_gap) << " mm at the tibia node ("
            << format_number(x[0]) << ", " << format_number(x[1]) << ", "
            << format_number(x[2]) << "), by " << format_number(closure)
            << " mm, and no tibia node is in contact";
    AssertThrow(closure <= min_gap,
                ExcInputError(
                  message.str() +
                  ": the contact was not resolved (covered area " +
                  format_number(model.coupling().statistics().covered_area) +
                  " mm^2). This is not a result."));
    model.pcout() << "Warning: no contact. " << message.str()
                  << ": the bodies stay apart." << std::endl;
  }

  // Solve the same discrete problem with Ipopt and compare: displacements
  // relative to the largest displacement, pressures relative to the
  // largest pressure. The active-set solution stays the result.
  void
  ContactProblem::cross_check_with_ipopt()
  {
    Contact::ContactState ipopt_state;
    Contact::IpoptSolver  ipopt(
      model.elasticity(),
      model.coupling(),
      model.parameters().contact_solver,
      model.parameters().materials.tibia.youngs_modulus,
      model.communicator(),
      model.pcout(),
      model.timer());
    ipopt.setup(model.mapping(), dirichlet, loads);
    const ContactStatistics statistics =
      ipopt.solve(model.mapping(), loads, 0., ipopt_state);
    const TrilinosWrappers::MPI::Vector ipopt_solution =
      ipopt.compute_solution();

    double max_u = 0, du = 0, max_p = 0, dp = 0;
    for (unsigned int i = 0; i < solution.size(); ++i)
      {
        max_u = std::max(max_u, std::abs(solution[i]));
        du    = std::max(du, std::abs(solution[i] - ipopt_solution[i]));
      }
    for (unsigned int j = 0; j < state.pressure.size(); ++j)
      {
        max_p = std::max(max_p, std::abs(state.pressure[j]));
        dp =
          std::max(dp, std::abs(state.pressure[j] - ipopt_state.pressure[j]));
      }
    unsigned int n_differ = 0;
    for (unsigned int j = 0; j < state.active.size(); ++j)
      n_differ += (state.active[j] != ipopt_state.active[j]);

    model.pcout() << "Cross-check with Ipopt: "
                  << (statistics.converged ? "converged" : "did NOT converge")
                  << std::endl
                  << "  displacement difference / max displacement below 1e-6: "
                  << (du < 1e-6 * max_u ? "yes" : "no") << std::endl
                  << "  pressure difference / max pressure below 1e-6:         "
                  << (dp < 1e-6 * max_p ? "yes" : "no") << std::endl
                  << "  nodes whose active status differs:                     "
                  << n_differ << std::endl;
    model.summary().set("ipopt_displacement_difference", du / max_u);
    model.summary().set("ipopt_pressure_difference", dp / max_p);
  }

  void
  ContactProblem::report(const ContactStatistics &statistics)
  {
    auto        &summary = model.summary();
    const double radius  = std::sqrt(statistics.contact_area / numbers::PI);
    const double force   = statistics.contact_force.norm();
    model.pcout() << "Contact "
                  << (statistics.converged ? "converged" : "did NOT converge");
    if (!model.parameters().output.testing)
      model.pcout() << " in " << statistics.newton_iterations
                    << " active-set iterations";
    model.pcout() << std::endl
                  << "  active nodes:       " << statistics.n_active
                  << std::endl
                  << "  contact force:      " << force << " N" << std::endl
                  << "  contact area:       " << statistics.contact_area
                  << " mm^2" << std::endl
                  << "  contact radius:     " << radius << " mm (sqrt(area/pi))"
                  << std::endl
                  << "  max pressure:       " << statistics.max_pressure
                  << " MPa" << std::endl;
    summary.set("max_pressure_MPa", statistics.max_pressure);
    summary.set("contact_area_mm2", statistics.contact_area);
    summary.set("contact_radius_mm", radius);
    summary.set("contact_force_N", force);
    summary.set("active_nodes", statistics.n_active);
    summary.set("newton_iterations", statistics.newton_iterations);
    if (statistics.cg_iterations > 0)
      summary.set("cg_iterations", statistics.cg_iterations);
    if (statistics.computed_columns > 0)
      summary.set("computed_columns", statistics.computed_columns);

    // A tibia held only by contact: the contact must carry the axial force
    // (the tangential springs act in x and y only).
    const auto &sc = model.parameters().static_contact;
    if (sc.tibia_inferior == Parameters::TibiaSupport::loaded &&
        sc.axial_force != 0.)
      {
        const double ratio = -statistics.contact_force[2] / sc.axial_force;
        model.pcout() << "  force balance: axial contact force / axial force "
                      << ratio << " (equal to 1e-6: "
                      << (std::abs(ratio - 1.) < 1e-6 ? "yes" : "no") << ")"
                      << std::endl;
        summary.set("axial_force_balance", ratio);
      }
  }

  // Hertz's solution for the computed force, and a fit of Hertz's elliptic
  // profile to the nodal pressures. Distances are measured from the
  // pressure-weighted centre of the contact (in y only for the cylinder).
  void
  ContactProblem::compare_with_hertz(const ContactStatistics &statistics)
  {
    const auto &parameters   = model.parameters();
    auto       &summary      = model.summary();
    const auto &verification = parameters.verification;
    const bool  is_sphere    = verification.analytic_solution ==
                           Parameters::AnalyticSolution::hertz_sphere;
    const double E_star =
      Contact::Hertz::effective_modulus(parameters.materials.femur,
                                        parameters.materials.tibia);
    const double                   F = statistics.contact_force.norm();
    const Contact::Hertz::Solution exact =
      is_sphere ? Contact::Hertz::sphere(F, verification.radius, E_star) :
                  Contact::Hertz::cylinder(F,
                                           verification.cylinder_length,
                                           verification.radius,
                                           E_star);

    const auto &vertices = model.geometry().vertex_positions();
    Point<3>    centre;
    double      weight = 0;
    for (unsigned int j = 0; j < state.active.size(); ++j)
      if (state.active[j])
        {
          centre += state.pressure[j] *
                    vertices[model.slave_surface().nodes()[j].vertex];
          weight += state.pressure[j];
        }
    centre /= weight;
    std::vector<double> r, p;
    for (unsigned int j = 0; j < state.active.size(); ++j)
      if (state.active[j])
        {
          Tensor<1, 3> d =
            vertices[model.slave_surface().nodes()[j].vertex] - centre;
          d[2] = 0;
          if (!is_sphere)
            d[0] = 0;
          r.push_back(d.norm());
          p.push_back(state.pressure[j]);
        }
    const Contact::Hertz::Solution fitted = Contact::Hertz::fit(r, p);
    const double                   area_measure =
      is_sphere ? std::sqrt(statistics.contact_area / numbers::PI) :
                                    statistics.contact_area / (2. * verification.cylinder_length);

    model.pcout() << "Hertz "
                  << (is_sphere ? "sphere" : "cylinder (plane strain)")
                  << " for the computed force (E* = " << E_star
                  << " MPa):" << std::endl
                  << "  " << (is_sphere ? "contact radius" : "half-width    ")
                  << ":  Hertz " << exact.a << " mm, fitted " << fitted.a
                  << " mm (ratio " << fitted.a / exact.a << "), from area "
                  << area_measure << " mm (ratio " << area_measure / exact.a
                  << ")" << std::endl
                  << "  peak pressure :  Hertz " << exact.p0
                  << " MPa, max nodal " << statistics.max_pressure
                  << " MPa (ratio " << statistics.max_pressure / exact.p0
                  << "), fitted " << fitted.p0 << " MPa (ratio "
                  << fitted.p0 / exact.p0 << ")" << std::endl;
    summary.set("hertz_radius_mm", exact.a);
    summary.set("hertz_max_pressure_MPa", exact.p0);
    summary.set("fitted_radius_mm", fitted.a);
    summary.set("fitted_max_pressure_MPa", fitted.p0);
    summary.set("radius_ratio_fitted", fitted.a / exact.a);
    summary.set("radius_ratio_area", area_measure / exact.a);
    summary.set("max_pressure_ratio", statistics.max_pressure / exact.p0);
    const double tolerance = verification.hertz_tolerance;
    const bool   within    = std::abs(fitted.a / exact.a - 1.) <= tolerance &&
                        std::abs(fitted.p0 / exact.p0 - 1.) <= tolerance;
    model.pcout() << "  fitted " << (is_sphere ? "radius" : "half-width")
                  << " and peak pressure within " << 100. * tolerance
                  << " % of Hertz: " << (within ? "yes" : "no") << std::endl;
    summary.set("hertz_within_tolerance", within);
  }

  void
  ContactProblem::output_results()
  {
    TimerOutput::Scope scope(model.timer(), "output");
    Output::VtuSeries  series(model.parameters().output.directory,
                             "solution",
                             model.communicator());
    Output::write_solution(model.elasticity(),
                           solution,
                           model.mapping(),
                           series,
                           0,
                           0.,
                           {{&model.slave_surface(),
                             {"contact_pressure", "gap", "active"},
                             {state.pressure,
                              state.gap,
                              std::vector<double>(state.active.begin(),
                                                  state.active.end())}}});
  }

  bool
  ContactProblem::run()
  {
    const auto &parameters = model.parameters();
    model.start("static two-body contact");
    model.make_grid([&](Triangulation<3> &triangulation) {
      if (parameters.static_contact.roller_axis >= 0)
        mark_roller_faces(triangulation, parameters.static_contact.roller_axis);
    });
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
    return model.finish(statistics.converged);
  }
} // namespace TKR::Problems
