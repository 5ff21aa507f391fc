// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

// The solvers' parameters: `Static contact`, `Contact solver`,
// `Verification` and `Linear solver` (parameters.h).

#include <deal.II/base/utilities.h>

#include <tkr/base/exceptions.h>
#include <tkr/parameters/parameters.h>

#include "vector_entry.h"

namespace TKR::Parameters
{
  using namespace dealii;
  using internal::get_vector;
  using internal::vector_pattern;

  void
  StaticContact::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Static contact");
    {
      prm.declare_entry("Femur displacement",
                        "0, 0, -0.01",
                        vector_pattern(),
                        "(Problem = contact) Displacement of the femoral "
                        "fixation surface, x,y,z in mm.");
      prm.declare_entry("Tibia inferior",
                        "clamped",
                        Patterns::Selection("clamped|loaded"),
                        "(Problem = contact) clamped: zero displacement on "
                        "the tibial inferior surface; loaded: the axial force "
                        "acts there and the tibia is held only by contact.");
      prm.declare_entry("Axial force",
                        "1000",
                        Patterns::Double(0, Patterns::Double::max_double_value),
                        "(Problem = contact, Tibia inferior = loaded) Force "
                        "on the tibial inferior surface along +z, in N.");
      prm.declare_entry("Tibia tangential spring",
                        "100",
                        Patterns::Double(0),
                        "(Tibia inferior = loaded) Total stiffness in N/mm of "
                        "the x and y springs spread uniformly over the "
                        "tibial inferior surface; they hold the in-plane "
                        "rigid motions that frictionless contact cannot.");
      prm.declare_entry("Roller faces",
                        "none",
                        Patterns::Selection("none|x|y|z"),
                        "Untagged (free) faces whose normal is parallel to "
                        "this axis get the roller condition u.n = 0, e.g. x "
                        "for plane strain in a slab normal to x.");
    }
    prm.leave_subsection();
  }

  void
  StaticContact::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Static contact");
    {
      femur_displacement = get_vector(prm, "Femur displacement");
      tibia_inferior =
        (prm.get("Tibia inferior") == "loaded" ? TibiaSupport::loaded :
                                                 TibiaSupport::clamped);
      axial_force            = prm.get_double("Axial force");
      tangential_spring      = prm.get_double("Tibia tangential spring");
      const std::string axis = prm.get("Roller faces");
      roller_axis            = (axis == "none" ? -1 :
                                axis == "x"    ? 0 :
                                axis == "y"    ? 1 :
                                                 2);
    }
    prm.leave_subsection();
  }

  void
  ContactSolver::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Contact solver");
    {
      prm.declare_entry(
        "Solver",
        "auto",
        Patterns::Selection("auto|active set|condensed active set|ipopt"),
        "active set: primal-dual active set (semismooth Newton) with "
        "AMG-preconditioned CG on the whole body; condensed active set: the "
        "same iteration on the contact surface (Delassus matrix from one "
        "sparse Cholesky factorisation (CHOLMOD) of the stiffness, kept for "
        "all solves; "
        "needs a stiffness without rigid-body motion); ipopt: the same "
        "discrete problem as a convex QP solved by Ipopt (reference, slow, "
        "Problem = contact only); auto: condensed active set for Problem = "
        "wear, active set for Problem = contact.");
      prm.declare_entry("Tolerance",
                        "1e-8",
                        Patterns::Double(0),
                        "Relative residual at which a contact solve with an "
                        "unchanged active set counts as converged.");
      prm.declare_entry("Max iterations",
                        "50",
                        Patterns::Integer(1),
                        "Maximum number of active-set (Newton) iterations.");
      prm.declare_entry("Search distance",
                        "2",
                        Patterns::Double(0),
                        "Master faces farther than this (mm) from a slave "
                        "face are not coupled to it. Larger than any gap "
                        "that can close in one solve.");
      prm.declare_entry(
        "Coupling window",
        "0.05",
        Patterns::Double(0),
        "Problem = wear: each contact solve of a warm-started step (blocks "
        "after the first) integrates the mortar coupling only around the "
        "slave faces that come within this distance (mm) of the femur after "
        "the displacement of the step's previous solve (and the nodes of "
        "their faces). After the solve it checks that "
        "every face left out stayed at least half of it away; if not, the "
        "solve is repeated with the whole search distance. The results do "
        "not change, only the cost. 0: always the whole search distance.");
      prm.declare_entry("Initial contact distance",
                        "0.01",
                        Patterns::Double(0),
                        "Slave nodes whose initial gap exceeds the smallest "
                        "by at most this (mm) start in the active set (when "
                        "there is no warm start). Problem = contact raises it "
                        "to half the approach of the Femur displacement "
                        "beyond the smallest gap (the edge of Hertz's "
                        "contact zone), which saves Newton steps.");
      prm.declare_entry("Overlap tolerance",
                        "0.05",
                        Patterns::Double(0),
                        "Problem = contact: the bodies may overlap by at most "
                        "this (mm) in the initial geometry; more is refused "
                        "as a mesh error. (A wear run takes an overlap up by "
                        "the tray's axial position: Gait/Largest initial "
                        "overlap.)");
    }
    prm.leave_subsection();
  }

  void
  ContactSolver::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Contact solver");
    {
      const std::string name = prm.get("Solver");
      algorithm =
        (name == "ipopt"      ? ContactAlgorithm::ipopt :
         name == "active set" ? ContactAlgorithm::active_set :
         name == "condensed active set" ?
                                ContactAlgorithm::condensed_active_set :
                                ContactAlgorithm::automatic);
      tolerance                = prm.get_double("Tolerance");
      max_iterations           = prm.get_integer("Max iterations");
      search_distance          = prm.get_double("Search distance");
      coupling_window          = prm.get_double("Coupling window");
      initial_contact_distance = prm.get_double("Initial contact distance");
      overlap_tolerance        = prm.get_double("Overlap tolerance");
    }
    prm.leave_subsection();
  }

  void
  Verification::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Verification");
    {
      prm.declare_entry("Analytic solution",
                        "none",
                        Patterns::Selection("none|hertz sphere|hertz cylinder"),
                        "(Problem = contact) Compare the contact pressure "
                        "with Hertz's solution for the computed contact "
                        "force: a sphere on a half-space, or a cylinder (axis "
                        "along x) on a half-space in plane strain.");
      prm.declare_entry("Radius",
                        "20",
                        Patterns::Double(0),
                        "Radius of the sphere or cylinder, mm.");
      prm.declare_entry("Cylinder length",
                        "10",
                        Patterns::Double(0),
                        "Length of the cylinder along x, mm (the force per "
                        "length is the contact force over it).");
      prm.declare_entry(
        "Hertz tolerance",
        "0.05",
        Patterns::Double(0),
        "(Analytic solution = hertz ...) The comparison passes when the "
        "fitted contact radius (half-width) and the fitted peak pressure "
        "lie within this fraction of Hertz's values; the screen and "
        "summary.json (hertz_within_tolerance) say whether they do "
        "(doc/verification.md lists what each mesh reaches).");
      prm.declare_entry(
        "Cross-check with Ipopt",
        "false",
        Patterns::Bool(),
        "(Problem = contact, Solver = (condensed) active set, one MPI "
        "rank) Solve the same discrete problem again with "
        "Ipopt and report the largest differences of "
        "displacement and pressure.");
    }
    prm.leave_subsection();
  }

  void
  Verification::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Verification");
    {
      const std::string name = prm.get("Analytic solution");
      analytic_solution =
        (name == "hertz sphere"   ? AnalyticSolution::hertz_sphere :
         name == "hertz cylinder" ? AnalyticSolution::hertz_cylinder :
                                    AnalyticSolution::none);
      radius                 = prm.get_double("Radius");
      cylinder_length        = prm.get_double("Cylinder length");
      hertz_tolerance        = prm.get_double("Hertz tolerance");
      cross_check_with_ipopt = prm.get_bool("Cross-check with Ipopt");
    }
    prm.leave_subsection();
  }

  void
  LinearSolver::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Linear solver");
    {
      prm.declare_entry("Tolerance",
                        "1e-10",
                        Patterns::Double(0),
                        "Relative residual reduction of the CG solver.");
      prm.declare_entry(
        "Newton step tolerance",
        "1e-6",
        Patterns::Double(0),
        "Relative CG residual of the Newton steps of the AMG-CG active set "
        "(Contact solver/Solver = active set) that only decide the next "
        "active set (inexact Newton). A step is solved on to Tolerance when "
        "the active set does not change (its solution is the result) or "
        "when the sign of a node's complementarity function is not yet "
        "certain at this accuracy. Values at or below Tolerance solve every "
        "step to Tolerance.");
      prm.declare_entry("Max iterations",
                        "2000",
                        Patterns::Integer(1),
                        "Maximum number of CG iterations.");
      prm.declare_entry("Rigid body modes",
                        "true",
                        Patterns::Bool(),
                        "Give Trilinos ML the six rigid-body modes as "
                        "near-null space (false: the three translations).");
      prm.declare_entry("AMG aggregation threshold",
                        "0.02",
                        Patterns::Double(0),
                        "Trilinos ML aggregation threshold: matrix entries "
                        "weaker than this (relative) are dropped when "
                        "building aggregates.");
      prm.declare_entry("AMG smoother sweeps",
                        "2",
                        Patterns::Integer(1),
                        "Degree of the Chebyshev smoother of Trilinos ML.");
    }
    prm.leave_subsection();
  }

  void
  LinearSolver::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Linear solver");
    {
      tolerance             = prm.get_double("Tolerance");
      newton_step_tolerance = prm.get_double("Newton step tolerance");
      max_iterations        = prm.get_integer("Max iterations");
      rigid_body_modes      = prm.get_bool("Rigid body modes");
      aggregation_threshold = prm.get_double("AMG aggregation threshold");
      smoother_sweeps       = prm.get_integer("AMG smoother sweeps");
    }
    prm.leave_subsection();
  }
} // namespace TKR::Parameters
