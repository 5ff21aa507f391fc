// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.
//
// Contact patch test (patch_test.h) on unstructured meshes: two flat blocks
// meshed with tetrahedra split into hexahedra
// (meshes/verification/patch-unstructured.msh: warped hexahedra, 198 slave
// against 354 master quadrilaterals of different size and orientation on the
// interface): lambda_j = p at every slave node to 1e-8 (measured: 2e-12),
// on 1 and 2 ranks.

#include "patch_test.h"

int
main(int argc, char **argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  initlog();
  const double max_error = run_patch_test("patch-unstructured.msh");
  deallog << "pressure uniform (= p) to 1e-8: " << yes_no(max_error < 1e-8)
          << std::endl;
  deallog << "pressure uniform (= p) to 1e-10: " << yes_no(max_error < 1e-10)
          << std::endl;
}
