// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <deal.II/base/numbers.h>

#include <tkr/base/exceptions.h>
#include <tkr/gait/tibia_pose.h>
#include <tkr/mesh/mesh.h>

#include <map>

namespace TKR::Gait
{
  using namespace dealii;

  TibiaPose::TibiaPose(const Parameters::Gait &parameters,
                       const GaitLoads        &gait_loads)
    : parameters(parameters)
    , gait_loads(gait_loads)
  {}

  // The simulator holds the insert in a tray that translates (x, y, z),
  // rotates about z (IE) and ab/adducts (about y), but does not tilt in the
  // sagittal plane. The inferior surface (flat, z = z_A) then moves as
  //   u = u_A + theta_z e_z x (x - x_A) + theta_y e_y x (x - x_A),
  // with theta_z = -(u_Bx - u_Ax)/(y_B - y_A) and
  // theta_y = -(u_Cz - u_Az)/(x_C - x_A) from three anchor nodes: A near the
  // centroid, B far from it in y, C far from it in x. Every other node of
  // the surface gets three constraint lines on these five DoFs.
  unsigned int
  TibiaPose::add_tray_constraints(const DoFHandler<3>       &dof_handler,
                                  AffineConstraints<double> &constraints) const
  {
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
    const auto    &vertices = dof_handler.get_triangulation().get_vertices();
    const Point<3> centroid = gait_loads.inferior_centroid();
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
            constraints.add_line(dofs[0]);
            constraints.add_entry(dofs[0], dA[0], 1. - dy / dy_B);
            constraints.add_entry(dofs[0], dB[0], dy / dy_B);
          }
        // u_y = u_Ay - (u_Bx - u_Ax) dx / dy_B
        constraints.add_line(dofs[1]);
        constraints.add_entry(dofs[1], dA[1], 1.);
        constraints.add_entry(dofs[1], dA[0], dx / dy_B);
        constraints.add_entry(dofs[1], dB[0], -dx / dy_B);
        // u_z = u_Az + (u_Cz - u_Az) dx / dx_C
        if (v != C)
          {
            constraints.add_line(dofs[2]);
            constraints.add_entry(dofs[2], dA[2], 1. - dx / dx_C);
            constraints.add_entry(dofs[2], dC[2], dx / dx_C);
          }
      }
    return nodes.size();
  }

  // The axial stabilisation spring acts on the displacement relative to the
  // pose only, so that no linear system is singular while the active set
  // is still wrong; it vanishes as the pose converges.
  Elasticity::BoundaryLoads
  TibiaPose::springs() const
  {
    Elasticity::BoundaryLoads loads = gait_loads.springs();
    Tensor<2, 3>              axial_spring;
    axial_spring[2][2] =
      parameters.axial_stabilisation_spring / gait_loads.inferior_area();
    loads.springs[Mesh::BoundaryIds::tibia_inferior] = axial_spring;
    return loads;
  }

  // The restraint springs act on pose plus displacement: the pose part,
  // -S(x) pose, is a traction.
  std::vector<Elasticity::BoundaryLoads>
  TibiaPose::load_basis() const
  {
    std::vector<Elasticity::BoundaryLoads> basis = gait_loads.traction_basis();
    const auto id     = Mesh::BoundaryIds::tibia_inferior;
    const auto spring = gait_loads.springs().spring_fields.at(id);
    for (unsigned int d = 0; d < 3; ++d)
      {
        Elasticity::BoundaryLoads pose;
        pose.traction_fields[id] = [spring, d](const Point<3> &x) {
          return Tensor<1, 3>(-spring(x)[d]);
        };
        basis.push_back(pose);
      }
    return basis;
  }

  std::vector<double>
  TibiaPose::load_coefficients(const GaitState &gait,
                               const PoseState &pose) const
  {
    std::vector<double> c = gait_loads.resultants(gait);
    c[1] += pose.restraint_force;
    c[2] += pose.restraint_torque;
    for (unsigned int d = 0; d < 3; ++d)
      c.push_back(pose.translation[d]);
    return c;
  }

  Elasticity::BoundaryLoads
  TibiaPose::loads(const GaitState &gait, const PoseState &pose) const
  {
    return Elasticity::linear_combination(load_basis(),
                                          load_coefficients(gait, pose),
                                          springs());
  }

  // The rigid part of the tibia's displacement, measured on its inferior
  // surface (far from the contact's local deformation): the mean
  // displacement int u / A (the work of the unit tractions 1/A), and the
  // rotation about z that fits it best,
  // theta = int (dx u_y - dy u_x) / int (dx^2 + dy^2) about the centroid
  // (the work of the traction (-dy, dx, 0) / J, in degrees).
  std::array<Elasticity::BoundaryLoads, 4>
  TibiaPose::motion_functionals() const
  {
    const auto    &surface = gait_loads.inferior_surface();
    const Point<3> c       = surface.centroid;
    std::array<Elasticity::BoundaryLoads, 4> functionals;
    for (unsigned int d = 0; d < 3; ++d)
      functionals[d].traction_fields[Mesh::BoundaryIds::tibia_inferior] =
        [d, area = surface.area](const Point<3> &) {
          Tensor<1, 3> t;
          t[d] = 1. / area;
          return t;
        };
    functionals[3].traction_fields[Mesh::BoundaryIds::tibia_inferior] =
      [c, J = surface.J](const Point<3> &x) {
        return Tensor<1, 3>({-(x[1] - c[1]) / J, (x[0] - c[0]) / J, 0.}) *
               (180. / numbers::PI);
      };
    return functionals;
  }

  InferiorMotion
  TibiaPose::motion_from(const std::array<double, 4> &functionals)
  {
    InferiorMotion motion;
    for (unsigned int d = 0; d < 3; ++d)
      motion.mean[d] = functionals[d];
    motion.rotation_z = functionals[3];
    return motion;
  }

  PoseIteration
  TibiaPose::iterate(
    PoseState                                                      &pose,
    const std::function<bool(const PoseState &, InferiorMotion &)> &solve) const
  {
    const double force_damping =
      parameters.ap_spring_stiffness / parameters.ap_spring_stiffness_beyond;
    const double torque_damping =
      parameters.ie_spring_stiffness / parameters.ie_spring_stiffness_beyond;
    // The rotation tolerance: the pose tolerance at the insert's rim.
    const double rotation_tolerance =
      parameters.pose_tolerance / (0.5 * gait_loads.inferior_surface().width) *
      180. / numbers::PI;

    PoseIteration result;
    double        relaxation = 1.;
    Tensor<1, 3>  previous_correction;
    for (unsigned int iteration = 0;; ++iteration)
      {
        const bool         contact_converged = solve(pose, result.motion);
        const Tensor<1, 3> mean              = result.motion.mean;
        const double       force_change =
          gait_loads.ap_restraint_excess(pose.translation[1] + mean[1]) -
          pose.restraint_force;
        const double torque_change =
          gait_loads.ie_restraint_excess(result.motion.rotation_z) -
          pose.restraint_torque;
        result.converged =
          mean.norm() <= parameters.pose_tolerance &&
          std::abs(force_change) <=
            parameters.ap_spring_stiffness_beyond * parameters.pose_tolerance &&
          std::abs(torque_change) <=
            parameters.ie_spring_stiffness_beyond * rotation_tolerance;
        if (!contact_converged || result.converged ||
            iteration + 1 >= max_iterations)
          break;
        pose.restraint_force += force_damping * force_change;
        pose.restraint_torque += torque_damping * torque_change;
        if (mean * previous_correction < 0)
          relaxation *= 0.5;
        previous_correction = relaxation * mean;
        pose.translation += previous_correction;
        ++result.n_updates;
      }
    return result;
  }
} // namespace TKR::Gait
