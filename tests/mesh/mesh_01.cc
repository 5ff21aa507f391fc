// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.
//
// read_mesh() on the patch-test mesh: physical names, material and boundary
// ids, volumes and areas (exact for these flat blocks). Then the two broken
// meshes of this folder and a misnamed group: each must be refused with a
// message that names the problem.

#include <deal.II/distributed/shared_tria.h>

#include <tkr/base/exceptions.h>
#include <tkr/mesh/mesh.h>

#include "../tests.h"

namespace
{
  const std::string source_dir = SOURCE_DIR;

  /** The message without the machine-dependent source path. */
  std::string
  strip_path(std::string message)
  {
    for (auto pos = message.find(source_dir); pos != std::string::npos;
         pos      = message.find(source_dir))
      message.replace(pos, source_dir.size(), "SOURCE_DIR");
    return message;
  }

  void
  try_to_read(const TKR::Parameters::Mesh &parameters)
  {
    Triangulation<3> triangulation;
    try
      {
        TKR::Mesh::read_mesh(parameters, triangulation);
        deallog << "read (unexpected)" << std::endl;
      }
    catch (const TKR::ExcInputError &exc)
      {
        deallog << strip_path(TKR::exception_message(exc)) << std::endl;
      }
  }
} // namespace

int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  initlog();

  TKR::Parameters::Mesh parameters = TKR::Parameters::Mesh::with_default_groups(
    source_dir + "/../../meshes/verification/patch-coarse.msh");
  for (const auto &group : TKR::Mesh::read_physical_names(parameters.file))
    deallog << "group " << group.dim << ' ' << group.tag << ' ' << group.name
            << std::endl;

  parallel::shared::Triangulation<3> triangulation(MPI_COMM_WORLD);
  TKR::Mesh::read_mesh(parameters, triangulation);
  const auto s = TKR::Mesh::compute_statistics(triangulation);
  deallog << "cells femur " << s.femur_cells << " tibia " << s.tibia_cells
          << " vertices " << s.n_vertices << std::endl;
  deallog << "volume femur " << s.femur_volume << " tibia " << s.tibia_volume
          << std::endl;
  for (unsigned int id = 0; id < 5; ++id)
    deallog << "area " << TKR::Mesh::boundary_name(id) << ' '
            << s.boundary_area[id] << std::endl;

  deallog.push("missing group");
  auto broken = parameters;
  broken.file = source_dir + "/patch-missing-group.msh";
  try_to_read(broken);
  deallog.pop();

  deallog.push("twisted cell");
  broken.file = source_dir + "/patch-twisted.msh";
  try_to_read(broken);
  deallog.pop();

  deallog.push("renamed group");
  broken                    = parameters;
  broken.tibia_contact_name = "tibia_top";
  try_to_read(broken);
  deallog.pop();

  deallog.push("no file");
  broken.file = "no-such-file.msh";
  try_to_read(broken);
  deallog.pop();
}
