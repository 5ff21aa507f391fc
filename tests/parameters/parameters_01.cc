// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.
//
// The default parameter file written by print_default_parameters() reads
// back with the documented defaults; a file that changes some entries is
// read correctly; Lame constants follow from E and nu.

#include <tkr/parameters/parameters.h>

#include <fstream>

#include "../tests.h"

namespace
{
  void
  print(const TKR::Parameters::AllParameters &p)
  {
    deallog << "Problem: " << TKR::Parameters::to_string(p.problem)
            << std::endl;
    deallog << "Mesh: " << p.mesh.file << " degree " << p.mesh.fe_degree
            << " groups " << p.mesh.femur_name << ' ' << p.mesh.tibia_name
            << ' ' << p.mesh.femur_contact_name << ' '
            << p.mesh.femur_fixation_name << ' ' << p.mesh.tibia_contact_name
            << ' ' << p.mesh.tibia_inferior_name << std::endl;
    for (const auto *m : {&p.materials.femur, &p.materials.tibia})
      deallog << "Material: E " << m->youngs_modulus << " nu "
              << m->poissons_ratio << " density " << m->density << " lambda "
              << m->lambda() << " mu " << m->mu() << std::endl;
    deallog << "Elasticity: " << p.elasticity.femur_contact_traction << " | "
            << p.elasticity.tibia_contact_traction << std::endl;
    deallog << "Static contact: " << p.static_contact.femur_displacement
            << " loaded "
            << (p.static_contact.tibia_inferior ==
                TKR::Parameters::TibiaSupport::loaded)
            << " force " << p.static_contact.axial_force << std::endl;
    deallog << "Gait: " << p.gait.waveform_file << " steps "
            << p.gait.steps_per_cycle << " axis " << p.gait.flexion_axis_point
            << " medial " << p.gait.medial_direction << " offset "
            << p.gait.axial_load_offset << " springs "
            << p.gait.ap_spring_stiffness << ' ' << p.gait.ie_spring_stiffness
            << " signs " << p.gait.ap_force_sign << ' ' << p.gait.ie_torque_sign
            << std::endl;
    deallog << "Wear: k " << p.wear.wear_coefficient << " cycles "
            << p.wear.cycles << " n_Delta "
            << p.wear.cycles_per_extrapolation_step << " threshold "
            << p.wear.wear_area_threshold << std::endl;
    deallog << "Contact solver: ipopt "
            << (p.contact_solver.algorithm ==
                TKR::Parameters::ContactAlgorithm::ipopt)
            << " tolerance " << p.contact_solver.tolerance << " max "
            << p.contact_solver.max_iterations << std::endl;
    deallog << "Linear solver: " << p.linear_solver.tolerance << ' '
            << p.linear_solver.max_iterations << ' '
            << p.linear_solver.rigid_body_modes << std::endl;
    deallog << "Output: " << p.output.directory << ' ' << p.output.vtu_interval
            << ' ' << p.output.checkpoint_interval << ' ' << p.output.testing
            << std::endl;
  }
} // namespace

int
main()
{
  initlog();
  {
    std::ofstream out("defaults.prm");
    TKR::Parameters::print_default_parameters(out);
  }
  deallog.push("defaults");
  print(TKR::Parameters::read_parameters("defaults.prm"));
  deallog.pop();

  {
    std::ofstream out("changed.prm");
    out << "set Problem = contact\n"
        << "subsection Materials\n  subsection Tibia\n"
        << "    set Young's modulus = 1000\n    set Poisson's ratio = 0.25\n"
        << "  end\nend\n"
        << "subsection Static contact\n  set Tibia inferior = loaded\n"
        << "  set Femur displacement = 0.5, -1, 2e-3\nend\n"
        << "subsection Contact solver\n  set Solver = ipopt\nend\n"
        << "subsection Gait\n  set Medial side = -x\n  set AP force sign = -1\n"
        << "end\n";
  }
  deallog.push("changed");
  print(TKR::Parameters::read_parameters("changed.prm"));
  deallog.pop();
}
