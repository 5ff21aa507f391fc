// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.
//
// Archard against an analytic answer: the flat blocks of the patch mesh,
// the tibia loaded by 1200 N and held only by contact. A two-step cycle
// slides the femur rigidly by s = 0.8 mm in y and back, so every point in
// contact slides 2 s per cycle and the worn volume must be k F 2 s (to
// 1e-8), the depth k p 2 s at every node.

#include <tkr/problems/contact_problem.h>
#include <tkr/wear/wear_law.h>

#include <fstream>

#include "../tests.h"

int
main(int argc, char **argv)
{
  using namespace TKR;
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  initlog();
  {
    std::ofstream out("archard_01.prm");
    out << "set Problem = contact\nsubsection Mesh\n  set File = " << SOURCE_DIR
        << "/../../meshes/verification/patch-fine.msh\nend\n"
        << "subsection Static contact\n  set Femur displacement = 0, 0, 0\n"
        << "  set Tibia inferior = loaded\n  set Axial force = 1200\nend\n"
        << "subsection Linear solver\n  set Tolerance = 1e-13\nend\n"
        << "subsection Output\n  set Directory = results\n"
        << "  set VTU interval = 0\n  set Testing = true\nend\n";
  }
  const auto      parameters = Parameters::read_parameters("archard_01.prm");
  std::streambuf *screen     = std::cout.rdbuf(nullptr);
  Problems::ContactProblem problem(parameters, MPI_COMM_WORLD);
  const bool               converged = problem.run();
  std::cout.rdbuf(screen);

  const double         k = 2e-7 * 1e-3; // mm^3/(N mm)
  const double         s = 0.8;         // mm
  Gait::RelativeMotion at_rest, slid;
  slid.femur.translation[1]                 = s;
  const std::vector<Wear::StepRecord> steps = {
    Wear::make_step_record(problem.get_coupling(),
                           problem.get_state(),
                           at_rest),
    Wear::make_step_record(problem.get_coupling(), problem.get_state(), slid)};
  const auto          law   = Wear::create_wear_law(parameters.wear);
  const auto          wear  = law->cycle_wear(Wear::CycleSliding(steps));
  const auto         &depth = wear.depth;
  const auto         &slip  = wear.slip;
  std::vector<double> area;
  for (const auto &node : problem.get_coupling().slave_nodes())
    area.push_back(node.D);
  const double volume = Wear::measure_wear(depth, area, 0.).volume;
  const double exact  = k * 1200. * 2. * s;

  double max_depth_error = 0;
  for (unsigned int j = 0; j < depth.size(); ++j)
    max_depth_error =
      std::max(max_depth_error,
               std::abs(depth[j] -
                        k * problem.get_state().pressure[j] * 2 * s));
  deallog << "contact converged: " << yes_no(converged) << std::endl;
  deallog << "worn volume / (k F 2 s): " << volume / exact << std::endl;
  deallog << "worn volume = k F 2 s to 1e-8: "
          << yes_no(std::abs(volume - exact) < 1e-8 * exact) << std::endl;
  deallog << "depth = k p 2 s at every node to 1e-8: "
          << yes_no(max_depth_error < 1e-8 * k * 3. * 2 * s) << std::endl;
  deallog << "slip of a node in contact (mm): " << slip[0] << std::endl;
}
