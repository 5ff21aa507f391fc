// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.
//
// The tractions GaitLoads puts on tibia_inferior (coarse TKR mesh) add up
// to the prescribed axial and AP force, the medial offset moment of the
// axial force and the IE torque (to 1e-10 of the axial force), with the
// documented signs for both medial sides; the distributed springs have the
// prescribed rigid-body stiffnesses in y (AP) and about z (IE) (in x the
// ML spring plus the rotation spring's by-product).

#include <deal.II/base/numbers.h>
#include <deal.II/base/quadrature_lib.h>

#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/mapping_q1.h>

#include <tkr/gait/gait_loads.h>
#include <tkr/mesh/mesh.h>

#include "../tests.h"

int
main()
{
  using namespace TKR;
  initlog();
  Parameters::Mesh mesh = Parameters::Mesh::with_default_groups(
    std::string(SOURCE_DIR) + "/../../meshes/tkr/tkr-a-coarse.msh");
  Triangulation<3> triangulation;
  Mesh::read_mesh(mesh, triangulation);
  const auto surface = Gait::measure_inferior_surface(triangulation);
  deallog << "inferior area " << surface.area << " mm^2, width "
          << surface.width << " mm" << std::endl;

  Parameters::Gait gait;
  gait.axial_load_offset   = 0.07;
  gait.ml_spring_stiffness = 10;
  gait.flexion_axis_point  = Point<3>(0, -2, 53);
  Gait::Restraints restraints;
  restraints.ap_spring_stiffness        = 9.3;
  restraints.ie_spring_stiffness        = 130;
  restraints.ap_spring_range            = 2.5;
  restraints.ap_spring_stiffness_beyond = 44;
  restraints.ie_spring_range            = 6;
  restraints.ie_spring_stiffness_beyond = 360;

  const FE_Q<3>         fe(1);
  const MappingQ1<3>    mapping;
  FEFaceValues<3>       fe_face_values(mapping,
                                 fe,
                                 QGauss<2>(3),
                                 update_quadrature_points | update_JxW_values);
  const Gait::GaitState state{13, 15.31, 2600, -120, 4.5};

  for (const int medial : {1, -1})
    {
      gait.medial_direction = medial;
      const Gait::GaitLoads gait_loads(gait, restraints, surface);
      const auto            loads = gait_loads.loads(state);
      Tensor<1, 3>          force, moment;
      Tensor<2, 3>          translation_stiffness;
      double                rotation_stiffness = 0;
      for (const auto &cell : triangulation.active_cell_iterators())
        for (const auto f : cell->face_indices())
          if (cell->face(f)->at_boundary() &&
              cell->face(f)->boundary_id() == Mesh::BoundaryIds::tibia_inferior)
            {
              fe_face_values.reinit(cell, f);
              for (const unsigned int q :
                   fe_face_values.quadrature_point_indices())
                {
                  const Point<3> &x   = fe_face_values.quadrature_point(q);
                  const double    JxW = fe_face_values.JxW(q);
                  const auto      t =
                    loads.traction(Mesh::BoundaryIds::tibia_inferior, x);
                  const auto S =
                    loads.spring(Mesh::BoundaryIds::tibia_inferior, x);
                  force += t * JxW;
                  moment += cross_product_3d(x - surface.centroid, t) * JxW;
                  translation_stiffness += S * JxW;
                  const Tensor<1, 3> w({-(x[1] - surface.centroid[1]),
                                        x[0] - surface.centroid[0],
                                        0.});
                  rotation_stiffness += w * (S * w) * JxW;
                }
            }
      const Tensor<1, 3> F = gait_loads.force(state);
      // Only the x and y moments of the axial and AP parts about the
      // centroid of the (not necessarily flat) surface; z is the torque.
      const Tensor<1, 3> M = gait_loads.moment(state);
      deallog << "medial side " << (medial > 0 ? "+x" : "-x") << std::endl;
      deallog << "  force (N): " << force << std::endl;
      deallog << "  force = (0, AP, axial) to 1e-10: "
              << yes_no((force - F).norm() < 1e-10 * F.norm()) << std::endl;
      deallog << "  moment about centroid (N mm): y " << moment[1] << ", z "
              << moment[2] << std::endl;
      deallog << "  offset moment -e F_z and IE torque to 1e-10: "
              << yes_no(std::abs(moment[1] - M[1]) <
                          1e-10 * F.norm() * surface.width &&
                        std::abs(moment[2] - M[2]) <
                          1e-10 * F.norm() * surface.width)
              << std::endl;
      deallog << "  e = " << -M[1] / F[2] << " mm (0.07 x width, medial)"
              << std::endl;
      deallog << "  ML stiffness (N/mm): " << translation_stiffness[0][0]
              << std::endl;
      deallog << "  AP stiffness = 9.3 N/mm to 1e-10: "
              << yes_no(std::abs(translation_stiffness[1][1] - 9.3) <
                        1e-10 * 9.3)
              << std::endl;
      deallog << "  IE stiffness = 130 N mm/deg to 1e-10: "
              << yes_no(std::abs(rotation_stiffness * numbers::PI / 180. -
                                 130.) < 1e-10 * 130.)
              << std::endl;
    }
  // The two-rate restraints: the linear inner rate (in the springs) plus
  // the excess give the ISO law, and the excess acts through a traction
  // with exactly the requested resultants.
  const Gait::GaitLoads gait_loads(gait, restraints, surface);
  deallog << "two-rate restraint (linear rate + excess):" << std::endl;
  for (const double d : {1., 4., -4.})
    deallog << "  AP at " << d
            << " mm: " << -9.3 * d + gait_loads.ap_restraint_excess(d) << " N"
            << std::endl;
  deallog << "  AP at 4 mm = -(9.3 x 2.5 + 44 x 1.5) N to 1e-12: "
          << yes_no(std::abs(-9.3 * 4 + gait_loads.ap_restraint_excess(4.) +
                             (9.3 * 2.5 + 44 * 1.5)) < 1e-12 * 89.25)
          << std::endl;
  for (const double theta : {5., 10., -10.})
    deallog << "  IE at " << theta
            << " deg: " << -130 * theta + gait_loads.ie_restraint_excess(theta)
            << " N mm" << std::endl;
  const auto   traction = gait_loads.restraint_traction(-50., 700.);
  Tensor<1, 3> force, moment;
  for (const auto &cell : triangulation.active_cell_iterators())
    for (const auto f : cell->face_indices())
      if (cell->face(f)->at_boundary() &&
          cell->face(f)->boundary_id() == Mesh::BoundaryIds::tibia_inferior)
        {
          fe_face_values.reinit(cell, f);
          for (const unsigned int q : fe_face_values.quadrature_point_indices())
            {
              const Point<3>    &x = fe_face_values.quadrature_point(q);
              const Tensor<1, 3> t = traction(x);
              force += t * fe_face_values.JxW(q);
              moment += cross_product_3d(x - surface.centroid, t) *
                        fe_face_values.JxW(q);
            }
        }
  deallog << "  restraint traction: force (0, -50, 0) N and torque 700 N mm "
             "about z to 1e-10: "
          << yes_no((force - Tensor<1, 3>({0., -50., 0.})).norm() <
                      1e-10 * 50 &&
                    std::abs(moment[2] - 700.) < 1e-10 * 700.)
          << std::endl;
}
