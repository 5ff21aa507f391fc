// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.
//
// The rigid tibial tray (TibiaPose::add_tray_constraints) on inferior
// surfaces that are not exactly planar: the coarse TKR mesh with its
// tibia_inferior nodes moved off the plane by up to 0.03 mm (as on a
// CAD-derived insert), and the same surface tilted by 2 degrees about x.
// The constraints must reproduce every rigid motion of the tray (a
// translation, a rotation about z, one about y) at every node to 1e-12,
// and a surface 1 mm off its plane must be refused with a message that
// names the deviation.

#include <deal.II/dofs/dof_handler.h>

#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_system.h>

#include <deal.II/lac/vector.h>

#include <tkr/base/exceptions.h>
#include <tkr/gait/tibia_pose.h>
#include <tkr/mesh/mesh.h>

#include <cmath>
#include <map>

#include "../tests.h"

namespace
{
  using namespace TKR;

  Parameters::Gait
  gait_parameters()
  {
    Parameters::Gait gait;
    gait.axial_load_offset       = 0.07;
    gait.medial_direction        = 1;
    gait.ml_spring_stiffness     = 10;
    gait.tray_flatness_tolerance = 1e-3;
    return gait;
  }

  /**
   * Move the tibia_inferior vertices by dz(x, y) along z, then tilt the
   * whole mesh by @p tilt (rad) about the x axis.
   */
  void
  deform(Triangulation<3>                              &triangulation,
         const std::function<double(const Point<3> &)> &dz,
         const double                                   tilt)
  {
    std::vector<bool> moved(triangulation.n_vertices(), false);
    for (const auto &cell : triangulation.active_cell_iterators())
      for (const auto f : cell->face_indices())
        if (cell->face(f)->at_boundary() &&
            cell->face(f)->boundary_id() == Mesh::BoundaryIds::tibia_inferior)
          for (const auto v : cell->face(f)->vertex_indices())
            if (!moved[cell->face(f)->vertex_index(v)])
              {
                Point<3> &x = cell->face(f)->vertex(v);
                x[2] += dz(x);
                moved[cell->face(f)->vertex_index(v)] = true;
              }
    const double      c = std::cos(tilt), s = std::sin(tilt);
    std::vector<bool> rotated(triangulation.n_vertices(), false);
    for (const auto &cell : triangulation.active_cell_iterators())
      for (const auto v : cell->vertex_indices())
        if (!rotated[cell->vertex_index(v)])
          {
            Point<3>    &x = cell->vertex(v);
            const double y = x[1], z = x[2];
            x[1]                           = c * y - s * z;
            x[2]                           = s * y + c * z;
            rotated[cell->vertex_index(v)] = true;
          }
  }

  /**
   * The largest difference between the constrained displacement of the
   * inferior nodes and the rigid motion u = t + w x (x - x_0) whose values
   * at the free DoFs were set (w has no x component: no sagittal tilt).
   */
  double
  rigid_motion_error(const Triangulation<3> &triangulation)
  {
    const Gait::InferiorSurface surface =
      Gait::measure_inferior_surface(triangulation);
    const Parameters::Gait parameters = gait_parameters();
    Gait::Restraints       restraints;
    restraints.ap_spring_stiffness = 9.3;
    restraints.ie_spring_stiffness = 130;
    const Gait::GaitLoads gait_loads(parameters, restraints, surface);
    const Gait::TibiaPose pose(parameters, gait_loads);
    DoFHandler<3>         dof_handler(triangulation);
    dof_handler.distribute_dofs(FESystem<3>(FE_Q<3>(1), 3));
    AffineConstraints<double> constraints;
    pose.add_tray_constraints(dof_handler, constraints);
    constraints.close();

    const Tensor<1, 3>                        t({0.1, -0.2, 0.05});
    const Tensor<1, 3>                        w({0., 0.003, -0.004});
    const Point<3>                            x0 = surface.centroid;
    Vector<double>                            u(dof_handler.n_dofs());
    std::map<types::global_dof_index, double> exact;
    for (const auto &cell : dof_handler.active_cell_iterators())
      for (const auto f : cell->face_indices())
        if (cell->face(f)->at_boundary() &&
            cell->face(f)->boundary_id() == Mesh::BoundaryIds::tibia_inferior)
          for (const auto v : cell->face(f)->vertex_indices())
            {
              const Tensor<1, 3> motion =
                t + cross_product_3d(w, cell->face(f)->vertex(v) - x0);
              for (unsigned int c = 0; c < 3; ++c)
                {
                  const auto dof = cell->face(f)->vertex_dof_index(v, c);
                  exact[dof]     = motion[c];
                  u(dof)         = motion[c];
                }
            }
    // Keep the values of the free (anchor) DoFs, rebuild the others.
    constraints.distribute(u);
    double error = 0;
    for (const auto &[dof, value] : exact)
      error = std::max(error, std::abs(u(dof) - value));
    return error;
  }

  Triangulation<3>
  coarse_tkr()
  {
    Triangulation<3> triangulation;
    Mesh::read_mesh(Parameters::Mesh::with_default_groups(
                      std::string(SOURCE_DIR) +
                      "/../../meshes/tkr/tkr-a-coarse.msh"),
                    triangulation);
    return triangulation;
  }
} // namespace

int
main()
{
  initlog();
  const auto wavy = [](const Point<3> &x) {
    return 0.03 * std::sin(0.3 * x[0]) * std::cos(0.2 * x[1]);
  };
  for (const double tilt : {0., 2. * numbers::PI / 180.})
    {
      Triangulation<3> triangulation = coarse_tkr();
      deform(triangulation, wavy, tilt);
      const double error = rigid_motion_error(triangulation);
      deallog << "surface off its plane by up to 0.03 mm, tilted "
              << std::round(tilt * 180. / numbers::PI)
              << " deg: rigid tray motion reproduced to 1e-12: "
              << yes_no(error < 1e-12) << std::endl;
    }

  Triangulation<3> triangulation = coarse_tkr();
  deform(
    triangulation,
    [](const Point<3> &x) { return x[0] > 0 ? 1. : 0.; },
    0.);
  try
    {
      rigid_motion_error(triangulation);
      deallog << "a 1 mm step in the surface was accepted" << std::endl;
    }
  catch (const ExcInputError &exc)
    {
      deallog << exception_message(exc) << std::endl;
    }
}
