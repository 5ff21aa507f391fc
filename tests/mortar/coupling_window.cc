// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.
//
// The coupling window of MortarCoupling::reinit() on the TKR meshes: the
// block-structured coarse TKR A and the unstructured mesh-implant output
// (tkr-a-implant.msh, warped faces), the femur at its mesh position and
// flexed by 30 degrees about the flexion axis and lowered until it touches:
// (a) the face distance bounds are lower bounds: no covered node of the
//     coupling over the whole search distance has a mean gap g_j / D_jj
//     below the smallest bound of its faces (less a tolerance of 0.01 mm
//     for the mortar mean against the pointwise bound);
// (b) with windows of 0.05 and 0.3 mm around the clearances at no
//     displacement: every node that is not left out has the same row
//     (D_jj, covered, weighted gap, M) as over the whole search distance,
//     to 1e-12; left-out nodes are not covered and have no row; every
//     node with a gap below the window's width (less 0.01 mm) is kept;
// (c) window_holds(): true at no displacement and when the tibia moves
//     1 mm away from the femur, false when it moves towards it by the
//     width, or the femur's displacement bound is the width.

#include <deal.II/base/numbers.h>

#include <tkr/mesh/mesh.h>
#include <tkr/mortar/mortar_coupling.h>

#include "../tests.h"
#include "surface_pair.h"

namespace
{
  using namespace TKR;

  /** The vertices with the femur flexed by @p degrees and lowered by
   *  @p dz. */
  std::vector<Point<3>>
  femur_moved(const Triangulation<3> &triangulation,
              const double            degrees,
              const double            dz)
  {
    return ::femur_moved(triangulation, degrees, Tensor<1, 3>({0., 0., -dz}));
  }

  /** True if the rows of node @p j agree to 1e-12. */
  bool
  same_row(const Mortar::SlaveNode &a, const Mortar::SlaveNode &b)
  {
    const double scale = a.D;
    bool         same  = a.covered == b.covered && a.M.size() == b.M.size() &&
                std::abs(a.D - b.D) <= 1e-12 * scale &&
                std::abs(a.weighted_gap - b.weighted_gap) <= 1e-12 * scale;
    for (unsigned int k = 0; same && k < a.M.size(); ++k)
      same = a.M[k].first == b.M[k].first &&
             std::abs(a.M[k].second - b.M[k].second) <= 1e-12 * scale;
    return same;
  }

  void
  check(const std::string &name, const double degrees)
  {
    Triangulation<3> triangulation;
    read_test_mesh("tkr/" + name, triangulation);
    const SurfacePair      surfaces(triangulation);
    const auto            &slave = surfaces.slave;
    Mortar::MortarCoupling full(slave, surfaces.master),
      narrow(slave, surfaces.master);
    const double search_distance = 2;

    // Flexed: lower the femur until it touches (the smallest mean gap).
    std::vector<Point<3>> x = femur_moved(triangulation, degrees, 0.);
    full.reinit(x, search_distance);
    x = femur_moved(triangulation, degrees, smallest_gap(full));
    full.reinit(x, search_distance);
    deallog << name << ", femur flexed by " << degrees << " deg: covered nodes "
            << full.statistics().n_covered_nodes << " of "
            << slave.nodes().size() << ", smallest gap "
            << (std::abs(smallest_gap(full)) < 0.01 ? "below" : "not below")
            << " 0.01 mm" << std::endl;

    // (a) Lower bounds: g_j / D_jj against the smallest bound of the
    // node's faces.
    const std::vector<Tensor<1, 3>> zero(slave.nodes().size());
    const std::vector<double>       clearance = full.face_clearances(zero, 0.);
    double                          worst     = 1e300;
    for (unsigned int j = 0; j < slave.nodes().size(); ++j)
      if (full.slave_nodes()[j].covered)
        {
          double bound = 1e300;
          for (const unsigned int e : slave.node_faces()[j])
            bound = std::min(bound, clearance[e]);
          worst = std::min(worst,
                           full.slave_nodes()[j].weighted_gap /
                               full.slave_nodes()[j].D -
                             bound);
        }
    deallog << "  mean gaps above their face bounds less 0.01 mm: "
            << yes_no(worst >= -0.01) << std::endl;

    for (const double width : {0.05, 0.3})
      {
        // (b) The same rows where kept.
        Mortar::CouplingWindow window;
        window.width          = width;
        window.face_clearance = clearance;
        narrow.reinit(x, search_distance, unit_symmetric_tensor<3>(), &window);
        const auto  &s         = narrow.statistics();
        bool         same      = true;
        bool         near_kept = true;
        unsigned int left_out  = 0;
        for (unsigned int j = 0; j < slave.nodes().size(); ++j)
          {
            const auto &a = full.slave_nodes()[j];
            const auto &b = narrow.slave_nodes()[j];
            if (!b.covered && b.M.empty() && a.covered_fraction > 0 &&
                !same_row(a, b))
              {
                ++left_out;
                near_kept = near_kept &&
                            !(a.covered && a.weighted_gap / a.D < width - 0.01);
              }
            else
              same = same && same_row(a, b);
          }
        deallog << "  window " << width << " mm: integrated faces "
                << s.n_window_faces << " (faces in reach " << s.n_faces_in_reach
                << ", near " << s.n_near_faces << ")"
                << "; left-out nodes counted alike: "
                << yes_no(left_out <= s.n_left_out_nodes)
                << "; kept rows the same: " << yes_no(same)
                << "; nodes within the width kept: " << yes_no(near_kept)
                << std::endl;

        // (c) The check of a solve.
        std::vector<Tensor<1, 3>> away(zero), towards(zero);
        for (unsigned int j = 0; j < zero.size(); ++j)
          {
            away[j]    = -narrow.slave_nodes()[j].normal;
            towards[j] = width * narrow.slave_nodes()[j].normal;
          }
        deallog << "  holds at no displacement: "
                << yes_no(narrow.window_holds(zero, 0.))
                << ", tibia 1 mm away: "
                << yes_no(narrow.window_holds(away, 0.))
                << ", by the width towards: "
                << yes_no(narrow.window_holds(towards, 0.))
                << ", femur displaced by the width: "
                << yes_no(narrow.window_holds(zero, width)) << std::endl;
      }
  }
} // namespace

int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  initlog();
  for_each_tkr_a_pose(check);
}
