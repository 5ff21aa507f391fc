// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.
//
// The Hertz sphere (coarse) solved on all ranks of MPI_COMM_WORLD and, in
// the same run, by each rank alone (MPI_COMM_SELF): the same active set,
// and pressures and gaps (which contain the displacements) equal to 1e-10
// relative. The DoF numbering differs between the two (it follows the
// partition); the slave nodes do not.

#include <tkr/problems/contact_problem.h>

#include <fstream>

#include "../tests.h"

int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  initlog();
  const unsigned int rank = Utilities::MPI::this_mpi_process(MPI_COMM_WORLD);
  const std::string  prm  = "ranks_01-" + std::to_string(rank) + ".prm";
  {
    std::ofstream out(prm);
    out << "set Problem = contact\n"
        << "subsection Mesh\n  set File = " << SOURCE_DIR
        << "/../../meshes/verification/sphere-coarse.msh\nend\n"
        << "subsection Static contact\n  set Femur displacement = 0, 0, -0.3\n"
        << "end\n"
        << "subsection Linear solver\n  set Tolerance = 1e-13\nend\n"
        << "subsection Output\n  set Directory = results-" << rank
        << "\n  set VTU interval = 0\n  set Testing = true\nend\n";
  }
  const auto parameters = TKR::Parameters::read_parameters(prm);

  // Silence the problems' screen output; this test reports via deallog.
  std::streambuf               *screen = std::cout.rdbuf(nullptr);
  TKR::Problems::ContactProblem parallel(parameters, MPI_COMM_WORLD);
  const bool                    parallel_converged = parallel.run();
  TKR::Problems::ContactProblem serial(parameters, MPI_COMM_SELF);
  const bool                    serial_converged = serial.run();
  std::cout.rdbuf(screen);

  const auto &a     = parallel.get_state();
  const auto &b     = serial.get_state();
  double      max_p = 0, dp = 0, max_g = 0, dg = 0;
  for (unsigned int j = 0; j < a.pressure.size(); ++j)
    {
      max_p = std::max(max_p, std::abs(a.pressure[j]));
      dp    = std::max(dp, std::abs(a.pressure[j] - b.pressure[j]));
      if (std::isfinite(a.gap[j]))
        {
          max_g = std::max(max_g, std::abs(a.gap[j]));
          dg    = std::max(dg, std::abs(a.gap[j] - b.gap[j]));
        }
    }
  const bool same = Utilities::MPI::min(static_cast<int>(a.active == b.active &&
                                                         dp < 1e-10 * max_p &&
                                                         dg < 1e-10 * max_g),
                                        MPI_COMM_WORLD);
  deallog << "ranks: " << Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD)
          << ", both converged: "
          << yes_no(parallel_converged && serial_converged) << std::endl;
  deallog << "active nodes: " << a.n_active() << std::endl;
  deallog << "same active set, pressures and gaps to 1e-10: " << yes_no(same)
          << std::endl;
  if (!same)
    deallog << "differences: " << dp / max_p << ' ' << dg / max_g << std::endl;
}
