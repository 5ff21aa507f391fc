// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.
//
// Geometry::MeshMotion and Geometry::WornGeometry with a smooth wear-like
// depth field d = d0 (1 + sin(x / 10) cos(y / 8) / 2), d0 = 2 um, on
// tibia_contact, moved inward along the worn surface's nodal normals:
// - on a smooth curved surface (the outer sphere of half a spherical
//   shell, R = 30 mm, inner sphere tibia_inferior, the cut plane free),
//   refined twice: the volume the tibia loses equals sum_j d_j A_j (A_j
//   the nodal areas) to O(h^2), the difference shrinking about 4-fold per
//   halving of h;
// - on the coarse and medium TKR A insert, whose surface has creases (the
//   dishes meet the plateau), where the averaged nodal normal makes the
//   difference O(h): below 4 % and shrinking;
// - always: the tibia_contact vertices move by exactly -d n, the
//   tibia_inferior vertices and the femur do not move, the free sides do
//   not bulge (they slide), no cell distorts, and the geometry
//   round-trips through vertex_displacements().
// The same on 2 ranks (mpirun=2.output equals the serial output).

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/base/timer.h>

#include <deal.II/distributed/shared_tria.h>

#include <deal.II/fe/fe_nothing.h>
#include <deal.II/fe/fe_values.h>

#include <deal.II/grid/grid_generator.h>

#include <tkr/geometry/mesh_motion.h>
#include <tkr/geometry/worn_geometry.h>
#include <tkr/mesh/mesh.h>

#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "../tests.h"

namespace
{
  /** The tibia's volume in the geometry's current mapping (mm^3). */
  double
  tibia_volume(const TKR::Geometry::WornGeometry &geometry,
               const MPI_Comm                     communicator)
  {
    FEValues<3> fe_values(geometry.get_mapping(),
                          geometry.get_dof_handler().get_fe(),
                          QGauss<3>(2),
                          update_JxW_values);
    double      volume = 0;
    for (const auto &cell : geometry.get_dof_handler().active_cell_iterators())
      if (cell->is_locally_owned() &&
          cell->material_id() == TKR::Mesh::MaterialIds::tibia)
        {
          fe_values.reinit(cell);
          for (const unsigned int q : fe_values.quadrature_point_indices())
            volume += fe_values.JxW(q);
        }
    return Utilities::MPI::sum(volume, communicator);
  }

  /** The vertices on boundary part @p id. */
  std::vector<bool>
  on_boundary(const Triangulation<3> &triangulation, const unsigned int id)
  {
    std::vector<bool> on(triangulation.n_vertices(), false);
    for (const auto &cell : triangulation.active_cell_iterators())
      for (const auto f : cell->face_indices())
        if (cell->face(f)->at_boundary() && cell->face(f)->boundary_id() == id)
          for (const auto v : cell->face(f)->vertex_indices())
            on[cell->face(f)->vertex_index(v)] = true;
    return on;
  }

  /** Half a spherical shell as a tibia, refined @p n_refinements times. */
  void
  make_shell(Triangulation<3> &triangulation, const unsigned int n_refinements)
  {
    GridGenerator::half_hyper_shell(triangulation, Point<3>(), 20., 30.);
    triangulation.refine_global(n_refinements);
    for (const auto &cell : triangulation.active_cell_iterators())
      {
        cell->set_material_id(TKR::Mesh::MaterialIds::tibia);
        for (const auto f : cell->face_indices())
          if (cell->face(f)->at_boundary())
            {
              const double r = cell->face(f)->center(true).norm();
              cell->face(f)->set_boundary_id(
                r > 29. ? TKR::Mesh::BoundaryIds::tibia_contact :
                r < 21. ? TKR::Mesh::BoundaryIds::tibia_inferior :
                          TKR::Mesh::BoundaryIds::free);
            }
      }
  }

