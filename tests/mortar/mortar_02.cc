// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.
//
// Mortar coupling on unstructured, non-matching surfaces (tetrahedra split
// into hexahedra: meshes/verification/patch-unstructured.msh, 198 slave
// against 354 master quadrilaterals of different size and orientation on
// the flat interface z = 0 of a 20 x 20 mm square):
// (a) touching: sum_j D_jj = area = sum_jk M_jk = covered area, every node
//     covered, row sums of M equal D, linear fields reproduced
//     (sum_k M_jk x_k = D_jj x_j), all gaps 0, to 1e-12;
// (b) the femur lifted by 0.25 mm: g_j / D_jj = 0.25 mm at every node to
//     1e-12 relative;
// (c) the femur tilted about the y axis (gap 0.25 + 0.01 x mm):
//     g_j / D_jj equals the gap at the node to 1e-12 mm;
// (d) the femur lifted by 0.25 mm and shifted by (7.3, -4.1) mm, so that it
//     covers 12.7 x 15.9 mm of the slave surface (the edge rule): the
//     covered area is exactly that; the nodes with the full constraint (no
//     edge offset) are those that lie on the femur's footprint, more than
//     1 mm from its edges and away from its corner (those outside need to
//     penetrate before they carry a force); every node with any coverage,
//     partly covered ones included, has g_j / D_jj minus its edge offset = 0.25
//     mm to 1e-12 (no fake gaps at the edge), and its row of M sums to D_jj;
// (e) as (d), tilted as in (c): at fully covered nodes g_j / D_jj is the
//     gap at the node; at partly covered nodes a mean of the gap over the
//     covered part of the support, within the range of the gap there.

#include <tkr/mesh/mesh.h>
#include <tkr/mortar/mortar_coupling.h>

#include <functional>

#include "../tests.h"
#include "surface_pair.h"

namespace
{
  using namespace TKR;

  /** Femur vertices moved by @p motion, tibia vertices kept. */
  std::vector<Point<3>>
  moved(const Triangulation<3>                          &triangulation,
        const std::function<Point<3>(const Point<3> &)> &motion)
  {
    std::vector<Point<3>>   x = triangulation.get_vertices();
    const std::vector<bool> is_femur =
      Mesh::material_vertices(triangulation, Mesh::MaterialIds::femur);
    for (unsigned int v = 0; v < x.size(); ++v)
      if (is_femur[v])
        x[v] = motion(x[v]);
    return x;
  }

  void
  report(const Mortar::MortarCoupling &coupling)
  {
    const auto &s = coupling.statistics();
    deallog << "slave faces " << s.n_slave_faces << ", master faces "
            << s.n_master_faces << ", integration cells "
            << s.n_overlapping_pairs << ", faces fully covered "
            << s.n_fully_covered_faces << ", partly "
            << s.n_partly_covered_faces << std::endl;
    deallog << "covered nodes " << s.n_covered_nodes << " (partly "
            << s.n_partly_covered_nodes << "), touched but not covered "
            << s.n_uncovered_touched_nodes << ", of "
            << coupling.slave_nodes().size() << std::endl;
    deallog << "rejected pairs " << s.n_rejected_pairs << ", fitted faces "
            << s.n_fitted_faces
            << ", fitting exact to 1e-13: " << yes_no(s.fitting_error < 1e-13)
            << std::endl;
    deallog << "slave area " << s.slave_area << " mm^2, covered area "
            << s.covered_area << " mm^2" << std::endl;
  }

  /**
   * Largest deviation of g_j / D_jj from @p gap(x_j) over the nodes with
   * any coverage (fully covered ones only if @p fully_only), and largest
   * relative deviation of a row sum of M from D_jj.
   */
  std::pair<double, double>
  gap_errors(const Mortar::MortarCoupling                  &coupling,
             const std::vector<Point<3>>                   &x,
             const std::function<double(const Point<3> &)> &gap,
             const bool                                     fully_only)
  {
    double gap_error = 0, row_error = 0;
    for (unsigned int j = 0; j < coupling.slave_nodes().size(); ++j)
      {
        const auto &node = coupling.slave_nodes()[j];
        if (node.covered_fraction == 0 ||
            (fully_only && node.covered_fraction < 1 - 1e-9))
          continue;
        const Point<3> &xj = x[coupling.slave_surface().nodes()[j].vertex];
        // (Relative to 1 mm plus the offset: a node with little coverage
        // has an offset of up to 1e5 mm, with its round-off.)
        gap_error  = std::max(gap_error,
                             std::abs(node.weighted_gap / node.D -
                                      node.gap_offset - gap(xj)) /
                               (1. + node.gap_offset));
        double row = 0;
        for (const auto &entry : node.M)
          row += entry.second;
        row_error = std::max(row_error, std::abs(row - node.D) / node.D);
      }
    return {gap_error, row_error};
  }
} // namespace

