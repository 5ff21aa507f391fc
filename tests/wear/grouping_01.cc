// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.
//
// The wear of a (10-step) gait cycle on the coarse TKR does not depend on
// how the steps are distributed: two step groups of one rank, one group of
// two ranks, and one rank alone give the same wear depth at every node
// (to 1e-6 of the largest depth: the contact solves agree to the linear
// solver's tolerance, 1e-10, and the pose iteration stops within 0.01 mm).
// Two groups of one rank each solve every step alone, as one rank does:
// they agree to round-off (1.3e-12 with the pose Newton, whose dense LU
// and compliance columns batched differently per group change the last
// digits; below 1e-10).

#include <tkr/problems/wear_problem.h>

#include <fstream>

#include "../tests.h"

namespace
{
  std::vector<double>
  run(const std::string &prm_text,
      const unsigned int groups,
      const MPI_Comm     communicator,
      const std::string &name)
  {
    const std::string prm =
      name + "-" +
      std::to_string(Utilities::MPI::this_mpi_process(MPI_COMM_WORLD)) + ".prm";
    // (each rank's own file and directory: a run on both ranks writes only
    // rank 0's, so no VTU, whose pieces every rank would write)
    {
      std::ofstream out(prm);
      out << prm_text << "subsection Gait\n  set Step groups = " << groups
          << "\nend\nsubsection Output\n  set Directory = results-" << prm
          << "\n  set VTU interval = 0\n  set Worn VTU interval = 0\n  set "
             "Plots = false\n  set Testing = true\nend\n";
    }
    const auto      parameters = TKR::Parameters::read_parameters(prm);
    std::streambuf *screen     = std::cout.rdbuf(nullptr);
    TKR::Problems::WearProblem problem(parameters, communicator);
    const bool                 converged = problem.run();
    std::cout.rdbuf(screen);
    deallog << name << ": converged " << yes_no(converged) << std::endl;
    return problem.get_wear_depth();
  }

  double
  difference(const std::vector<double> &a, const std::vector<double> &b)
  {
    double max = 0, diff = 0;
    for (unsigned int j = 0; j < a.size(); ++j)
      {
        max  = std::max(max, std::abs(a[j]));
        diff = std::max(diff, std::abs(a[j] - b[j]));
      }
    return diff / max;
  }
} // namespace

int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  initlog();
  const std::string source = SOURCE_DIR;
  const std::string prm_text =
    "set Problem = wear\nsubsection Mesh\n  set File = " + source +
    "/../../meshes/tkr/tkr-a-coarse.msh\nend\n"
    "subsection Gait\n  set Waveform file = " +
    source +
    "/../../data/iso14243-1.csv\n  set Steps per cycle = 10\n"
    "  set Flexion axis point = 0, -2, 53.001\n"
    "  set ML spring stiffness = 10\nend\n"
    "subsection Wear\n  set Cycles per extrapolation step = 5e6\nend\n"
    "subsection Contact solver\n  set Initial contact distance = 0.05\nend\n";

  const auto two_groups = run(prm_text, 2, MPI_COMM_WORLD, "two groups");
  const auto one_group  = run(prm_text, 1, MPI_COMM_WORLD, "one group of two");
  const auto serial     = run(prm_text, 1, MPI_COMM_SELF, "one rank");
  double     max_depth  = 0;
  for (const double d : serial)
    max_depth = std::max(max_depth, d);
  deallog << "wear depth found: " << yes_no(max_depth > 0) << std::endl;
  deallog << "differences: "
          << (difference(two_groups, serial) < 1e-10 ? "below 1e-10" : "larger")
          << ", "
          << (difference(one_group, serial) < 1e-6 ? "below 1e-6" : "larger")
          << std::endl;
  deallog << "two groups = one rank to 1e-6: "
          << yes_no(difference(two_groups, serial) < 1e-6) << std::endl;
  deallog << "one group of two = one rank to 1e-6: "
          << yes_no(difference(one_group, serial) < 1e-6) << std::endl;
}