  /** Returns the relative difference of lost volume and sum d_j A_j. */
  double
  check(const std::string                             &name,
        const std::function<void(Triangulation<3> &)> &make_grid,
        const MPI_Comm                                 communicator)
  {
    deallog.push(name);
    parallel::shared::Triangulation<3> triangulation(
      communicator,
      Triangulation<3>::none,
      false,
      parallel::shared::Triangulation<3>::partition_metis);
    make_grid(triangulation);
    TKR::Geometry::WornGeometry geometry(triangulation, communicator);
    geometry.initialize();
    TimerOutput               timer(MPI_COMM_SELF,
                      deallog.get_file_stream(),
                      TimerOutput::never,
                      TimerOutput::wall_times);
    TKR::Geometry::MeshMotion motion(geometry, communicator, timer);
    motion.setup();

    const auto               &surface  = geometry.worn_surface().nodes();
    const auto                measures = geometry.worn_surface_measures();
    const auto               &x        = geometry.vertex_positions();
    const double              d0       = 2e-3;
    std::vector<Tensor<1, 3>> target(triangulation.n_vertices());
    double                    expected = 0;
    for (unsigned int j = 0; j < surface.size(); ++j)
      {
        const Point<3> &p = x[surface[j].vertex];
        const double    d =
          d0 * (1. + 0.5 * std::sin(p[0] / 10.) * std::cos(p[1] / 8.));
        target[surface[j].vertex] = -d * measures.normal[j];
        expected += d * measures.area[j];
      }
    const double volume_before = tibia_volume(geometry, communicator);
    const auto   moved         = motion.extend(target);

    const auto contact =
      on_boundary(triangulation, TKR::Mesh::BoundaryIds::tibia_contact);
    const auto inferior =
      on_boundary(triangulation, TKR::Mesh::BoundaryIds::tibia_inferior);
    const auto femur =
      TKR::Mesh::material_vertices(triangulation,
                                   TKR::Mesh::MaterialIds::femur);
    double contact_error = 0, inferior_motion = 0, femur_motion = 0;
    for (unsigned int v = 0; v < moved.size(); ++v)
      {
        if (contact[v])
          contact_error =
            std::max(contact_error, (moved[v] - target[v]).norm());
        if (inferior[v])
          inferior_motion = std::max(inferior_motion, moved[v].norm());
        if (femur[v])
          femur_motion = std::max(femur_motion, moved[v].norm());
      }
    deallog << "tibia_contact vertices moved by -d n to 1e-14: "
            << yes_no(contact_error < 1e-14) << std::endl;
    deallog << "tibia_inferior and femur vertices do not move: "
            << yes_no(inferior_motion == 0. && femur_motion == 0.) << std::endl;
    const auto distortion = motion.distortion(moved);
    deallog << "smallest Jacobian ratio above 0.99: "
            << yes_no(distortion.min_ratio > 0.99) << std::endl;

    geometry.set_vertex_displacements(moved);
    double     round_trip = 0;
    const auto back       = geometry.vertex_displacements();
    for (unsigned int v = 0; v < moved.size(); ++v)
      round_trip = std::max(round_trip, (back[v] - moved[v]).norm());
    deallog << "vertex displacements round-trip to 1e-15: "
            << yes_no(round_trip < 1e-15) << std::endl;

    const double lost = volume_before - tibia_volume(geometry, communicator);
    const double relative = std::abs(lost - expected) / expected;
    deallog << "lost volume " << lost << " mm^3, sum d_j A_j " << expected
            << " mm^3, relative difference x 1e3: " << 1e3 * relative
            << std::endl;
    double position_error = 0;
    for (unsigned int j = 0; j < surface.size(); ++j)
      {
        const unsigned int v = surface[j].vertex;
        position_error =
          std::max(position_error,
                   (geometry.vertex_positions()[v] -
                    (triangulation.get_vertices()[v] + target[v]))
                     .norm());
      }
    deallog << "worn positions = mesh - d n at tibia_contact to 1e-12: "
            << yes_no(position_error < 1e-12) << std::endl;
    deallog.pop();
    return relative;
  }
} // namespace

int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  initlog();
  std::vector<double> shell;
  for (const unsigned int n : {1u, 2u, 3u})
    shell.push_back(check(
      "shell-" + std::to_string(n),
      [n](Triangulation<3> &triangulation) { make_shell(triangulation, n); },
      MPI_COMM_WORLD));
  deallog << "smooth surface, difference ratios per halving of h (O(h^2): "
             "4): "
          << shell[0] / shell[1] << ' ' << shell[1] / shell[2] << std::endl;
  deallog << "second order (ratios above 3): "
          << yes_no(shell[0] > 3. * shell[1] && shell[1] > 3. * shell[2])
          << std::endl;

  const auto tkr = [](const std::string &mesh) {
    return [mesh](Triangulation<3> &triangulation) {
      TKR::Mesh::read_mesh(TKR::Parameters::Mesh::with_default_groups(
                             std::string(SOURCE_DIR) + "/../../meshes/tkr/" +
                             mesh + ".msh"),
                           triangulation);
    };
  };
  const double coarse =
    check("tkr-a-coarse", tkr("tkr-a-coarse"), MPI_COMM_WORLD);
  const double medium =
    check("tkr-a-medium", tkr("tkr-a-medium"), MPI_COMM_WORLD);
  deallog << "creased surface: below 4 % and shrinking: "
          << yes_no(coarse < 0.04 && medium < coarse) << std::endl;
}
