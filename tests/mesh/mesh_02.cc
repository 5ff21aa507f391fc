// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.
//
// Every committed mesh listed in meshes/volumes.csv reads through
// read_mesh() (all physical groups present, no inverted or twisted cell),
// has the listed numbers of hexahedra and of vertices per body, and body
// volumes within 1 % of the exact (CAD or analytic) volumes of its
// geometry (the meshes approximate curved surfaces with bilinear faces).

#include <deal.II/grid/tria.h>

#include <tkr/mesh/mesh.h>

#include <fstream>
#include <set>
#include <sstream>

#include "../tests.h"

int
main()
{
  initlog();
  const std::string meshes = std::string(SOURCE_DIR) + "/../../meshes/";
  std::ifstream     csv(meshes + "volumes.csv");
  std::string       line;
  std::getline(csv, line); // header
  unsigned int n_meshes = 0;
  while (std::getline(csv, line))
    {
      if (line.empty())
        continue;
      std::istringstream in(line);
      std::string        file, field;
      double             volume[2];
      unsigned int       vertices[2], hexahedra;
      std::getline(in, file, ',');
      std::getline(in, field, ',');
      volume[0] = std::stod(field);
      std::getline(in, field, ',');
      volume[1] = std::stod(field);
      std::getline(in, field, ',');
      vertices[0] = std::stoul(field);
      std::getline(in, field, ',');
      vertices[1] = std::stoul(field);
      std::getline(in, field, ',');
      hexahedra = std::stoul(field);

      TKR::Parameters::Mesh parameters =
        TKR::Parameters::Mesh::with_default_groups(meshes + file);
      Triangulation<3> triangulation;
      TKR::Mesh::read_mesh(parameters, triangulation);
      const auto s = TKR::Mesh::compute_statistics(triangulation);

      std::set<unsigned int> body_vertices[2];
      for (const auto &cell : triangulation.active_cell_iterators())
        for (const auto v : cell->vertex_indices())
          body_vertices[cell->material_id() == TKR::Mesh::MaterialIds::femur ?
                          0 :
                          1]
            .insert(cell->vertex_index(v));

      const double femur_error = std::abs(s.femur_volume / volume[0] - 1.);
      const double tibia_error = std::abs(s.tibia_volume / volume[1] - 1.);
      deallog << file << ": read, groups and Jacobians ok; hexahedra "
              << yes_no(triangulation.n_active_cells() == hexahedra)
              << ", vertices "
              << yes_no(body_vertices[0].size() == vertices[0] &&
                        body_vertices[1].size() == vertices[1])
              << ", volumes within 1 %: "
              << yes_no(femur_error < 0.01 && tibia_error < 0.01) << std::endl;
      if (femur_error >= 0.01 || tibia_error >= 0.01)
        deallog << "  volume errors " << femur_error << ' ' << tibia_error
                << std::endl;
      ++n_meshes;
    }
  deallog << n_meshes << " meshes checked" << std::endl;
}
