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

  namespace
  {
    /** The tibia_inferior vertices (of this rank's cells) and their DoFs. */
    std::map<unsigned int, std::array<types::global_dof_index, 3>>
    inferior_nodes(const DoFHandler<3> &dof_handler)
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
      return nodes;
    }
  } // namespace

  // The simulator holds the insert in a tray that translates (x, y, z),
  // rotates about z (IE) and ab/adducts (about y), but does not tilt in the
  // sagittal plane. A node at d = x - x_A from the anchor A then moves as
  //   u = u_A + theta_z e_z x d + theta_y e_y x d,
  // u_x = u_Ax - theta_z d_y + theta_y d_z, u_y = u_Ay + theta_z d_x,
  // u_z = u_Az - theta_y d_x, with the two angles read from two more
  // anchors: C far from A in x gives theta_y = -(u_Cz - u_Az) / dx_C, B
  // far from A in y gives theta_z = (u_Ax - u_Bx + theta_y dz_B) / dy_B.
  // Every other node gets three constraint lines on these five DoFs, at
  // its own position (d_z is not assumed zero: real inserts' backs are not
  // exactly planar). Only the flatness is checked: the distances of the
  // nodes from the least-squares plane z = a + b x + c y.
  // Holding the AP translation and the IE rotation (hold_ap_ie) adds
  // u_Ay = 0 and theta_z = 0, i.e. u_Bx = u_Ax + theta_y dz_B; every other
  // node's lines refer to these DoFs, close() resolves the chains.
  unsigned int
  TibiaPose::add_tray_constraints(const DoFHandler<3>       &dof_handler,
                                  AffineConstraints<double> &constraints,
                                  const bool                 hold_ap_ie) const
  {
    auto        nodes    = inferior_nodes(dof_handler);
    const auto &vertices = dof_handler.get_triangulation().get_vertices();
    check_tray_flatness(nodes, vertices);

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
    const Point<3>    &a  = vertices[A];
    const Tensor<1, 3> dB = vertices[B] - a, dC = vertices[C] - a;
    const auto        &uA = nodes[A], &uB = nodes[B], &uC = nodes[C];
    const auto         add = [&](const types::global_dof_index line,
                         const types::global_dof_index dof,
                         const double                  value) {
      if (value != 0.)
        constraints.add_entry(line, dof, value);
    };
    for (const auto &[v, dofs] : nodes)
      {
        if (v == A)
          continue;
        const Tensor<1, 3> d = vertices[v] - a;
        // theta_y d = (u_Az - u_Cz) d / dx_C; theta_z d = (u_Ax - u_Bx) d /
        // dy_B + (u_Az - u_Cz) (dz_B / dy_B) d / dx_C.
        const auto theta_y         = [&](const double d) { return d / dC[0]; };
        const auto theta_z_by_tilt = [&](const double d) {
          return dB[2] / dB[1] * d / dC[0];
        };
        // u_x = u_Ax - theta_z d_y + theta_y d_z (B's u_x is free)
        if (v != B)
          {
            constraints.add_line(dofs[0]);
            add(dofs[0], uA[0], 1. - d[1] / dB[1]);
            add(dofs[0], uB[0], d[1] / dB[1]);
            add(dofs[0], uA[2], -theta_z_by_tilt(d[1]) + theta_y(d[2]));
            add(dofs[0], uC[2], theta_z_by_tilt(d[1]) - theta_y(d[2]));
          }
        // u_y = u_Ay + theta_z d_x
        constraints.add_line(dofs[1]);
        add(dofs[1], uA[1], 1.);
        add(dofs[1], uA[0], d[0] / dB[1]);
        add(dofs[1], uB[0], -d[0] / dB[1]);
        add(dofs[1], uA[2], theta_z_by_tilt(d[0]));
        add(dofs[1], uC[2], -theta_z_by_tilt(d[0]));
        // u_z = u_Az - theta_y d_x (C's u_z is free)
        if (v != C)
          {
            constraints.add_line(dofs[2]);
            add(dofs[2], uA[2], 1. - theta_y(d[0]));
            add(dofs[2], uC[2], theta_y(d[0]));
          }
      }
    if (hold_ap_ie)
      {
        constraints.add_line(uA[1]);
        constraints.add_line(uB[0]);
        add(uB[0], uA[0], 1.);
        add(uB[0], uA[2], dB[2] / dC[0]);
        add(uB[0], uC[2], -dB[2] / dC[0]);
      }
    return nodes.size();
  }

  // The least-squares plane z = a + b x + c y through the inferior nodes;
  // farther from it than the tolerance (a fraction of the insert's width)
  // the tray cannot be rigid.
  void
  TibiaPose::check_tray_flatness(
    const std::map<unsigned int, std::array<types::global_dof_index, 3>> &nodes,
    const std::vector<Point<3>> &vertices) const
  {
    Tensor<2, 3> normal_matrix;
    Tensor<1, 3> rhs;
    for (const auto &node : nodes)
      {
        const Point<3>    &x = vertices[node.first];
        const Tensor<1, 3> phi({1., x[0], x[1]});
        normal_matrix += outer_product(phi, phi);
        rhs += x[2] * phi;
      }
    const Tensor<1, 3> plane     = invert(normal_matrix) * rhs;
    double             deviation = 0;
    Point<3>           farthest;
    for (const auto &node : nodes)
      {
        const Point<3> &x = vertices[node.first];
        const double    distance =
          std::abs(x[2] - plane[0] - plane[1] * x[0] - plane[2] * x[1]) /
          std::sqrt(1. + plane[1] * plane[1] + plane[2] * plane[2]);
        if (distance > deviation)
          {
            deviation = distance;
            farthest  = x;
          }
      }
    const double width     = gait_loads.inferior_surface().width;
    const double tolerance = parameters.tray_flatness_tolerance * width;
    AssertThrow(
      deviation <= tolerance,
      ExcInputError(
        "Gait/Tibial tray = rigid needs a nearly flat "
        "tibia_inferior surface, but its node at (" +
        format_number(farthest[0]) + ", " + format_number(farthest[1]) + ", " +
        format_number(farthest[2]) + ") lies " + format_number(deviation) +
        " mm from the least-squares plane of the surface, more "
        "than the Tray flatness tolerance (" +
        format_number(parameters.tray_flatness_tolerance) + " of the " +
        format_number(width) + " mm width = " + format_number(tolerance) +
        " mm). Check the mesh's tibia_inferior group, raise the "
        "tolerance or set Tibial tray = free."));
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
  // -S(x) pose, is a traction; for the rotation the pose's rigid
  // displacement is theta w with w = (-dy, dx, 0) about the centroid.
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
    Elasticity::BoundaryLoads ml;
    ml.tractions[id] = Tensor<1, 3>({1. / gait_loads.inferior_area(), 0., 0.});
    basis.push_back(ml);
    Elasticity::BoundaryLoads rotation;
    rotation.traction_fields[id] =
      [spring, c = gait_loads.inferior_centroid()](const Point<3> &x) {
        const Tensor<1, 3> w({-(x[1] - c[1]), x[0] - c[0], 0.});
        return Tensor<1, 3>(-(spring(x) * w) * numbers::PI / 180.);
      };
    basis.push_back(rotation);
    return basis;
  }

  // In the tibia's frame, turned by theta about z against the simulator's:
  // the AP force F (along the simulator's y) has the components
  // F (sin theta, cos theta) and the pose translation t those of
  // R^T t.
  std::vector<double>
  TibiaPose::load_coefficients(const GaitState &gait,
                               const PoseState &pose) const
  {
    std::vector<double> c     = gait_loads.resultants(gait);
    const double        theta = pose.rotation * numbers::PI / 180.;
    const double        cos = std::cos(theta), sin = std::sin(theta);
    const double        ap_force = c[1] + pose.restraint_force;
    const Tensor<1, 3> &t        = pose.translation;
    c[1]                         = ap_force * cos;
    c[2] += pose.restraint_torque;
    c.push_back(cos * t[0] + sin * t[1]);
    c.push_back(-sin * t[0] + cos * t[1]);
    c.push_back(t[2]);
    c.push_back(ap_force * sin);
    c.push_back(pose.rotation);
    return c;
  }

  RigidMotion
  TibiaPose::motion(const PoseState &pose) const
  {
    RigidMotion motion =
      RigidMotion::rotation_about(2,
                                  pose.rotation,
                                  gait_loads.inferior_centroid());
    motion.translation += pose.translation;
    return motion;
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

  namespace
  {
    /** The names of the inferior motion's observations. */
    const std::array<std::string, 4> motion_names = {
      {"inferior_mean_displacement_x",
       "inferior_mean_displacement_y",
       "inferior_mean_displacement_z",
       "inferior_rotation_z_deg"}};
  } // namespace

  std::vector<std::pair<std::string, Elasticity::BoundaryLoads>>
  TibiaPose::motion_observations() const
  {
    const auto functionals = motion_functionals();
    std::vector<std::pair<std::string, Elasticity::BoundaryLoads>> named;
    for (unsigned int i = 0; i < functionals.size(); ++i)
      named.emplace_back(motion_names[i], functionals[i]);
    return named;
  }

  double
  TibiaPose::axial_balance(const double        axial_force,
                           const Tensor<1, 3> &contact_resultant,
                           const double        relative_allowance) const
  {
    const double bound =
      parameters.axial_stabilisation_spring * parameters.pose_tolerance +
      relative_allowance * std::abs(axial_force);
    return std::abs(contact_resultant[2] + axial_force) / bound;
  }

  InferiorMotion
  TibiaPose::inferior_motion(const Observations &observations)
  {
    InferiorMotion motion;
    for (unsigned int d = 0; d < 3; ++d)
      motion.mean[d] = observations[motion_names[d]];
    motion.rotation_z = observations[motion_names[3]];
    return motion;
  }
} // namespace TKR::Gait
