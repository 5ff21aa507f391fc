// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.
//
// ISO 14243-3 displacement control (Gait::DisplacementControl) on the
// coarse TKR A, against force control and against a rigid rotation:
// 1. Force control, 20 steps (every 5 %) (ML held by a stiff ML spring in both
//    protocols, so that the tray's x is the same in both). Displacement
//    control then prescribes the AP position and IE rotation that force
//    control reached (a waveform written from its poses, same flexion and
//    axial force). Its reactions (the AP force and IE torque that hold the
//    tray) must equal what held the tibia under force control (applied
//    force and torque plus restraints, i.e. minus the contact's force
//    along the tray's y and its moment about the IE axis), within what the
//    pose tolerance allows: the contact's AP stiffness (a finite difference
//    of the reactions over the AP positions) times the tolerance, and the
//    same for IE.
// 2. Zero axial load, flexion 0, the IE rotation prescribed from -1.5 to 6
//    deg in 4 steps: no contact force and no elastic displacement (no
//    strain). The tray's height is solved for a contact force of 0, which
//    any height clear of the femur gives: the iteration stops where the
//    femur just touches, with a contact force below the stabilisation
//    spring times the pose tolerance; with a pose tolerance of 1e-8 mm:
//    contact force < 1e-4 N, elastic displacement < 1e-6 mm. And the slip
//    between two steps that the wear chain computes (CycleSliding, for
//    femur points spread over the insert put into the records with a unit
//    pressure) is the tangential part of the rigid rotation's field minus
//    the change of the (vanishing) elastic displacement, computed here
//    independently (the femur point X at R(-phi)(X - c - t) + c in the
//    tray's frame, phi the rotation about +z through the inferior centroid
//    c: -internal for medial +x), to 1e-12 mm.

#include <deal.II/base/numbers.h>

#include <tkr/base/mpi.h>
#include <tkr/gait/displacement_control.h>
#include <tkr/gait/force_control.h>
#include <tkr/parameters/parameters.h>
#include <tkr/problems/gait_cycle.h>
#include <tkr/problems/two_body_model.h>
#include <tkr/wear/sliding.h>

#include <fstream>
#include <sstream>

#include "../tests.h"

namespace
{
  using namespace TKR;

  struct CycleResult
  {
    std::vector<Gait::StepReport> reports;
    std::vector<Wear::StepRecord> records;
    Point<3>                      centroid;
  };

