// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.
//
// The cross-shear laws and the tables on the flat blocks of the patch
// mesh (as wear/archard_01): the femur slides rigidly by s = 0.8 mm in y
// and back, so every node in contact slides 2 s along one line (cross-shear
// 0) and the pressure is p_j. Against the definitions (doc/wear.md):
// - area law, C(0) = 3e-9: depth = C 2 s at every node in contact, the
//   same at 1200 N and 2400 N (independent of the load);
// - archard_cs with a constant table 2e-7 = archard (to 1e-14 relative);
// - archard_cs with k = 1e-7 at 0 MPa and 3e-7 at 20 MPa: depth =
//   k(p_j) p_j 2 s with k(p) = (1e-7 + 1e-8 p) 1e-3 mm^2/N.

#include <tkr/base/exceptions.h>
#include <tkr/problems/contact_problem.h>
#include <tkr/wear/cross_shear_laws.h>
#include <tkr/wear/wear_law.h>

#include <cmath>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include "../tests.h"

namespace
{
  using namespace TKR;

  const double s = 0.8; // mm

  /** The contact of the patch blocks under @p force: the pressures and the
   *  cycle sliding back and forth by s. */
  std::pair<std::vector<double>, Wear::CycleSliding>
  slide(const double force, Parameters::AllParameters &parameters)
  {
    {
      std::ofstream out("laws_01.prm");
      out << "set Problem = contact\nsubsection Mesh\n  set File = "
          << SOURCE_DIR << "/../../meshes/verification/patch-fine.msh\nend\n"
          << "subsection Static contact\n  set Femur displacement = 0, 0, 0\n"
          << "  set Tibia inferior = loaded\n  set Axial force = " << force
          << "\nend\nsubsection Linear solver\n  set Tolerance = 1e-13\nend\n"
          << "subsection Output\n  set Directory = results\n"
          << "  set VTU interval = 0\n  set Testing = true\nend\n";
    }
    parameters = Parameters::read_parameters("laws_01.prm");
    std::streambuf          *screen = std::cout.rdbuf(nullptr);
    Problems::ContactProblem problem(parameters, MPI_COMM_WORLD);
    AssertThrow(problem.run(), ExcMessage("The contact did not converge."));
    std::cout.rdbuf(screen);
    Gait::RelativeMotion at_rest, slid;
    slid.femur.translation[1]                 = s;
    const std::vector<Wear::StepRecord> steps = {
      Wear::make_step_record(problem.get_coupling(),
                             problem.get_state(),
                             at_rest),
      Wear::make_step_record(problem.get_coupling(),
                             problem.get_state(),
                             slid)};
    return {problem.get_state().pressure, Wear::CycleSliding(steps)};
  }

  std::vector<double>
  depth(const Parameters::Wear &wear, const Wear::CycleSliding &sliding)
  {
    return Wear::create_wear_law(wear)->cycle_wear(sliding).depth;
  }

  void
  write(const std::string &name, const std::string &text)
  {
    std::ofstream(name) << text;
  }
} // namespace

int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  initlog();
  write("c.csv", "# C(CS)\ncross_shear,C\n0,3e-9\n0.5,3e-9\n");
  write("k.csv", "cross_shear,k_mm3_per_Nm\n0,2e-7\n");
  write("kp.csv",
        "cross_shear,k_mm3_per_Nm,pressure_MPa\n0,1e-7,0\n0.5,1e-7,0\n"
        "0,3e-7,20\n0.5,3e-7,20\n");
  Parameters::AllParameters parameters;
  const auto [p1, sliding1] = slide(1200, parameters);
  const auto [p2, sliding2] = slide(2400, parameters);

  auto area = parameters.wear;
  area.law  = "area";
  area.laws.set("area", Wear::CrossShearLawParameters{"c.csv"});
  const auto   d1         = depth(area, sliding1);
  const auto   d2         = depth(area, sliding2);
  double       area_error = 0, load_difference = 0;
  unsigned int n_contact = 0;
  for (unsigned int j = 0; j < d1.size(); ++j)
    if (p1[j] > 0 && p2[j] > 0)
      {
        ++n_contact;
        area_error      = std::max(area_error, std::abs(d1[j] - 3e-9 * 2 * s));
        load_difference = std::max(load_difference, std::abs(d1[j] - d2[j]));
      }
  deallog << "nodes in contact at both loads: "
          << (n_contact > 10 ? "many" : "few") << std::endl;
  deallog << "area law: depth = C 2 s at every node to 1e-14 C 2 s: "
          << yes_no(area_error < 1e-14 * 3e-9 * 2 * s) << std::endl;
  deallog << "area law: depth at 2400 N = depth at 1200 N: "
          << yes_no(load_difference < 1e-14 * 3e-9 * 2 * s) << std::endl;

  const auto archard  = depth(parameters.wear, sliding1);
  auto       constant = parameters.wear;
  constant.law        = "archard_cs";
  constant.laws.set("archard_cs", Wear::CrossShearLawParameters{"k.csv"});
  const auto dc          = depth(constant, sliding1);
  auto       by_pressure = constant;
  by_pressure.laws.set("archard_cs", Wear::CrossShearLawParameters{"kp.csv"});
  const auto dp             = depth(by_pressure, sliding1);
  double     constant_error = 0, pressure_error = 0, largest = 0;
  for (unsigned int j = 0; j < dc.size(); ++j)
    {
      largest        = std::max(largest, archard[j]);
      constant_error = std::max(constant_error, std::abs(dc[j] - archard[j]));
      const double k = (1e-7 + 1e-8 * p1[j]) * 1e-3;
      pressure_error =
        std::max(pressure_error, std::abs(dp[j] - k * p1[j] * 2 * s));
    }
  deallog << "archard depth 2e-7 p 2 s > 0 somewhere: " << yes_no(largest > 0)
          << std::endl;
  deallog << "archard_cs, constant table = archard to 1e-14: "
          << yes_no(constant_error <= 1e-14 * largest) << std::endl;
  deallog << "archard_cs, k(p) table: depth = k(p) p 2 s to 1e-12: "
          << yes_no(pressure_error <= 1e-12 * largest) << std::endl;

  // The registry: the laws registered themselves; a name no law has and a
  // law without its table are refused with the law's own message.
  deallog << "registered laws: " << Wear::WearLaws::kind().names() << std::endl;
  for (const auto &[name, table] :
       std::vector<std::pair<std::string, std::string>>{{"energy", ""},
                                                        {"area", ""}})
    try
      {
        auto wear = parameters.wear;
        wear.law  = name;
        wear.laws.set(name, Wear::CrossShearLawParameters{table});
        Wear::create_wear_law(wear);
        deallog << name << ": accepted" << std::endl;
      }
    catch (const ExceptionBase &e)
      {
        deallog << name << ": refused: " << exception_message(e) << std::endl;
      }
}