int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  initlog();
  Triangulation<3> triangulation;
  read_test_mesh("verification/patch-unstructured.msh", triangulation);
  const SurfacePair             surfaces(triangulation);
  const Mortar::ContactSurface &slave  = surfaces.slave,
                               &master = surfaces.master;
  Mortar::MortarCoupling coupling(slave, master);
  const double           g0 = 0.25, slope = 0.01;

  {
    deallog.push("touching");
    const auto &x = triangulation.get_vertices();
    coupling.reinit(x, 1.);
    report(coupling);
    const auto  &s     = coupling.statistics();
    const auto  &nodes = coupling.slave_nodes();
    double       sum_D = 0, sum_M = 0, linear_error = 0, gap_error = 0;
    unsigned int n_covered = 0;
    for (unsigned int j = 0; j < nodes.size(); ++j)
      {
        const auto  &node     = nodes[j];
        Tensor<1, 3> mortar_x = -node.D * x[slave.nodes()[j].vertex];
        for (const auto &[k, M] : node.M)
          {
            sum_M += M;
            mortar_x += M * x[master.nodes()[k].vertex];
          }
        sum_D += node.D;
        n_covered += node.covered;
        linear_error = std::max(linear_error, mortar_x.norm() / (node.D * 20.));
        gap_error = std::max(gap_error, std::abs(node.weighted_gap / node.D));
      }
    const auto [unused, row_error] = gap_errors(
      coupling,
      x,
      [](const Point<3> &) { return 0.; },
      false);
    (void)unused;
    deallog << "sum D_jj = 400 mm^2 to 1e-12: "
            << yes_no(std::abs(sum_D - 400.) < 1e-12 * 400.) << std::endl;
    deallog << "covered area = 400 mm^2 to 1e-12: "
            << yes_no(std::abs(s.covered_area - 400.) < 1e-12 * 400.)
            << std::endl;
    deallog << "sum M_jk = covered area to 1e-12: "
            << yes_no(std::abs(sum_M - s.covered_area) < 1e-12 * 400.)
            << std::endl;
    deallog << "all nodes covered: " << yes_no(n_covered == nodes.size())
            << std::endl;
    deallog << "row sums of M = D_jj to 1e-12: " << yes_no(row_error < 1e-12)
            << std::endl;
    deallog << "linear fields reproduced to 1e-12: "
            << yes_no(linear_error < 1e-12) << std::endl;
    deallog << "gaps zero to 1e-12 mm: " << yes_no(gap_error < 1e-12)
            << std::endl;
    deallog.pop();
  }

  {
    deallog.push("lifted");
    const auto x = moved(triangulation, [&](const Point<3> &p) {
      return p + Tensor<1, 3>({0., 0., g0});
    });
    coupling.reinit(x, 1.);
    const auto [error, row_error] = gap_errors(
      coupling,
      x,
      [&](const Point<3> &) { return g0; },
      false);
    deallog << "covered nodes " << coupling.statistics().n_covered_nodes
            << std::endl;
    deallog << "g_j / D_jj = 0.25 mm to 1e-12 relative: "
            << yes_no(error < 1e-12 * g0) << std::endl;
    deallog << "row sums of M = D_jj to 1e-12: " << yes_no(row_error < 1e-12)
            << std::endl;
    deallog.pop();
  }

  const auto tilt = [&](const Point<3> &p) {
    return Point<3>(p[0], p[1], p[2] + g0 + slope * p[0]);
  };
  {
    deallog.push("tilted");
    const auto x = moved(triangulation, tilt);
    coupling.reinit(x, 1.);
    const auto [error, row_error] = gap_errors(
      coupling,
      x,
      [&](const Point<3> &p) { return g0 + slope * p[0]; },
      false);
    deallog << "g_j / D_jj = gap at the node to 1e-12 mm: "
            << yes_no(error < 1e-12) << std::endl;
    deallog << "row sums of M = D_jj to 1e-12: " << yes_no(row_error < 1e-12)
            << std::endl;
    deallog.pop();
  }

  const Tensor<1, 3> shift({7.3, -4.1, g0});
  const auto on_footprint = [&](const Point<3> &p, const double tolerance) {
    return p[0] >= shift[0] - tolerance && p[1] <= 20. + shift[1] + tolerance;
  };
  {
    deallog.push("edge");
    const auto x =
      moved(triangulation, [&](const Point<3> &p) { return p + shift; });
    coupling.reinit(x, 1.);
    report(coupling);
    const double exact_area = (20. - shift[0]) * (20. + shift[1]);
    deallog << "covered area = " << exact_area << " mm^2 to 1e-12: "
            << yes_no(std::abs(coupling.statistics().covered_area -
                               exact_area) < 1e-12 * exact_area)
            << std::endl;
    unsigned int n_inside = 0, n_wrong = 0;
    for (unsigned int j = 0; j < slave.nodes().size(); ++j)
      {
        const Point<3> &p = x[slave.nodes()[j].vertex];
        n_inside += on_footprint(p, 0.);
        // Nodes within 1 mm of the footprint's edge may go either way (the
        // rule is half the support covered), and so may nodes near its
        // corner (a node inside may have less than half covered there).
        if (on_footprint(p, -1.) != on_footprint(p, 1.) ||
            (std::abs(p[0] - shift[0]) < 3. &&
             std::abs(p[1] - 20. - shift[1]) < 3.))
          continue;
        const auto &node = coupling.slave_nodes()[j];
        n_wrong += (node.covered_fraction > 0 &&
                    (node.gap_offset == 0.) != on_footprint(p, 0.));
      }
    deallog << "nodes on the footprint " << n_inside
            << ", nodes more than 1 mm from its edges with the full "
               "constraint iff on it (off its corner): "
            << yes_no(n_wrong == 0) << std::endl;
    const auto [error, row_error] = gap_errors(
      coupling,
      x,
      [&](const Point<3> &) { return g0; },
      false);
    deallog << "g_j / D_jj minus the edge offset = 0.25 mm to 1e-12 "
               "relative at every node with coverage: "
            << yes_no(error < 1e-12 * g0) << std::endl;
    deallog << "row sums of M = D_jj to 1e-12: " << yes_no(row_error < 1e-12)
            << std::endl;
    deallog.pop();
  }

  {
    deallog.push("edge+tilt");
    const auto x = moved(triangulation, [&](const Point<3> &p) {
      return tilt(p + Tensor<1, 3>({shift[0], shift[1], 0.}));
    });
    coupling.reinit(x, 1.);
    // The gap at a slave point p: the femur surface above it is at
    // z = g0 + slope p_x.
    const auto gap = [&](const Point<3> &p) { return g0 + slope * p[0]; };
    const auto [error, row_error] = gap_errors(coupling, x, gap, true);
    deallog << "fully covered nodes: g_j / D_jj = gap at the node to 1e-12 "
               "mm: "
            << yes_no(error < 1e-12) << std::endl;
    // A partly covered node's support reaches at most h = 3 mm from it.
    unsigned int n_partly = 0, n_outside = 0;
    for (unsigned int j = 0; j < slave.nodes().size(); ++j)
      {
        const auto &node = coupling.slave_nodes()[j];
        if (node.covered_fraction == 0 || node.covered_fraction >= 1 - 1e-9)
          continue;
        ++n_partly;
        const Point<3> &p    = x[slave.nodes()[j].vertex];
        const double    mean = node.weighted_gap / node.D - node.gap_offset;
        n_outside += (std::abs(mean - gap(p)) > slope * 3.);
      }
    deallog << "partly covered nodes " << n_partly
            << ", their gap a mean over the covered part: "
            << yes_no(n_outside == 0) << std::endl;
    deallog.pop();
  }
}