  /** One gait cycle of the coarse TKR A with the Gait entries @p gait. */
  CycleResult
  run_cycle(const std::string &name, const std::string &gait)
  {
    const std::string prm = name + ".prm";
    if (Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) == 0)
      {
        std::ofstream out(prm);
        out << "set Problem = wear\n"
            << "subsection Mesh\n  set File = " << SOURCE_DIR
            << "/../../meshes/tkr/tkr-a-coarse.msh\nend\n"
            << "subsection Gait\n  set Flexion axis point = 0, -2, 53.001\n"
            << "  set ML spring stiffness = 1e5\n"
            << gait << "end\n"
            << "subsection Contact solver\n"
            << "  set Initial contact distance = 0.05\nend\n"
            << "subsection Output\n  set Directory = results-" << name
            << "\n  set VTU interval = 0\n  set Testing = true\nend\n";
      }
    MPI_Barrier(MPI_COMM_WORLD);
    const auto             parameters = Parameters::read_parameters(prm);
    std::streambuf        *screen     = std::cout.rdbuf(nullptr);
    StepGroups             groups(MPI_COMM_WORLD, 1);
    Problems::TwoBodyModel model(parameters,
                                 MPI_COMM_WORLD,
                                 groups.communicator);
    model.make_grid();
    model.distribute_dofs();
    Problems::GaitCycle cycle(model, groups, parameters.gait);
    cycle.setup();
    cycle.solve(false, false, true);
    std::cout.rdbuf(screen);
    return {cycle.get_reports(),
            cycle.get_records(),
            Gait::measure_inferior_surface(model.triangulation()).centroid};
  }

  /** A waveform file of the rows @p rows (percent first). */
  void
  write_waveform(const std::string                      &file,
                 const std::string                      &header,
                 const std::vector<std::vector<double>> &rows)
  {
    if (Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) != 0)
      return;
    std::ofstream out(file);
    out << header << '\n' << std::setprecision(17);
    for (const auto &row : rows)
      {
        for (unsigned int i = 0; i < row.size(); ++i)
          out << (i > 0 ? "," : "") << row[i];
        out << '\n';
      }
  }

  // Part 1: the reactions against force control.
  void
  reactions_against_force_control()
  {
    std::vector<std::vector<double>> rows;
    // data/iso14243-1.csv in 20 steps (every 5 % of the cycle).
    const std::string force_gait =
      "  set Waveform file = " + std::string(SOURCE_DIR) +
      "/../../data/iso14243-1.csv\n  set Steps per cycle = 20\n";
    const CycleResult force = run_cycle("force", force_gait);

    // The waveform of displacement control: every step's flexion, axial
    // force and the pose force control reached (AP along +y, IE internal =
    // about -z with medial +x).
    for (unsigned int s = 0; s < force.reports.size(); ++s)
      {
        const auto &r    = force.reports[s];
        const auto  pose = Gait::ForceControl::pose_state(r.pose);
        rows.push_back({r.input.percent,
                        r.input.values[0],
                        r.input.values[1],
                        pose.translation[1],
                        -pose.rotation});
      }
    rows.push_back(rows[0]);
    rows.back()[0] = 100;
    write_waveform("prescribed.csv",
                   "percent_cycle,flexion_deg,axial_force_N,"
                   "ap_displacement_mm,ie_rotation_deg",
                   rows);
    MPI_Barrier(MPI_COMM_WORLD);
    const CycleResult displacement =
      run_cycle("displacement",
                "  set Control = displacement\n"
                "  set Waveform file = prescribed.csv\n"
                "  set Steps per cycle = 20\n");

    const double        medial = 1; // Medial side = +x
    double              max_ap = 0, max_ie = 0, d_ap = 0, d_ie = 0;
    double              k_ap = 0, k_ie = 0;
    bool                all_converged = true;
    std::vector<double> ap_held, ie_held, ap_position, ie_position;
    for (unsigned int s = 0; s < force.reports.size(); ++s)
      {
        const auto &f = force.reports[s];
        const auto &d = displacement.reports[s];
        all_converged = all_converged && f.converged && d.converged;
        // What held the tibia under force control, in the tray's frame.
        const double moment_z =
          f.contact_moment[2] -
          cross_product_3d(force.centroid, f.contact_resultant)[2];
        const double ap = -f.contact_resultant[1];
        const double ie = medial * moment_z * 1e-3;
        ap_held.push_back(ap);
        ie_held.push_back(ie);
        ap_position.push_back(rows[s][3]);
        ie_position.push_back(rows[s][4]);
        max_ap = std::max(max_ap, std::abs(ap));
        max_ie = std::max(max_ie, std::abs(ie));
        d_ap   = std::max(d_ap, std::abs(d.pose_values[0] - ap));
        d_ie   = std::max(d_ie, std::abs(d.pose_values[1] - ie));
        if (s > 0 && std::abs(ap_position[s] - ap_position[s - 1]) > 0.05)
          k_ap = std::max(k_ap,
                          std::abs((ap_held[s] - ap_held[s - 1]) /
                                   (ap_position[s] - ap_position[s - 1])));
        if (s > 0 && std::abs(ie_position[s] - ie_position[s - 1]) > 0.05)
          k_ie = std::max(k_ie,
                          std::abs((ie_held[s] - ie_held[s - 1]) /
                                   (ie_position[s] - ie_position[s - 1])));
      }
    // The pose tolerance bounds the force-controlled position's error (mm;
    // the IE one at the insert's rim, 35 mm).
    const double tolerance    = 1e-3;
    const double ie_tolerance = tolerance / (35. * numbers::PI / 180.);
    const double ap_bound     = 2 * k_ap * tolerance + 1e-3 * max_ap;
    const double ie_bound     = 2 * k_ie * ie_tolerance + 1e-3 * max_ie;
    deallog << "steps: " << force.reports.size()
            << ", all converged under both protocols: " << yes_no(all_converged)
            << std::endl;
    deallog << "largest AP force holding the tibia (N / 100): "
            << std::setprecision(3) << max_ap / 100 << std::endl;
    deallog << "largest IE torque holding the tibia (N m): " << max_ie
            << std::endl;
    deallog << "AP reaction = force control's AP force within "
               "2 x contact stiffness x pose tolerance: "
            << yes_no(d_ap <= ap_bound) << std::endl;
    deallog << "IE reaction = force control's IE torque within "
               "2 x contact stiffness x pose tolerance: "
            << yes_no(d_ie <= ie_bound) << std::endl;
    std::cout << "differences " << d_ap << " N (bound " << ap_bound << "), "
              << d_ie << " N m (bound " << ie_bound << ")" << std::endl;
  }

  // Part 2: a rigid IE rotation without load.
  void
  rigid_rotation()
  {
    const std::vector<double>        angles = {-1.5, 0.5, 3, 6};
    std::vector<std::vector<double>> rows;
    for (unsigned int s = 0; s < angles.size(); ++s)
      rows.push_back({25. * s, 0., 0., 0., angles[s]});
    rows.push_back({100., 0., 0., 0., angles[0]});
    write_waveform("rotation.csv",
                   "percent_cycle,flexion_deg,axial_force_N,"
                   "ap_displacement_mm,ie_rotation_deg",
                   rows);
    MPI_Barrier(MPI_COMM_WORLD);
    CycleResult result = run_cycle("rotation",
                                   "  set Control = displacement\n"
                                   "  set Waveform file = rotation.csv\n"
                                   "  set Steps per cycle = 4\n"
                                   "  set Pose tolerance = 1e-8\n");
    double      force = 0, displacement = 0;
    for (const auto &r : result.reports)
      force = std::max(force, r.contact_resultant.norm());
    unsigned int n_covered = 0;
    for (auto &record : result.records)
      for (unsigned int j = 0; j < record.pressure.size(); ++j)
        {
          displacement = std::max(displacement, record.displacement[j].norm());
          // No node is in contact: give every node a unit pressure and a
          // femur point spread over the insert (20 mm up), so that the
          // wear chain computes the slips of those points.
          record.pressure[j] = 1;
          record.femur_point[j] =
            Point<3>(-30. + 60. * std::fmod(0.618 * j, 1.),
                     -25. + 50. * std::fmod(0.377 * j, 1.),
                     20.);
        }
    const Wear::CycleSliding sliding(result.records);
    double                   error = 0, largest = 0;
    const auto in_tray = [&](const Wear::StepRecord &r, const Point<3> &X) {
      // T^{-1}(X) = R(-phi)(X - c - t) + c, phi from the tray's rotation.
      const double       phi = std::atan2(r.motion.tibia.rotation[1][0],
                                    r.motion.tibia.rotation[0][0]);
      const Point<3>    &c   = result.centroid;
      const Tensor<1, 3> t   = r.motion.tibia(c) - c;
      const Tensor<1, 3> a   = X - c - t;
      return Point<3>(c[0] + std::cos(phi) * a[0] + std::sin(phi) * a[1],
                      c[1] - std::sin(phi) * a[0] + std::cos(phi) * a[1],
                      c[2] + a[2]);
    };
    for (unsigned int i = 0; i < sliding.n_intervals(); ++i)
      {
        const auto &a = result.records[i];
        const auto &b = result.records[(i + 1) % result.records.size()];
        for (unsigned int j = 0; j < sliding.n_nodes(); ++j)
          if (a.pressure[j] > 0)
            {
              ++n_covered;
              const Point<3> &X = a.femur_point[j];
              Tensor<1, 3>    s = in_tray(b, X) - in_tray(a, X) -
                               (b.displacement[j] - a.displacement[j]);
              s -= (s * a.normal[j]) * a.normal[j];
              error =
                std::max(error, (sliding.interval(i).slip_start[j] - s).norm());
              largest = std::max(largest, s.norm());
            }
      }
    std::cout << "rotation: force " << force << " N, displacement "
              << displacement << " mm, slip error " << error << " mm"
              << std::endl;
    deallog << "rigid IE rotation without load: contact force 0: "
            << yes_no(force < 1e-4)
            << ", elastic displacement 0: " << yes_no(displacement < 1e-6)
            << std::endl;
    deallog << "slips equal the rotation's field to 1e-12 mm: "
            << yes_no(n_covered > 100 && error < 1e-12) << " (largest slip "
            << std::setprecision(3) << largest << " mm)" << std::endl;
  }
} // namespace

int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  initlog();
  reactions_against_force_control();
  rigid_rotation();
}
