// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.
//
// Time MortarCoupling::reinit() on a two-body mesh, as the gait calls it
// (about 900 times per cycle): the vertex positions of the mesh file (the
// 0 % pose), optionally the femur moved by DZ along z and then rotated by
// FLEXION degrees about the x axis through (y, z) = (-2, 53.001) (the
// flexion axis of the TKR A meshes).
//   cmake --build build/release --target mortar-coupling (scripts/run-tests
//   builds it)
//   build/release/mortar-coupling FILE.msh [N_CALLS [SEARCH_DISTANCE [DZ
//   [FLEXION [WINDOW]]]]]
// Prints the coupling statistics and the mean wall time of one call. With
// WINDOW > 0 (mm) the timed calls use a coupling window of that width
// around the faces' clearances at no displacement (as the gait's solves,
// whose window follows the previous solve's deformed clearances).

#include <deal.II/base/mpi.h>
#include <deal.II/base/numbers.h>
#include <deal.II/base/timer.h>

#include <deal.II/dofs/dof_handler.h>

#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_system.h>

#include <deal.II/grid/tria.h>

#include <tkr/mesh/mesh.h>
#include <tkr/mortar/mortar_coupling.h>

#include <iomanip>
#include <iostream>

int
main(int argc, char **argv)
{
  using namespace dealii;
  using namespace TKR;
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  if (argc < 2)
    {
      std::cerr << "usage: mortar-coupling FILE.msh [N_CALLS "
                   "[SEARCH_DISTANCE [DZ [FLEXION [WINDOW]]]]]"
                << std::endl;
      return 1;
    }
  const unsigned int n_calls         = argc > 2 ? std::stoi(argv[2]) : 20;
  const double       search_distance = argc > 3 ? std::stod(argv[3]) : 2.;
  const double       dz              = argc > 4 ? std::stod(argv[4]) : 0.;
  const double       flexion =
    (argc > 5 ? std::stod(argv[5]) : 0.) * numbers::PI / 180.;
  Mortar::CouplingWindow window;
  window.width = argc > 6 ? std::stod(argv[6]) : 0.;

  Triangulation<3> triangulation;
  Mesh::read_mesh(Parameters::Mesh::with_default_groups(argv[1]),
                  triangulation);
  const FESystem<3> fe(FE_Q<3>(1), 3);
  DoFHandler<3>     dof_handler(triangulation);
  dof_handler.distribute_dofs(fe);
  const Mortar::ContactSurface slave(dof_handler,
                                     Mesh::BoundaryIds::tibia_contact);
  const Mortar::ContactSurface master(dof_handler,
                                      Mesh::BoundaryIds::femur_contact);
  Mortar::MortarCoupling       coupling(slave, master);

  std::vector<Point<3>>   positions = triangulation.get_vertices();
  const std::vector<bool> is_femur =
    Mesh::material_vertices(triangulation, Mesh::MaterialIds::femur);
  for (unsigned int v = 0; v < positions.size(); ++v)
    if (is_femur[v])
      {
        const double y  = positions[v][1] + 2.,
                     z  = positions[v][2] + dz - 53.001;
        positions[v][1] = -2. + std::cos(flexion) * y - std::sin(flexion) * z;
        positions[v][2] =
          53.001 + std::sin(flexion) * y + std::cos(flexion) * z;
      }

  coupling.reinit(positions, search_distance); // warm-up
  if (window.width > 0)
    window.face_clearance =
      coupling.face_clearances(std::vector<Tensor<1, 3>>(slave.nodes().size()),
                               0.);
  Timer timer;
  for (unsigned int i = 0; i < n_calls; ++i)
    coupling.reinit(positions,
                    search_distance,
                    unit_symmetric_tensor<3>(),
                    &window);
  timer.stop();

  const auto &s = coupling.statistics();
  std::cout << argv[1] << ": " << s.n_slave_faces << " slave faces, "
            << s.n_master_faces << " master faces, search distance "
            << search_distance << " mm, femur moved by " << dz
            << " mm and flexed by " << flexion * 180. / numbers::PI << " deg"
            << std::endl
            << "  candidate pairs " << s.n_candidate_pairs
            << ", overlapping pairs " << s.n_overlapping_pairs
            << ", covered nodes " << s.n_covered_nodes << " of "
            << coupling.slave_nodes().size() << std::endl
            << "  integrated faces " << s.n_integrated_faces
            << " (fully covered " << s.n_fully_covered_faces << ", partly "
            << s.n_partly_covered_faces << ", over-covered "
            << s.n_overcovered_faces << ", invalid " << s.n_invalid_faces
            << "), rejected pairs " << s.n_rejected_pairs << ", fitted faces "
            << s.n_fitted_faces << ", fitting error " << s.fitting_error
            << ", quadrature points " << s.n_quadrature_points << std::endl
            << "  partly covered nodes " << s.n_partly_covered_nodes
            << ", touched but not covered " << s.n_uncovered_touched_nodes
            << std::endl
            << "  covered area " << s.covered_area << " of slave area "
            << s.slave_area << " mm^2" << std::endl;
  if (window.width > 0)
    std::cout << "  window " << window.width << " mm: slave faces within the "
              << "search distance " << s.n_faces_in_reach << ", near "
              << s.n_near_faces << ", integrated " << s.n_window_faces
              << ", nodes left out " << s.n_left_out_nodes << std::endl;
  std::cout << "  reinit: " << std::fixed << std::setprecision(2)
            << 1e3 * timer.wall_time() / n_calls << " ms per call (mean of "
            << n_calls << ")" << std::endl;
}
