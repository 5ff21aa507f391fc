// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.
//
// The mortar coupling loses and double-counts no area:
// (a) flat, non-matching, touching blocks (the patch mesh): sum_j D_jj is the
//     slave area, sum_k M_jk = D_jj, the mortar operator reproduces linear
//     fields (sum_k M_jk x_k = D_jj x_j) and all gaps vanish, to 1e-10;
// (b) a curved pair, two coaxial tubes with 16 and 24 facets around and a
//     radial clearance of 0.1 mm: sum_j D_jj is the (faceted) slave area and
//     sum_jk M_jk equals it to 1e-10; the gaps lie within the clearance
//     plus the facets' sagittas.

#include <deal.II/distributed/shared_tria.h>

#include <deal.II/grid/grid_generator.h>

#include <tkr/mesh/mesh.h>
#include <tkr/mortar/mortar_coupling.h>

#include "../tests.h"
#include "surface_pair.h"

namespace
{
  using namespace TKR;

  /** Checks on a coupling; @p h is a length for scaling the errors. */
  void
  check(const Mortar::MortarCoupling &coupling,
        const std::vector<Point<3>>  &x,
        const double                  expected_area,
        const double                  h,
        const bool                    flat)
  {
    const auto &s     = coupling.statistics();
    const auto &nodes = coupling.slave_nodes();
    deallog << "slave faces " << s.n_slave_faces << ", master faces "
            << s.n_master_faces << ", overlapping pairs "
            << s.n_overlapping_pairs << ", covered nodes " << s.n_covered_nodes
            << " of " << nodes.size() << std::endl;
    deallog << "candidate pairs per slave face below 12: "
            << yes_no(s.n_candidate_pairs < 12 * s.n_slave_faces) << std::endl;

    double sum_D = 0, sum_M = 0, row_error = 0, linear_error = 0;
    double min_gap = 1e300, max_gap = -1e300;
    for (unsigned int j = 0; j < nodes.size(); ++j)
      {
        const auto &node = nodes[j];
        sum_D += node.D;
        double       row = 0;
        Tensor<1, 3> mortar_x =
          -node.D * x[coupling.slave_surface().nodes()[j].vertex];
        for (const auto &[k, M] : node.M)
          {
            row += M;
            mortar_x += M * x[coupling.master_surface().nodes()[k].vertex];
          }
        sum_M += row;
        row_error    = std::max(row_error, std::abs(row - node.D) / node.D);
        linear_error = std::max(linear_error, mortar_x.norm() / (node.D * h));
        min_gap      = std::min(min_gap, node.weighted_gap / node.D);
        max_gap      = std::max(max_gap, node.weighted_gap / node.D);
      }
    deallog << "slave area (mm^2): " << sum_D << std::endl;
    deallog << "sum D_jj = area to 1e-10: "
            << yes_no(std::abs(sum_D - expected_area) < 1e-10 * expected_area)
            << std::endl;
    deallog << "sum M_jk = sum D_jj to 1e-10: "
            << yes_no(std::abs(sum_M - sum_D) < 1e-10 * sum_D) << std::endl;
    deallog << "row sums of M equal D to 1e-10: " << yes_no(row_error < 1e-10)
            << std::endl;
    if (flat)
      {
        deallog << "linear fields reproduced to 1e-10: "
                << yes_no(linear_error < 1e-10) << std::endl;
        deallog << "gaps zero to 1e-10 mm: "
                << yes_no(std::max(-min_gap, max_gap) < 1e-10) << std::endl;
      }
    else
      deallog << "gap range (um): " << std::setprecision(4) << 1e3 * min_gap
              << " .. " << 1e3 * max_gap << std::endl;
  }
} // namespace

