// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.
//
// Contact patch test (patch_test.h) on two flat blocks with non-matching,
// structured interface meshes (meshes/verification/patch-fine.msh):
// lambda_j = p at every slave node to 1e-8, on 1 and 2 ranks.

#include "patch_test.h"

int
main(int argc, char **argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  initlog();
  const double max_error = run_patch_test("patch-fine.msh");
  deallog << "pressure uniform (= p) to 1e-8: " << yes_no(max_error < 1e-8)
          << std::endl;
  if (max_error >= 1e-8)
    deallog << "max relative pressure error: " << max_error << std::endl;
}
