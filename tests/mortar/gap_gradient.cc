// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.
//
// Mortar::SlaveNode::gap_gradient, the derivative of the weighted gap with
// respect to a rigid translation of the master surface, against central
// differences of the coupling itself (the femur translated by +-h in x, y
// and z), on the coarse TKR A and the unstructured mesh-implant output,
// the femur flexed by 0 and 30 degrees and lowered until it touches. The
// pose Newton of the gait (doc/gait.md) builds its Jacobian from it. Over
// the nodes whose support stays fully covered (a partly covered node's
// gap jumps where its coverage changes): the largest error relative to the
// largest derivative, for the gradient and for D_jj n_j (the surfaces taken
// parallel, the first version): the gradient is right to 1e-3, D n is not.

#include <tkr/mesh/mesh.h>
#include <tkr/mortar/mortar_coupling.h>

#include "../tests.h"
#include "surface_pair.h"

namespace
{
  using namespace TKR;

  void
  check(const std::string &name, const double degrees)
  {
    Triangulation<3> triangulation;
    read_test_mesh("tkr/" + name, triangulation);
    const SurfacePair      surfaces(triangulation);
    Mortar::MortarCoupling coupling(surfaces.slave, surfaces.master);
    const double           search_distance = 2;

    // Lower the femur until it touches (the smallest mean gap).
    Tensor<1, 3> lowered;
    coupling.reinit(femur_moved(triangulation, degrees, lowered),
                    search_distance);
    double smallest = 1e300;
    for (const auto &node : coupling.slave_nodes())
      if (node.covered)
        smallest = std::min(smallest, node.weighted_gap / node.D);
    lowered[2] = -smallest;
    coupling.reinit(femur_moved(triangulation, degrees, lowered),
                    search_distance);
    const std::vector<Mortar::SlaveNode> nodes = coupling.slave_nodes();

    const double h       = 1e-4;
    double       largest = 0, error = 0, parallel_error = 0;
    unsigned int n_nodes = 0;
    for (unsigned int d = 0; d < 3; ++d)
      {
        Tensor<1, 3> plus = lowered, minus = lowered;
        plus[d] += h;
        minus[d] -= h;
        coupling.reinit(femur_moved(triangulation, degrees, plus),
                        search_distance);
        const std::vector<Mortar::SlaveNode> up = coupling.slave_nodes();
        coupling.reinit(femur_moved(triangulation, degrees, minus),
                        search_distance);
        const std::vector<Mortar::SlaveNode> &down = coupling.slave_nodes();
        for (unsigned int j = 0; j < nodes.size(); ++j)
          if (nodes[j].covered_fraction >= 1. - 1e-9 &&
              up[j].covered_fraction >= 1. - 1e-9 &&
              down[j].covered_fraction >= 1. - 1e-9)
            {
              const double fd =
                (up[j].weighted_gap - down[j].weighted_gap) / (2 * h);
              largest = std::max(largest, std::abs(fd));
              error = std::max(error, std::abs(nodes[j].gap_gradient[d] - fd));
              parallel_error =
                std::max(parallel_error,
                         std::abs(nodes[j].D * nodes[j].normal[d] - fd));
              n_nodes += (d == 0);
            }
      }
    deallog << name << ", femur flexed by " << degrees
            << " deg: fully covered nodes "
            << (n_nodes > 20 ? "over" : "not over")
            << " 20; largest error of the gap gradient below 1e-3 of the "
               "largest derivative: "
            << yes_no(error <= 1e-3 * largest)
            << "; of D n (parallel surfaces) below 1e-3: "
            << yes_no(parallel_error <= 1e-3 * largest) << std::endl;
  }
} // namespace

int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  initlog();
  for (const std::string name : {"tkr-a-coarse.msh", "tkr-a-implant.msh"})
    for (const double degrees : {0., 30.})
      check(name, degrees);
}
