// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_elasticity_rigid_body_modes_h
#define tkr_elasticity_rigid_body_modes_h

#include <deal.II/base/index_set.h>

#include <deal.II/dofs/dof_handler.h>

#include <deal.II/fe/mapping.h>

#include <Epetra_Map.h>
#include <Epetra_MultiVector.h>

#include <memory>

namespace TKR::Elasticity
{
  /**
   * The six rigid-body modes of a 3d displacement field (three translations,
   * three infinitesimal rotations about the centre of the mesh's bounding
   * box) as an Epetra_MultiVector over the locally owned DoFs, for use as
   * the near-null space of Trilinos ML. deal.II 9.4 has no
   * extract_rigid_body_modes(), and its AMG AdditionalData::constant_modes
   * only covers translations. @p owned_map must list @p owned_dofs in
   * order (as the maps of deal.II's Trilinos matrices do).
   */
  std::unique_ptr<Epetra_MultiVector>
  rigid_body_modes(const dealii::Mapping<3>    &mapping,
                   const dealii::DoFHandler<3> &dof_handler,
                   const dealii::IndexSet      &owned_dofs,
                   const Epetra_Map            &owned_map);
} // namespace TKR::Elasticity

#endif