int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  initlog();

  {
    deallog.push("flat");
    Triangulation<3> triangulation;
    read_test_mesh("verification/patch-coarse.msh", triangulation);
    const SurfacePair      surfaces(triangulation);
    Mortar::MortarCoupling coupling(surfaces.slave, surfaces.master);
    coupling.reinit(triangulation.get_vertices(), 1.);
    check(coupling, triangulation.get_vertices(), 400., 5., true);
    deallog.pop();
  }

  {
    deallog.push("curved");
    const double       R = 10., clearance = 0.1, L = 10.;
    const unsigned int n_slave = 16, n_master = 24;
    Triangulation<3>   inner, outer, triangulation;
    GridGenerator::cylinder_shell(inner, L, 8., R, n_slave, 3);
    GridGenerator::cylinder_shell(outer, L, R + clearance, 12., n_master, 4);
    GridGenerator::merge_triangulations(inner, outer, triangulation);
    for (const auto &cell : triangulation.active_cell_iterators())
      {
        const bool is_tibia =
          Point<2>(cell->center()[0], cell->center()[1]).norm() < R;
        cell->set_material_id(is_tibia ? Mesh::MaterialIds::tibia :
                                         Mesh::MaterialIds::femur);
        for (const auto &face : cell->face_iterators())
          if (face->at_boundary())
            {
              bool on_r = true, on_r_clearance = true;
              for (const auto v : face->vertex_indices())
                {
                  const double r =
                    Point<2>(face->vertex(v)[0], face->vertex(v)[1]).norm();
                  on_r = on_r && std::abs(r - R) < 1e-8;
                  on_r_clearance =
                    on_r_clearance && std::abs(r - R - clearance) < 1e-8;
                }
              face->set_boundary_id(on_r ? Mesh::BoundaryIds::tibia_contact :
                                    on_r_clearance ?
                                           Mesh::BoundaryIds::femur_contact :
                                           Mesh::BoundaryIds::free);
            }
      }
    const SurfacePair      surfaces(triangulation);
    Mortar::MortarCoupling coupling(surfaces.slave, surfaces.master);
    coupling.reinit(triangulation.get_vertices(), 1.);
    const double faceted_area =
      n_slave * 2. * R * std::sin(numbers::PI / n_slave) * L;
    check(coupling, triangulation.get_vertices(), faceted_area, 1., false);
    const double sagittas =
      R * (1 - std::cos(numbers::PI / n_slave)) +
      (R + clearance) * (1 - std::cos(numbers::PI / n_master));
    double min_gap = 1e300, max_gap = -1e300;
    for (const auto &node : coupling.slave_nodes())
      {
        min_gap = std::min(min_gap, node.weighted_gap / node.D);
        max_gap = std::max(max_gap, node.weighted_gap / node.D);
      }
    deallog << "gaps within clearance +- sagittas: "
            << yes_no(min_gap >= clearance - sagittas &&
                      max_gap <= clearance + sagittas)
            << std::endl;

    // reinit() keeps its working space: a second call on the same
    // positions gives the same nodes to the last bit.
    const auto first = coupling.slave_nodes();
    coupling.reinit(triangulation.get_vertices(), 1.);
    bool same = coupling.slave_nodes().size() == first.size();
    for (unsigned int j = 0; same && j < first.size(); ++j)
      {
        const auto &a = first[j], &b = coupling.slave_nodes()[j];
        same = a.weighted_gap == b.weighted_gap && a.D == b.D && a.M == b.M &&
               a.gap_gradient == b.gap_gradient && a.covered == b.covered;
      }
    deallog << "second reinit identical: " << yes_no(same) << ", generation "
            << coupling.generation() << std::endl;
    deallog.pop();
  }

  {
    // A square and the same square turned by 45 degrees meet in a regular
    // octagon of inradius 1: area 8 tan(pi/8), eight vertices.
    deallog.push("clip");
    const double          r       = std::sqrt(2.);
    const Mortar::Polygon square  = {Point<2>(-1, -1),
                                     Point<2>(1, -1),
                                     Point<2>(1, 1),
                                     Point<2>(-1, 1)};
    const Mortar::Polygon diamond = {Point<2>(r, 0),
                                     Point<2>(0, r),
                                     Point<2>(-r, 0),
                                     Point<2>(0, -r)};
    const Mortar::Polygon octagon = Mortar::clip_polygon(diamond, square);
    deallog << "vertices " << octagon.size() << ", area 8 tan(pi/8) to 1e-12: "
            << yes_no(std::abs(Mortar::signed_area(octagon) -
                               8. * std::tan(numbers::PI / 8.)) < 1e-12)
            << std::endl;
    deallog.pop();
  }
}
